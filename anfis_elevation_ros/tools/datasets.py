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
Loaders for the public foot-IMU datasets in the shared data directory.

This module is the only place that knows each source's file layout, axes and units. Every loader
returns an :class:`ImuRecording` in SI units (m/s^2, rad/s, int64 nanosecond stamps) but in the
SENSOR's own axes: nothing is rotated, because the navigator has to cope with any mounting.

Public API
----------
shared_data_dir()                          the folder holding the sets (``ANFIS_SHARED_DATA``)
dataset_files(name, data_dir=None)         sorted recording files of one set
load_pyshoe_vicon(path)                    -> (ImuRecording, gt_pos (N, 3) m)
load_pyshoe_reference(path)                -> PyshoeReference (pyshoe's optimal SHOE labels)
load_mad_stairs(path, foot='left')         -> ImuRecording
load_xio(path)                             -> ImuRecording
load_hugadb(path, foot='right', *, gyro_range_dps=2000) -> (ImuRecording, activity (N,) int)
hugadb_index(data_dir=None)                -> list of HugadbIndexRow (file_index.csv)

gdin_hallway (MicroStrain 3DM-GX5-25, two layouts, per-stride truth) has a module of its own,
``gdin_hallway.load_gdin_walk``.

Sets, as found in the files (provenance: ``../shared/data/README.md``)
---------------------------------------------------------------------
All four are right-handed as stored (gyro-propagated gravity matches the accelerometer at the
stances; it does not after negating one axis), except pyshoe's ``gt`` (see below).

pyshoe_vicon  LORD 3DM-GX3-25, ~200 Hz, jittery stamps ``ts`` [s] (steps 1.1-8.6 ms), sensor
              z DOWN (acc_z ~ -9.4 at rest); VICON truth ``gt`` [m] per IMU sample, z up, stored
              in a mirrored (left-handed) frame: the loader negates its y axis.
mad_stairs    NilsPod, 204.8 Hz, acc [m/s^2], gyr [deg/s], x forward, y left, z up. Stair files:
              instep sensor pitched ~50 deg (acc ~ [-7.5, 0.8, 6.2] at rest) and the right
              sensor reads |g| ~ 9.47 m/s^2 at rest (left ~ 9.76). Column ORDER differs between
              files, so columns are picked by their (sensor, axis) header pair.
xio_foot      x-IMU, 256 Hz (time = row index / 256; the packet number skips), gyr [deg/s],
              acc [g] (|g| reads ~0.97 g at rest), z up. Acc saturates at +-8 g.
hugadb        six int16 IMUs, ~58.8 Hz nominal (no stamps), acc counts / 16384 = g (+-2 g,
              saturates often), gyr counts / 16.4 = deg/s (+-2000 deg/s) -- except the gyros
              that ``file_index.csv`` marks ``rf_gyro_ok``/``lf_gyro_ok`` False ("Corrupted"
              upstream): those were set to +-250 deg/s, counts / 131 = deg/s, and clip at
              250 deg/s in 12-20 % of moving samples (see ``HUGADB_GYR_COUNTS_PER_DPS``).
              Foot z ~ up.

References
----------
1. Wagstaff, Peretroukhin, Kelly, "Robust data-driven zero-velocity detection for foot-mounted
   inertial navigation", IEEE Sensors Journal 20(2), 2020 (pyshoe_vicon).
2. Roth et al., Sensors 21(19):6559, 2021 (MaD Stair Ambulation; mad_stairs stair files).
3. Chereshnev, Kertesz-Farkas, "HuGaDB: Human Gait Database for Activity Recognition from
   Wearable Inertial Sensor Networks", AIST 2017 (hugadb).

"""

import csv
from dataclasses import dataclass
import os
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.imu_data import ImuRecording

#: Environment variable that overrides the shared data directory.
SHARED_DATA_ENV = 'ANFIS_SHARED_DATA'
#: Standard gravity used to convert g to m/s^2.
STANDARD_GRAVITY_MPS2 = 9.80665

#: Sub-folder and file pattern of each set.
DATASET_PATTERNS = {
    'pyshoe_vicon': '*.mat',
    'mad_stairs': '*.csv',
    'xio_foot': '*.csv',
    'hugadb': 'HuGaDB_*.txt',
    'gdin_hallway': 'SensorConnectData_*.csv',
}

PYSHOE_RATE_HZ = 200.0
#: Factor applied to the pyshoe ``gt`` columns to make its frame right-handed (see the loader).
PYSHOE_GT_MIRROR = np.array([1.0, -1.0, 1.0])
PYSHOE_GT_MIRROR.setflags(write=False)
MAD_RATE_HZ = 204.8
XIO_RATE_HZ = 256.0
#: HuGaDB has no stamps; 58.8 Hz is the rate implied by the authors' table (samples / seconds).
HUGADB_RATE_HZ = 58.8
HUGADB_ACC_COUNTS_PER_G = 16384.0
HUGADB_GYR_COUNTS_PER_DPS = {2000: 16.4, 250: 131.0}
"""Gyro counts per deg/s of each full scale (deg/s) found in HuGaDB (MPU-6050/9250 settings).

The gyros flagged not ok in ``file_index.csv`` ("Corrupted" upstream; every foot gyro of
subjects 4 and 5, the right foot of 3 and 7, both feet of files 09_04-09_08) read counts / 131,
the +-250 deg/s setting, not counts / 16.4. Read at 16.4 they make no sense: in the quietest
second they show 9-23 deg/s where the other gyros show 1-2 deg/s, the median |w| of walking is
over 1000 deg/s (other gyros about 150 deg/s), and the gyro-propagated gravity direction misses
the accelerometer's at the next rest by 50-75 deg over unclipped stretches. At 131 the quiet
rate is 1.4-2.0 deg/s, the walking median 130-180 deg/s and the miss 2-6 deg, as for the other
gyros (test_datasets.py checks subjects 4 and 6); their p99 of 1998 'deg/s' is the
int16 rail, 250 deg/s. A foot's pitch rate peaks at 400-600 deg/s, so these gyros clip in
every swing (measured 2026-11: leave-one-subject-out accuracy of such feet 0.88 read at 131,
0.31 read at 16.4, model of the unclipped feet; test/benchmarks/bench_hugadb_errors.py).
"""
HUGADB_GYR_RANGE_DPS = 2000
"""Full scale of the unflagged gyros, deg/s."""
HUGADB_CLIPPED_GYR_RANGE_DPS = 250
"""Full scale of the gyros ``file_index.csv`` flags not ok, deg/s."""

#: HuGaDB activity ids (README table 1 of the HuGaDB repository).
HUGADB_ACTIVITIES = {
    1: 'walking', 2: 'running', 3: 'going_up', 4: 'going_down', 5: 'sitting',
    6: 'sitting_down', 7: 'standing_up', 8: 'standing', 9: 'bicycling',
    10: 'up_by_elevator', 11: 'down_by_elevator', 12: 'sitting_in_car',
}
HUGADB_WALKING, HUGADB_GOING_UP, HUGADB_GOING_DOWN, HUGADB_STANDING = 1, 3, 4, 8

_AXES = ('x', 'y', 'z')
_FEET = {'left': 'l', 'right': 'r'}


def shared_data_dir() -> Path:
    """
    Return the shared data directory, or raise InputError when it does not exist.

    ``$ANFIS_SHARED_DATA`` when set, else ``<project root>/../shared/data`` (the project root being
    the folder that holds the ``anfis_elevation_ros`` package).
    """
    override = os.environ.get(SHARED_DATA_ENV)
    if override:
        path = Path(override)
    else:
        path = Path(__file__).resolve().parents[2].parent / 'shared' / 'data'
    if not path.is_dir():
        raise InputError(
            f'shared data directory {path} not found; set {SHARED_DATA_ENV} to the folder that '
            f'holds {", ".join(sorted(DATASET_PATTERNS))}')
    return path


def dataset_files(name: str, data_dir=None) -> list:
    """
    List the recording files of one public set, sorted by name.

    Parameters
    ----------
    name : str
        One of 'pyshoe_vicon', 'mad_stairs', 'xio_foot', 'hugadb', 'gdin_hallway'.
    data_dir : str or Path, optional
        The shared data directory; default :func:`shared_data_dir`.

    Returns
    -------
    list of pathlib.Path
        Never empty: InputError when the folder is missing or holds no recording.

    """
    if name not in DATASET_PATTERNS:
        raise InputError(
            f'unknown dataset {name!r}; choose one of {", ".join(sorted(DATASET_PATTERNS))}')
    folder = (Path(data_dir) if data_dir is not None else shared_data_dir()) / name
    files = sorted(folder.glob(DATASET_PATTERNS[name])) if folder.is_dir() else []
    if not files:
        raise InputError(
            f'no {DATASET_PATTERNS[name]} files in {folder}; is the shared data directory '
            f'complete? (override it with {SHARED_DATA_ENV})')
    return files


# ---------------------------------------------------------------------------------------------
# pyshoe_vicon
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class PyshoeReference:
    """
    Per-trial results stored by pyshoe in a VICON ``.mat`` file (useful as references).

    Attributes
    ----------
    shoe_threshold : ``G_shoe_opt``, the SHOE threshold that minimised the 2D ARMSE of this trial
        in pyshoe's grid search. Only meaningful for pyshoe's statistic: blocks of W = 5 samples,
        g = 9.8029 m/s^2, sigma_a = 0.00098 m/s^2, sigma_w = 8.7266463e-5 rad/s.
    zv_shoe : (N,) bool, ``zv_shoe_opt``: zero-velocity labels of SHOE at that threshold.
    shoe_error_m : ``trial_error[0]``, the 2D ARMSE [m] pyshoe's filter reached with ``zv_shoe``
        (metric: :func:`anfis_elevation_ros.tools.metrics.pyshoe_position_error`, rounded to mm).
    best_detector : ``best_detector``, the detector with the lowest error on this trial.
    best_error_m : ``best_error``, that lowest error [m].

    """

    shoe_threshold: float
    zv_shoe: np.ndarray
    shoe_error_m: float
    best_detector: str
    best_error_m: float


def _load_mat(path):
    # scipy is imported here so the other loaders work without it.
    import scipy.io
    try:
        return scipy.io.loadmat(str(path))
    except ValueError as err:  # scipy raises ValueError for files that are not MATLAB files
        raise InputError(f'{path}: not a MATLAB .mat file ({err})') from err


def _mat_field(mat, key, path):
    if key not in mat:
        raise InputError(f'{path}: field {key!r} missing; is this a pyshoe VICON .mat file?')
    return np.asarray(mat[key])


def _check_finite(array, what, path):
    if not np.all(np.isfinite(array)):
        bad = int(np.argmax(~np.all(np.isfinite(array.reshape(len(array), -1)), axis=1)))
        raise InputError(f'{path}: {what} has a non-finite value at sample {bad}')


def load_pyshoe_vicon(path, *, frame_id: str = 'imu_link'):
    """
    Load one pyshoe VICON trial: IMU in its own z-down sensor frame and the VICON truth.

    The file's ``imu`` (N x 6) already holds acc [m/s^2] and gyr [rad/s]; ``ts`` (1 x N) [s]
    gives the stamps (about 200 Hz, with jitter of a few ms: steps of 1.1 to 8.6 ms occur) and
    ``gt`` (N x 3) [m] the VICON foot position at every IMU sample, z up.

    The stored ``gt`` is MIRRORED with respect to the IMU: its (x, y, z up) axes form a
    left-handed frame, matching pyshoe's own output (a z-down navigation frame with z negated).
    A right-handed strapdown solution from ``imu`` fits ``gt`` to ~0.1-0.4 m after a rotation
    about z only when one horizontal axis of ``gt`` is negated (and misses by 1.5-1.8 m
    otherwise), while the IMU itself is right-handed (gyro-propagated gravity agrees with the
    accelerometer to < 1 deg at every stance). This loader therefore returns ``gt`` with y
    negated: a right-handed, z-up frame that any ENU estimate can be compared with by a rotation
    about z (as :func:`~anfis_elevation_ros.tools.metrics.pyshoe_position_error` does). Negate
    y again to get the file's values.

    Parameters
    ----------
    path : str or Path
        The ``.mat`` file.
    frame_id : str
        Frame name for the recording.

    Returns
    -------
    recording : ImuRecording
        Sensor axes (z down: acc_z ~ -9.8 m/s^2 at rest), acc [m/s^2], gyr [rad/s].
    gt_pos : (N, 3) float array
        VICON position [m] in a right-handed frame with z up (the file's ``gt`` with y
        negated), at the recording's samples.

    """
    mat = _load_mat(path)
    imu = _mat_field(mat, 'imu', path).astype(float)
    ts_s = _mat_field(mat, 'ts', path).astype(float).ravel()
    gt_pos = _mat_field(mat, 'gt', path).astype(float)
    n = len(ts_s)
    if imu.shape != (n, 6) or gt_pos.shape != (n, 3):
        raise InputError(
            f'{path}: expected imu (N, 6), ts (N,), gt (N, 3); got imu {imu.shape}, '
            f'ts {ts_s.shape}, gt {gt_pos.shape}')
    for array, what in ((imu, 'imu'), (ts_s, 'ts'), (gt_pos, 'gt')):
        _check_finite(array, what, path)
    stamp_ns = np.round(ts_s * 1e9).astype(np.int64)
    _check_increasing(stamp_ns, path)
    recording = ImuRecording(stamp_ns=stamp_ns, acc_b=imu[:, 0:3].copy(),
                             gyr_b=imu[:, 3:6].copy(), frame_id=frame_id)
    return recording, gt_pos * PYSHOE_GT_MIRROR


def load_pyshoe_reference(path) -> PyshoeReference:
    """Load pyshoe's per-trial optimal SHOE threshold, labels and errors from a VICON file."""
    mat = _load_mat(path)
    zv_shoe = _mat_field(mat, 'zv_shoe_opt', path).ravel().astype(bool)
    trial_error = _mat_field(mat, 'trial_error', path).astype(float).ravel()
    return PyshoeReference(
        shoe_threshold=float(_mat_field(mat, 'G_shoe_opt', path).ravel()[0]),
        zv_shoe=zv_shoe,
        shoe_error_m=float(trial_error[0]),
        best_detector=str(_mat_field(mat, 'best_detector', path).ravel()[0]).strip(),
        best_error_m=float(_mat_field(mat, 'best_error', path).ravel()[0]))


# ---------------------------------------------------------------------------------------------
# Text files
# ---------------------------------------------------------------------------------------------

def _check_increasing(stamp_ns, path):
    steps = np.diff(stamp_ns)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0)) + 1
        raise InputError(f'{path}: time does not increase at sample {k}')


