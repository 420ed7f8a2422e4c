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
Heading aids of the ZUPT filter: heuristic drift elimination (HDE) and zero angular rate (ZARU).

A ZUPT observes velocity only: the heading and the z-gyro bias are unobservable and drift.
Two pseudo-measurements bound them where their assumption holds:

HDE, once per stride: buildings are built along a few dominant directions d_i (modulo 90
deg), and people walk along them. When the stride's direction psi_s, from the positions of
the stances at its ends, is within a tolerance of one and of the directions of the strides
before it (walking straight, not through a curve or a slalom that crosses d), the heading
error is measured as dpsi = d - psi_s (the stride was along d, the filter's heading is off by
-dpsi). With the error state true = estimate + error and C_nb,true = (I + [dphi x]) C_nb,est,
a yaw error dphi_z turns the whole track by dphi_z, so y = d - psi_s, H = [0 0 0 e_z 0]
(dphi_z), R = sigma^2. The directions come from the building file (``dominant_directions_deg``),
or are learned from the walk: the first stride's direction modulo 90 deg.

ZARU, at every stance sample while the foot stands still (every |w| of the detector window
below a bound): the gyro reads its bias, y = w - b_g, H = [0 0 0 0 I3], R = sigma^2 I3
(``ekf.zaru_correction``, applied in the navigator's compiled step; here only its
parameters). Over a whole stand it learns the bias that the 0.1 s start-up stance of a
swaying foot gets wrong, and takes back the heading the wrong bias turned meanwhile.

References
----------
[1] J. Borenstein, L. Ojeda, "Heuristic drift elimination for personnel tracking systems",
    J. Navigation 63(4), 2010.
[2] A. R. Jimenez, F. Seco, J. C. Prieto, J. Guevara, "Improved heuristic drift elimination
    (iHDE) for pedestrian navigation in complex buildings", IPIN 2011.
[3] I. Skog, J.-O. Nilsson, P. Handel, "Pedestrian tracking using an IMU array", IEEE
    CONECCT 2014 (zero angular rate updates).

