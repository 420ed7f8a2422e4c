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
Gait-cycle segmentation and features, patent CN111649742A step S4, eq. (8)-(12).

A gait cycle runs from the last stance sample before a swing to the first stance sample
after it (the sample that closes the cycle). With h_j the EKF-corrected foot height of swing
sample j relative to the stance height h_0 of the stance the swing left, j = 1..n (the
closing sample included), the five features are

    (8)  mean height       m_h  = 1/n sum_j h_j
    (9)  height spread     s_h  = sqrt(1/n sum_j (h_j - m_h)^2)
    (10) height change     dh   = h_n                       (end minus start)
    (11) max height excursion   max_j |h_j|
    (12) max pitch         max_j (theta_j - theta_0)

h_n is the closing sample's height with its landing ZUPT's height correction kept to the part
the swing's own vertical velocity error explains (:func:`landing_height_correction`): the rest
takes back height error from before the swing, which no stride climbed.

where theta is the inclination of the foot's forward axis above the horizontal (toe up
positive), so the pitch is relative to the stance attitude and a tilted mounting cannot bias
it. The foot's forward axis in the IMU frame comes from a mounting rotation, or (automatic
mode) from the direction of the first strides.

After these five, every cycle carries the eleven motion features of ``core/motion_features.py``
(specific force, angular rate and horizontal speed over the same samples, in the foot frame):
:data:`FEATURE_NAMES` lists all sixteen. Code reads a feature by its name
(:func:`feature_index`), never by a raw position.
"""

from dataclasses import dataclass
import math

import numpy as np

from .errors import InputError
from .motion_features import foot_frame, MOTION_FEATURE_NAMES, motion_features
from .validation import check_range

PATENT_FEATURE_NAMES = ('mean_height_m', 'std_height_m', 'height_change_m', 'max_abs_height_m',
                        'max_pitch_rad')
"""Eq. (8)-(12), the ANFIS inputs of the patent."""
FEATURE_NAMES = PATENT_FEATURE_NAMES + MOTION_FEATURE_NAMES
"""Every feature of a gait cycle, in ``GaitCycle.features`` order."""
N_FEATURES = len(FEATURE_NAMES)


def feature_index(names) -> np.ndarray:
    """
    Positions of named features in :data:`FEATURE_NAMES` (for column selection).

    Raises
    ------
    InputError : a name that is not a gait-cycle feature.

    """
    unknown = [name for name in names if name not in FEATURE_NAMES]
    if unknown:
        raise InputError(f'unknown gait-cycle feature(s) {unknown}; known: '
                         f'{", ".join(FEATURE_NAMES)}')
    return np.array([FEATURE_NAMES.index(name) for name in names], dtype=np.int64)


HEIGHT_CHANGE = FEATURE_NAMES.index('height_change_m')


@dataclass(frozen=True)
class GaitParams:
    """
    Gait-cycle segmentation parameters.

    Attributes
    ----------
    min_swing_s : shorter swings (detector flicker, shuffles) do not make a gait cycle.
    max_swing_s : longer swings (crawling, ladders, a foot never at rest) make an invalid cycle.
    min_stride_m : horizontal stride length below which a stride says nothing of the foot's
        forward axis (turning on the spot).
    mounting_strides : strides averaged by the automatic mounting mode.

    """

    min_swing_s: float = 0.15
    max_swing_s: float = 2.5
    min_stride_m: float = 0.3
    mounting_strides: int = 5

    def __post_init__(self):
        if not 0.02 <= self.min_swing_s < self.max_swing_s <= 10.0:
            raise InputError(f'need 0.02 <= min_swing_s ({self.min_swing_s}) < max_swing_s '
                             f'({self.max_swing_s}) <= 10 s')
        check_range('min_stride_m', self.min_stride_m, 0.05, 2.0)
        check_range('mounting_strides', self.mounting_strides, 1, 100)


@dataclass(frozen=True)
class GaitCycle:
    """
    One gait cycle, as the IMU node publishes it.

    Attributes
    ----------
    stamp_ns : stamp of the first stance sample that closes the cycle.
    start_stamp_ns : stamp of the last stance sample before the swing.
    pos_n : (3,) EKF-corrected position at the closing sample, m, ENU.
    features : (16,) eq. (8)-(12) and the motion features, in FEATURE_NAMES order.
    valid : False when the swing was too long or had a gap in its samples; such a cycle's
        features describe no stride and are not classified.

    """

    stamp_ns: int
    start_stamp_ns: int
    pos_n: np.ndarray
    features: np.ndarray
    valid: bool

    @property
    def height_change_m(self) -> float:
        """Raw EKF height change over the cycle, eq. (10) with the landing's (10a)."""
        return float(self.features[HEIGHT_CHANGE])


