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

"""Offline replay through the command line: CSV contracts and exact stamps."""

import csv

from anfis_elevation_ros.sim import Segment, simulate_walk
from anfis_elevation_ros.tools.bags import write_imu_bag
from anfis_elevation_ros.tools.cli import main
import numpy as np


def test_replay_writes_the_csv_contract_with_exact_stamps(tmp_path):
    segments = (Segment.level(3), Segment.stairs(6, +1, steps_per_stride=2), Segment.level(2))
    walk = simulate_walk(segments, rng=np.random.default_rng(3), rate_hz=200.0, imu='tactical',
                         step_height_m=0.17)
    write_imu_bag(tmp_path / 'bag', walk.to_recording())
    assert main(['replay', str(tmp_path / 'bag'), '--out', str(tmp_path / 'out')]) == 0

    with open(tmp_path / 'out' / 'track.csv') as f:
        track = list(csv.reader(f))
    assert track[0][:4] == ['stamp_ns', 'x_m', 'y_m', 'z_m']
    stamps = np.array([int(row[0]) for row in track[1:]], dtype=np.int64)
    # Every row is an IMU sample, to the nanosecond (float64 would round to 256 ns here).
    assert np.isin(stamps, walk.stamp_ns).all() and np.all(np.diff(stamps) > 0)
    assert len(stamps) > 0.9 * len(walk.stamp_ns)

    with open(tmp_path / 'out' / 'cycles.csv') as f:
        cycles = list(csv.DictReader(f))
    assert list(cycles[0])[:5] == ['stamp_ns', 'mode', 'height_m', 'x_m', 'y_m']
    assert np.isin([int(c['stamp_ns']) for c in cycles], stamps).all()
    assert len(cycles) == len(walk.strides.stamp_ns)
    k_m = float(cycles[-1]['step_height_m'])      # six steps of K = 0.17 m, K estimated
    assert abs(float(cycles[-1]['height_m']) - 6 * k_m) < 1e-9 and abs(k_m - 0.17) < 0.001
