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

from dataclasses import dataclass
import math

import numpy as np

from . import ekf
from .frames import GRAVITY_MPS2
from .jit import jit
from .validation import check_range

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
    young_stance_s, young_stance_max_nis : a stance younger than ``young_stance_s`` whose
        ZUPT innovation is implausible (NIS above ``young_stance_max_nis``) gets no ZUPT yet
        (``young_stance_waits``); 0 turns the rule off.
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
    young_stance_s: float = 0.075
    young_stance_max_nis: float = 600.0
    intensity_block_s: float = 0.4
    intensity_blocks: int = 5

    def __post_init__(self):
        check_range('window_s', self.window_s, 0.005, 0.5)
        check_range('threshold', self.threshold, 1.0, 1e12)
        check_range('sigma_acc_mps2', self.sigma_acc_mps2, 1e-5, 10.0)
        check_range('sigma_gyr_rps', self.sigma_gyr_rps, 1e-6, 1.0)
        check_range('ref_peak_gyr_rps', self.ref_peak_gyr_rps, 0.5, 30.0)
        check_range('intensity_exponent', self.intensity_exponent, 0.0, 10.0)
        check_range('min_threshold', self.min_threshold, 1.0, self.max_threshold)
        check_range('max_threshold', self.max_threshold, self.min_threshold, 1e13)
        check_range('min_stance_s', self.min_stance_s, 0.0, 0.5)
        check_range('young_stance_s', self.young_stance_s, 0.0, 0.5)
        check_range('young_stance_max_nis', self.young_stance_max_nis, 0.0, 1e12)
        check_range('intensity_block_s', self.intensity_block_s, 0.2, 10.0)
        check_range('intensity_blocks', self.intensity_blocks, 1, 60)

    def window_samples(self, rate_hz: float) -> int:
        """Window length W in samples at a sample rate."""
        return max(3, int(round(self.window_s * rate_hz)))

    def min_stance_samples(self, rate_hz: float) -> int:
        """Consecutive still samples before a stance counts, at a sample rate (at least 1)."""
        return max(1, int(round(self.min_stance_s * rate_hz)))

    def young_stance_samples(self, rate_hz: float) -> int:
        """Still samples before a stance is no longer young, at a sample rate (0: rule off)."""
        if self.young_stance_max_nis <= 0.0:
            return 0
        return int(round(self.young_stance_s * rate_hz))

    def threshold_law(self) -> tuple:
        """Return the arguments of ``adaptive_threshold`` after the intensity, in order."""
        return (self.threshold, self.ref_peak_gyr_rps, self.intensity_exponent,
                self.min_threshold, self.max_threshold)


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


@jit
def adaptive_threshold(peak_gyr_rps: float, threshold: float, ref_peak_gyr_rps: float,
                       intensity_exponent: float, min_threshold: float,
                       max_threshold: float) -> float:
    """
    Threshold for the gait's intensity: gamma = clip(gamma_0 (m / m_0)^p, gamma_min, gamma_max).

    m (``peak_gyr_rps``) is the median of the peak angular-rate magnitudes of the last blocks;
    gamma_0, m_0, p, gamma_min, gamma_max are the ``ZuptParams`` fields ``threshold``,
    ``ref_peak_gyr_rps``, ``intensity_exponent``, ``min_threshold``, ``max_threshold`` (pass
    ``*params.threshold_law()``). A faster gait never stops the foot as completely, so its
    stance statistic stays higher: on the 36 pyshoe VICON trials the per-trial optimal gamma
    grows with m as m^4.4 (log-log correlation 0.86), from slow walking (m = 3 rad/s, gamma
    about 1e6) to running (m = 11 rad/s, 1e8). Peak specific force predicts as well there, but
    heel-strike spikes depend on the sensor and its mounting (a NilsPod on the instep
    saturates at 16 g): the rate is steadier. gamma_max = 2e8 keeps a gyro that reads spikes
    past 20 rad/s (x-io, 256 Hz) from declaring whole swings stance; gamma_min = 3e6 keeps the
    first strides after a stand from losing their stances. The block length and count (0.4 s,
    5) and the bounds were chosen on the same 36 trials, checked on the MaD and x-io stairs
    (README, "Accuracy").
    """
    gamma = threshold * (peak_gyr_rps / ref_peak_gyr_rps) ** intensity_exponent
    return min(max(gamma, min_threshold), max_threshold)


