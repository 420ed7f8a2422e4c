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

"""The import-csv tool: CSV in g, deg/s and ms -> bag -> SI values back; clear one-line errors."""

import math

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.tools import datasets
from anfis_elevation_ros.tools.bags import read_imu_bag
from anfis_elevation_ros.tools.cli import main
from anfis_elevation_ros.tools.import_csv import CsvImuFormat, read_imu_csv
import numpy as np
import pytest

G = 9.80665
N = 400


def imu_table(n=N):
    """Return (time_ms (n,) str, acc_g (n, 3), gyr_dps (n, 3)): still for 0.5 s, then moving."""
    k = np.arange(n)
    # 200 Hz with a jitter of a few tenths of a ms, written as decimal strings.
    time_ms = [f'{1000 + 5 * i + 0.125 * (i % 3)}' for i in range(n)]
    moving = (k >= 100).astype(float)
    phase = 2 * np.pi * k / 200.0
    acc_g = np.column_stack([0.02 + 0.5 * moving * np.sin(phase),
                             -0.01 + 0.3 * moving * np.cos(phase),
                             1.0 + 0.8 * moving * np.sin(2 * phase)])
    gyr_dps = np.column_stack([0.3 + 250.0 * moving * np.sin(phase),
                               -0.2 + 400.0 * moving * np.cos(phase),
                               0.1 + 120.0 * moving * np.sin(3 * phase)])
    return time_ms, acc_g, gyr_dps


def write_csv(path, time_col, acc, gyr, delimiter=',', preamble=(), names=None):
    """Write a CSV with columns (time_col?, ax, ay, az, gx, gy, gz, temp)."""
    names = names or ['ax', 'ay', 'az', 'gx', 'gy', 'gz']
    header = ([] if time_col is None else ['time_ms']) + names + ['temp']
    lines = list(preamble) + [delimiter.join(header)]
    for i in range(len(acc)):
        cells = [] if time_col is None else [str(time_col[i])]
        cells += [repr(float(v)) for v in acc[i]] + [repr(float(v)) for v in gyr[i]] + ['21.5']
        lines.append(delimiter.join(cells))
    path.write_text('\n'.join(lines) + '\n')
    return path


def run(args, capsys):
    """Run the CLI; return (exit code, stderr)."""
    code = main([str(a) for a in args])
    return code, capsys.readouterr().err


def assert_one_line_error(code, err, *fragments):
    """Exit code 1 and a single 'error: ...' line holding every fragment."""
    assert code == 1
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith('error: ')
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


IMU_ARGS = ['--acc-cols', 'ax,ay,az', '--gyr-cols', 'gx,gy,gz']


@pytest.mark.parametrize('storage', ['sqlite3', 'mcap'])
def test_g_dps_ms_csv_round_trips_through_a_bag_in_si(tmp_path, capsys, storage):
    time_ms, acc_g, gyr_dps = imu_table()
    csv_path = write_csv(tmp_path / 'log.csv', time_ms, acc_g, gyr_dps)
    bag = tmp_path / 'bag'
    code, err = run(['import-csv', csv_path, '--out', bag, '--time-col', 'time_ms',
                     '--time-unit', 'ms', '--acc-unit', 'g', '--gyr-unit', 'dps',
                     '--frame-id', 'left_foot_imu', '--topic', '/foot/imu', '--storage', storage]
                    + IMU_ARGS, capsys)
    assert code == 0, err
    assert f'wrote {N} samples' in err
    rec = read_imu_bag(bag, topic='/foot/imu')
    # 1000.125 ms = 1000125000 ns exactly: stamps are parsed as decimals, not floats.
    expected_ns = np.array([int(round(float(t) * 1000)) * 1000 for t in time_ms])
    np.testing.assert_array_equal(rec.stamp_ns, expected_ns)
    assert rec.stamp_ns[1] == 1_005_125_000
    np.testing.assert_allclose(rec.acc_b, acc_g * G, rtol=1e-12, atol=0)
    np.testing.assert_allclose(rec.gyr_b, np.deg2rad(gyr_dps), rtol=1e-12, atol=0)
    assert rec.frame_id == 'left_foot_imu'


