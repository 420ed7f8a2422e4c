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
Loader of the gdin_hallway walks: MicroStrain 3DM-GX5-25 on the foot, per-stride truth.

One walk is a SensorConnect CSV and a ``.mat`` of the same name (``../shared/data/README.md``,
gdin_hallway). The CSV comes in two column layouts, told apart by their headers:

- trials 31-40, 200 Hz: ``...:scaledAccelX/Y/Z`` [g], ``...:scaledGyroX/Y/Z`` [rad/s],
  ``...:scaledMagX/Y/Z`` [gauss], then the sensor's own ``roll/pitch/yaw``;
- trials 41-46, 250 Hz: ``...:estCompensatedAccelX/Y/Z`` [m/s^2, gravity included],
  ``...:estAngularRateX/Y/Z`` [rad/s], ``...:estRoll/estPitch/estYaw``, each followed by a
  ``...:valid`` flag column (the attitude columns turn invalid mid-walk; acc and gyro must not).

The sensor frame is x forward, y right, z down (acc_z about -9.8 m/s^2 at rest); nothing is
rotated (as every loader of ``datasets``). Stamps come from the ``Time`` column [s].

The ``.mat`` holds ``GCP_meters`` ((S+1) x 2): the foot's position after each stride, measured
on floor tiles (``tile_edge_length``), row 0 = (0, 0) the start; ``numberOfStrides`` = S. The
GCP frame is right-handed with z up, its heading unrelated to the IMU's.

Public API
----------
load_gdin_walk(path) -> GdinWalk    (path: the CSV or the .mat; the other is found beside it)

References
----------
1. Koroglu et al., the gait-driven inertial navigation dataset, own data part
   (``data/own/SensorConnectData_N``), MIT licence (``gdin_hallway/LICENSE``).

"""

import csv
from dataclasses import dataclass
import math
from pathlib import Path

import numpy as np

from .datasets import _check_finite, _check_increasing, _load_mat, _rows_to_array
from .datasets import STANDARD_GRAVITY_MPS2
from ..core.errors import InputError
from ..core.imu_data import ImuRecording

GAUSS_TO_TESLA = 1e-4
GYRO_RANGE_RPS = math.radians(500.0)
"""The gyro's range on these walks: flat runs of samples at 8.70-8.72 rad/s in fast swings."""
_AXES = ('X', 'Y', 'Z')
#: Column stems of the two layouts: (acc stem, acc scale to m/s^2, gyr stem, mag stem or None).
LAYOUTS = {
    'scaled': ('scaledAccel', STANDARD_GRAVITY_MPS2, 'scaledGyro', 'scaledMag'),
    'estimated': ('estCompensatedAccel', 1.0, 'estAngularRate', None),
}


@dataclass(frozen=True)
class GdinWalk:
    """
    One gdin_hallway walk.

    Attributes
    ----------
    recording : ImuRecording in the sensor axes (x forward, y right, z down), SI units.
    mag_t : (N, 3) magnetic field [T] in the sensor axes, or None (the 250 Hz layout has none).
    stride_pos_m : (S + 1, 2) foot position after each stride [m], right-handed, z up; row 0 is
        the start (0, 0).
    tile_edge_m : edge of the floor tiles the truth was counted on [m].

    """

    recording: ImuRecording
    mag_t: np.ndarray
    stride_pos_m: np.ndarray
    tile_edge_m: float

    @property
    def n_strides(self) -> int:
        """Return S, the number of strides (``numberOfStrides``)."""
        return len(self.stride_pos_m) - 1

    @property
    def path_length_m(self) -> float:
        """Return the length of the polyline through the stride positions [m]."""
        return float(np.sum(np.linalg.norm(np.diff(self.stride_pos_m, axis=0), axis=1)))


def _column(header, name, path):
    matches = [i for i, cell in enumerate(header) if cell.split(':')[-1] == name]
    if len(matches) != 1:
        raise InputError(f'{path}: expected one column ending in {name!r}, found {len(matches)}')
    return matches[0]