def height_features(height_m: np.ndarray) -> np.ndarray:
    """
    Height features eq. (8)-(11) of one cycle.

    Parameters
    ----------
    height_m : (n,) array
        Foot height of each swing sample and of the closing stance sample,
        relative to the stance height h_0, m.

    Returns
    -------
    (4,) [mean, std, end minus start, max |h|], m.

    """
    return np.array([height_m.mean(), height_m.std(), height_m[-1], np.abs(height_m).max()])


def landing_height_correction(dpos_z_m: float, dvel_z_mps: float, swing_s: float) -> float:
    """
    Return the part of a landing ZUPT's height correction its swing explains, eq. (10a).

        delta_h = clip(delta_p_z, -|delta_v_z| T, |delta_v_z| T)

    with delta_p_z and delta_v_z the ZUPT's corrections of height and vertical velocity at the
    sample that closes a swing of duration T. A vertical velocity error no larger than the one
    the ZUPT measured there, held over the whole swing, moves the foot by at most |delta_v_z| T.
    The rest of delta_p_z is height error from before the swing that the covariance's
    correlations take back now (a consumer IMU's misalignment made observable by a stand and
    turns on the spot): a correction of the absolute height, not a climb of this stride.
    """
    bound = abs(dvel_z_mps) * swing_s
    return min(max(dpos_z_m, -bound), bound)


def foot_inclination(up_b: np.ndarray, forward_b: np.ndarray) -> np.ndarray:
    """
    Inclination of the foot's forward axis above the horizontal, rad (toe up positive).

    theta = asin(f_b . u_b), with u_b the navigation up axis seen in the body frame
    (the third row of C_nb) and f_b the unit forward axis of the foot in the body frame.

    Parameters
    ----------
    up_b : (..., 3) array
        Up axis in the body frame at each sample.
    forward_b : (3,) array
        Foot forward axis in the body frame.

    """
    return np.arcsin(np.clip(up_b @ forward_b, -1.0, 1.0))


def max_relative_pitch(up_b: np.ndarray, up_b_stance: np.ndarray,
                       forward_b: np.ndarray) -> float:
    """Max pitch during the swing relative to the stance attitude, eq. (12), rad."""
    return float(np.max(foot_inclination(up_b, forward_b))
                 - foot_inclination(up_b_stance, forward_b))


def slope(displacement_n: np.ndarray) -> float:
    """Return a stride's slope |dh| / run, its height change over its horizontal length."""
    return abs(displacement_n[2]) / max(1e-9, math.hypot(displacement_n[0], displacement_n[1]))


def horizontal_direction_b(displacement_n: np.ndarray, C_nb: np.ndarray):
    """
    Return the unit horizontal direction of a displacement in the body frame, or None.

    The navigation-frame displacement with its vertical part removed is rotated into the body
    frame, d_b = C_nb^T d_h; None when it is shorter than 1 mm.
    """
    d_h = np.array([displacement_n[0], displacement_n[1], 0.0])
    norm = math.hypot(d_h[0], d_h[1])
    return None if norm < 1e-3 else C_nb.T @ d_h / norm