@jit
def intensity_update(peaks: np.ndarray, state: np.ndarray, counts: np.ndarray,
                     gyr_norm_rps: float) -> bool:
    """
    Add a sample's |w| to the gait intensity (see ``GaitIntensity``); True when m changed.

    Parameters
    ----------
    peaks : (blocks,) array
        Ring of the peak |w| of the last completed blocks, rad/s.
    state : (2,) array
        [m, peak of the current block], rad/s.
    counts : (4,) int array
        [samples in the current block, samples per block, completed blocks, next ring slot].
    gyr_norm_rps : float
        |w| of the new sample.

    """
    changed = False
    if gyr_norm_rps > state[1]:
        state[1] = gyr_norm_rps
        if gyr_norm_rps > state[0]:
            state[0] = gyr_norm_rps
            changed = True
    counts[0] += 1
    if counts[0] < counts[1]:
        return changed
    peaks[counts[3]] = state[1]
    counts[3] = (counts[3] + 1) % len(peaks)
    counts[2] = min(counts[2] + 1, len(peaks))
    counts[0] = 0
    state[1] = 0.0
    state[0] = np.median(peaks[:counts[2]])
    return True


class GaitIntensity:
    """
    Median peak |angular rate| of the last blocks, the m of adaptive_threshold.

    Blocks of fixed duration, not swings, so the measure does not depend on the detector it
    steers (a run that starts fast would otherwise never leave the start threshold). It rises
    at once with a faster sample and falls only with the median of completed blocks: the
    first strides after a stand are the ones a low threshold would miss. The state lives in
    three arrays (``peaks``, ``state``, ``counts``) that the navigator's compiled step updates
    through ``intensity_update``, as ``update`` does.
    """

    def __init__(self, params: ZuptParams, rate_hz: float):
        self.peaks = np.zeros(params.intensity_blocks)
        self.state = np.array([params.ref_peak_gyr_rps, 0.0])
        block_samples = max(1, int(round(params.intensity_block_s * rate_hz)))
        self.counts = np.array([0, block_samples, 0, 0], dtype=np.int64)

    @property
    def value(self) -> float:
        """Return the intensity m, rad/s."""
        return float(self.state[0])

    def update(self, gyr_norm_rps: float) -> bool:
        """Add a sample's |w|; return True when the intensity m changed."""
        return intensity_update(self.peaks, self.state, self.counts, float(gyr_norm_rps))


