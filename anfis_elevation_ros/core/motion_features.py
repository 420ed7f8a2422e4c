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
Motion features of a gait cycle, in the foot's own frame: seed 001's scene-classifier inputs.

Beside the patent's five height and pitch features (``core/gait.py``, eq. 8-12), the random
forest of the second classifier backend (``core/forest.py``) reads the shape of the swing's
specific force and angular rate. They are taken over the same samples as eq. (8)-(11) (the
swing and the closing stance sample), in the foot frame f of the stance the swing left:

    z_f = u_b (up, from gravity at the stance),  x_f = forward axis of the foot with its
    z_f part removed,  y_f = z_f x x_f (left);   C_fb = [x_f; y_f; z_f],  a_f = C_fb a_b

so a rotated mounting of the IMU on the boot changes none of them. With w the angular rate
and a the specific force (gravity included, as measured):

    acc x min, acc y skewness, acc z max, max |a|       (:func:`acceleration_features`)
    gyro x mean, gyro y variance, gyro z max, |w| mean, skewness and variance
                                                        (:func:`rotation_features`)
    max horizontal speed                                (:func:`max_horizontal_speed`)

The twelfth feature of the seed, the height difference, is eq. (10), ``height_change_m``.
"""

import numpy as np

MOTION_FEATURE_NAMES = (
    'acc_x_min_mps2', 'acc_y_skewness', 'acc_z_max_mps2', 'acc_norm_max_mps2',
    'gyr_x_mean_rps', 'gyr_y_var_rps2', 'gyr_z_max_rps', 'gyr_norm_mean_rps',
    'gyr_norm_skewness', 'gyr_norm_var_rps2', 'max_horizontal_speed_mps')
"""Order of :func:`motion_features`' output; x forward, y left, z up in the foot frame."""


def foot_frame(up_b: np.ndarray, forward_b: np.ndarray) -> np.ndarray:
    """
    Rotation C_fb from the body frame to the foot frame of a stance.

    z_f = u_b / |u_b|,  x_f = (f_b - (f_b . z_f) z_f) / |...|,  y_f = z_f x x_f,
    C_fb = [x_f; y_f; z_f] (rows), so v_f = C_fb v_b.

    Parameters
    ----------
    up_b : (3,) array
        Navigation up axis in the body frame at the stance (third row of C_nb).
    forward_b : (3,) array
        Forward axis of the foot in the body frame (not parallel to up_b).

    """
    z_f = up_b / np.linalg.norm(up_b)
    x_f = forward_b - (forward_b @ z_f) * z_f
    x_f = x_f / np.linalg.norm(x_f)
    return np.stack((x_f, np.cross(z_f, x_f), z_f))


def skewness(values: np.ndarray) -> float:
    """
    Sample skewness, g1 = mean((v - m)^3) / s^3 with s the population standard deviation.

    0 for a constant series (s below 1e-12 of the scale of the values).
    """
    centred = values - values.mean()
    spread = np.sqrt(np.mean(centred ** 2))
    if spread <= 1e-12 * max(1.0, float(np.abs(values).max())):
        return 0.0
    return float(np.mean(centred ** 3) / spread ** 3)


def acceleration_features(acc_f: np.ndarray) -> np.ndarray:
    """
    [min a_x, skewness a_y, max a_z, max |a|] of the specific force in the foot frame.

    Parameters
    ----------
    acc_f : (n, 3) array
        Specific force of the cycle's samples, foot frame, m/s^2.

    """
    norm = np.sqrt(np.einsum('ij,ij->i', acc_f, acc_f))
    return np.array([acc_f[:, 0].min(), skewness(acc_f[:, 1]), acc_f[:, 2].max(), norm.max()])


def rotation_features(gyr_f: np.ndarray) -> np.ndarray:
    """
    [mean w_x, var w_y, max w_z, mean |w|, skewness |w|, var |w|] in the foot frame.

    Parameters
    ----------
    gyr_f : (n, 3) array
        Angular rate of the cycle's samples, foot frame, rad/s.

    """
    norm = np.sqrt(np.einsum('ij,ij->i', gyr_f, gyr_f))
    return np.array([gyr_f[:, 0].mean(), gyr_f[:, 1].var(), gyr_f[:, 2].max(), norm.mean(),
                     skewness(norm), norm.var()])


def max_horizontal_speed(vel_n: np.ndarray) -> float:
    """
    max_j sqrt(v_E^2 + v_N^2) over the cycle's samples, m/s.

    Parameters
    ----------
    vel_n : (n, 3) array
        Corrected velocity, navigation frame (ENU), m/s.

    """
    return float(np.sqrt(vel_n[:, 0] ** 2 + vel_n[:, 1] ** 2).max())


def motion_features(acc_b: np.ndarray, gyr_b: np.ndarray, vel_n: np.ndarray,
                    C_fb: np.ndarray) -> np.ndarray:
    """
    Compute the eleven motion features of one cycle, in :data:`MOTION_FEATURE_NAMES` order.

    Parameters
    ----------
    acc_b, gyr_b : (n, 3) arrays
        Specific force (m/s^2) and angular rate (rad/s) of the cycle's samples, body frame.
    vel_n : (n, 3) array
        Corrected velocity of the same samples, m/s, ENU.
    C_fb : (3, 3) array
        Body-to-foot rotation of the stance the swing left, :func:`foot_frame`.

    """
    return np.concatenate((acceleration_features(acc_b @ C_fb.T),
                           rotation_features(gyr_b @ C_fb.T), [max_horizontal_speed(vel_n)]))