def _rows_to_array(rows, path, first_line):
    try:
        return np.array(rows, dtype=float)
    except ValueError:
        for i, row in enumerate(rows):
            try:
                [float(cell) for cell in row]
            except ValueError:
                raise InputError(
                    f'{path}: line {first_line + i}: non-numeric cell in {row!r}') from None
        raise InputError(f'{path}: rows have different lengths') from None


def _uniform_stamps_ns(n: int, rate_hz: float) -> np.ndarray:
    return np.round(np.arange(n) * (1e9 / rate_hz)).astype(np.int64)


def _imu_from_columns(stamp_ns, acc, gyr, path, frame_id):
    _check_finite(acc, 'acc', path)
    _check_finite(gyr, 'gyr', path)
    return ImuRecording(stamp_ns=stamp_ns, acc_b=acc, gyr_b=gyr, frame_id=frame_id)


def _check_foot(foot):
    if foot not in _FEET:
        raise InputError(f'foot must be one of {", ".join(sorted(_FEET))}, got {foot!r}')


def load_mad_stairs(path, foot: str = 'left', *, frame_id: str = 'imu_link') -> ImuRecording:
    """
    Load one foot of a MaD/gaitmap sample CSV (NilsPod, 204.8 Hz), gyr converted to rad/s.

    The file has two header rows, (sensor, axis), e.g. ('left_sensor', 'gyr_z'); columns are
    found by that pair because the stair files list left acc_x..gyr_z then right, while the level
    file interleaves left and right per axis. The first column is the index: time in s in the
    stair files (step 1/204.8 s), the sample number in the level file (stamps = index / 204.8 Hz).

    Parameters
    ----------
    path : str or Path
        The CSV file.
    foot : str
        'left' or 'right'.
    frame_id : str
        Frame name for the recording.

    Returns
    -------
    ImuRecording
        Sensor axes (x forward, y left, z up), acc [m/s^2], gyr [rad/s].

    """
    _check_foot(foot)
    with open(path, newline='') as stream:
        rows = [row for row in csv.reader(stream) if row]
    if len(rows) < 3:
        raise InputError(f'{path}: expected two header rows (sensor, axis) and data rows')
    header = list(zip(rows[0], rows[1]))
    sensor = f'{foot}_sensor'
    columns = []
    for name in ('acc_x', 'acc_y', 'acc_z', 'gyr_x', 'gyr_y', 'gyr_z'):
        matches = [i for i, pair in enumerate(header) if pair == (sensor, name)]
        if len(matches) != 1:
            raise InputError(
                f'{path}: expected one column ({sensor}, {name}) in the two header rows, '
                f'found {len(matches)}')
        columns.append(matches[0])
    data = _rows_to_array(rows[2:], path, first_line=3)
    index = data[:, 0]
    steps = np.diff(index)
    if np.all(steps == 1.0) and index[0] == np.round(index[0]):
        stamp_ns = np.round(index * (1e9 / MAD_RATE_HZ)).astype(np.int64)
    elif abs(np.median(steps) * MAD_RATE_HZ - 1.0) < 0.01:
        stamp_ns = np.round(index * 1e9).astype(np.int64)
    else:
        raise InputError(
            f'{path}: index column is neither sample numbers nor time in s at {MAD_RATE_HZ} Hz '
            f'(median step {np.median(steps):g})')
    _check_increasing(stamp_ns, path)
    acc = data[:, columns[0:3]]
    gyr = np.deg2rad(data[:, columns[3:6]])
    return _imu_from_columns(stamp_ns, acc, gyr, path, frame_id)