@jit
def shoe_update(samples: np.ndarray, sums: np.ndarray, count: np.ndarray, config: np.ndarray,
                acc_b: np.ndarray, gyr_b: np.ndarray) -> float:
    """
    Add a sample to a trailing window and return its SHOE statistic T_k, eq. (4); NaN first.

    Running sums over the ring buffer, with
    sum_j ||a_j - g u||^2 = sum_j ||a_j||^2 - 2 g W ||abar|| + W g^2 (u = abar / ||abar||).

    Parameters
    ----------
    samples : (W, 6) array
        Ring buffer of [acc_b, gyr_b] of the window.
    sums : (5,) array
        [sum a_x, sum a_y, sum a_z, sum ||a||^2, sum ||w||^2] over the window.
    count : (1,) int array
        Samples added so far.
    config : (3,) array
        [g, 1 / sigma_a^2, 1 / sigma_w^2].
    acc_b, gyr_b : (3,) array
        The new sample, m/s^2 and rad/s.

    Returns
    -------
    T_k of the window ending at the new sample, or NaN while the first window fills.

    """
    w = samples.shape[0]
    i = count[0] % w
    ax, ay, az = acc_b[0], acc_b[1], acc_b[2]
    gx, gy, gz = gyr_b[0], gyr_b[1], gyr_b[2]
    old = samples[i]
    sums[0] += ax - old[0]
    sums[1] += ay - old[1]
    sums[2] += az - old[2]
    sums[3] += ax * ax + ay * ay + az * az - old[0] * old[0] - old[1] * old[1] - old[2] * old[2]
    sums[4] += gx * gx + gy * gy + gz * gz - old[3] * old[3] - old[4] * old[4] - old[5] * old[5]
    samples[i, 0], samples[i, 1], samples[i, 2] = ax, ay, az
    samples[i, 3], samples[i, 4], samples[i, 5] = gx, gy, gz
    count[0] += 1
    if count[0] % (w * max(1, REBUILD_SAMPLES // w)) == 0:
        # Rebuilt from the buffer now and then, so rounding cannot accumulate over a shift.
        sums[:] = 0.0
        for j in range(w):
            sums[0] += samples[j, 0]
            sums[1] += samples[j, 1]
            sums[2] += samples[j, 2]
            sums[3] += samples[j, 0] ** 2 + samples[j, 1] ** 2 + samples[j, 2] ** 2
            sums[4] += samples[j, 3] ** 2 + samples[j, 4] ** 2 + samples[j, 5] ** 2
    if count[0] < w:
        return np.nan
    g = config[0]
    norm_mean_acc = math.sqrt(sums[0] ** 2 + sums[1] ** 2 + sums[2] ** 2) / w
    acc_term = sums[3] - 2.0 * g * w * norm_mean_acc + w * g * g
    return (acc_term * config[1] + sums[4] * config[2]) / w


@jit
def young_stance_waits(still_samples: int, young_samples: int, P: np.ndarray,
                       vel_n: np.ndarray, zupt_sigma_mps: float, max_nis: float) -> bool:
    """
    Return True when a young stance's ZUPT must wait: the innovation it would apply is implausible.

    A stance of fewer than ``young_samples`` still samples waits when the normalised innovation
    squared of its ZUPT (eq. 7, z = -v_n, H = [0 I 0 0 0], R = sigma^2 I),

        NIS = v_n^T (H P H^T + R)^-1 v_n > NIS_max,

    says the INS velocity is tens of sigma from zero. Either the foot is not still: in mid-swing
    a foot that moves at constant velocity without turning looks still to an IMU for an
    instant (the first stride up a flight after brisk walking, 1-2.3 m/s), and a ZUPT there
    stops the INS at the swing's speed and cuts the stride in two; or the INS has run away (a
    gyro at its rail) and the stance is real. The first ends within a few samples; the second
    stays still and gets its ZUPTs once it is no longer young.

    Parameters
    ----------
    still_samples : int
        Consecutive samples below the threshold so far.
    young_samples : int
        ``ZuptParams.young_stance_samples`` (0: the rule is off).
    P : (15, 15) array
        Predicted covariance.
    vel_n : (3,) array
        The INS velocity, m/s.
    zupt_sigma_mps : float
        The ZUPT's measurement noise sigma, m/s.
    max_nis : float
        NIS_max.

    """
    if still_samples >= young_samples:
        return False
    return ekf.zupt_nis(P, vel_n, zupt_sigma_mps) > max_nis


@jit
def window_is_still(samples: np.ndarray, max_gyr_rps: float) -> bool:
    """
    Return True when no angular rate of the window exceeds the bound: max_j ||w_j|| < w_max.

    The SHOE statistic (eq. 4) lets a walking stance pass while the foot rolls at 0.3-0.9
    rad/s; a zero angular rate update needs a foot standing still (sway of a few deg/s).

    Parameters
    ----------
    samples : (W, 6) array
        The detector's window of [acc_b, gyr_b] (``shoe_update``'s ring buffer).
    max_gyr_rps : float
        The bound w_max, rad/s.

    """
    bound = max_gyr_rps * max_gyr_rps
    for j in range(samples.shape[0]):
        if samples[j, 3] ** 2 + samples[j, 4] ** 2 + samples[j, 5] ** 2 >= bound:
            return False
    return True


class ShoeDetector:
    """
    Per-sample SHOE detector over a trailing window, eq. (4) from running sums.

    ``update(acc_b, gyr_b)`` returns T_k of the window ending at the new sample, or None while
    the first window fills. The sums are rebuilt from the ring buffer every ``REBUILD_SAMPLES``
    or so (a whole number of windows), so rounding errors cannot accumulate over a long
    shift. ``gravity_mps2`` is the g of eq. (4); the navigator sets it to the magnitude the
    sensor reads at rest, so that an accelerometer scale or bias error along gravity does not
    lift the statistic of every stance. The state lives in arrays (``samples``, ``sums``,
    ``count``, ``config``) that the navigator's compiled step updates through ``shoe_update``,
    as ``update`` does.
    """

    def __init__(self, params: ZuptParams, rate_hz: float, gravity_mps2: float = GRAVITY_MPS2):
        self.params = params
        self.window = params.window_samples(rate_hz)
        self.samples = np.zeros((self.window, 6))
        self.sums = np.zeros(5)
        self.count = np.zeros(1, dtype=np.int64)
        self.config = np.array([gravity_mps2, 1.0 / params.sigma_acc_mps2 ** 2,
                                1.0 / params.sigma_gyr_rps ** 2])

    @property
    def gravity_mps2(self) -> float:
        """Return g of eq. (4), m/s^2."""
        return float(self.config[0])

    @gravity_mps2.setter
    def gravity_mps2(self, value: float):
        self.config[0] = value

    def update(self, acc_b: np.ndarray, gyr_b: np.ndarray):
        """Add a sample; return T_k of the trailing window, or None before it is full."""
        statistic = shoe_update(self.samples, self.sums, self.count, self.config,
                                np.asarray(acc_b, dtype=float), np.asarray(gyr_b, dtype=float))
        return None if math.isnan(statistic) else statistic

    def mean_acc(self) -> np.ndarray:
        """Return the mean specific force over the window, a-bar of eq. (4), m/s^2."""
        return self.sums[:3] / self.window
