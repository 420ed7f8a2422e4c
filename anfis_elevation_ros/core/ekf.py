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
15-state error-state EKF with zero-velocity updates, patent CN111649742A step S3, eq. (5)-(7).

Error state, in the patent's order (each a 3-vector, navigation frame ENU unless noted):
    dx = [dP, dV, accelerometer bias (body), dphi (attitude), gyro bias (body)]
with true = estimate + error for position, velocity and biases, and
C_nb_true = (I + [dphi x]) C_nb_est for attitude. Linearised error dynamics (Earth rotation
ignored, flat Earth):

    dP'  = dV
    dV'  = -[f_n x] dphi - C_nb dba - C_nb n_a
    dphi' = -C_nb dbg - C_nb n_g
    dba' = n_ba,  dbg' = n_bg                (random walks)

discretised to first order, Phi = I + F dt. Every stance sample brings the pseudo-measurement
v_n = 0 (ZUPT); the estimated error is fed back into the nominal state and reset to zero
(closed loop), so the filter runs causally, sample by sample.

References
----------
[1] J. Sola, "Quaternion kinematics for the error-state Kalman filter", arXiv:1711.02508, 2017.
[2] J.-O. Nilsson, I. Skog, P. Handel, K. V. S. Hari, "Foot-mounted INS for everybody - an
    open-source embedded implementation", IEEE/ION PLANS 2012 (OpenShoe).
[3] P. D. Groves, Principles of GNSS, Inertial, and Multisensor Integrated Navigation Systems,
    2nd ed., 2013, sec. 14.2 (error-state dynamics) and 3.2 (Joseph form).

