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
Zero-velocity detection with the SHOE statistic, patent CN111649742A step S2, eq. (4).

The statistic of a window of W samples ending at sample k (a trailing window, so the live
node decides on a sample as soon as it arrives) is

    T_k = 1/W sum_j [ ||a_j - g abar/||abar|| ||^2 / sigma_a^2 + ||w_j||^2 / sigma_w^2 ]

and sample k is a stance sample when T_k < gamma. ``shoe_statistic`` evaluates it directly
over any stack of windows; ``ShoeDetector`` evaluates the same equation per sample from
running sums over a ring buffer, using the exact rearrangement

    sum_j ||a_j - g u||^2 = sum_j ||a_j||^2 - 2 g W ||abar|| + W g^2,   u = abar / ||abar||.

References
----------
[1] I. Skog, P. Handel, J.-O. Nilsson, J. Rantakokko, "Zero-velocity detection - an algorithm
    evaluation", IEEE Trans. Biomed. Eng. 57(11), 2010 (the SHOE detector).
[2] B. Wagstaff, V. Peretroukhin, J. Kelly, "Robust data-driven zero-velocity detection for
    foot-mounted inertial navigation", IEEE Sensors J. 20(2), 2020 (the pyshoe reference).

"""

from collections import deque
from dataclasses import dataclass
import math

import numpy as np

from .errors import InputError
from .frames import GRAVITY_MPS2

REBUILD_SAMPLES = 256
"""About how often ShoeDetector recomputes its running sums from its buffer, samples."""


@dataclass(frozen=True)
class ZuptParams:
    """
    Parameters of the SHOE zero-velocity detector.

    Attributes
    ----------
    window_s : window length, s (W = round(window_s * rate), at least 3 samples).
    threshold : gamma_0, dimensionless; a sample is stance when T_k < gamma. With
        ``adaptive`` it is the threshold at the reference intensity, else the fixed gamma.
    sigma_acc_mps2 : accelerometer noise scale sigma_a of eq. (4), m/s^2.
    sigma_gyr_rps : gyroscope noise scale sigma_w of eq. (4), rad/s.
    adaptive : scale gamma with the gait's intensity (see ``adaptive_threshold``).
    ref_peak_gyr_rps : intensity m_0 at which gamma = gamma_0, rad/s.
    intensity_exponent : p in gamma = gamma_0 (m / m_0)^p.
    min_threshold, max_threshold : bounds of the adaptive gamma.
    min_stance_s : a stance counts only after T_k < gamma held this long (a foot that moves at
        constant velocity without turning looks still to an IMU for an instant; a real
        stance lasts 0.1 s or more).
    intensity_block_s : block over which the peak angular rate is taken, s.
    intensity_blocks : blocks whose median peak is the intensity m.

    Notes
    -----
    sigma_a and sigma_w only weight the two terms; gamma scales with 1/sigma^2. The defaults
    are (rounded) those pyshoe uses on its VICON data (sigma_a = 0.00098 m/s^2,
    sigma_w = 0.005 deg/s), so thresholds compare with its published ones; the window is
    pyshoe's 5 samples at 200 Hz, as a duration.

    """

    window_s: float = 0.025
    threshold: float = 1.2e7
    sigma_acc_mps2: float = 1.0e-3
    sigma_gyr_rps: float = math.radians(0.005)
    adaptive: bool = True
    ref_peak_gyr_rps: float = 6.0
    intensity_exponent: float = 4.4
    min_threshold: float = 3.0e6
    max_threshold: float = 2.0e8
    min_stance_s: float = 0.02
    intensity_block_s: float = 0.4
    intensity_blocks: int = 5

    def __post_init__(self):
        _check_range('window_s', self.window_s, 0.005, 0.5)
        _check_range('threshold', self.threshold, 1.0, 1e12)
        _check_range('sigma_acc_mps2', self.sigma_acc_mps2, 1e-5, 10.0)
        _check_range('sigma_gyr_rps', self.sigma_gyr_rps, 1e-6, 1.0)
        _check_range('ref_peak_gyr_rps', self.ref_peak_gyr_rps, 0.5, 30.0)
        _check_range('intensity_exponent', self.intensity_exponent, 0.0, 10.0)
        _check_range('min_threshold', self.min_threshold, 1.0, self.max_threshold)
        _check_range('max_threshold', self.max_threshold, self.min_threshold, 1e13)
        _check_range('min_stance_s', self.min_stance_s, 0.0, 0.5)
        _check_range('intensity_block_s', self.intensity_block_s, 0.2, 10.0)
        _check_range('intensity_blocks', self.intensity_blocks, 1, 60)

    def window_samples(self, rate_hz: float) -> int:
        """Window length W in samples at a sample rate."""
        return max(3, int(round(self.window_s * rate_hz)))

    def min_stance_samples(self, rate_hz: float) -> int:
        """Consecutive still samples before a stance counts, at a sample rate (at least 1)."""
        return max(1, int(round(self.min_stance_s * rate_hz)))


def _check_range(name, value, low, high):
    if not low <= value <= high:
        raise InputError(f'{name} = {value} is outside [{low}, {high}]')


def shoe_statistic(acc_b: np.ndarray, gyr_b: np.ndarray, sigma_acc_mps2: float,
                   sigma_gyr_rps: float, gravity_mps2: float = GRAVITY_MPS2) -> np.ndarray:
    """
    SHOE statistic of windows of samples, eq. (4).

    T = 1/W sum_j [ ||a_j - g abar/||abar|| ||^2 / sigma_a^2 + ||w_j||^2 / sigma_w^2 ]

    Parameters
    ----------
    acc_b : (..., W, 3) array
        Specific force of each window, m/s^2.
    gyr_b : (..., W, 3) array
        Angular rate of each window, rad/s.
    sigma_acc_mps2, sigma_gyr_rps : float
        Noise scales sigma_a, sigma_w.
    gravity_mps2 : float
        Gravity magnitude g, m/s^2.

    Returns
    -------
    (...,) the statistic of each window.

    """
    acc_mean = acc_b.mean(axis=-2, keepdims=True)
    up_b = acc_mean / np.linalg.norm(acc_mean, axis=-1, keepdims=True)
    acc_term = np.sum((acc_b - gravity_mps2 * up_b) ** 2, axis=(-2, -1)) / sigma_acc_mps2 ** 2
    gyr_term = np.sum(gyr_b ** 2, axis=(-2, -1)) / sigma_gyr_rps ** 2
    return (acc_term + gyr_term) / acc_b.shape[-2]


def shoe_statistic_trailing(acc_b: np.ndarray, gyr_b: np.ndarray, window: int,
                            sigma_acc_mps2: float, sigma_gyr_rps: float,
                            gravity_mps2: float = GRAVITY_MPS2) -> np.ndarray:
    """
    SHOE statistic of the trailing window ending at each sample (NaN for the first W-1).

    Parameters
    ----------
    acc_b, gyr_b : (N, 3) array
        Samples.
    window : int
        W, samples.
    sigma_acc_mps2, sigma_gyr_rps : float
        Noise scales sigma_a, sigma_w.
    gravity_mps2 : float
        Gravity magnitude g, m/s^2.

    Returns
    -------
    (N,) T_k of the window [k - W + 1, k].

    """
    view = np.lib.stride_tricks.sliding_window_view
    stat = np.full(len(acc_b), np.nan)
    stat[window - 1:] = shoe_statistic(
        view(acc_b, window, axis=0).swapaxes(-1, -2), view(gyr_b, window, axis=0).swapaxes(-1, -2),
        sigma_acc_mps2, sigma_gyr_rps, gravity_mps2)
    return stat


def adaptive_threshold(peak_gyr_rps: float, params: ZuptParams) -> float:
    """
    Threshold for the gait's intensity: gamma = clip(gamma_0 (m / m_0)^p, gamma_min, gamma_max).

    m is the median of the peak angular-rate magnitudes of the last blocks. A faster gait never
    stops the foot as completely, so its stance statistic stays higher: on the 36 pyshoe
    VICON trials the per-trial optimal gamma grows with m as m^4.4 (log-log correlation
    0.86), from slow walking (m = 3 rad/s, gamma about 1e6) to running (m = 11 rad/s, 1e8).
    Peak specific force predicts as well there, but heel-strike spikes depend on the sensor
    and its mounting (a NilsPod on the instep saturates at 16 g): the rate is steadier.
    gamma_max = 2e8 keeps a gyro that reads spikes past 20 rad/s (x-io, 256 Hz) from
    declaring whole swings stance; gamma_min = 3e6 keeps the first strides after a stand from
    losing their stances. The block length and count (0.4 s, 5) and the bounds were chosen on
    the same 36 trials, checked on the MaD and x-io stairs (README, accuracy).
    """
    gamma = params.threshold * (peak_gyr_rps / params.ref_peak_gyr_rps) ** \
        params.intensity_exponent
    return min(max(gamma, params.min_threshold), params.max_threshold)


class GaitIntensity:
    """
    Median peak |angular rate| of the last blocks, the m of adaptive_threshold.

    Blocks of fixed duration, not swings, so the measure does not depend on the detector it
    steers (a run that starts fast would otherwise never leave the start threshold). It rises
    at once with a faster sample and falls only with the median of completed blocks: the
    first strides after a stand are the ones a low threshold would miss.
    """

    def __init__(self, params: ZuptParams, rate_hz: float):
        self._peaks = deque(maxlen=params.intensity_blocks)
        self._block_samples = max(1, int(round(params.intensity_block_s * rate_hz)))
        self._count = 0
        self._block_peak = 0.0
        self.value = params.ref_peak_gyr_rps

    def update(self, gyr_norm_rps: float) -> bool:
        """Add a sample's |w|; return True when the intensity m changed."""
        changed = False
        if gyr_norm_rps > self._block_peak:
            self._block_peak = gyr_norm_rps
            if gyr_norm_rps > self.value:
                self.value = gyr_norm_rps
                changed = True
        self._count += 1
        if self._count < self._block_samples:
            return changed
        self._peaks.append(self._block_peak)
        self._count = 0
        self._block_peak = 0.0
        self.value = float(np.median(self._peaks))
        return True