def test_rate_hz_tab_delimiter_and_skip_rows(tmp_path, capsys):
    _, acc_g, gyr_dps = imu_table()
    csv_path = write_csv(tmp_path / 'log.tsv', None, acc_g * G, np.deg2rad(gyr_dps),
                         delimiter='\t', preamble=['# logger v2', 'device: foot'])
    bag = tmp_path / 'bag'
    code, err = run(['import-csv', csv_path, '--out', bag, '--rate-hz', 256,
                     '--delimiter', 'tab', '--skip-rows', 2] + IMU_ARGS, capsys)
    assert code == 0, err
    rec = read_imu_bag(bag)
    np.testing.assert_array_equal(rec.stamp_ns, np.arange(N) * 3_906_250)  # 1e9 / 256 exactly
    np.testing.assert_allclose(rec.acc_b, acc_g * G, rtol=1e-12)
    np.testing.assert_allclose(rec.gyr_b, np.deg2rad(gyr_dps), rtol=1e-12)


def test_real_xio_file_matches_the_dataset_loader(tmp_path, capsys):
    # A real user's CSV: column names with spaces, g and deg/s, no time column (256 Hz).
    path = datasets.dataset_files('xio_foot')[-1]
    assert path.name == 'xio_straightLine_CalInertialAndMag.csv'
    bag = tmp_path / 'bag'
    code, err = run(['import-csv', path, '--out', bag, '--rate-hz', 256, '--storage', 'mcap',
                     '--acc-cols', ','.join(f'Accelerometer {a} (g)' for a in 'XYZ'),
                     '--gyr-cols', ','.join(f'Gyroscope {a} (deg/s)' for a in 'XYZ'),
                     '--acc-unit', 'g', '--gyr-unit', 'dps'], capsys)
    assert code == 0, err
    rec, ref = read_imu_bag(bag), datasets.load_xio(path)
    np.testing.assert_array_equal(rec.stamp_ns, ref.stamp_ns)
    np.testing.assert_allclose(rec.acc_b, ref.acc_b, rtol=1e-15)
    np.testing.assert_allclose(rec.gyr_b, ref.gyr_b, rtol=1e-15)


def test_stamps_are_exact_decimals(tmp_path):
    _, acc_g, gyr_dps = imu_table(12)
    times = [f'1700000000.{123456789 + 1000 * i}' for i in range(12)]
    path = write_csv(tmp_path / 'log.csv', times, acc_g * G, np.deg2rad(gyr_dps))
    rec = read_imu_csv(path, CsvImuFormat(time_col='time_ms', acc_cols=('ax', 'ay', 'az'),
                                          gyr_cols=('gx', 'gy', 'gz')))
    assert rec.stamp_ns[0] == 1_700_000_000_123_456_789   # beyond float64 resolution
    assert np.all(np.diff(rec.stamp_ns) == 1000)


def test_missing_column(tmp_path, capsys):
    time_ms, acc_g, gyr_dps = imu_table()
    csv_path = write_csv(tmp_path / 'log.csv', time_ms, acc_g, gyr_dps)
    code, err = run(['import-csv', csv_path, '--out', tmp_path / 'bag', '--time-col', 'time_ms',
                     '--acc-cols', 'ax,ay,accz', '--gyr-cols', 'gx,gy,gz'], capsys)
    assert_one_line_error(code, err, "column 'accz' not in the header", '--acc-cols')
    assert not (tmp_path / 'bag').exists()


def test_non_increasing_time(tmp_path, capsys):
    time_ms, acc_g, gyr_dps = imu_table()
    time_ms[57] = time_ms[56]
    csv_path = write_csv(tmp_path / 'log.csv', time_ms, acc_g, gyr_dps)
    code, err = run(['import-csv', csv_path, '--out', tmp_path / 'bag', '--time-col', 'time_ms',
                     '--time-unit', 'ms', '--acc-unit', 'g', '--gyr-unit', 'dps'] + IMU_ARGS,
                    capsys)
    # Header is line 1, so sample 57 is on line 59.
    assert_one_line_error(code, err, 'log.csv:59', 'does not increase')
    assert not (tmp_path / 'bag').exists()


def test_non_numeric_cell_and_too_few_rows(tmp_path, capsys):
    time_ms, acc_g, gyr_dps = imu_table()
    path = write_csv(tmp_path / 'log.csv', time_ms, acc_g, gyr_dps)
    lines = path.read_text().splitlines()
    lines[10] = lines[10].replace(lines[10].split(',')[5], 'n/a', 1)
    path.write_text('\n'.join(lines) + '\n')
    code, err = run(['import-csv', path, '--out', tmp_path / 'bag', '--time-col', 'time_ms',
                     '--time-unit', 'ms', '--acc-unit', 'g', '--gyr-unit', 'dps'] + IMU_ARGS,
                    capsys)
    assert_one_line_error(code, err, 'log.csv:11', "'gy'", "'n/a'", 'not a number')
    short = write_csv(tmp_path / 'short.csv', time_ms[:5], acc_g[:5], gyr_dps[:5])
    code, err = run(['import-csv', short, '--out', tmp_path / 'bag', '--time-col', 'time_ms']
                    + IMU_ARGS, capsys)
    assert_one_line_error(code, err, '5 data rows', 'at least 10')