class MountingEstimator:
    """
    Foot forward axis in the IMU frame: given, or learnt from the first strides.

    Automatic mode averages the horizontal direction of the first ``mounting_strides``
    strides longer than ``min_stride_m``, each seen in the body frame of the stance it left;
    until then each cycle uses its own direction. A firefighter walks forwards when starting,
    so the average is the foot's forward axis.
    """

    def __init__(self, params: GaitParams, C_fb: np.ndarray = None):
        self._params = params
        self._sum_b = np.zeros(3)
        self._count = 0
        self.forward_b = None if C_fb is None else C_fb[0, :].copy()
        self.fixed = C_fb is not None

    def forward_for_cycle(self, stride_n: np.ndarray, C_nb_stance: np.ndarray):
        """Forward axis to use for this cycle's pitch (learning from it in automatic mode)."""
        if self.fixed:
            return self.forward_b
        direction_b = horizontal_direction_b(stride_n, C_nb_stance)
        if math.hypot(stride_n[0], stride_n[1]) < self._params.min_stride_m:
            # Too short to learn from; until an axis is learnt it is still the best guess.
            return direction_b if self.forward_b is None else self.forward_b
        self._sum_b += direction_b
        self._count += 1
        if self._count >= self._params.mounting_strides:
            self.forward_b = self._sum_b / np.linalg.norm(self._sum_b)
            self.fixed = True
            return self.forward_b
        return direction_b


