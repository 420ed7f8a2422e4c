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
Strapdown mechanisation of the foot IMU, patent CN111649742A step S1, eq. (1)-(3).

Local-level ENU navigation frame, flat Earth, constant gravity, Earth rotation ignored (a foot
MEMS gyro cannot sense 15 deg/h through its noise, and a walk lasts minutes between stances).
Each sample k integrates the interval from t_(k-1) to t_k with the mean of the two samples
(trapezoidal rule), so the error is second order in the sample interval.

Public API: ``update_attitude`` (eq. 1), ``update_velocity`` (eq. 2), ``update_position`` (eq. 3),
``strapdown_step`` (one sample of all three) and ``strapdown`` (a batch, a loop over
``strapdown_step``).

References
----------
[1] P. G. Savage, "Strapdown inertial navigation integration algorithm design", J. Guidance,
    Control and Dynamics 21(1), 1998.
[2] I. Skog et al., "Zero-velocity detection - an algorithm evaluation", IEEE Trans. Biomed.
    Eng. 57(11), 2010 (the foot-mounted INS model used here).

"""

import math

import numpy as np

from .frames import GRAVITY_MPS2, mat_vec, quat_multiply, quat_to_dcm, rotvec_to_quat
from .jit import jit


@jit
def update_attitude(q_nb: np.ndarray, gyr_b: np.ndarray, dt_s: float) -> np.ndarray:
    """
    Attitude update, eq. (1): q_nb(k) = q_nb(k-1) * exp(omega_b dt / 2).

    Parameters
    ----------
    q_nb : (4,) array
        Attitude at t_(k-1), body to navigation, [w, x, y, z].
    gyr_b : (3,) array
        Mean angular rate over the interval, rad/s.
    dt_s : float
        Interval, s.

    """
    q = quat_multiply(q_nb, rotvec_to_quat(gyr_b * dt_s))
    return q / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])


@jit
def update_velocity(vel_n: np.ndarray, C_nb_mid: np.ndarray, acc_b: np.ndarray, dt_s: float,
                    gravity_mps2: float = GRAVITY_MPS2) -> np.ndarray:
    """
    Velocity update, eq. (2): v_n(k) = v_n(k-1) + (C_nb f_b + g_n) dt, g_n = [0, 0, -g].

    Parameters
    ----------
    vel_n : (3,) array
        Velocity at t_(k-1), m/s, ENU.
    C_nb_mid : (3, 3) array
        Attitude at the middle of the interval.
    acc_b : (3,) array
        Mean specific force over the interval, m/s^2.
    dt_s : float
        Interval, s.
    gravity_mps2 : float
        Local gravity magnitude g, m/s^2.

    """
    acc_n = mat_vec(C_nb_mid, acc_b)
    acc_n[2] -= gravity_mps2
    return vel_n + acc_n * dt_s


@jit
def update_position(pos_n: np.ndarray, vel_n_old: np.ndarray, vel_n_new: np.ndarray,
                    dt_s: float) -> np.ndarray:
    """Position update, eq. (3): p_n(k) = p_n(k-1) + (v_n(k-1) + v_n(k)) dt / 2."""
    return pos_n + 0.5 * (vel_n_old + vel_n_new) * dt_s


@jit
def strapdown_step(q_nb, vel_n, pos_n, acc_b, gyr_b, dt_s, gravity_mps2=GRAVITY_MPS2):
    """
    Integrate one interval with eq. (1)-(3); acc_b and gyr_b are interval means.

    Returns
    -------
    q_nb, vel_n, pos_n at the end of the interval, and C_nb_mid, the mid-interval attitude
    (the EKF linearises about it).

    """
    q_mid = update_attitude(q_nb, gyr_b, 0.5 * dt_s)
    q_new = update_attitude(q_mid, gyr_b, 0.5 * dt_s)
    C_nb_mid = quat_to_dcm(q_mid)
    vel_new = update_velocity(vel_n, C_nb_mid, acc_b, dt_s, gravity_mps2)
    return q_new, vel_new, update_position(pos_n, vel_n, vel_new, dt_s), C_nb_mid


def strapdown(q_nb0, vel_n0, pos_n0, stamp_ns, acc_b, gyr_b, gravity_mps2=GRAVITY_MPS2):
    """
    Free-inertial navigation over a batch of samples (no aiding), a loop of strapdown_step.

    Parameters
    ----------
    q_nb0, vel_n0, pos_n0 : (4,), (3,), (3,) arrays
        State at the first sample.
    stamp_ns : (N,) int array
        Sample stamps, ns.
    acc_b, gyr_b : (N, 3) array
        Specific force (m/s^2) and angular rate (rad/s).
    gravity_mps2 : float
        Local gravity magnitude g, m/s^2.

    Returns
    -------
    quat_nb (N, 4), vel_n (N, 3), pos_n (N, 3) at every sample.

    """
    n = len(stamp_ns)
    quat_nb = np.empty((n, 4))
    vel_n = np.empty((n, 3))
    pos_n = np.empty((n, 3))
    quat_nb[0], vel_n[0], pos_n[0] = q_nb0, vel_n0, pos_n0
    dt_s = np.diff(np.asarray(stamp_ns, dtype=np.int64)) * 1e-9
    acc_mid = 0.5 * (acc_b[1:] + acc_b[:-1])
    gyr_mid = 0.5 * (gyr_b[1:] + gyr_b[:-1])
    for k in range(1, n):
        quat_nb[k], vel_n[k], pos_n[k], _ = strapdown_step(
            quat_nb[k - 1], vel_n[k - 1], pos_n[k - 1], acc_mid[k - 1], gyr_mid[k - 1],
            dt_s[k - 1], gravity_mps2)
    return quat_nb, vel_n, pos_n
