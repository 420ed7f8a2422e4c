# Copyright 2026 The anfis_elevation_ros Authors
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
Foot-mounted IMU simulator: a walk plan, its true foot trajectory and the IMU readings.

Not part of the estimator (``core`` never imports it): it makes the data that tests, training
and benchmarks check the estimator against. A walk is a sequence of ``Segment`` s (level
walking, stair flights, turns on the spot, standing); ``simulate_walk`` turns it into a
``SimulatedWalk``: exact truth at every sample and per stride, and IMU readings corrupted by an
``ImuErrorModel``.

Modules: ``plan`` (segments, gait ranges), ``motion`` (the analytic swing: knots, quintic
pieces, the stride planner; its docstring gives the motion model), ``imu_errors`` (error model
and presets), ``walk`` (simulation and results), ``scenarios`` (walk plans of the tools).

Public API: ``Segment``, ``GaitParams``, ``ImuErrorModel``, ``IMU_PRESETS``, ``imu_error_model``,
``StrideTruth``, ``SimulatedWalk``, ``simulate_walk``, ``apply_imu_errors``, ``interval_means``,
``knot_profile``, ``building_walk``, ``tower_walk``, ``tower_floor_elevations_m``, ``random_walk``,
``sample_walk``, ``nominal_duration_s``,
``EPOCH_NS``, ``DEFAULT_INITIAL_STAND_S``, ``DEFAULT_FINAL_STAND_S``, ``DEFAULT_TREAD_M``.
"""

from .imu_errors import apply_imu_errors, imu_error_model, IMU_PRESETS, ImuErrorModel
from .motion import knot_profile
from .plan import DEFAULT_FINAL_STAND_S, DEFAULT_INITIAL_STAND_S, DEFAULT_TREAD_M, EPOCH_NS
from .plan import GaitParams, Segment
from .scenarios import building_walk, nominal_duration_s, random_walk, sample_walk
from .scenarios import tower_floor_elevations_m, tower_walk
from .walk import interval_means, simulate_walk, SimulatedWalk, StrideTruth

__all__ = ['apply_imu_errors', 'building_walk', 'DEFAULT_FINAL_STAND_S',
           'DEFAULT_INITIAL_STAND_S', 'DEFAULT_TREAD_M', 'EPOCH_NS', 'GaitParams', 'IMU_PRESETS',
           'imu_error_model', 'ImuErrorModel', 'interval_means', 'knot_profile',
           'nominal_duration_s', 'random_walk', 'sample_walk', 'Segment', 'simulate_walk',
           'SimulatedWalk', 'StrideTruth', 'tower_floor_elevations_m', 'tower_walk']
