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

"""The error-state EKF, eq. (5)-(7): transition matrix, ZUPT update, covariance properties."""

from anfis_elevation_ros.core import ekf
from anfis_elevation_ros.core.frames import (
    dcm_to_quat, quat_multiply, quat_to_dcm, quat_to_rotvec, rotvec_to_quat, skew)
from anfis_elevation_ros.core.strapdown import strapdown_step
import numpy as np
import pytest

G = 9.80665


def test_transition_matrix_blocks():
    C = quat_to_dcm(rotvec_to_quat(np.array([0.1, 0.2, -0.3])))
    acc_n = np.array([1.0, -2.0, 9.0])
    phi = ekf.error_transition_matrix(C, acc_n, 0.01)
    assert np.allclose(phi[ekf.POS, ekf.VEL], 0.01 * np.eye(3))
    assert np.allclose(phi[ekf.VEL, ekf.ATT], -0.01 * skew(acc_n))
    assert np.allclose(phi[ekf.VEL, ekf.ACC_BIAS], -0.01 * C)
    assert np.allclose(phi[ekf.ATT, ekf.GYR_BIAS], -0.01 * C)
    off_blocks = phi.copy()
    for rows, cols in ((ekf.POS, ekf.VEL), (ekf.VEL, ekf.ATT), (ekf.VEL, ekf.ACC_BIAS),
                       (ekf.ATT, ekf.GYR_BIAS)):
        off_blocks[rows, cols] = 0.0
    assert np.array_equal(off_blocks, np.eye(15))


def test_transition_matrix_predicts_how_the_mechanisation_spreads_an_error():
    # Perturb the true state by a small error dx, run the mechanisation on both and compare
    # the difference with Phi dx: checks every sign convention of eq. (5).
    rng = np.random.default_rng(2)
    dt = 0.005
    q = rotvec_to_quat(np.array([0.3, -0.5, 1.2]))
    vel, pos = np.array([0.5, -0.2, 0.1]), np.zeros(3)
    acc_meas, gyr_meas = np.array([2.0, -1.0, 11.0]), np.array([1.5, -3.0, 0.7])
    dx = rng.normal(size=15) * 1e-6
    q_true = quat_multiply(rotvec_to_quat(dx[ekf.ATT]), q)  # C_true = (I + [dphi x]) C
    # The true sensor errors are the biases dx; the estimate corrects no bias.
    true_step = strapdown_step(q_true, vel + dx[ekf.VEL], pos + dx[ekf.POS],
                               acc_meas - dx[ekf.ACC_BIAS], gyr_meas - dx[ekf.GYR_BIAS], dt, G)
    est_step = strapdown_step(q, vel, pos, acc_meas, gyr_meas, dt, G)
    C_mid = est_step[3]
    phi = ekf.error_transition_matrix(C_mid, C_mid @ acc_meas, dt)
    predicted = phi @ dx
    d_vel = true_step[1] - est_step[1]
    conj_est = est_step[0] * np.array([1.0, -1.0, -1.0, -1.0])
    d_att = quat_to_rotvec(quat_multiply(true_step[0], conj_est))
    assert np.allclose(d_vel, predicted[ekf.VEL], rtol=0.05, atol=1e-9)
    assert np.allclose(d_att, predicted[ekf.ATT], rtol=0.05, atol=1e-11)


def test_zupt_update_matches_the_scalar_kalman_gain():
    P = np.diag(np.full(15, 0.01))
    vel = np.array([0.1, -0.2, 0.05])
    dx, P_new, nis = ekf.zupt_correction(P, vel, 0.01)
    gain = 0.01 / (0.01 + 0.01 ** 2)
    assert np.allclose(dx[ekf.VEL], -vel * gain)
    assert np.allclose(np.delete(dx, range(3, 6)), 0.0)  # uncorrelated states stay put
    assert np.allclose(np.diag(P_new)[ekf.VEL], 0.01 * (1 - gain))
    assert nis == pytest.approx(vel @ vel / (0.01 + 0.01 ** 2))


def test_zupt_update_is_the_textbook_joseph_form():
    """
    The rank-3 evaluation equals (I - K H) P (I - K H)^T + K R K^T with the full H.

    And, for the optimal gain, the standard form P - K S K^T.
    """
    rng = np.random.default_rng(5)
    A = rng.normal(size=(15, 15))
    P = A @ A.T + np.eye(15)
    vel = rng.normal(size=3)
    dx, P_new, nis = ekf.zupt_correction(P, vel, 0.02)
    H = np.zeros((3, 15))
    H[:, ekf.VEL] = np.eye(3)
    R = 0.02 ** 2 * np.eye(3)
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    I_KH = np.eye(15) - K @ H
    assert np.allclose(P_new, I_KH @ P @ I_KH.T + K @ R @ K.T, rtol=0.0, atol=1e-12)
    assert np.allclose(P_new, P - K @ S @ K.T, rtol=0.0, atol=1e-10)
    assert np.allclose(dx, K @ -vel, rtol=0.0, atol=1e-12)
    assert nis == pytest.approx(vel @ np.linalg.solve(S, vel), rel=1e-12)


