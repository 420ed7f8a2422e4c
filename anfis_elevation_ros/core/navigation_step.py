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
The navigator's compiled per-sample step: mechanisation, detector and EKF on plain arrays.

``navigation_step`` takes one IMU sample after start-up through S1-S3: the strapdown step
(eq. 1-3), the SHOE detector and the stride gate (eq. 4), the covariance prediction (eq. 5-6),
the ZUPT (eq. 7) at every stance sample and the ZARU while the foot stands still. It calls the
equation functions of ``strapdown``, ``zupt``, ``stride_gate`` and ``ekf``, compiled with
numba (``core/jit.py``); a numba function takes no objects, so its state lives in arrays whose
layout the constants below name. ``FootNavigator`` (``core/navigator.py``) owns those arrays,
the start-up and the gait cycles.

Public API: ``navigation_step``, ``attitude_at_rest`` and the layout constants.
"""

import math

import numpy as np

from . import ekf
from .frames import dcm_to_quat, dcm_to_rpy, level_attitude_from_gravity, mat_mul, mat_vec
from .frames import quat_to_dcm, rpy_to_dcm
from .jit import jit
from .strapdown import strapdown_step
from .stride_gate import CANDIDATE_VEL, LATE_DPOS, LATE_DVEL, LATE_SIGMA, RELAXED_SIGMA
from .stride_gate import stride_gate_update
from .zupt import adaptive_threshold, intensity_update, shoe_update, window_is_still
from .zupt import young_stance_waits

# The arrays' layout:
# the nominal state,
Q_NB, VEL_N, POS_N, ACC_BIAS_B, GYR_BIAS_B = (
    slice(0, 4), slice(4, 7), slice(7, 10), slice(10, 13), slice(13, 16))
N_NOMINAL = 16
# the navigator's integer state and counters,
PREV_STAMP_NS, STILL_SAMPLES, MIN_STANCE_SAMPLES, RELEVEL, GAPS, MISSING_SAMPLES, \
    STANCE_SAMPLES, ZARU_SAMPLES, YOUNG_STANCE_SAMPLES, WAITING_ZUPTS, RELAXED_STANCES = range(11)
# and its real-valued state and settings (THRESHOLD_LAW: the arguments of adaptive_threshold).
THRESHOLD, LAST_NIS, GRAVITY, RATE_HZ, MAX_GAP_S, MAX_DT_S, ZUPT_SIGMA, ADAPTIVE, GYR_RAIL, \
    GYR_RAIL_NOISE, ZARU_MAX_GYR, ZARU_SIGMA, YOUNG_MAX_NIS = range(13)
THRESHOLD_LAW = slice(13, 18)


@jit
def attitude_at_rest(acc_mean_b: np.ndarray, yaw_rad: float) -> np.ndarray:
    """Return q_nb with roll and pitch from the specific force at rest and the given yaw."""
    C_nb = level_attitude_from_gravity(acc_mean_b)
    return dcm_to_quat(mat_mul(rpy_to_dcm(0.0, 0.0, yaw_rad - dcm_to_rpy(C_nb)[2]), C_nb))


@jit
def navigation_step(stamp_ns, acc_b, gyr_b, sensor_gyr_b, nominal, P, phi, Q_per_s, P_initial,
                    prev_sample, C_nb_out, zupt_dx_out, counts, scalars, shoe_samples,
                    shoe_sums, shoe_count, shoe_config, peaks, intensity_state, intensity_counts,
                    gate_state, gate_config) -> int:
    """
    One IMU sample through S1-S3 (after start-up): mechanisation, detector, EKF.

    ``gyr_b`` is integrated; the detector, its threshold and the rail noise see
    ``sensor_gyr_b``, the rate as the sensor gave it (they differ only where clipped samples
    were rebuilt, ``core/gyro_rail.py``: the stances stay where they were). Updates the arrays
    in place (layouts: the constants above, ``ShoeDetector``,
    ``GaitIntensity`` and ``core/stride_gate.py``), writes the corrected attitude to
    ``C_nb_out`` and the sample's ZUPT correction of position and velocity to ``zupt_dx_out``
    (zero without a ZUPT: the gait cycles tell a landing's own correction from the rest).

    Returns
    -------
    1 if the sample is a stance sample (ZUPT), plus 2 if samples were missing before it (a
    gap), plus 4 if it is a gait stance (it closes or continues a gait cycle's stance, see
    ``stride_gate_update``), plus 8 if the gate found a stance after the fact (a late stance,
    the sample the gate's state gives: its velocity is measured here as a ZUPT, the correction
    in the gate's state for the buffered samples).

    """
    dt_s = (stamp_ns - counts[PREV_STAMP_NS]) * 1e-9
    counts[PREV_STAMP_NS] = stamp_ns
    gap = dt_s > scalars[MAX_GAP_S]
    if gap:
        counts[GAPS] += 1
        counts[RELEVEL] = 1
    counts[MISSING_SAMPLES] += max(0, round(dt_s * scalars[RATE_HZ]) - 1)
    dt_s = min(dt_s, scalars[MAX_DT_S])

    # S1, eq. (1)-(3): bias-corrected interval means, trapezoidal integration.
    acc_mid = 0.5 * (acc_b + prev_sample[0:3]) - nominal[ACC_BIAS_B]
    gyr_mid = 0.5 * (gyr_b + prev_sample[3:6]) - nominal[GYR_BIAS_B]
    prev_sample[0:3] = acc_b
    prev_sample[3:6] = gyr_b
    q_nb, vel_n, pos_n, C_mid = strapdown_step(nominal[Q_NB], nominal[VEL_N], nominal[POS_N],
                                               acc_mid, gyr_mid, dt_s, scalars[GRAVITY])
    acc_bias_b, gyr_bias_b = nominal[ACC_BIAS_B], nominal[GYR_BIAS_B]

    # S3, eq. (5)-(6): covariance prediction.
    phi = ekf.error_transition_matrix(C_mid, mat_vec(C_mid, acc_mid), dt_s, phi)
    P[:, :] = ekf.predict_covariance(P, phi, Q_per_s * dt_s)
    rail = scalars[GYR_RAIL]
    if rail > 0.0 and max(abs(sensor_gyr_b[0]), abs(sensor_gyr_b[1]),
                          abs(sensor_gyr_b[2])) >= rail:
        ekf.clipped_gyro_noise(P, scalars[GYR_RAIL_NOISE], dt_s)

    # S2, eq. (4): zero-velocity decision (NaN while the window fills: not still), a young
    # stance's implausible ZUPT held back (not after a gap: the INS velocity is no evidence
    # then), then the gait's structure (one stance between two swings; its relaxed stances
    # are young stances too).
    statistic = shoe_update(shoe_samples, shoe_sums, shoe_count, shoe_config, acc_b,
                            sensor_gyr_b)
    counts[STILL_SAMPLES] = counts[STILL_SAMPLES] + 1 if statistic < scalars[THRESHOLD] else 0
    still = counts[STILL_SAMPLES] >= counts[MIN_STANCE_SAMPLES]
    if still and counts[RELEVEL] == 0 and young_stance_waits(
            counts[STILL_SAMPLES], counts[YOUNG_STANCE_SAMPLES], P, vel_n, scalars[ZUPT_SIGMA],
            scalars[YOUNG_MAX_NIS]):
        still = False
        counts[WAITING_ZUPTS] += 1
    young_max_nis = scalars[YOUNG_MAX_NIS] \
        if counts[RELEVEL] == 0 and counts[YOUNG_STANCE_SAMPLES] > 0 else 0.0
    gate = stride_gate_update(gate_state, gate_config, statistic, scalars[THRESHOLD], still,
                              vel_n, P, young_max_nis)
    stance = gate & 1 == 1
    if gate & 4 == 4:
        counts[RELAXED_STANCES] += 1
    if gate & 16 == 16:
        counts[WAITING_ZUPTS] += 1
    if scalars[ADAPTIVE] != 0.0 and intensity_update(
            peaks, intensity_state, intensity_counts,
            math.sqrt(sensor_gyr_b[0] ** 2 + sensor_gyr_b[1] ** 2 + sensor_gyr_b[2] ** 2)):
        law = scalars[THRESHOLD_LAW]
        scalars[THRESHOLD] = adaptive_threshold(intensity_state[0], law[0], law[1], law[2],
                                                law[3], law[4])

    # S3, eq. (7): ZUPT in every stance sample.
    zupt_dx_out[:] = 0.0
    if stance:
        counts[STANCE_SAMPLES] += 1
        if counts[RELEVEL]:
            # First stance after a gap: roll and pitch from gravity again, velocity zero.
            yaw_rad = dcm_to_rpy(quat_to_dcm(q_nb))[2]
            q_nb = attitude_at_rest(shoe_sums[0:3] / shoe_samples.shape[0] - acc_bias_b,
                                    yaw_rad)
            vel_n = np.zeros(3)
            P[:, :] = ekf.relevelled_covariance(P, P_initial)
            counts[RELEVEL] = 0
        sigma = gate_config[RELAXED_SIGMA] if gate & 4 == 4 else scalars[ZUPT_SIGMA]
        dx, P_new, nis = ekf.zupt_correction(P, vel_n, sigma)
        P[:, :] = P_new
        scalars[LAST_NIS] = nis
        zupt_dx_out[0:3] = dx[ekf.POS]
        zupt_dx_out[3:6] = dx[ekf.VEL]
        q_nb, vel_n, pos_n, acc_bias_b, gyr_bias_b = ekf.apply_correction(
            q_nb, vel_n, pos_n, acc_bias_b, gyr_bias_b, dx)
        # ZARU while the foot stands still (0 disables): the gyro bias from the whole stand.
        if scalars[ZARU_MAX_GYR] > 0.0 and window_is_still(shoe_samples, scalars[ZARU_MAX_GYR]):
            counts[ZARU_SAMPLES] += 1
            dx, P_new, _ = ekf.zaru_correction(P, gyr_b, gyr_bias_b, scalars[ZARU_SIGMA])
            P[:, :] = P_new
            q_nb, vel_n, pos_n, acc_bias_b, gyr_bias_b = ekf.apply_correction(
                q_nb, vel_n, pos_n, acc_bias_b, gyr_bias_b, dx)

    if gate & 8 == 8:
        # A late stance: the velocity error at it, carried to now, measured (a delayed ZUPT).
        dx, P_new, _ = ekf.zupt_correction(P, gate_state[CANDIDATE_VEL], gate_config[LATE_SIGMA])
        P[:, :] = P_new
        gate_state[LATE_DPOS] = dx[ekf.POS]
        gate_state[LATE_DVEL] = dx[ekf.VEL]
        q_nb, vel_n, pos_n, acc_bias_b, gyr_bias_b = ekf.apply_correction(
            q_nb, vel_n, pos_n, acc_bias_b, gyr_bias_b, dx)

    nominal[Q_NB] = q_nb
    nominal[VEL_N] = vel_n
    nominal[POS_N] = pos_n
    nominal[ACC_BIAS_B] = acc_bias_b
    nominal[GYR_BIAS_B] = gyr_bias_b
    C_nb_out[:, :] = quat_to_dcm(q_nb)
    return int(stance) + 2 * int(gap) + 4 * int(gate & 2 == 2) + (gate & 8)
