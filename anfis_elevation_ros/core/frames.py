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

from .jit import jit

GRAVITY_MPS2 = 9.80665  # standard gravity; the local value can be set by parameter


@jit
def skew(v: np.ndarray) -> np.ndarray:
    """Return the cross-product matrix [v x] of v (its product with u is v x u)."""
    S = np.zeros((3, 3))
    S[0, 1], S[0, 2] = -v[2], v[1]
    S[1, 0], S[1, 2] = v[2], -v[0]
    S[2, 0], S[2, 1] = -v[1], v[0]
    return S


@jit
def mat_vec(A: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Return the product A v of a matrix and a vector (compiled: no BLAS call for 3 x 3)."""
    out = np.zeros(A.shape[0])
    for i in range(A.shape[0]):
        for j in range(A.shape[1]):
            out[i] += A[i, j] * v[j]
    return out


@jit
def mat_mul(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Return the product A B of two matrices (compiled: no BLAS call for 3 x 3)."""
    out = np.zeros((A.shape[0], B.shape[1]))
    for i in range(A.shape[0]):
        for k in range(A.shape[1]):
            a_ik = A[i, k]
            for j in range(B.shape[1]):
                out[i, j] += a_ik * B[k, j]
    return out


@jit
def quat_multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product p * q of quaternions [w, x, y, z]."""
    pw, px, py, pz = p[0], p[1], p[2], p[3]
    qw, qx, qy, qz = q[0], q[1], q[2], q[3]
    out = np.empty(4)
    out[0] = pw * qw - px * qx - py * qy - pz * qz
    out[1] = pw * qx + px * qw + py * qz - pz * qy
    out[2] = pw * qy - px * qz + py * qw + pz * qx
    out[3] = pw * qz + px * qy - py * qx + pz * qw
    return out


@jit
def rotvec_to_quat(rotvec: np.ndarray) -> np.ndarray:
    """Return the quaternion of rotation vector r: q = [cos(|r|/2), sin(|r|/2) r/|r|]."""
    x, y, z = rotvec[0], rotvec[1], rotvec[2]
    angle = math.sqrt(x * x + y * y + z * z)
    out = np.empty(4)
    if angle < 1e-12:
        out[0], out[1], out[2], out[3] = 1.0, 0.5 * x, 0.5 * y, 0.5 * z
        return out
    s = math.sin(0.5 * angle) / angle
    out[0], out[1], out[2], out[3] = math.cos(0.5 * angle), s * x, s * y, s * z
    return out


@jit
def quat_to_rotvec(q: np.ndarray) -> np.ndarray:
    """Rotation vector (axis times angle, rad) of a quaternion, angle in [0, pi]."""
    w = q[0] if q[0] >= 0.0 else -q[0]
    v = q[1:] if q[0] >= 0.0 else -q[1:]
    norm_v = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
    if norm_v < 1e-12:
        return 2.0 * v
    return (2.0 * math.atan2(norm_v, w) / norm_v) * v


@jit
def quat_to_dcm(q: np.ndarray) -> np.ndarray:
    """Direction cosine matrix C of a unit quaternion, v_n = C @ v_b."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    C = np.empty((3, 3))
    C[0, 0], C[0, 1], C[0, 2] = 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)
    C[1, 0], C[1, 1], C[1, 2] = 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)
    C[2, 0], C[2, 1], C[2, 2] = 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)
    return C


@jit
def dcm_to_quat(C: np.ndarray) -> np.ndarray:
    """Return the unit quaternion [w, x, y, z] (w >= 0) of a rotation matrix (Shepperd)."""
    trace = C[0, 0] + C[1, 1] + C[2, 2]
    # The largest of trace, C00, C11, C22 (the first on ties) gives the best-conditioned root.
    largest, value = 0, trace
    for i in range(3):
        if C[i, i] > value:
            largest, value = i + 1, C[i, i]
    q = np.empty(4)
    if largest == 0:
        s = 2.0 * math.sqrt(1.0 + trace)
        q[0], q[1], q[2], q[3] = (0.25 * s, (C[2, 1] - C[1, 2]) / s, (C[0, 2] - C[2, 0]) / s,
                                  (C[1, 0] - C[0, 1]) / s)
    elif largest == 1:
        s = 2.0 * math.sqrt(1.0 + C[0, 0] - C[1, 1] - C[2, 2])
        q[0], q[1], q[2], q[3] = ((C[2, 1] - C[1, 2]) / s, 0.25 * s, (C[0, 1] + C[1, 0]) / s,
                                  (C[0, 2] + C[2, 0]) / s)
    elif largest == 2:
        s = 2.0 * math.sqrt(1.0 - C[0, 0] + C[1, 1] - C[2, 2])
        q[0], q[1], q[2], q[3] = ((C[0, 2] - C[2, 0]) / s, (C[0, 1] + C[1, 0]) / s, 0.25 * s,
                                  (C[1, 2] + C[2, 1]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 - C[0, 0] - C[1, 1] + C[2, 2])
        q[0], q[1], q[2], q[3] = ((C[1, 0] - C[0, 1]) / s, (C[0, 2] + C[2, 0]) / s,
                                  (C[1, 2] + C[2, 1]) / s, 0.25 * s)
    return q if q[0] >= 0.0 else -q


@jit
def rpy_to_dcm(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Return C = Rz(yaw) Ry(pitch) Rx(roll) of fixed-axis roll, pitch, yaw (rad), REP 103."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    C = np.empty((3, 3))
    C[0, 0], C[0, 1], C[0, 2] = cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr
    C[1, 0], C[1, 1], C[1, 2] = sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr
    C[2, 0], C[2, 1], C[2, 2] = -sp, cp * sr, cp * cr
    return C


@jit
def dcm_to_rpy(C: np.ndarray) -> np.ndarray:
    """Return roll, pitch, yaw (rad) of a rotation matrix, pitch in [-pi/2, pi/2]."""
    rpy = np.empty(3)
    rpy[0] = math.atan2(C[2, 1], C[2, 2])
    rpy[1] = math.asin(max(-1.0, min(1.0, -C[2, 0])))
    rpy[2] = math.atan2(C[1, 0], C[0, 0])
    return rpy


@jit
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
    up_b = acc_b / math.sqrt(acc_b[0] ** 2 + acc_b[1] ** 2 + acc_b[2] ** 2)
    axis = np.array([up_b[1], -up_b[0], 0.0])        # u_b x [0, 0, 1]
    sin_angle = math.sqrt(axis[0] ** 2 + axis[1] ** 2)
    cos_angle = up_b[2]
    if sin_angle < 1e-12:
        return np.eye(3) if cos_angle > 0 else np.diag(np.array([1.0, -1.0, -1.0]))
    rotvec = axis / sin_angle * math.atan2(sin_angle, cos_angle)
    C = quat_to_dcm(rotvec_to_quat(rotvec))
    # Remove the heading the minimal rotation introduced, so that body x keeps yaw 0.
    yaw = math.atan2(C[1, 0], C[0, 0]) if abs(C[2, 0]) < 0.999 else 0.0
    return mat_mul(rpy_to_dcm(0.0, 0.0, -yaw), C)