class GaitSegmenter:
    """
    Cuts the corrected track into gait cycles and computes their features, sample by sample.

    ``update`` takes each navigated sample and returns a ``GaitCycle`` on the sample that
    closes one, else None. Memory is bounded: a swing longer than ``max_swing_s`` stops
    collecting samples and yields an invalid cycle.
    """

    def __init__(self, params: GaitParams, rate_hz: float, mounting: MountingEstimator):
        self._params = params
        self._mounting = mounting
        self._max_samples = int(params.max_swing_s * rate_hz) + 2
        self._in_swing = False
        self._stance_stamp_ns = None
        self._stance_pos_n = None
        self._stance_C_nb = None
        self._up_b = []
        self._motion = []
        self._stamps_ns = []
        self._positions = []
        self._attitudes = []
        self._gap = False
        self._last_slope = 0.0         # |dh| / run of the last cycle closed

    def update(self, stamp_ns: int, stance: bool, pos_n: np.ndarray, C_nb: np.ndarray,
               acc_b: np.ndarray, gyr_b: np.ndarray, vel_n: np.ndarray, gap: bool = False,
               zupt_dx: np.ndarray = None):
        """
        Add one navigated sample; return the GaitCycle it closes, or None.

        Parameters
        ----------
        stamp_ns : int
            Sample stamp.
        stance : bool
            Zero-velocity decision for the sample.
        pos_n : (3,) array
            Corrected position, m.
        C_nb : (3, 3) array
            Corrected attitude.
        acc_b, gyr_b : (3,) arrays
            The sample's specific force (m/s^2) and angular rate (rad/s).
        vel_n : (3,) array
            Corrected velocity, m/s.
        gap : bool
            True when samples are missing before this one.
        zupt_dx : (6,) array or None
            The sample's ZUPT correction of position (m) and velocity (m/s), None for none.

        """
        if stance and not self._in_swing:
            self._stance_stamp_ns, self._stance_pos_n, self._stance_C_nb = stamp_ns, pos_n, C_nb
            return None
        if self._stance_pos_n is None:
            return None
        if not self._in_swing:
            self._in_swing = True
            for values in self._held():
                values.clear()
            self._gap = False
        self._gap = self._gap or gap
        if len(self._stamps_ns) < self._max_samples:
            self._up_b.append(C_nb[2, :])
            self._motion.append(np.concatenate((acc_b, gyr_b, vel_n)))
            self._stamps_ns.append(stamp_ns)
            self._positions.append(pos_n)
            self._attitudes.append(C_nb)
        if not stance:
            return None
        self._in_swing = False
        cycle = self._close(stamp_ns, pos_n, zupt_dx)
        self._stance_stamp_ns, self._stance_pos_n, self._stance_C_nb = stamp_ns, pos_n, C_nb
        return cycle

    def late_stance(self, age: int, dpos_n: np.ndarray, dvel_n: np.ndarray,
                    max_slope: float):
        """
        Take a stance found after the fact, ``age`` samples ago; return the cycle it closes.

        Its ZUPT, applied at the last sample, corrected the position by ``dpos_n`` and the
        velocity by ``dvel_n``; with the velocity error constant since the late stance, sample j
        is corrected by dpos_n - dvel_n (t_last - t_j) in position and dvel_n in velocity (the
        last sample's are already). The stance closes the cycle when the foot reached it along
        a slope |dh| / run of at most ``max_slope`` and the cycle before also kept to it (level
        ground, a ramp): the samples after it begin the next swing. Elsewhere (on stairs and
        where they end) the cycle runs on to the next stance: the stair classifier calls
        HuGaDB's stair strides cut at late stances level (doc/hallway_notebook.md,
        "Late stances"). Returns the GaitCycle or None (not cut; outside a swing; a swing that
        has outgrown the samples held, whose cycle will be invalid; or a cut part too short to
        be a stride).
        """
        end = len(self._stamps_ns) - 1 - int(age)
        if not self._in_swing or end < 0 or len(self._stamps_ns) >= self._max_samples:
            return None
        last_ns = self._stamps_ns[-1]
        for j in range(end, len(self._stamps_ns) - 1):
            correction = dpos_n - dvel_n * ((last_ns - self._stamps_ns[j]) * 1e-9)
            self._positions[j] = self._positions[j] + correction
            self._motion[j] = np.concatenate((self._motion[j][:6], self._motion[j][6:] + dvel_n))
        stamp_ns, pos_n, C_nb = self._stamps_ns[end], self._positions[end], self._attitudes[end]
        if not (slope(pos_n - self._stance_pos_n) <= max_slope
                and self._last_slope <= max_slope):
            return None
        after = slice(end + 1, None)
        held = [values[after] for values in self._held()]
        for values in self._held():
            del values[after]
        cycle = self._close(stamp_ns, pos_n)
        self._stance_stamp_ns, self._stance_pos_n, self._stance_C_nb = stamp_ns, pos_n, C_nb
        self._up_b, self._motion, self._stamps_ns, self._positions, self._attitudes = held
        return cycle

    def _held(self):
        """Return the per-sample lists of the swing."""
        return self._up_b, self._motion, self._stamps_ns, self._positions, self._attitudes

    def _close(self, stamp_ns, pos_n, zupt_dx=None):
        """Close the cycle at the sample held last, whose ZUPT corrected it by ``zupt_dx``."""
        swing_s = (stamp_ns - self._stance_stamp_ns) * 1e-9
        if swing_s < self._params.min_swing_s:
            return None
        features = np.empty(N_FEATURES)
        # Heights above the stance, from the swing's positions (a late stance corrects them).
        heights_m = np.asarray(self._positions)[:, 2] - self._stance_pos_n[2]
        if zupt_dx is not None:
            heights_m[-1] -= zupt_dx[2] - landing_height_correction(
                zupt_dx[2], zupt_dx[5], swing_s)
        features[:4] = height_features(heights_m)
        stride_n = pos_n - self._stance_pos_n
        self._last_slope = slope(np.array([stride_n[0], stride_n[1], heights_m[-1]]))
        forward_b = self._mounting.forward_for_cycle(stride_n, self._stance_C_nb)
        if forward_b is None:
            # Not a single stride yet: the stance's most horizontal body axis stands in.
            up_b = self._stance_C_nb[2, :]
            forward_b = np.eye(3)[int(np.argmin(np.abs(up_b)))]
        features[4] = max_relative_pitch(np.asarray(self._up_b), self._stance_C_nb[2, :],
                                         forward_b)
        if abs(forward_b @ self._stance_C_nb[2, :]) > 0.99:
            # A given forward axis all but vertical at this stance (a foot on a ladder) spans
            # no foot frame: the stance's most horizontal body axis stands in.
            forward_b = np.eye(3)[int(np.argmin(np.abs(self._stance_C_nb[2, :])))]
        motion = np.asarray(self._motion)
        features[len(PATENT_FEATURE_NAMES):] = motion_features(
            motion[:, 0:3], motion[:, 3:6], motion[:, 6:9],
            foot_frame(self._stance_C_nb[2, :], forward_b))
        valid = swing_s <= self._params.max_swing_s and not self._gap
        return GaitCycle(stamp_ns, self._stance_stamp_ns, pos_n.copy(), features, valid)