def load_xio(path, *, frame_id: str = 'imu_link') -> ImuRecording:
    """
    Load an x-IMU ``CalInertialAndMag`` CSV at 256 Hz; deg/s -> rad/s, g -> m/s^2.

    Stamps are row index / 256 Hz: the packet number skips (steps of 1, 2 and 3 packets) and
    does not count samples. The magnetometer columns are ignored.

    Returns
    -------
    ImuRecording in the sensor axes (z up: acc_z ~ +9.5 m/s^2 at rest).

    """
    with open(path, newline='') as stream:
        rows = [row for row in csv.reader(stream) if row]
    if len(rows) < 2:
        raise InputError(f'{path}: expected a header row and data rows')
    header = [name.strip() for name in rows[0]]
    wanted = [f'Accelerometer {a.upper()} (g)' for a in _AXES]
    wanted += [f'Gyroscope {a.upper()} (deg/s)' for a in _AXES]
    missing = [name for name in wanted if name not in header]
    if missing:
        raise InputError(f'{path}: columns {missing} missing; is this an x-IMU CalInertial CSV?')
    data = _rows_to_array(rows[1:], path, first_line=2)
    columns = [header.index(name) for name in wanted]
    acc = data[:, columns[0:3]] * STANDARD_GRAVITY_MPS2
    gyr = np.deg2rad(data[:, columns[3:6]])
    return _imu_from_columns(_uniform_stamps_ns(len(data), XIO_RATE_HZ), acc, gyr, path,
                             frame_id)