"""

from collections import deque
from dataclasses import dataclass
import math

import numpy as np

from . import ekf
from .validation import check_range

QUARTER_TURN_RAD = 0.5 * math.pi


@dataclass(frozen=True)
class HeadingAidParams:
    """
    Parameters of the heading aids.

    Attributes
    ----------
    hde_enabled : apply heuristic drift elimination at every stride.
    hde_tolerance_deg : a stride within this of a dominant direction is taken to be along it.
    hde_sigma_deg : standard deviation of the HDE heading measurement, deg.
    hde_straight_strides : strides before this one whose directions must agree with it within
        the tolerance (a straight walk, not a curve or a slalom).
    zaru_enabled : apply a zero angular rate update at every still stance sample.
    zaru_max_gyr_rps : the stance is still when no |w| of the detector window exceeds this.
    zaru_sigma_rps : standard deviation of the ZARU measurement of one sample, rad/s (a
        standing foot sways by 1-2 deg/s).
    min_stride_m : shorter strides (turning on the spot) have no direction for HDE.

    """

    hde_enabled: bool = True
    hde_tolerance_deg: float = 4.0
    hde_sigma_deg: float = 2.0
    hde_straight_strides: int = 2
    zaru_enabled: bool = True
    zaru_max_gyr_rps: float = 0.02
    zaru_sigma_rps: float = 0.02
    min_stride_m: float = 0.3

    def __post_init__(self):
        for name, low, high in (('hde_tolerance_deg', 0.5, 45.0), ('hde_sigma_deg', 0.01, 90.0),
                                ('zaru_max_gyr_rps', 1e-4, 1.0), ('zaru_sigma_rps', 1e-6, 1.0),
                                ('hde_straight_strides', 1, 20), ('min_stride_m', 0.05, 2.0)):
            check_range(name, getattr(self, name), low, high)


def direction_offset(heading_rad: float, directions_rad) -> float:
    """
    Signed offset of a heading from the nearest dominant direction, rad, in [-45, 45) deg.

    delta = min over i of wrap(psi - d_i) with wrap to [-pi/4, pi/4) (directions modulo 90 deg).
    """
    offsets = [(heading_rad - d + 0.5 * QUARTER_TURN_RAD) % QUARTER_TURN_RAD
               - 0.5 * QUARTER_TURN_RAD for d in directions_rad]
    return min(offsets, key=abs)


def linear_correction(P: np.ndarray, H: np.ndarray, innovation: np.ndarray, R: np.ndarray):
    """
    Kalman update of the error state by a linear measurement, Joseph form.

    S = H P H^T + R, K = P H^T S^-1, dx = K y, P+ = (I - K H) P (I - K H)^T + K R K^T.

    Returns
    -------
    dx : (15,) estimated error state; P : updated covariance; nis : y^T S^-1 y.

    """
    S_inv = np.linalg.inv(H @ P @ H.T + R)
    K = P @ H.T @ S_inv
    A = np.eye(P.shape[0]) - K @ H
    P = A @ P @ A.T + K @ R @ K.T
    return K @ innovation, 0.5 * (P + P.T), float(innovation @ S_inv @ innovation)


def hde_correction(P: np.ndarray, innovation_rad: float, sigma_rad: float):
    """
    HDE heading measurement: y = d - psi_s, H = [0 0 0 e_z 0] (yaw error dphi_z), R = sigma^2.

    Returns ``linear_correction``'s (dx, P, nis).
    """
    H = np.zeros((1, ekf.N_STATES))
    H[0, ekf.ATT.start + 2] = 1.0
    return linear_correction(P, H, np.array([innovation_rad]), np.array([[sigma_rad ** 2]]))


def hde_directions_deg(building, in_map_frame: bool):
    """
    Return the building's dominant directions for HDE, or None to learn them from the walk.

    The directions are in the building's frame: they hold only when the track is in it (a
    building with a ``start``, ``core/map_frame.py``).
    """
    if building is None or not in_map_frame or not building.dominant_directions_deg:
        return None
    return tuple(building.dominant_directions_deg)


class HeadingAider:
    """
    When and with what the heading aids apply, stride by stride (state: the last stance).

    ``at_stance(pos_n, P)`` is called at the stance that closes each stride, with the
    filter-frame position; it returns the (dx, P) of HDE when it applies.
    ``directions_rad`` are the dominant directions in the filter frame, or None to learn them
    from the first stride. Counts of applied updates are kept for diagnostics.
    """

    def __init__(self, params: HeadingAidParams, directions_rad=None):
        self.params = params
        self.directions_rad = None if directions_rad is None else list(directions_rad)
        self.last_pos_n = None
        self.recent_headings_rad = deque(maxlen=params.hde_straight_strides + 1)
        self.hde_updates = 0

    def at_stance(self, pos_n, P):
        """Return the list of (dx, P) to apply now (HDE's, when it applies)."""
        if not self.params.hde_enabled:
            return []
        correction = self._hde(np.array(pos_n[:2], dtype=float), P)
        return [] if correction is None else [correction]

    def _hde(self, pos_xy, P):
        last, self.last_pos_n = self.last_pos_n, pos_xy
        if last is None:
            return None
        step = pos_xy - last
        if np.hypot(*step) < self.params.min_stride_m:
            self.last_pos_n = last       # turning on the spot: measure from the old stance
            return None
        heading = math.atan2(step[1], step[0])
        recent = self.recent_headings_rad
        recent.append(heading)
        if self.directions_rad is None:
            self.directions_rad = [heading % QUARTER_TURN_RAD]
            return None
        tolerance = math.radians(self.params.hde_tolerance_deg)
        offset = direction_offset(heading, self.directions_rad)
        # Along a direction and straight on from the strides before: not a curve or a slalom.
        if abs(offset) > tolerance or len(recent) < recent.maxlen or any(
                abs(math.remainder(heading - h, 2.0 * math.pi)) > tolerance for h in recent):
            return None
        dx, P, _ = hde_correction(P, -offset, math.radians(self.params.hde_sigma_deg))
        self.hde_updates += 1
        return dx, P