class ShoeDetector:
    """
    Per-sample SHOE detector over a trailing window, eq. (4) from running sums.

    ``update(acc_b, gyr_b)`` returns T_k of the window ending at the new sample, or None while
    the first window fills. The sums are rebuilt from the ring buffer every ``REBUILD_SAMPLES``
    or so (a whole number of windows), so rounding errors cannot accumulate over a long
    shift. ``gravity_mps2`` is the g of eq. (4); the navigator sets it to the magnitude the
    sensor reads at rest, so that an accelerometer scale or bias error along gravity does not
    lift the statistic of every stance.
    """

    def __init__(self, params: ZuptParams, rate_hz: float, gravity_mps2: float = GRAVITY_MPS2):
        self.params = params
        self.window = params.window_samples(rate_hz)
        self._inv_var_acc = 1.0 / params.sigma_acc_mps2 ** 2
        self._inv_var_gyr = 1.0 / params.sigma_gyr_rps ** 2
        self.gravity_mps2 = gravity_mps2
        self._acc = np.zeros((self.window, 3))
        self._gyr = np.zeros((self.window, 3))
        self._count = 0
        self._rebuild_period = self.window * max(1, REBUILD_SAMPLES // self.window)
        self._sum_acc = [0.0, 0.0, 0.0]
        self._sum_acc_sq = 0.0
        self._sum_gyr_sq = 0.0

    def update(self, acc_b: np.ndarray, gyr_b: np.ndarray):
        """Add a sample; return T_k of the trailing window, or None before it is full."""
        i = self._count % self.window
        ax, ay, az = acc_b.tolist()
        gx, gy, gz = gyr_b.tolist()
        old_ax, old_ay, old_az = self._acc[i].tolist()
        old_gx, old_gy, old_gz = self._gyr[i].tolist()
        self._sum_acc[0] += ax - old_ax
        self._sum_acc[1] += ay - old_ay
        self._sum_acc[2] += az - old_az
        self._sum_acc_sq += (ax * ax + ay * ay + az * az
                             - old_ax * old_ax - old_ay * old_ay - old_az * old_az)
        self._sum_gyr_sq += (gx * gx + gy * gy + gz * gz
                             - old_gx * old_gx - old_gy * old_gy - old_gz * old_gz)
        self._acc[i] = acc_b
        self._gyr[i] = gyr_b
        self._count += 1
        if self._count % self._rebuild_period == 0:
            self._sum_acc = self._acc.sum(axis=0).tolist()
            self._sum_acc_sq = float(np.sum(self._acc ** 2))
            self._sum_gyr_sq = float(np.sum(self._gyr ** 2))
        if self._count < self.window:
            return None
        w = self.window
        sx, sy, sz = self._sum_acc
        norm_mean_acc = math.sqrt(sx * sx + sy * sy + sz * sz) / w
        g = self.gravity_mps2
        acc_term = self._sum_acc_sq - 2.0 * g * w * norm_mean_acc + w * g * g
        return (acc_term * self._inv_var_acc + self._sum_gyr_sq * self._inv_var_gyr) / w

    def mean_acc(self) -> np.ndarray:
        """Return the mean specific force over the window, a-bar of eq. (4), m/s^2."""
        return np.array(self._sum_acc) / self.window