def load_hugadb(path, foot: str = 'right', *, gyro_range_dps: int = HUGADB_GYR_RANGE_DPS,
                frame_id: str = 'imu_link'):
    """
    Load the foot IMU of one HuGaDB v1 file and its per-sample activity labels.

    Tab-separated: three '#' lines (activities, activity ids, date), a column header
    (``acc_rf_x`` ... ``gyro_lt_z EMG_r EMG_l act``), then int16 counts. acc / 16384 = g,
    gyro / 16.4 = deg/s (+-2000 deg/s), or gyro / 131 = deg/s for the +-250 deg/s gyros that
    ``file_index.csv`` flags (``HugadbIndexRow.gyro_range_dps``). The files have no stamps:
    stamps assume the nominal 58.8 Hz (the rate implied by the dataset's sample counts and
    durations), starting at 0.

    Parameters
    ----------
    path : str or Path
        The ``.txt`` file.
    foot : str
        'right' (columns ``*_rf_*``) or 'left' (``*_lf_*``).
    gyro_range_dps : int
        Full scale of the foot gyro, deg/s: 2000 (default) or 250 (the flagged gyros).
    frame_id : str
        Frame name for the recording.

    Returns
    -------
    recording : ImuRecording
        Sensor axes (z roughly up at rest), acc [m/s^2], gyr [rad/s].
    activity : (N,) int64 array
        HuGaDB activity id per sample (see ``HUGADB_ACTIVITIES``).

    """
    _check_foot(foot)
    if gyro_range_dps not in HUGADB_GYR_COUNTS_PER_DPS:
        raise InputError(f'gyro_range_dps must be one of {sorted(HUGADB_GYR_COUNTS_PER_DPS)} '
                         f'deg/s, got {gyro_range_dps!r}')
    with open(path, newline='') as stream:
        lines = stream.read().splitlines()
    n_comments = 0
    while n_comments < len(lines) and lines[n_comments].startswith('#'):
        n_comments += 1
    if n_comments != 3 or len(lines) < 5:
        raise InputError(
            f'{path}: expected 3 "#" header lines, a column header and data rows; '
            'is this a HuGaDB v1 file?')
    header = lines[3].split('\t')
    tag = _FEET[foot] + 'f'
    wanted = [f'acc_{tag}_{a}' for a in _AXES] + [f'gyro_{tag}_{a}' for a in _AXES] + ['act']
    missing = [name for name in wanted if name not in header]
    if missing:
        raise InputError(f'{path}: columns {missing} missing from the header')
    rows = [line.split('\t') for line in lines[4:] if line.strip()]
    data = _rows_to_array(rows, path, first_line=5)
    columns = [header.index(name) for name in wanted]
    acc = data[:, columns[0:3]] / HUGADB_ACC_COUNTS_PER_G * STANDARD_GRAVITY_MPS2
    gyr = np.deg2rad(data[:, columns[3:6]] / HUGADB_GYR_COUNTS_PER_DPS[gyro_range_dps])
    activity = data[:, columns[6]].astype(np.int64)
    recording = _imu_from_columns(_uniform_stamps_ns(len(data), HUGADB_RATE_HZ), acc, gyr, path,
                                  frame_id)
    return recording, activity