@pytest.mark.parametrize('units, fragment', [
    ([], '--acc-unit g'),                                      # g data claimed m/s^2
    (['--acc-unit', 'g'], '--gyr-unit dps'),                   # deg/s data claimed rad/s
], ids=['acc-in-g', 'gyr-in-dps'])
def test_si_claimed_but_g_or_dps_is_refused(tmp_path, capsys, units, fragment):
    time_ms, acc_g, gyr_dps = imu_table()
    csv_path = write_csv(tmp_path / 'log.csv', time_ms, acc_g, gyr_dps)
    code, err = run(['import-csv', csv_path, '--out', tmp_path / 'bag', '--time-col', 'time_ms',
                     '--time-unit', 'ms'] + units + IMU_ARGS, capsys)
    assert_one_line_error(code, err, fragment)
    assert not (tmp_path / 'bag').exists()


@pytest.mark.parametrize('time_unit', ['s', 'us'])
def test_wrong_time_unit_is_refused(tmp_path, capsys, time_unit):
    # ms read as s gives 0.2 Hz, read as us 200 kHz.
    time_ms, acc_g, gyr_dps = imu_table()
    csv_path = write_csv(tmp_path / 'log.csv', time_ms, acc_g, gyr_dps)
    code, err = run(['import-csv', csv_path, '--out', tmp_path / 'bag', '--time-col', 'time_ms',
                     '--time-unit', time_unit, '--acc-unit', 'g', '--gyr-unit', 'dps']
                    + IMU_ARGS, capsys)
    assert_one_line_error(code, err, 'implausible', '--time-unit')


def test_converting_si_data_again_is_refused(tmp_path, capsys):
    time_ms, acc_g, gyr_dps = imu_table()
    csv_path = write_csv(tmp_path / 'log.csv', time_ms, acc_g * G, np.deg2rad(gyr_dps))
    code, err = run(['import-csv', csv_path, '--out', tmp_path / 'bag', '--time-col', 'time_ms',
                     '--time-unit', 'ms', '--acc-unit', 'g'] + IMU_ARGS, capsys)
    assert_one_line_error(code, err, 'already in m/s^2', '--acc-unit mps2')


def test_existing_output_and_bad_usage(tmp_path, capsys):
    time_ms, acc_g, gyr_dps = imu_table()
    csv_path = write_csv(tmp_path / 'log.csv', time_ms, acc_g, gyr_dps)
    (tmp_path / 'bag').mkdir()
    code, err = run(['import-csv', csv_path, '--out', tmp_path / 'bag', '--time-col', 'time_ms',
                     '--acc-unit', 'g', '--gyr-unit', 'dps'] + IMU_ARGS, capsys)
    assert_one_line_error(code, err, 'exists')
    with pytest.raises(SystemExit) as exc:   # neither --time-col nor --rate-hz: usage, exit 2
        main(['import-csv', str(csv_path), '--out', str(tmp_path / 'bag2')])
    assert exc.value.code == 2
    assert 'one of the arguments --time-col --rate-hz is required' in capsys.readouterr().err
    code, err = run(['import-csv', tmp_path / 'nope.csv', '--out', tmp_path / 'bag3',
                     '--rate-hz', 100], capsys)
    assert_one_line_error(code, err, 'nope.csv')


def test_binary_file_is_a_clear_error(tmp_path, capsys):
    path = tmp_path / 'log.bin'
    path.write_bytes(bytes(range(256)) * 4)
    code, err = run(['import-csv', path, '--out', tmp_path / 'bag', '--rate-hz', 100], capsys)
    assert_one_line_error(code, err, 'log.bin')


def test_format_validation_names_the_field():
    with pytest.raises(InputError, match='exactly one of time_col'):
        CsvImuFormat()
    with pytest.raises(InputError, match='rate_hz'):
        CsvImuFormat(rate_hz=-5.0)
    with pytest.raises(InputError, match='acc_unit'):
        CsvImuFormat(rate_hz=100.0, acc_unit='mg')
    assert CsvImuFormat(rate_hz=100.0).acc_cols == ('acc_x', 'acc_y', 'acc_z')
    assert math.isclose(CsvImuFormat(rate_hz=100.0).rate_hz, 100.0)
