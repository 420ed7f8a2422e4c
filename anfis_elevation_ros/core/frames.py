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
Rotations in the project's conventions: quaternions [w, x, y, z], ENU navigation frame.

``q_nb`` rotates body vectors into the navigation frame, ``v_n = C_nb @ v_b`` with
``C_nb = quat_to_dcm(q_nb)``. Small-angle errors ``phi_n`` act on the navigation side:
``C_nb_true = (I + [phi_n x]) C_nb_est``.

References
----------
[1] P. D. Groves, Principles of GNSS, Inertial, and Multisensor Integrated Navigation Systems,
    2nd ed., Artech House, 2013, ch. 2 and 5.

"""

import math

import numpy as np

GRAVITY_MPS2 = 9.80665  # standard gravity; the local value can be set by parameter


def skew(v: np.ndarray) -> np.ndarray:
    """Return the cross-product matrix [v x] of v (its product with u is v x u)."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def quat_multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product p * q of quaternions [w, x, y, z]."""
    pw, px, py, pz = p.tolist()
    qw, qx, qy, qz = q.tolist()
    return np.array([
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    ])


def rotvec_to_quat(rotvec: np.ndarray) -> np.ndarray:
    """Return the quaternion of rotation vector r: q = [cos(|r|/2), sin(|r|/2) r/|r|]."""
    x, y, z = rotvec.tolist()
    angle = math.sqrt(x * x + y * y + z * z)
    if angle < 1e-12:
        return np.array([1.0, 0.5 * x, 0.5 * y, 0.5 * z])
    s = math.sin(0.5 * angle) / angle
    return np.array([math.cos(0.5 * angle), s * x, s * y, s * z])


def quat_to_rotvec(q: np.ndarray) -> np.ndarray:
    """Rotation vector (axis times angle, rad) of a quaternion, angle in [0, pi]."""
    w = q[0] if q[0] >= 0.0 else -q[0]
    v = q[1:] if q[0] >= 0.0 else -q[1:]
    norm_v = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
    if norm_v < 1e-12:
        return 2.0 * v
    return (2.0 * math.atan2(norm_v, w) / norm_v) * v


def quat_to_dcm(q: np.ndarray) -> np.ndarray:
    """Direction cosine matrix C of a unit quaternion, v_n = C @ v_b."""
    w, x, y, z = q.tolist()
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def dcm_to_quat(C: np.ndarray) -> np.ndarray:
    """Return the unit quaternion [w, x, y, z] (w >= 0) of a rotation matrix (Shepperd)."""
    trace = C[0, 0] + C[1, 1] + C[2, 2]
    candidates = (trace, C[0, 0], C[1, 1], C[2, 2])
    i = int(np.argmax(candidates))
    if i == 0:
        s = 2.0 * math.sqrt(1.0 + trace)
        q = [0.25 * s, (C[2, 1] - C[1, 2]) / s, (C[0, 2] - C[2, 0]) / s, (C[1, 0] - C[0, 1]) / s]
    elif i == 1:
        s = 2.0 * math.sqrt(1.0 + C[0, 0] - C[1, 1] - C[2, 2])
        q = [(C[2, 1] - C[1, 2]) / s, 0.25 * s, (C[0, 1] + C[1, 0]) / s, (C[0, 2] + C[2, 0]) / s]
    elif i == 2:
        s = 2.0 * math.sqrt(1.0 - C[0, 0] + C[1, 1] - C[2, 2])
        q = [(C[0, 2] - C[2, 0]) / s, (C[0, 1] + C[1, 0]) / s, 0.25 * s, (C[1, 2] + C[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 - C[0, 0] - C[1, 1] + C[2, 2])
        q = [(C[1, 0] - C[0, 1]) / s, (C[0, 2] + C[2, 0]) / s, (C[1, 2] + C[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q if q[0] >= 0.0 else -q


def rpy_to_dcm(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Return C = Rz(yaw) Ry(pitch) Rx(roll) of fixed-axis roll, pitch, yaw (rad), REP 103."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])


def dcm_to_rpy(C: np.ndarray) -> np.ndarray:
    """Return roll, pitch, yaw (rad) of a rotation matrix, pitch in [-pi/2, pi/2]."""
    return np.array([
        math.atan2(C[2, 1], C[2, 2]),
        math.asin(max(-1.0, min(1.0, -C[2, 0]))),
        math.atan2(C[1, 0], C[0, 0]),
    ])


def level_attitude_from_gravity(acc_b: np.ndarray) -> np.ndarray:
    """
    Return the attitude C_nb given by the mean specific force at rest, with yaw 0.

    At rest f_b = C_bn [0, 0, g], so the navigation z axis seen in the body frame is
    u_b = f_b / |f_b|. The returned C_nb is the smallest rotation taking u_b to [0, 0, 1]
    (roll and pitch from gravity; heading is unobservable and set to the body's own heading).

    Parameters
    ----------
    acc_b : (3,) array
        Mean specific force at rest, m/s^2.

    """
    up_b = acc_b / np.linalg.norm(acc_b)
    z_n = np.array([0.0, 0.0, 1.0])
    axis = np.cross(up_b, z_n)
    sin_angle = np.linalg.norm(axis)
    cos_angle = float(up_b @ z_n)
    if sin_angle < 1e-12:
        return np.eye(3) if cos_angle > 0 else np.diag([1.0, -1.0, -1.0])
    rotvec = axis / sin_angle * math.atan2(sin_angle, cos_angle)
    C = quat_to_dcm(rotvec_to_quat(rotvec))
    # Remove the heading the minimal rotation introduced, so that body x keeps yaw 0.
    yaw = math.atan2(C[1, 0], C[0, 0]) if abs(C[2, 0]) < 0.999 else 0.0
    return rpy_to_dcm(0.0, 0.0, -yaw) @ C
