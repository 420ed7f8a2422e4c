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

"""Analytic checks of the frames and strapdown mechanisation, eq. (1)-(3)."""

import math

from anfis_elevation_ros.core.frames import (
    dcm_to_quat, dcm_to_rpy, level_attitude_from_gravity, quat_multiply, quat_to_dcm,
    quat_to_rotvec, rotvec_to_quat, rpy_to_dcm, skew)
from anfis_elevation_ros.core.strapdown import (
    strapdown, update_attitude, update_position, update_velocity)
import numpy as np
import pytest

G = 9.80665


def stamps(n, rate_hz):
    return (np.arange(n) * (1e9 / rate_hz)).astype(np.int64)


def test_quaternion_and_dcm_round_trip():
    rng = np.random.default_rng(0)
    for rotvec in rng.normal(size=(20, 3)):
        q = rotvec_to_quat(rotvec)
        assert np.allclose(dcm_to_quat(quat_to_dcm(q)), q if q[0] >= 0 else -q, atol=1e-12)
        C = quat_to_dcm(q)
        assert np.allclose(C @ C.T, np.eye(3), atol=1e-12)
        assert np.allclose(rpy_to_dcm(*dcm_to_rpy(C)), C, atol=1e-12)
        angle = np.linalg.norm(rotvec) % (2 * math.pi)
        if angle < math.pi - 1e-6:  # the rotation vector is unique below pi
            assert np.allclose(quat_to_rotvec(q), rotvec / np.linalg.norm(rotvec) * angle)


def test_hamilton_product_composes_rotations():
    p, q = rotvec_to_quat(np.array([0.3, -0.2, 1.0])), rotvec_to_quat(np.array([-1.0, 0.4, 0.1]))
    assert np.allclose(quat_to_dcm(quat_multiply(p, q)), quat_to_dcm(p) @ quat_to_dcm(q))
    assert np.allclose(skew(np.array([1.0, 2.0, 3.0])) @ np.array([-1.0, 0.5, 2.0]),
                       np.cross([1.0, 2.0, 3.0], [-1.0, 0.5, 2.0]))


@pytest.mark.parametrize('acc_b', [[0, 0, G], [0, 0, -G], [1.0, -2.0, 9.5], [-9.6, 0.5, 1.0]])
def test_level_attitude_puts_gravity_on_up_axis_with_zero_yaw(acc_b):
    acc_b = np.array(acc_b, dtype=float)
    C_nb = level_attitude_from_gravity(acc_b)
    assert np.allclose(C_nb @ acc_b / np.linalg.norm(acc_b), [0, 0, 1], atol=1e-12)
    assert np.allclose(C_nb @ C_nb.T, np.eye(3), atol=1e-12)
    x_n = C_nb[:, 0]
    if abs(x_n[2]) < 0.99:  # yaw is defined when body x is not vertical
        assert abs(math.atan2(x_n[1], x_n[0])) < 1e-12


def test_attitude_update_integrates_a_constant_rate_exactly():
    # eq. (1): constant rate w for time t turns by w t about the rate axis.
    q = np.array([1.0, 0, 0, 0])
    gyr_b = np.array([0.2, -0.5, 1.0])
    for _ in range(1000):
        q = update_attitude(q, gyr_b, 0.002)
    assert np.allclose(quat_to_rotvec(q), gyr_b * 2.0, atol=1e-12)


def test_velocity_and_position_updates_match_hand_computed_values():
    # eq. (2): a level IMU reading [1, 0, g] accelerates at 1 m/s^2 east.
    vel = update_velocity(np.zeros(3), np.eye(3), np.array([1.0, 0.0, G]), 0.5, G)
    assert np.allclose(vel, [0.5, 0.0, 0.0])
    # eq. (3): trapezoidal position update.
    assert np.allclose(update_position(np.zeros(3), np.zeros(3), vel, 0.5), [0.125, 0, 0])


def test_stationary_imu_stays_put_in_any_orientation():
    n = 2000
    C_nb = rpy_to_dcm(0.4, -0.3, 2.0)
    acc_b = np.tile(C_nb.T @ [0, 0, G], (n, 1))
    q, v, p = strapdown(dcm_to_quat(C_nb), np.zeros(3), np.zeros(3), stamps(n, 200.0), acc_b,
                        np.zeros((n, 3)))
    assert np.abs(v).max() < 1e-12 and np.abs(p).max() < 1e-10
    assert np.allclose(quat_to_dcm(q[-1]), C_nb, atol=1e-12)


def test_constant_acceleration_gives_the_kinematic_solution():
    # Trapezoidal integration is exact for a constant acceleration: p = a t^2 / 2.
    n, rate_hz = 401, 200.0
    acc_b = np.tile([0.3, -0.2, G + 0.1], (n, 1))
    q, v, p = strapdown(np.array([1.0, 0, 0, 0]), np.zeros(3), np.zeros(3), stamps(n, rate_hz),
                        acc_b, np.zeros((n, 3)))
    t = (n - 1) / rate_hz
    assert np.allclose(v[-1], np.array([0.3, -0.2, 0.1]) * t, atol=1e-12)
    assert np.allclose(p[-1], 0.5 * np.array([0.3, -0.2, 0.1]) * t ** 2, atol=1e-12)