def test_zaru_update_measures_the_bias_and_takes_back_the_yaw_it_turned():
    """
    Check a ZARU against a hand-computed case.

    The foot stood T = 2 s with an unknown z-bias error, so yaw and bias are correlated as the
    prediction makes them (dphi_z = -T dbg_z): P_yy = T^2 p, P_yb = -T p.
    """
    p, T, sigma = 1e-4, 2.0, 0.01
    yaw, bias_z = ekf.ATT.start + 2, ekf.GYR_BIAS.start + 2
    P = np.diag(np.full(15, p))
    P[yaw, yaw], P[yaw, bias_z] = T * T * p + 1e-6, -T * p
    P[bias_z, yaw] = P[yaw, bias_z]
    gyr, bias = np.array([0.01, -0.02, 0.03]), np.array([0.0, 0.0, 0.01])
    dx, P_new, nis = ekf.zaru_correction(P, gyr, bias, sigma)
    gain = p / (p + sigma ** 2)
    y = gyr - bias
    assert dx[ekf.GYR_BIAS] == pytest.approx(gain * y)
    assert dx[yaw] == pytest.approx(-T * p / (p + sigma ** 2) * y[2])   # the yaw turned back
    assert np.all(dx[:ekf.ATT.start + 2] == 0.0)
    assert np.diag(P_new)[ekf.GYR_BIAS] == pytest.approx(np.full(3, p * (1.0 - gain)))
    assert nis == pytest.approx(y @ y / (p + sigma ** 2))
    H = np.zeros((3, 15))
    H[:, ekf.GYR_BIAS] = np.eye(3)
    S = H @ P @ H.T + sigma ** 2 * np.eye(3)
    K = P @ H.T @ np.linalg.inv(S)
    assert np.allclose(P_new, P - K @ S @ K.T, rtol=0.0, atol=1e-15)


def test_covariance_prediction_equals_the_dense_products():
    """The zero-skipping products give Phi P Phi^T + Q of the full matrices."""
    rng = np.random.default_rng(6)
    A = rng.normal(size=(15, 15))
    P = A @ A.T
    C = quat_to_dcm(rotvec_to_quat(rng.normal(size=3)))
    phi = ekf.error_transition_matrix(C, rng.normal(size=3) * 20, 0.005)
    Q = ekf.process_noise(ekf.EkfParams(), 0.005)
    assert np.allclose(ekf.predict_covariance(P, phi, Q), phi @ P @ phi.T + Q,
                       rtol=1e-13, atol=1e-13)


def test_covariance_stays_symmetric_positive_definite():
    rng = np.random.default_rng(4)
    params = ekf.EkfParams()
    P = ekf.initial_covariance(params)
    for k in range(3000):
        C = quat_to_dcm(rotvec_to_quat(rng.normal(size=3)))
        phi = ekf.error_transition_matrix(C, rng.normal(size=3) * 20, 0.0025)
        P = ekf.predict_covariance(P, phi, ekf.process_noise(params, 0.0025))
        if k % 3:
            _, P, _ = ekf.zupt_correction(P, rng.normal(size=3), params.zupt_sigma_mps)
    assert np.allclose(P, P.T, atol=1e-15)
    assert np.linalg.eigvalsh(P).min() > 0.0


def test_correction_feeds_the_error_back():
    q = dcm_to_quat(np.eye(3))
    dx = np.zeros(15)
    dx[ekf.POS], dx[ekf.VEL], dx[ekf.ATT] = [1, 2, 3], [0.1, 0.2, 0.3], [0.0, 0.0, 0.01]
    dx[ekf.ACC_BIAS], dx[ekf.GYR_BIAS] = [0.01, 0, 0], [0, 0.001, 0]
    q2, v, p, ba, bg = ekf.apply_correction(q, np.zeros(3), np.zeros(3), np.zeros(3),
                                            np.zeros(3), dx)
    assert np.allclose(p, [1, 2, 3]) and np.allclose(v, [0.1, 0.2, 0.3])
    assert np.allclose(ba, [0.01, 0, 0]) and np.allclose(bg, [0, 0.001, 0])
    assert np.allclose(quat_to_dcm(q2), np.eye(3) + skew(dx[ekf.ATT]), atol=1e-4)


@pytest.mark.parametrize('field', list(ekf.EkfParams.__dataclass_fields__))
def test_noise_parameters_must_be_positive(field):
    with pytest.raises(ValueError, match=field):
        ekf.EkfParams(**{field: 0.0})


def test_relevelled_covariance_resets_velocity_roll_and_pitch_only():
    rng = np.random.default_rng(4)
    A = rng.normal(size=(ekf.N_STATES, ekf.N_STATES))
    P = A @ A.T
    params = ekf.EkfParams()
    R = ekf.relevelled_covariance(P, ekf.initial_covariance(params))
    reset = [3, 4, 5, 9, 10]                              # dV, roll, pitch
    kept = [i for i in range(ekf.N_STATES) if i not in reset]
    initial = np.diag(ekf.initial_covariance(params))
    assert np.array_equal(np.diag(R)[reset], initial[reset])
    off_diagonal = R[reset][:, reset] - np.diag(initial[reset])
    assert not off_diagonal.any() and not R[reset][:, kept].any()
    assert np.array_equal(R[np.ix_(kept, kept)], P[np.ix_(kept, kept)])
    assert np.all(np.linalg.eigvalsh(R) > 0)