def _layout(header, path):
    names = {cell.split(':')[-1] for cell in header}
    for layout, (acc_stem, _, gyr_stem, _) in LAYOUTS.items():
        if f'{acc_stem}X' in names and f'{gyr_stem}X' in names:
            return layout
    raise InputError(
        f'{path}: neither scaledAccel/scaledGyro nor estCompensatedAccel/estAngularRate '
        'columns; is this a SensorConnect CSV of gdin_hallway?')


def _read_imu_csv(path, frame_id):
    with open(path, newline='') as stream:
        rows = [row for row in csv.reader(stream) if row]
    if len(rows) < 3 or rows[0][0] != 'Time':
        raise InputError(f'{path}: expected a header row starting with Time and data rows')
    header = rows[0]
    acc_stem, acc_scale, gyr_stem, mag_stem = LAYOUTS[_layout(header, path)]
    data = _rows_to_array(rows[1:], path, first_line=2)
    stems = [acc_stem, gyr_stem] + ([mag_stem] if mag_stem else [])
    columns = {stem: [_column(header, f'{stem}{a}', path) for a in _AXES] for stem in stems}
    for stem in (acc_stem, gyr_stem):
        for column in columns[stem]:
            flag = f'{header[column]}:valid'
            if flag in header and np.any(data[:, header.index(flag)] != 1.0):
                bad = int(np.argmax(data[:, header.index(flag)] != 1.0))
                raise InputError(f'{path}: {header[column]} is flagged invalid at sample {bad}')
    _check_finite(data, 'a column', path)
    stamp_ns = np.round(data[:, 0] * 1e9).astype(np.int64)
    _check_increasing(stamp_ns, path)
    recording = ImuRecording(stamp_ns=stamp_ns, acc_b=data[:, columns[acc_stem]] * acc_scale,
                             gyr_b=data[:, columns[gyr_stem]].copy(), frame_id=frame_id)
    mag_t = data[:, columns[mag_stem]] * GAUSS_TO_TESLA if mag_stem else None
    return recording, mag_t


def _read_truth(path):
    mat = _load_mat(path)
    for key in ('GCP_meters', 'numberOfStrides', 'tile_edge_length'):
        if key not in mat:
            raise InputError(f'{path}: field {key!r} missing; is this a gdin_hallway .mat file?')
    stride_pos_m = np.asarray(mat['GCP_meters'], dtype=float)
    n_strides = int(np.asarray(mat['numberOfStrides']).ravel()[0])
    if stride_pos_m.shape != (n_strides + 1, 2):
        raise InputError(f'{path}: GCP_meters is {stride_pos_m.shape}, expected '
                         f'({n_strides + 1}, 2) for numberOfStrides = {n_strides}')
    _check_finite(stride_pos_m, 'GCP_meters', path)
    if np.any(stride_pos_m[0] != 0.0):
        raise InputError(f'{path}: GCP_meters must start at (0, 0), got {stride_pos_m[0]}')
    return stride_pos_m, float(np.asarray(mat['tile_edge_length']).ravel()[0])


def load_gdin_walk(path, *, frame_id: str = 'imu_link') -> GdinWalk:
    """
    Load one gdin_hallway walk: the IMU (either layout), magnetometer if any, stride truth.

    Parameters
    ----------
    path : str or Path
        ``SensorConnectData_N.csv`` or ``.mat``; both must exist.
    frame_id : str
        Frame name for the recording.

    Raises
    ------
    InputError : a missing file or column, an invalid acc/gyro flag, a non-finite value,
        time that does not increase, or truth that does not match ``numberOfStrides``.

    """
    path = Path(path)
    csv_path, mat_path = path.with_suffix('.csv'), path.with_suffix('.mat')
    for needed in (csv_path, mat_path):
        if not needed.is_file():
            raise InputError(f'{needed} not found (a gdin_hallway walk is a .csv and a .mat)')
    recording, mag_t = _read_imu_csv(csv_path, frame_id)
    stride_pos_m, tile_edge_m = _read_truth(mat_path)
    return GdinWalk(recording, mag_t, stride_pos_m, tile_edge_m)
