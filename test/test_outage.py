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

"""Outages: cycles lost from sensor time, when they leave the floor in doubt, the snap to it."""

from anfis_elevation_ros.core.gait import N_FEATURES
from anfis_elevation_ros.core.height import ElevationParams, ElevationTracker, HEIGHT_CHANGE
from anfis_elevation_ros.core.outage import FloorDoubt, outage_cycle_count
from anfis_elevation_ros.core.outage import max_unobserved_climb, outage_leaves_doubt
from anfis_elevation_ros.core.outage import snapped_floor_height, UNKNOWN_CLIMB_M
from live_support import write_linear_model
import numpy as np
import pytest


def test_cycles_lost_from_sensor_time_and_the_stride_period():
    assert outage_cycle_count(3.4, 1.1) == 3        # 3.09 strides
    assert outage_cycle_count(3.9, 1.1) == 4        # 3.55
    assert outage_cycle_count(0.2, 1.1) == 0
    assert outage_cycle_count(1e6, 0.1) == 1000     # bounded
    with pytest.raises(ValueError, match='stride_period_s'):
        outage_cycle_count(1.0, 0.0)


def test_doubt_after_a_long_or_a_mixed_outage_only():
    assert not outage_leaves_doubt(3, 1, 1) and not outage_leaves_doubt(2, 0, 0)
    assert outage_leaves_doubt(4, 1, 1) and outage_leaves_doubt(1, 1, 0)
    assert outage_leaves_doubt(1, -1, 1)


def test_a_level_stretch_snaps_only_to_the_one_floor_within_reach():
    floors = [0.0, 4.2, 7.2, 10.2]                   # a taller lobby
    # The case: four lost strides of two risers of 0.17 m, the height four risers low.
    reach_m = max_unobserved_climb(4, 2, 0.17) + 0.17
    assert reach_m == pytest.approx(1.53)
    assert snapped_floor_height(7.2 - 0.68, floors, reach_m) == 7.2
    assert snapped_floor_height(5.7, floors, reach_m) is None   # two floors within reach
    assert snapped_floor_height(5.7, floors, 1.0) is None       # none within reach
    assert snapped_floor_height(1.2, [0.0, 5.4, 10.8], 17 * 2 * 0.15) is None
    assert snapped_floor_height(3.0, [], reach_m) is None       # no building: no floors
    assert max_unobserved_climb(3, 4, 0.15) == pytest.approx(1.8)  # four risers a stride


def test_floor_doubt_counts_and_clears():
    doubt = FloorDoubt()
    assert doubt.certain and doubt.doubts == 0
    doubt.doubt('5 gait cycles unobserved', 1.5)
    doubt.doubt('2 gait cycles unobserved', 0.6)
    assert not doubt.certain and doubt.doubts == 2 and doubt.reach_m == pytest.approx(2.1)
    doubt.doubt('a new walk')
    assert doubt.reach_m == UNKNOWN_CLIMB_M
    doubt.clear()
    assert doubt.certain and doubt.reach_m == 0.0
    assert not FloorDoubt('saved as uncertain', 0.9).certain


def stair_cycle(dh_m):
    features = np.zeros(N_FEATURES)
    features[HEIGHT_CHANGE] = dh_m
    return features


def test_a_resumed_tracker_bridges_the_outage_of_a_flight(tmp_path):
    """
    A restart in a flight: the tracker resumed with the last stride bridges the lost cycles.

    Two risers of 0.15 m per stride, three strides, three lost in the outage, two after: the
    height is the nine strides' 18 risers, as if the node had never stopped.
    """
    from anfis_elevation_ros.core.anfis import Anfis

    model = Anfis.load(write_linear_model(tmp_path / 'model.json', 0.15))
    params = ElevationParams(step_height_m=0.15, mode_threshold=0.5)
    before = ElevationTracker(model, params)
    for k in range(4):
        before.update(k, stair_cycle(0.30), 0.7 * k, 0.0)
    after = ElevationTracker(model, params, height_m=before.height_m)
    after.resume_flight(before.last_mode, before.last_abs_dh_m)
    for k in range(4, 7):
        after.update(k, None, 0.7 * k, 0.0, valid=False)
    for k in range(7, 9):
        after.update(k, stair_cycle(0.30), 0.7 * k, 0.0)
    assert after.bridged_cycles == 3 and after.unbridged_cycles == 0
    assert after.height_m == pytest.approx(9 * 0.30)
    with pytest.raises(ValueError):
        after.resume_flight(2, 0.3)


def test_correct_height_moves_the_height_and_its_floor(tmp_path):
    from anfis_elevation_ros.core.anfis import Anfis

    model = Anfis.load(write_linear_model(tmp_path / 'model.json', 0.15))
    tracker = ElevationTracker(model, ElevationParams(step_height_m=0.15, mode_threshold=0.5,
                                                      floor_height_m=3.0))
    tracker.correct_height(2.96)
    assert tracker.height_m == pytest.approx(2.96) and tracker.floor == 1
    assert tracker.floor_certain