@dataclass(frozen=True)
class HugadbIndexRow:
    """
    One row of HuGaDB's ``file_index.csv`` (prepared with the shared data).

    ``rf_gyro_ok``/``lf_gyro_ok`` are False where that foot's gyroscope clips: its 99th
    percentile ``*_gyro_p99_dps`` (counts / 16.4) is then the int16 rail, ~1998; such a gyro is
    a +-250 deg/s one (counts / 131, see ``HUGADB_GYR_COUNTS_PER_DPS``) that clips at 250 deg/s
    in every swing.
    """

    file: str
    subject: int
    n_samples: int
    n_walking: int
    n_going_up: int
    n_going_down: int
    rf_gyro_p99_dps: float
    lf_gyro_p99_dps: float
    rf_gyro_ok: bool
    lf_gyro_ok: bool

    def gyro_ok(self, foot: str) -> bool:
        """Return whether the gyroscope of 'left' or 'right' foot is usable (not clipped)."""
        _check_foot(foot)
        return self.rf_gyro_ok if foot == 'right' else self.lf_gyro_ok

    def gyro_range_dps(self, foot: str) -> int:
        """Return the full scale of a foot's gyroscope, deg/s: 2000, or 250 if not ok."""
        return HUGADB_GYR_RANGE_DPS if self.gyro_ok(foot) else HUGADB_CLIPPED_GYR_RANGE_DPS


