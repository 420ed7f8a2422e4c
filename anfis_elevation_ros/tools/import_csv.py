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
``import-csv``: turn a CSV log of one IMU into a ROS 2 bag of ``sensor_msgs/msg/Imu``.

The CSV has one header row naming the columns (after ``--skip-rows`` preamble lines) and one
sample per row. Columns are chosen by name; units are given by options and converted to SI
once, here: time to int nanoseconds, acc to m/s^2 (g x 9.80665), gyro to rad/s. The result is
checked with :func:`anfis_elevation_ros.core.units.check_si_units`, so data that still look
like g or deg/s are refused with the option that fixes them.

Example (one command line)::

    python -m anfis_elevation_ros import-csv log.csv --out log_bag --time-col t --time-unit ms
        --acc-cols ax,ay,az --acc-unit g --gyr-cols gx,gy,gz --gyr-unit dps

Public API
----------
CsvImuFormat          column names, units and layout of a CSV (frozen dataclass)
read_imu_csv(path, fmt) -> ImuRecording in SI units
check_csv_units(recording, fmt)   SI plausibility check with option-specific hints
add_parser(subparsers), run_import_csv(args)   the subcommand
"""

import argparse
import csv
from dataclasses import dataclass
import decimal
import itertools
import math
from pathlib import Path
import sys

import numpy as np

from ..core.errors import InputError
from ..core.imu_data import ImuRecording
from ..core.units import check_si_units
from ..core.validation import check_positive, check_range

STANDARD_GRAVITY_MPS2 = 9.80665
#: Nanoseconds per unit of the time column.
TIME_UNITS_NS = {'s': 10 ** 9, 'ms': 10 ** 6, 'us': 10 ** 3, 'ns': 1}
#: Factor to m/s^2 per accelerometer unit.
ACC_UNITS = {'mps2': 1.0, 'g': STANDARD_GRAVITY_MPS2}
#: Factor to rad/s per gyroscope unit.
GYR_UNITS = {'rps': 1.0, 'dps': math.pi / 180.0}
STORAGES = ('sqlite3', 'mcap')
#: Fewer rows than this are no usable recording (usually a wrong delimiter or --skip-rows).
MIN_SAMPLES = 10
#: Median sample rates outside this range [Hz] mean a wrong --time-unit (a factor of 1000).
PLAUSIBLE_RATE_HZ = (10.0, 10000.0)
_INT64_MAX = 2 ** 63 - 1


@dataclass(frozen=True)
class CsvImuFormat:
    """
    Where the IMU quantities are in a CSV file, and in which units.

    Exactly one of ``time_col`` (a column of stamps in ``time_unit``) and ``rate_hz`` (rows are
    equally spaced, the first at t = 0) must be given.
    """

    acc_cols: tuple = ('acc_x', 'acc_y', 'acc_z')
    gyr_cols: tuple = ('gyr_x', 'gyr_y', 'gyr_z')
    time_col: str = None
    rate_hz: float = None
    time_unit: str = 's'
    acc_unit: str = 'mps2'
    gyr_unit: str = 'rps'
    delimiter: str = ','
    skip_rows: int = 0
    frame_id: str = 'imu_link'

    def __post_init__(self):
        for field, value in (('acc_cols', self.acc_cols), ('gyr_cols', self.gyr_cols)):
            if len(value) != 3 or not all(isinstance(name, str) and name for name in value):
                raise InputError(f'{field} must name 3 columns (x, y, z), got {value!r}')
        if (self.time_col is None) == (self.rate_hz is None):
            raise InputError('give exactly one of time_col (--time-col) and rate_hz (--rate-hz)')
        if self.rate_hz is not None:
            check_positive('rate_hz', self.rate_hz)
        for field, value, allowed in (('time_unit', self.time_unit, TIME_UNITS_NS),
                                      ('acc_unit', self.acc_unit, ACC_UNITS),
                                      ('gyr_unit', self.gyr_unit, GYR_UNITS)):
            if value not in allowed:
                raise InputError(f'{field} must be one of {", ".join(allowed)}, got {value!r}')
        if len(self.delimiter) != 1:
            raise InputError(f'delimiter must be one character, got {self.delimiter!r}')
        check_range('skip_rows', self.skip_rows, 0, math.inf)
        if not self.frame_id:
            raise InputError('frame_id must not be empty')


def _parse_stamp_ns(cell: str, factor_ns: int, where: str) -> int:
    """Convert one time cell to int nanoseconds exactly (decimal arithmetic, no float rounding)."""
    try:
        value = decimal.Decimal(cell)
    except decimal.InvalidOperation:
        raise InputError(f'{where}: time {cell!r} is not a number') from None
    if not value.is_finite():
        raise InputError(f'{where}: time {cell!r} is not a finite number')
    # Checked before multiplying: 1e999999 s in ns would overflow the decimal context.
    if value.copy_abs() >= _INT64_MAX:
        raise InputError(f'{where}: time {cell} is too large for nanosecond stamps; check '
                         '--time-unit')
    stamp_ns = int((value * factor_ns).to_integral_value(rounding=decimal.ROUND_HALF_EVEN))
    if stamp_ns < 0:
        raise InputError(f'{where}: time {cell} is negative; ROS stamps start at 0, shift the '
                         'time column')
    if stamp_ns > _INT64_MAX:
        raise InputError(f'{where}: time {cell} is too large for nanosecond stamps; check '
                         '--time-unit')
    return stamp_ns


def _column_indices(header, fmt, path):
    wanted = list(fmt.acc_cols) + list(fmt.gyr_cols)
    if fmt.time_col is not None:
        wanted.append(fmt.time_col)
    indices = []
    for name in wanted:
        matches = [i for i, column in enumerate(header) if column == name]
        if not matches:
            raise InputError(
                f'{path}: column {name!r} not in the header {header}; choose columns with '
                '--time-col, --acc-cols, --gyr-cols (and --skip-rows, --delimiter for the '
                'header line)')
        if len(matches) > 1:
            raise InputError(f'{path}: column {name!r} appears {len(matches)} times in the header')
        indices.append(matches[0])
    return indices


def _read_rows(stream, fmt, path):
    """Return the (N, 6) values and the N stamps [ns] (empty without a time column)."""
    lines = itertools.islice(stream, fmt.skip_rows, None)
    reader = csv.reader(lines, delimiter=fmt.delimiter)
    header = next(reader, None)
    if header is None:
        raise InputError(f'{path}: no header line after skipping {fmt.skip_rows} lines')
    header = [name.strip() for name in header]
    indices = _column_indices(header, fmt, path)
    need = max(indices) + 1
    values, stamps_ns = [], []
    factor_ns = TIME_UNITS_NS[fmt.time_unit]
    for row in reader:
        if not any(cell.strip() for cell in row):
            continue
        where = f'{path}:{fmt.skip_rows + reader.line_num}'
        if len(row) < need:
            raise InputError(f'{where}: {len(row)} cells, the header has {len(header)}')
        cells = [row[i].strip() for i in indices]
        try:
            values.append([float(cell) for cell in cells[:6]])
        except ValueError:
            bad = next(i for i, cell in enumerate(cells[:6]) if not _is_float(cell))
            raise InputError(
                f'{where}: column {header[indices[bad]]!r} holds {cells[bad]!r}, not a '
                'number') from None
        if not all(math.isfinite(v) for v in values[-1]):
            raise InputError(f'{where}: non-finite value in {cells[:6]}')
        if fmt.time_col is not None:
            stamps_ns.append(_parse_stamp_ns(cells[6], factor_ns, where))
            if len(stamps_ns) > 1 and stamps_ns[-1] <= stamps_ns[-2]:
                raise InputError(
                    f'{where}: time {cells[6]} does not increase (previous row: '
                    f'{stamps_ns[-2] / factor_ns:g} {fmt.time_unit}); sort the rows or '
                    'drop duplicates')
    return values, stamps_ns


def read_imu_csv(path, fmt: CsvImuFormat) -> ImuRecording:
    """
    Read an IMU CSV into an :class:`ImuRecording` in SI units (no plausibility check).

    Parameters
    ----------
    path : str or Path
        The CSV file.
    fmt : CsvImuFormat
        Columns, units and layout.

    Returns
    -------
    ImuRecording
        stamp_ns (N,) int64 strictly increasing, acc_b (N, 3) m/s^2, gyr_b (N, 3) rad/s.

    Raises
    ------
    InputError
        Missing column, non-numeric or empty cell, short row, time not increasing, negative
        time, fewer than ``MIN_SAMPLES`` rows; one line naming the file and line.

    """
    try:
        with open(path, newline='', encoding='utf-8-sig') as stream:
            values, stamps_ns = _read_rows(stream, fmt, path)
    except UnicodeDecodeError as err:
        raise InputError(f'{path}: not a UTF-8 text file ({err.reason} at byte {err.start}); '
                         'is it a CSV?') from None
    except csv.Error as err:
        raise InputError(f'{path}: unreadable CSV: {err}') from None
    if len(values) < MIN_SAMPLES:
        raise InputError(
            f'{path}: {len(values)} data rows, need at least {MIN_SAMPLES}; check --delimiter '
            'and --skip-rows')
    data = np.array(values, dtype=float)
    if fmt.time_col is not None:
        stamp_ns = np.array(stamps_ns, dtype=np.int64)
    else:
        stamp_ns = np.round(np.arange(len(data)) * (1e9 / fmt.rate_hz)).astype(np.int64)
        if np.any(np.diff(stamp_ns) <= 0):
            raise InputError(f'--rate-hz {fmt.rate_hz} is too high for nanosecond stamps')
    return ImuRecording(stamp_ns=stamp_ns,
                        acc_b=data[:, 0:3] * ACC_UNITS[fmt.acc_unit],
                        gyr_b=data[:, 3:6] * GYR_UNITS[fmt.gyr_unit],
                        frame_id=fmt.frame_id)


def _is_float(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def check_csv_units(recording: ImuRecording, fmt: CsvImuFormat) -> None:
    """
    Refuse a converted recording that does not look like SI, naming the option that fixes it.

    Wraps :func:`anfis_elevation_ros.core.units.check_si_units` (first samples at rest read
    about 9.81 m/s^2; no rate beyond any MEMS gyro range) and adds the cases it cannot name:
    data converted twice (``--acc-unit g`` on data already in m/s^2), gyro rates beyond range
    even in deg/s, and a median sample rate outside ``PLAUSIBLE_RATE_HZ`` (a time column in
    ms read as s, or the reverse).

    Parameters
    ----------
    recording : ImuRecording
        The recording after unit conversion.
    fmt : CsvImuFormat
        The units the user claimed.

    Raises
    ------
    InputError
        The data do not look like SI after conversion.

    """
    if fmt.time_col is not None and not (
            PLAUSIBLE_RATE_HZ[0] <= recording.rate_hz <= PLAUSIBLE_RATE_HZ[1]):
        raise InputError(
            f'the time column gives {recording.rate_hz:.4g} Hz, implausible for an IMU; check '
            f'--time-unit (now {fmt.time_unit}; one of {", ".join(TIME_UNITS_NS)})')
    try:
        check_si_units(recording.acc_b, recording.gyr_b)
    except InputError as err:
        rest = np.linalg.norm(recording.acc_b[:20].mean(axis=0)) / ACC_UNITS[fmt.acc_unit]
        peak = np.max(np.abs(recording.gyr_b)) / GYR_UNITS[fmt.gyr_unit]
        if fmt.acc_unit == 'g' and 7.0 <= rest <= 12.5:
            raise InputError(
                f'accelerometer reads {rest:.3f} at rest before conversion: it is already in '
                'm/s^2; use --acc-unit mps2') from None
        if fmt.gyr_unit == 'dps' and 'gyroscope' in str(err):
            raise InputError(
                f'gyroscope reads {peak:.0f} deg/s, beyond any MEMS range even in deg/s: check '
                '--gyr-cols and --gyr-unit') from None
        raise


def _column_triplet(text: str) -> tuple:
    names = tuple(name.strip() for name in text.split(','))
    if len(names) != 3 or not all(names):
        raise argparse.ArgumentTypeError(f'expected 3 comma-separated column names, got {text!r}')
    return names


def _delimiter(text: str) -> str:
    text = {'\\t': '\t', 'tab': '\t', 'TAB': '\t'}.get(text, text)
    if len(text) != 1:
        raise argparse.ArgumentTypeError(f'expected one character (or "tab"), got {text!r}')
    return text


def add_parser(subparsers) -> None:
    """Add the ``import-csv`` subcommand."""
    parser = subparsers.add_parser(
        'import-csv', help='convert a CSV IMU log into a ROS 2 bag of sensor_msgs/Imu',
        description='Convert a CSV log of one IMU (a header line naming the columns, one sample '
                    'per row) into a ROS 2 bag of sensor_msgs/msg/Imu in SI units. Data that '
                    'still look like g or deg/s after conversion are refused.',
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('csv', metavar='CSV', type=Path, help='the CSV file')
    parser.add_argument('--out', metavar='BAGDIR', type=Path, required=True,
                        help='bag directory to create (must not exist)')
    timing = parser.add_mutually_exclusive_group(required=True)
    timing.add_argument('--time-col', metavar='NAME', help='column holding the sample time')
    timing.add_argument('--rate-hz', metavar='R', type=float,
                        help='sample rate when there is no time column (first row at t = 0)')
    parser.add_argument('--time-unit', choices=tuple(TIME_UNITS_NS), default='s',
                        help='unit of the time column')
    parser.add_argument('--acc-cols', metavar='AX,AY,AZ', type=_column_triplet,
                        default=','.join(CsvImuFormat.acc_cols),
                        help='accelerometer columns x,y,z')
    parser.add_argument('--gyr-cols', metavar='GX,GY,GZ', type=_column_triplet,
                        default=','.join(CsvImuFormat.gyr_cols),
                        help='gyroscope columns x,y,z')
    parser.add_argument('--acc-unit', choices=tuple(ACC_UNITS), default='mps2',
                        help='accelerometer unit: m/s^2 or g (x 9.80665)')
    parser.add_argument('--gyr-unit', choices=tuple(GYR_UNITS), default='rps',
                        help='gyroscope unit: rad/s or deg/s')
    parser.add_argument('--delimiter', type=_delimiter, default=',',
                        help='field separator (one character; "tab" for tabs)')
    parser.add_argument('--skip-rows', metavar='N', type=int, default=0,
                        help='lines to skip before the header line')
    parser.add_argument('--frame-id', default='imu_link', help='header.frame_id of the messages')
    parser.add_argument('--storage', choices=STORAGES, default='sqlite3',
                        help='rosbag2 storage plugin')
    parser.add_argument('--topic', default='/imu/data', help='topic of the Imu messages')
    parser.set_defaults(handler=run_import_csv)


def run_import_csv(args) -> int:
    """Convert ``args.csv`` into a bag at ``args.out``; return 0 (errors raise InputError)."""
    if args.out.exists():
        raise InputError(f'output {args.out} exists; choose another --out or remove it')
    fmt = CsvImuFormat(
        acc_cols=args.acc_cols, gyr_cols=args.gyr_cols, time_col=args.time_col,
        rate_hz=args.rate_hz, time_unit=args.time_unit, acc_unit=args.acc_unit,
        gyr_unit=args.gyr_unit, delimiter=args.delimiter, skip_rows=args.skip_rows,
        frame_id=args.frame_id)
    recording = read_imu_csv(args.csv, fmt)
    check_csv_units(recording, fmt)
    # Imported here: rosbags is only needed once the CSV has been read and checked.
    from .bags import write_imu_bag
    write_imu_bag(args.out, recording, topic=args.topic, storage=args.storage)
    duration_s = (recording.stamp_ns[-1] - recording.stamp_ns[0]) / 1e9
    print(f'wrote {len(recording)} samples ({duration_s:.1f} s, {recording.rate_hz:.1f} Hz) '
          f'on {args.topic} to {args.out} ({args.storage})', file=sys.stderr)
    return 0
