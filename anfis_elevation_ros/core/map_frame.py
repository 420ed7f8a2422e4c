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
The building's map frame: the track starts at the entrance and its first strides point along it.

A building file's ``start`` gives the first stance (x, y) and the direction of the first strides
(``heading_deg``). The INS starts at the origin with an arbitrary heading; the map frame is

    p_map = R(psi) p_n + t,   t = (start.x_m, start.y_m, 0),
    psi = heading_deg - atan2(dy, dx) of the displacement over the first ``align_strides`` strides

(:func:`frame_rotation_rad`). Heights are not touched (0 at the first stance). Until those
strides are walked, ``psi`` is the estimate from the strides so far (0 before the first): the
outputs are map coordinates from the first stride on, and may turn by a few degrees about the
entrance until the frame is fixed. Then the filter itself is rotated into the map frame
(:func:`rotate_error_covariance`, ``FootNavigator``): from then on its position, heading and
covariance are map-frame quantities, the stair-position database and heading aids work on them
directly, and a saved state resumes in the map frame.

Public API: :class:`MapAlignment`, :func:`map_alignment_for`, :func:`frame_rotation_rad`,
:func:`rotate_error_covariance`, :func:`rotation_z`.
"""

import math

import numpy as np

from .ekf import ATT, N_STATES, POS, VEL

MIN_ALIGN_DISTANCE_M = 1.0    # shorter displacements (turns on the spot) give no direction


def rotation_z(psi_rad: float) -> np.ndarray:
    """Return the 3 x 3 rotation about z (up) by psi, counter-clockwise."""
    c, s = math.cos(psi_rad), math.sin(psi_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def frame_rotation_rad(displacement_n, heading_rad: float) -> float:
    """
    Rotation from the navigation frame to the map frame, wrapped to (-pi, pi].

    psi = heading - atan2(d_y, d_x), d = displacement of the first strides in the n frame.
    """
    psi = heading_rad - math.atan2(displacement_n[1], displacement_n[0])
    return math.atan2(math.sin(psi), math.cos(psi))


def rotate_error_covariance(P: np.ndarray, psi_rad: float) -> np.ndarray:
    """
    Covariance of the error state after rotating the navigation frame by psi about z.

    P' = T P T^T, T = diag(R, R, I, R, I): position, velocity and attitude errors are
    navigation-frame vectors; the bias errors are body-frame and do not change.
    """
    T = np.eye(N_STATES)
    R = rotation_z(psi_rad)
    for block in (POS, VEL, ATT):
        T[block, block] = R
    return T @ P @ T.T


class MapAlignment:
    """
    The map-frame transform of one track, estimated from its first strides.

    Parameters
    ----------
    start_xy : (2,) the building's start, m.
    heading_rad : the direction of the first strides in the map frame, rad.
    strides : strides after which the rotation is fixed.

    """

    def __init__(self, start_xy, heading_rad: float, strides: int):
        self._offset = np.array([start_xy[0], start_xy[1], 0.0])
        self._heading_rad = heading_rad
        self._strides_needed = strides
        self._strides = 0
        self._origin_n = None
        self.psi_rad = 0.0
        self.fixed = False

    def start(self, pos_n: np.ndarray):
        """Take the first stance position (n frame) as the entrance."""
        self._origin_n = np.array([pos_n[0], pos_n[1], 0.0], dtype=float)

    def add_stride(self, pos_n: np.ndarray) -> bool:
        """
        Take the position (n frame) at the end of a stride; return True when the frame is fixed.

        The caller then rotates its filter by ``psi_rad`` about the entrance and moves it by the
        offset (``FootNavigator``), after which ``to_map`` is the identity.
        """
        self._strides += 1
        displacement = np.asarray(pos_n, dtype=float) - self._origin_n
        if math.hypot(displacement[0], displacement[1]) < MIN_ALIGN_DISTANCE_M:
            return False
        self.psi_rad = frame_rotation_rad(displacement, self._heading_rad)
        if self._strides >= self._strides_needed:
            self.fixed = True
        return self.fixed

    def to_map(self, pos_n: np.ndarray) -> np.ndarray:
        """Return p_map = R(psi) (p_n - p_0) + t with the current estimate of psi."""
        return rotation_z(self.psi_rad) @ (np.asarray(pos_n) - self._origin_n) + self._offset

    def rotation(self) -> np.ndarray:
        """Return R(psi) with the current estimate."""
        return rotation_z(self.psi_rad)


def map_alignment_for(building, align_strides: int):
    """Return the MapAlignment of a building with a ``start``, else None (the start frame)."""
    if building is None or building.start is None:
        return None
    start = building.start
    return MapAlignment((start.x_m, start.y_m), math.radians(start.heading_deg), align_strides)


__all__ = ['frame_rotation_rad', 'map_alignment_for', 'MapAlignment', 'rotate_error_covariance',
           'rotation_z']