def _parse_bool(text, where):
    if text == 'True':
        return True
    if text == 'False':
        return False
    raise InputError(f'{where}: expected True or False, got {text!r}')


def hugadb_index(data_dir=None) -> list:
    """
    Read HuGaDB's ``file_index.csv``: one :class:`HugadbIndexRow` per recording.

    Parameters
    ----------
    data_dir : str or Path, optional
        The ``hugadb`` folder; default ``<shared data>/hugadb``.

    """
    folder = Path(data_dir) if data_dir is not None else shared_data_dir() / 'hugadb'
    path = folder / 'file_index.csv'
    with open(path, newline='') as stream:
        records = list(csv.DictReader(stream))
    fields = HugadbIndexRow.__dataclass_fields__
    result = []
    for line, record in enumerate(records, start=2):
        missing = [name for name in fields if name not in record]
        if missing:
            raise InputError(f'{path}: columns {missing} missing')
        where = f'{path}:{line}'
        try:
            result.append(HugadbIndexRow(
                file=record['file'],
                subject=int(record['subject']),
                n_samples=int(record['n_samples']),
                n_walking=int(record['n_walking']),
                n_going_up=int(record['n_going_up']),
                n_going_down=int(record['n_going_down']),
                rf_gyro_p99_dps=float(record['rf_gyro_p99_dps']),
                lf_gyro_p99_dps=float(record['lf_gyro_p99_dps']),
                rf_gyro_ok=_parse_bool(record['rf_gyro_ok'], where),
                lf_gyro_ok=_parse_bool(record['lf_gyro_ok'], where)))
        except (TypeError, ValueError) as err:
            if isinstance(err, InputError):
                raise
            raise InputError(f'{where}: {err}') from None
    return result
