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
The gdin_hallway loader on the real walks (skipped when ../shared/data has no gdin_hallway).

Units by physics: |g| at rest in m/s^2 (the 200 Hz layout is in g), a quiet gyro in rad/s,
the Earth's field in tesla; the truth's size checked against ``numberOfStrides``.
"""

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.tools.gdin_hallway import load_gdin_walk
from gdin_support import gdin_files
import numpy as np
import pytest


def quietest_window(gyr_b, n=40):
    """Return the slice of the n samples with the least mean |w| (a walk may start moving)."""
    norm = np.convolve(np.linalg.norm(gyr_b, axis=1), np.ones(n), mode='valid')
    start = int(np.argmin(norm))
    return slice(start, start + n)


def test_every_walk_loads_in_si_units_with_its_truth():
    files = gdin_files()
    assert len(files) >= 9
    for path in files:
        walk = load_gdin_walk(path)
        rec = walk.recording
        assert round(rec.rate_hz) in (200, 250), path
        quiet = quietest_window(rec.gyr_b[:400])
        rest_acc = rec.acc_b[quiet].mean(axis=0)
        # Sensor z down: the specific force at rest points along -z.
        assert abs(np.linalg.norm(rest_acc) - 9.81) < 0.3, path
        assert rest_acc[2] < -6.0, path
        assert np.linalg.norm(rec.gyr_b[quiet], axis=1).mean() < 0.05, path
        assert walk.stride_pos_m.shape == (walk.n_strides + 1, 2)
        assert np.all(walk.stride_pos_m[0] == 0.0)
        # 24-102 strides of 0.8-2.2 m each (walk 35 is brisk: 2.0 m).
        assert 0.8 < walk.path_length_m / walk.n_strides < 2.2, path
        if round(rec.rate_hz) == 200:
            field_t = np.linalg.norm(walk.mag_t, axis=1)
            assert 20e-6 < np.median(field_t) < 80e-6, path
        else:
            assert walk.mag_t is None


def test_layouts_are_told_by_their_headers():
    rates = {round(load_gdin_walk(path).recording.rate_hz) for path in gdin_files()}
    assert rates == {200, 250}


def write_walk(tmp_path, header, rows):
    csv_path = tmp_path / 'SensorConnectData_99.csv'
    csv_path.write_text('\n'.join([','.join(header)] + [','.join(map(str, r)) for r in rows]))
    return csv_path


def test_bad_files_are_clear_errors(tmp_path):
    source = gdin_files()[0]
    with pytest.raises(InputError, match='not found'):
        load_gdin_walk(tmp_path / 'SensorConnectData_99.csv')
    header = ['Time'] + [f'inertial:estCompensatedAccel{a}' for a in 'XYZ'] \
        + [f'inertial:estAngularRate{a}' for a in 'XYZ'] + ['inertial:estAngularRateZ:valid']
    rows = [[k * 0.004, 0, 0, -9.8, 0, 0, 0, 1] for k in range(5)]
    rows[3][-1] = 0
    csv_path = write_walk(tmp_path, header, rows)
    (tmp_path / 'SensorConnectData_99.mat').write_bytes(source.with_suffix('.mat').read_bytes())
    with pytest.raises(InputError, match='flagged invalid at sample 3'):
        load_gdin_walk(csv_path)
    write_walk(tmp_path, ['Time', 'a', 'b'], rows)
    with pytest.raises(InputError, match='SensorConnect'):
        load_gdin_walk(csv_path)
