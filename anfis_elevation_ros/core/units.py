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

"""Plausibility checks of IMU units: SI is required, g and deg/s are refused with a clear error."""

import numpy as np

from .errors import InputError

MAX_PHYSICAL_GYR_RPS = 40.0  # above any MEMS range (2000 deg/s = 34.9 rad/s): deg/s data
GRAVITY_RANGE_MPS2 = (7.0, 12.5)
GRAVITY_RANGE_G = (0.7, 1.25)


def check_rest_gravity(acc_b_rest: np.ndarray) -> None:
    """
    Refuse a rest window whose mean specific force is not about 9.81 m/s^2.

    Parameters
    ----------
    acc_b_rest : (N, 3) array
        Specific force over a window where the foot is still.

    Raises
    ------
    InputError : naming the likely unit (g) or the wrong axis sign / scale.

    """
    magnitude = float(np.linalg.norm(np.mean(acc_b_rest, axis=0)))
    if GRAVITY_RANGE_MPS2[0] <= magnitude <= GRAVITY_RANGE_MPS2[1]:
        return
    if GRAVITY_RANGE_G[0] <= magnitude <= GRAVITY_RANGE_G[1]:
        raise InputError(f'accelerometer reads {magnitude:.3f} at rest: it looks like g, '
                         'not m/s^2; convert (x 9.80665) or use import-csv --acc-unit g')
    raise InputError(f'accelerometer reads {magnitude:.3f} m/s^2 at rest instead of about 9.81: '
                     'check its units and scale')


def check_acc_scale(acc_b: np.ndarray) -> None:
    """
    Refuse specific force whose typical magnitude is not about 9.81 m/s^2.

    The median of |f| over a few samples is close to g whether the foot stands or walks
    (it swings about gravity), so this works before any rest is found.

    Parameters
    ----------
    acc_b : (N, 3) array
        Specific force, m/s^2.

    """
    median = float(np.median(np.linalg.norm(acc_b, axis=1)))
    if GRAVITY_RANGE_G[0] <= median <= GRAVITY_RANGE_G[1]:
        raise InputError(f'accelerometer reads a median of {median:.3f}: it looks like g, not '
                         'm/s^2; convert (x 9.80665) or use import-csv --acc-unit g')
    if not 0.5 * GRAVITY_RANGE_MPS2[0] <= median <= 2.0 * GRAVITY_RANGE_MPS2[1]:
        raise InputError(f'accelerometer reads a median of {median:.3f} m/s^2 instead of about '
                         '9.81: check its units and scale')


def check_gyro_rate(gyr_b: np.ndarray) -> None:
    """
    Refuse angular rates no MEMS gyro measures in rad/s (the data are in deg/s).

    Parameters
    ----------
    gyr_b : (..., 3) array
        Angular rate, rad/s.

    """
    peak = float(np.max(np.abs(gyr_b))) if np.size(gyr_b) else 0.0
    if peak > MAX_PHYSICAL_GYR_RPS:
        raise InputError(f'gyroscope reads {peak:.1f} rad/s, beyond any MEMS range: it looks '
                         'like deg/s; convert (x pi/180) or use import-csv --gyr-unit dps')


def check_si_units(acc_b: np.ndarray, gyr_b: np.ndarray) -> None:
    """Refuse IMU data that look like g or deg/s (the first samples are taken to be at rest)."""
    check_rest_gravity(acc_b[: max(1, min(len(acc_b), 20))])
    check_gyro_rate(gyr_b)