"""

from dataclasses import dataclass
import math

import numpy as np

from .frames import mat_mul, mat_vec, quat_multiply, rotvec_to_quat, skew
from .jit import jit
from .validation import check_positive

N_STATES = 15
POS, VEL, ACC_BIAS, ATT, GYR_BIAS = (slice(i, i + 3) for i in range(0, N_STATES, 3))
STATE_NAMES = tuple(f'{block}_{axis}' for block in ('pos', 'vel', 'acc_bias', 'att', 'gyr_bias')
                    for axis in 'xyz')

_I3 = np.eye(3)


@dataclass(frozen=True)
class EkfParams:
    """
    Noise model of the error-state EKF.

    Attributes
    ----------
    acc_noise_mps2_sqrt_hz : accelerometer white-noise density (velocity random walk).
    gyr_noise_rps_sqrt_hz : gyroscope white-noise density (angle random walk).
    acc_bias_walk_mps3_sqrt_hz : accelerometer bias random-walk density.
    gyr_bias_walk_rps2_sqrt_hz : gyroscope bias random-walk density.
    zupt_sigma_mps : standard deviation of the zero-velocity pseudo-measurement.
    init_att_sigma_rad : initial roll/pitch uncertainty (heading: init_yaw_sigma_rad).
    init_acc_bias_sigma_mps2, init_gyr_bias_sigma_rps : initial bias uncertainties.

    Notes
    -----
    A boot sees impacts and vibration that no datasheet lists, so the densities are set well
    above a MEMS datasheet's (as OpenShoe and pyshoe do); their ratio to zupt_sigma_mps is
    what matters. Defaults were chosen on the pyshoe VICON trials (see README, "Accuracy").

    """

    acc_noise_mps2_sqrt_hz: float = 0.05
    gyr_noise_rps_sqrt_hz: float = 0.005
    acc_bias_walk_mps3_sqrt_hz: float = 1e-4
    gyr_bias_walk_rps2_sqrt_hz: float = 1e-5
    zupt_sigma_mps: float = 0.01
    init_att_sigma_rad: float = math.radians(1.0)
    init_yaw_sigma_rad: float = math.radians(0.1)
    init_acc_bias_sigma_mps2: float = 0.1
    init_gyr_bias_sigma_rps: float = math.radians(0.5)
    gyr_rail_noise_rps: float = 0.5

    def __post_init__(self):
        for name in self.__dataclass_fields__:
            check_positive(name, getattr(self, name))


@jit
def error_transition_matrix(C_nb: np.ndarray, acc_n: np.ndarray, dt_s: float,
                            out: np.ndarray = None) -> np.ndarray:
    """
    Discrete error-state transition matrix, eq. (5): Phi = I + F dt.

    F[dP, dV] = I,  F[dV, dphi] = -[f_n x],  F[dV, dba] = -C_nb,  F[dphi, dbg] = -C_nb.

    Parameters
    ----------
    C_nb : (3, 3) array
        Attitude at the middle of the interval.
    acc_n : (3,) array
        Specific force in the navigation frame f_n = C_nb f_b, m/s^2.
    dt_s : float
        Interval, s.
    out : (15, 15) array or None
        Optional array to fill; only the blocks above are written, so pass an array that
        already holds the identity elsewhere.

    """
    phi = np.eye(N_STATES) if out is None else out
    phi[POS, VEL] = dt_s * _I3
    phi[VEL, ATT] = -skew(acc_n * dt_s)
    phi[VEL, ACC_BIAS] = -dt_s * C_nb
    phi[ATT, GYR_BIAS] = -dt_s * C_nb
    return phi


def process_noise(params: EkfParams, dt_s: float) -> np.ndarray:
    """
    Discrete process noise, eq. (6) term Q: diagonal, density^2 * dt per block.

    White noise in body axes rotated to the navigation frame stays isotropic,
    C q I C^T = q I, so Q does not depend on attitude, and Q(dt) = Q(1 s) dt.
    """
    diag = np.empty(N_STATES)
    diag[POS] = 0.0
    diag[VEL] = params.acc_noise_mps2_sqrt_hz ** 2 * dt_s
    diag[ACC_BIAS] = params.acc_bias_walk_mps3_sqrt_hz ** 2 * dt_s
    diag[ATT] = params.gyr_noise_rps_sqrt_hz ** 2 * dt_s
    diag[GYR_BIAS] = params.gyr_bias_walk_rps2_sqrt_hz ** 2 * dt_s
    return np.diag(diag)


@jit
def clipped_gyro_noise(P: np.ndarray, sigma_rps: float, dt_s: float):
    """
    Attitude noise of a clipped gyro sample, in place: P[dphi, dphi] += (sigma dt)^2 I.

    A rate at the sensor's range stands for any rate beyond it: the rotation the sample
    misses is unknown, up to sigma dt per sample (sigma: ``gyr_rail_noise_rps``). Without
    this the filter trusts the clipped attitude, and the ZUPT after the swing books the
    lost rotation as gyro bias, which then corrupts every stride after it (gdin_hallway walk
    35: gyro y at its +-500 deg/s rail on 377 samples; learned bias -2.6, -4.7, +2.5 deg/s).
    """
    variance = (sigma_rps * dt_s) ** 2
    for i in range(ATT.start, ATT.stop):
        P[i, i] += variance


@jit
def relevelled_covariance(P: np.ndarray, P_initial: np.ndarray) -> np.ndarray:
    """
    Covariance after roll, pitch and velocity were reset at rest (after a data gap).

    Rows and columns of dV and of roll and pitch in dphi are cleared (the reset values do not
    depend on the old estimate), then take their start-up variances from ``P_initial`` (the
    diagonal ``initial_covariance``); position, yaw and biases keep theirs.
    """
    P = P.copy()
    for i in (VEL.start, VEL.start + 1, VEL.start + 2, ATT.start, ATT.start + 1):
        P[i, :] = 0.0
        P[:, i] = 0.0
        P[i, i] = P_initial[i, i]
    return P


@jit
def predict_covariance(P: np.ndarray, phi: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """
    Covariance prediction, eq. (6): P(k) = Phi P(k-1) Phi^T + Q.

    Phi = I + F dt has about 50 non-zero entries of 225, so both products skip its zeros
    (a fifth of the work of dense products).
    """
    n = P.shape[0]
    phi_P = np.zeros((n, n))
    for i in range(n):
        for k in range(n):
            phi_ik = phi[i, k]
            if phi_ik != 0.0:
                for j in range(n):
                    phi_P[i, j] += phi_ik * P[k, j]
    P_new = Q.copy()
    for j in range(n):
        for k in range(n):
            phi_jk = phi[j, k]
            if phi_jk != 0.0:
                for i in range(n):
                    P_new[i, j] += phi_P[i, k] * phi_jk
    return P_new


@jit
def zupt_correction(P: np.ndarray, vel_n: np.ndarray, zupt_sigma_mps: float):
    """
    Zero-velocity update, eq. (7).

    z = 0 - v_n (innovation, since the true velocity is zero), H = [0 I 0 0 0], R = sigma^2 I;
    solved by ``block_correction``.

    Parameters
    ----------
    P : (15, 15) array
        Predicted covariance.
    vel_n : (3,) array
        Estimated velocity, m/s.
    zupt_sigma_mps : float
        Measurement noise standard deviation, R = sigma^2 I.

    Returns
    -------
    dx : (15,) estimated error state; P : (15, 15) updated covariance;
    nis : normalised innovation squared z^T S^-1 z (chi-square, 3 dof, if the model holds).

    """
    return block_correction(P, -vel_n, VEL.start, zupt_sigma_mps ** 2)


@jit
def zupt_nis(P: np.ndarray, vel_n: np.ndarray, zupt_sigma_mps: float) -> float:
    """
    Normalised innovation squared of the zero-velocity update, eq. (7), without the update.

    NIS = v_n^T S^-1 v_n, S = H P H^T + R as in ``zupt_correction`` (``block_nis``).
    """
    return block_nis(P, -vel_n, VEL.start, zupt_sigma_mps ** 2)


@jit
def zaru_correction(P: np.ndarray, gyr_b: np.ndarray, gyr_bias_b: np.ndarray,
                    zaru_sigma_rps: float):
    """
    Zero angular rate update at a still stance sample (ZARU, Skog et al. 2014).

    A foot at rest does not turn, so the gyro reads its bias plus noise, w_m = b_g + n:
    y = w_m - b_g (innovation), H = [0 0 0 0 I], R = sigma^2 I; solved by ``block_correction``.
    Through the covariance of heading with gyro bias (dphi' = -C_nb dbg, eq. 5), the yaw
    that a wrong bias turned while the foot stood is taken back with the bias.

    Parameters
    ----------
    P : (15, 15) array
        Predicted covariance.
    gyr_b : (3,) array
        Measured angular rate, rad/s.
    gyr_bias_b : (3,) array
        Estimated gyro bias, rad/s.
    zaru_sigma_rps : float
        Measurement noise standard deviation (a standing foot sways), R = sigma^2 I.

    Returns
    -------
    dx, P, nis as ``block_correction``.

    """
    return block_correction(P, gyr_b - gyr_bias_b, GYR_BIAS.start, zaru_sigma_rps ** 2)


@jit
def block_correction(P: np.ndarray, innovation: np.ndarray, start: int, variance: float):
    """
    Kalman update by a measurement of one 3-state block of the error state, Joseph form.

    H = [0 .. I3 .. 0] (the block at ``start``), R = r I3:
    S = H P H^T + R, K = P H^T S^-1, dx = K y, P+ = (I - K H) P (I - K H)^T + K R K^T (Joseph
    form, which keeps P symmetric positive definite in floating point).

    H only selects the block B, so P H^T = P[:, B] and the Joseph form is computed as two
    rank-3 updates, A = P - K P[B, :], P+ = A - (A[:, B] - K R) K^T, instead of two 15 x 15
    products; the result is symmetrised against rounding.

    Returns
    -------
    dx : (15,) estimated error state; P : (15, 15) updated covariance;
    nis : normalised innovation squared y^T S^-1 y (chi-square, 3 dof, if the model holds).

    """
    block = slice(start, start + 3)
    S_inv = _block_innovation_inverse(P, start, variance)
    K = mat_mul(P[:, block], S_inv)
    A = P - mat_mul(K, P[block, :])
    P = A - mat_mul(A[:, block] - variance * K, K.T)
    return mat_vec(K, innovation), 0.5 * (P + P.T), _nis(S_inv, innovation)


@jit
def block_nis(P: np.ndarray, innovation: np.ndarray, start: int, variance: float) -> float:
    """
    Normalised innovation squared y^T S^-1 y of ``block_correction``'s measurement, no update.

    S = H P H^T + R = P[B, B] + r I3: a 3 x 3 solve, where the update costs two rank-3
    updates of the 15 x 15 covariance (a gate that may refuse the measurement needs only this).
    """
    return _nis(_block_innovation_inverse(P, start, variance), innovation)


@jit
def _block_innovation_inverse(P: np.ndarray, start: int, variance: float) -> np.ndarray:
    """Return S^-1 = (P[B, B] + r I3)^-1, B the 3-state block at ``start``."""
    return _inverse_3x3(P[start:start + 3, start:start + 3] + variance * _I3)


@jit
def _nis(S_inv: np.ndarray, innovation: np.ndarray) -> float:
    """Return y^T S^-1 y."""
    return np.sum(innovation * mat_vec(S_inv, innovation))


def position_correction(P: np.ndarray, innovation_xy: np.ndarray, sigma_m: float):
    """
    Horizontal position measurement (stair entry), seed 003 eq. (2) and (19)-(21).

    The database says where the foot is: z = P_ins,xy - P_database (eq. 2), so with
    true = estimate + error the innovation is y = P_database - P_ins,xy, H = [I2 0], R = s^2 I2:

        S = H P H^T + R,  K = P H^T S^-1,  dx = K y,
        P+ = (I - K H) P (I - K H)^T + K R K^T         (Joseph form)

    Through the covariances of position with heading and gyro bias that the ZUPT filter has
    built up, one position fix corrects the heading and the z-gyro bias too.

    Parameters
    ----------
    P : (15, 15) array
        Covariance.
    innovation_xy : (2,) array
        P_database - P_ins,xy, m.
    sigma_m : float
        Measurement standard deviation, m.

    Returns
    -------
    dx : (15,) estimated error state; P : (15, 15) updated covariance;
    nis : normalised innovation squared y^T S^-1 y (chi-square, 2 dof, if the model holds).

    """
    H = np.zeros((2, N_STATES))
    H[:, POS.start:POS.start + 2] = np.eye(2)
    R = sigma_m ** 2 * np.eye(2)
    S = H @ P @ H.T + R
    S_inv = np.linalg.inv(S)
    K = P @ H.T @ S_inv
    innovation = np.asarray(innovation_xy, dtype=float)
    A = np.eye(N_STATES) - K @ H
    P = A @ P @ A.T + K @ R @ K.T
    return K @ innovation, 0.5 * (P + P.T), float(innovation @ S_inv @ innovation)


@jit
def _inverse_3x3(S: np.ndarray) -> np.ndarray:
    """Inverse of a 3 x 3 matrix by cofactors."""
    a, b, c = S[0, 0], S[0, 1], S[0, 2]
    d, e, f = S[1, 0], S[1, 1], S[1, 2]
    g, h, i = S[2, 0], S[2, 1], S[2, 2]
    co_a, co_b, co_c = e * i - f * h, f * g - d * i, d * h - e * g
    inverse = np.empty((3, 3))
    inverse[0, 0], inverse[0, 1], inverse[0, 2] = co_a, c * h - b * i, b * f - c * e
    inverse[1, 0], inverse[1, 1], inverse[1, 2] = co_b, a * i - c * g, c * d - a * f
    inverse[2, 0], inverse[2, 1], inverse[2, 2] = co_c, b * g - a * h, a * e - b * d
    return inverse / (a * co_a + b * co_b + c * co_c)


@jit
def apply_correction(q_nb, vel_n, pos_n, acc_bias_b, gyr_bias_b, dx):
    """
    Feed the estimated error back into the nominal state (closed-loop EKF reset).

    p += dP, v += dV, ba += dba, bg += dbg, q_nb <- exp(dphi) * q_nb (navigation-side error).
    """
    q = quat_multiply(rotvec_to_quat(dx[ATT]), q_nb)
    q = q / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return (q, vel_n + dx[VEL], pos_n + dx[POS], acc_bias_b + dx[ACC_BIAS],
            gyr_bias_b + dx[GYR_BIAS])


def initial_covariance(params: EkfParams) -> np.ndarray:
    """Return the initial covariance: position and velocity known (start at rest at 0)."""
    diag = np.zeros(N_STATES)
    diag[POS] = 1e-8
    diag[VEL] = 1e-6
    diag[ACC_BIAS] = params.init_acc_bias_sigma_mps2 ** 2
    diag[ATT] = (params.init_att_sigma_rad ** 2, params.init_att_sigma_rad ** 2,
                 params.init_yaw_sigma_rad ** 2)
    diag[GYR_BIAS] = params.init_gyr_bias_sigma_rps ** 2
    return np.diag(diag)
