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
Benchmark of the navigator: accuracy on real recordings and replay throughput (a script).

Run from the repository root: ``python test/benchmarks/bench_accuracy.py``. Prints the pyshoe
VICON position error (36 trials, one parameter set), the final heights on the real stair
recordings, and IMU samples/s through the full replay pipeline (input gate, mechanisation,
detector, EKF, features, ANFIS) on one core. ``--gyro-range-rps R`` declares the gyro's range
(``gyro_range_rps``, unknown by default), whose clipped samples are then rebuilt
(``rail.enabled``, ``core/gyro_rail.py``; ``--no-rail-fill`` turns it off), both on the
pyshoe VICON trials (their sensor's range; not on the other recordings).
"""

import argparse
from dataclasses import replace
import time

from anfis_elevation_ros.core.gyro_rail import GyroRailParams
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.core.params import load_model, load_pipeline_params
from anfis_elevation_ros.core.stride_gate import StrideGateParams
from anfis_elevation_ros.sim import building_walk, simulate_walk
from anfis_elevation_ros.tools.datasets import (
    dataset_files, load_mad_stairs, load_pyshoe_vicon, load_xio)
from anfis_elevation_ros.tools.metrics import pyshoe_position_error
from anfis_elevation_ros.tools.replay import replay_recording
import numpy as np


def pyshoe_errors(params=None):
    errors = []
    for path in dataset_files('pyshoe_vicon'):
        recording, truth = load_pyshoe_vicon(path)
        track, _ = FootNavigator(params).run(recording.stamp_ns, recording.acc_b, recording.gyr_b)
        first = np.searchsorted(recording.stamp_ns, track[0].stamp_ns)
        errors.append(pyshoe_position_error(np.array([p.pos_n for p in track]), truth[first:]))
    return np.array(errors)


def final_height(recording, params=None):
    track, _ = FootNavigator(params).run(recording.stamp_ns, recording.acc_b, recording.gyr_b)
    return track[-1].pos_n[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--no-stride-gate', action='store_true',
                        help='stride_gate.enabled false (core/stride_gate.py; on by default)')
    parser.add_argument('--gyro-range-rps', type=float, default=0.0,
                        help='gyro_range_rps (the pyshoe VICON sensor clips near 9.25)')
    parser.add_argument('--no-rail-fill', action='store_true', help='rail.enabled false')
    parser.add_argument('--no-late-stances', action='store_true',
                        help='stride_gate.late_stances false')
    args = parser.parse_args()
    params = NavigatorParams(stride_gate=StrideGateParams(enabled=not args.no_stride_gate,
                                                          late_stances=not args.no_late_stances))
    errors = pyshoe_errors(replace(params, gyro_range_rps=args.gyro_range_rps,
                                   rail=GyroRailParams(enabled=not args.no_rail_fill)))
    print(f'pyshoe VICON, {len(errors)} trials: median {np.median(errors):.3f} m, mean '
          f'{errors.mean():.3f} m, max {errors.max():.3f} m, {np.sum(errors > 0.2)} above 0.2 m')
    for path in dataset_files('mad_stairs'):
        heights = [final_height(load_mad_stairs(path, foot), params)
                   for foot in ('left', 'right')]
        print(f'{path.name}: final height left {heights[0]:+.2f} m, right {heights[1]:+.2f} m')
    for path in dataset_files('xio_foot'):
        print(f'{path.name}: final height {final_height(load_xio(path), params):+.2f} m')

    walk = simulate_walk(building_walk(), rng=np.random.default_rng(0), rate_hz=200.0,
                         imu='consumer')
    recording = walk.to_recording()
    pipeline = load_pipeline_params()
    model = load_model(pipeline.model_path)
    start = time.process_time()
    replay_recording(recording, pipeline, model)
    cpu_s = time.process_time() - start
    print(f'replay throughput: {len(recording) / cpu_s:.0f} IMU samples per CPU second '
          f'({len(recording)} samples, {walk.duration_s:.0f} s of building walk at 200 Hz)')


if __name__ == '__main__':
    main()
