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
Online riser height K from the stair cycles themselves (nobody at an incident knows it).

Each stair stride i gives a raw INS height change dh_i = n_i K + e_i with n_i in {1..4}
risers, unknown. K is the maximum of the posterior over a grid of riser heights
(:data:`K_GRID_M`, 0.13-0.21 m in 1 mm steps, the maximum found between them,
:func:`grid_peak_m`):

    log p(K | dh) = log p(K) + sum_i log sum_n pi(n | L_i) N(|dh_i|; n K, sigma^2)

with a weak Gaussian prior p(K) around ``elevation.step_height_m`` (:func:`log_prior`), a
mixture over the riser count per stride (:func:`stride_log_likelihood`) and the counts a
stride's horizontal length L_i allows (:func:`allowed_riser_counts`: one tread is
:data:`TREAD_RANGE_M`), unless its height fits none of them (:func:`stride_riser_counts`: then
the length is wrong). Sub-harmonics: on this grid K/2 never fits (2 x 0.13 > 0.21), but 2
risers of 0.195 m look like 3 of 0.13 m; the stride length tells them apart, and
pi(n) prefers the smaller count (:data:`RISER_COUNT_PRIOR`). A riser height the building
file gives replaces the estimate (:class:`RiserHeightEstimator` with ``known_m``).

One estimate per stairwell (``core/stairwells.py``). Before a stride reaches the estimate its
slope error is removed, and its noise sigma is the level strides' (``core/level_strides.py``).

Public API: :func:`log_prior`, :func:`allowed_riser_counts`, :func:`stride_riser_counts`,
:func:`riser_count_bounds`, :func:`height_checked_mode`, :func:`stride_log_likelihood`,
:class:`RiserHeightEstimator`, :func:`grid_peak_m`, :func:`log_sum_exp`,
:func:`known_riser_height_m`,
:data:`K_GRID_M`.

References
----------
[1] Patent CN111649742A, eq. (14): the height is a whole number of risers K.

"""

import math
import numbers
from typing import Optional

import numpy as np

from .level_strides import STRIDE_SIGMA_M

K_GRID_M = np.round(np.arange(0.130, 0.2105, 0.001), 3)
"""Riser heights searched, m: building codes allow about 0.14-0.20 m."""

MAX_RISERS = 4
"""At most this many risers in one stride."""

UNBOUNDED_RISERS = 1000
"""Upper bound of a stride's riser count when its length says nothing."""

RISER_COUNT_PRIOR = np.array([0.4, 0.4, 0.15, 0.05])
"""pi(n), n = 1..4: step-to and alternating gaits are common, skipping steps is rare."""

TREAD_RANGE_M = (0.20, 0.38)
"""Horizontal depth of one tread, m (codes: 0.22-0.35 m, margin for INS length errors)."""

OUTLIER_PROB = 0.05
"""Probability that a stair stride fits no riser count (misclassified, INS glitch)."""

PRIOR_SIGMA_M = 0.02
"""Sigma of the prior around ``elevation.step_height_m``, m: weak, a few strides override it."""

RESUMED_SIGMA_M = 0.001
"""Narrowest prior of a resumed estimate, m (the grid step)."""


def log_prior(k_grid_m: np.ndarray, prior_m: float, sigma_m: float = PRIOR_SIGMA_M):
    """
    Log prior of the riser height, Gaussian around the configured K_0.

    log p(K) = -(K - K_0)^2 / (2 sigma_K^2)      (up to a constant)

    Parameters
    ----------
    k_grid_m : (G,) array
        Riser heights, m.
    prior_m : float
        K_0, m.
    sigma_m : float
        sigma_K, m.

    Returns
    -------
    (G,) array.

    """
    return -0.5 * ((np.asarray(k_grid_m) - prior_m) / sigma_m) ** 2


def allowed_riser_counts(length_m: Optional[float], from_level: bool = False) -> np.ndarray:
    """
    Riser counts a stride of horizontal length L can have: n T_min <= L <= n T_max.

    n in {1..MAX_RISERS} with T_min = TREAD_RANGE_M[0], T_max = TREAD_RANGE_M[1]; None or a
    length that allows none (a landing stride, an INS error) allows every n. A flight's first
    stride (``from_level``) starts on the floor before the stairs, so only n T_min <= L holds:
    a foot that stepped 0.9 m onto the first step climbed one riser, not three.

    Returns
    -------
    (MAX_RISERS,) bool array, entry n-1 for n risers.

    """
    counts = np.arange(1, MAX_RISERS + 1)
    if length_m is None or not math.isfinite(length_m):
        return np.ones(MAX_RISERS, dtype=bool)
    low, high = TREAD_RANGE_M
    allowed = (counts * low <= length_m) & (from_level or length_m <= counts * high)
    return allowed if allowed.any() else np.ones(MAX_RISERS, dtype=bool)


def stride_riser_counts(dh_m: float, length_m: Optional[float], from_level: bool = False,
                        sigma_m: float = STRIDE_SIGMA_M) -> np.ndarray:
    """
    Riser counts a stair stride can have: those its length allows, unless its height denies all.

        A = allowed(L)     if some n in allowed(L) has n K_min - 3 sigma <= |dh|
                           and |dh| <= n K_max + 3 sigma
        A = {1..N_max}     otherwise

    allowed(L) is :func:`allowed_riser_counts`, [K_min, K_max] the grid :data:`K_GRID_M` and
    sigma the stride's height noise. When no count the length allows gives a riser height on
    the grid, the length is wrong, not the height: a consumer IMU's strides out of a landing's
    turn read 0.38, 0.88 and 0.81 m long where each was 0.56 m (random walk 398), and a flight's
    last stride reads 1.31 m where it was 0.84 m as it steps onto the floor (361). Held to
    their lengths, such 2- and 3-riser strides fit no riser height (one riser of 0.30 m, four
    of 0.118 m), are left to the outlier term, and the flight's few other strides choose the
    stairwell and its K alone.

    Returns
    -------
    (MAX_RISERS,) bool array, entry n-1 for n risers.

    """
    allowed = allowed_riser_counts(length_m, from_level)
    counts = np.arange(1, MAX_RISERS + 1)
    fits = (counts * K_GRID_M[0] - 3.0 * sigma_m <= abs(dh_m)) \
        & (abs(dh_m) <= counts * K_GRID_M[-1] + 3.0 * sigma_m)
    return allowed if (allowed & fits).any() else np.ones(MAX_RISERS, dtype=bool)


def height_checked_mode(mode: int, dh_m: float, length_m: Optional[float],
                        step_height_m: float, last_mode: int) -> int:
    """
    Check the classifier's stair mode C against the stride's geometry; return C'.

        C' = 0           if C != 0, round(|dh| / K) = 0 and L > 2 T_max
        C' = sign(dh)    if C = 0, C_prev = 0, n = round(|dh| / K) in 2..N_max and
                         n T_min <= L <= n T_max
        C' = C           otherwise (and whenever L is unknown)

    dh is the stride's raw height change (not slope-corrected: a slope learnt on the few level
    strides of a stairwell can be decimetres per metre off, while a misaligned IMU's slope moves
    a stair stride by 2 cm at most), L its horizontal length, C_prev the checked mode of the
    cycle before, T_min, T_max :data:`TREAD_RANGE_M` and N_max :data:`MAX_RISERS`. A stride
    longer than two treads that climbed less than half a riser is level walking, where eq. 14
    would count it as one riser at least, or as many as its length allows (4 for a 1.4 m
    stride). Two or more whole risers over a length that n treads fit is no level stride when
    it follows level walking: a level stride reads centimetres, a ramp under 1:8 at most 0.18 m
    over 1.4 m, and a level cycle that reads decimetres (strides merged in a run, an INS glitch)
    is metres long. After a stair stride the classifier's level stands: the stride onto a
    landing can read decimetres (a consumer IMU's filter books, in the landing's turn, the
    height error its misalignment had built up: 0.46 m on one level stride), and a stair stride
    called level inside a flight is the first stride of the flight that goes on, which
    :meth:`ElevationTracker._missed_first_stride` recovers. Both lines trust the INS stride: an
    accelerometer that clips in every swing (HuGaDB's +-2 g) breaks them
    (README, "The stride's geometry checks the classifier").
    """
    if length_m is None:
        return mode
    n = int(round(abs(dh_m) / step_height_m))
    low, high = TREAD_RANGE_M
    if mode != 0:
        return 0 if n == 0 and length_m > 2 * high else mode
    if last_mode == 0 and 2 <= n <= MAX_RISERS and n * low <= length_m <= n * high:
        return int(math.copysign(1, dh_m))
    return 0


def riser_count_bounds(length_m: Optional[float], from_level: bool = False) -> tuple:
    """
    Fewest and most risers a stride of horizontal length L can have, (n_low, n_high).

    The ends of :func:`allowed_riser_counts`; (1, a large number) when the length allows no
    count or is unknown.
    """
    if length_m is None or not math.isfinite(length_m):
        return 1, UNBOUNDED_RISERS
    counts = np.flatnonzero(allowed_riser_counts(length_m, from_level)) + 1
    if len(counts) == MAX_RISERS:
        return 1, UNBOUNDED_RISERS
    return int(counts[0]), int(counts[-1])


def stride_log_likelihood(dh_m: float, k_grid_m: np.ndarray, allowed=None,
                          sigma_m: float = STRIDE_SIGMA_M) -> np.ndarray:
    """
    Log likelihood of one stair stride's raw height change for each riser height.

    p(dh | K) = (1 - eps) sum_{n allowed} pi(n) N(|dh|; n K, sigma^2) + eps / (N_max K_max)

    The last term (:data:`OUTLIER_PROB`, uniform over 0..N_max K_max) is a stride that fits no
    count (a misclassified cycle, an INS glitch): without it one such stride would drag K to
    the edge of the grid.

    Parameters
    ----------
    dh_m : float
        Raw height change of the stride, m (its sign is the direction).
    k_grid_m : (G,) array
        Riser heights K, m.
    allowed : (MAX_RISERS,) bool array or None
        From :func:`stride_riser_counts`; None allows every count.
    sigma_m : float
        Noise sigma, m.

    Returns
    -------
    (G,) array.

    """
    counts = np.arange(1, MAX_RISERS + 1)
    weights = RISER_COUNT_PRIOR * (np.ones(MAX_RISERS, bool) if allowed is None else allowed)
    weights = weights / weights.sum()
    z = (abs(dh_m) - counts[None, :] * np.asarray(k_grid_m)[:, None]) / sigma_m
    terms = np.log(np.maximum(weights * (1.0 - OUTLIER_PROB), 1e-300))[None, :] \
        - 0.5 * z ** 2 - math.log(math.sqrt(2.0 * math.pi) * sigma_m)
    outlier = math.log(OUTLIER_PROB / (MAX_RISERS * K_GRID_M[-1]))
    terms = np.concatenate([terms, np.full((len(terms), 1), outlier)], axis=1)
    top = terms.max(axis=1)
    return top + np.log(np.exp(terms - top[:, None]).sum(axis=1))


class RiserHeightEstimator:
    """
    Maximum a posteriori riser height over the stair strides seen, per stairwell.

    Parameters
    ----------
    prior_m : float
        ``elevation.step_height_m``: the prior's centre, and the answer before any stairs.
    known_m : float or None
        The building file's riser height: then it is the answer and nothing is estimated.
    prior_sigma_m : float
        Width of the prior, m (``elevation.step_height_sigma_m``); 0 takes ``prior_m`` as
        known (no estimation).

    Attributes
    ----------
    strides : int, stair strides in the current estimate.
    prior_m, prior_sigma_m : float, the configured prior, m (a resumed estimate narrows the
        prior in use, not these).

    """

    def __init__(self, prior_m: float, known_m: Optional[float] = None,
                 prior_sigma_m: float = PRIOR_SIGMA_M):
        if known_m is not None:
            _check_riser('known_m', known_m)
        self.known_m = None if known_m is None else float(known_m)
        self.set_prior(prior_m, prior_sigma_m)
        self.reset()

    def reset(self, prior_m: Optional[float] = None):
        """Forget the strides (a new stairwell); optionally move the prior's centre."""
        if prior_m is not None:
            self.set_prior(prior_m)
        self._log_likelihood = np.zeros(len(K_GRID_M))
        self.strides = 0

    def set_prior(self, prior_m: float, sigma_m: Optional[float] = None):
        """Set the prior (a live parameter change); the strides are kept."""
        _check_riser('prior_m', prior_m)
        sigma_m = getattr(self, 'prior_sigma_m', PRIOR_SIGMA_M) if sigma_m is None else sigma_m
        if isinstance(sigma_m, bool) or not isinstance(sigma_m, numbers.Real) \
                or not 0.0 <= sigma_m <= 1.0:
            raise ValueError('RiserHeightEstimator prior_sigma_m must be a number in [0, 1] m, '
                             f'got {sigma_m!r}')
        self.prior_m, self.prior_sigma_m = float(prior_m), float(sigma_m)
        self._prior_in_use = (self.prior_m, self.prior_sigma_m)

    def resume(self, estimate_m: float, strides: int):
        """
        Carry on from a saved estimate of ``strides`` strides (a restart).

        The strides themselves are not saved: the prior in use becomes a Gaussian around the
        saved estimate, as narrow as a posterior of that many strides of two risers,
        sigma / (2 sqrt(strides)) (sigma = :data:`STRIDE_SIGMA_M`), at least
        :data:`RESUMED_SIGMA_M`.
        """
        _check_riser('estimate_m', estimate_m)
        self.reset()
        self.strides = max(0, int(strides))
        if self.estimating and self.strides:
            self._prior_in_use = (float(estimate_m), max(
                RESUMED_SIGMA_M, STRIDE_SIGMA_M / (2.0 * math.sqrt(self.strides))))

    def add(self, dh_m: float, length_m: Optional[float] = None) -> float:
        """Take one stair stride's raw height change (m) and length (m); return the estimate."""
        if not math.isfinite(dh_m):
            raise ValueError(f'RiserHeightEstimator.add: dh_m must be finite, got {dh_m!r}')
        if self.estimating:
            self._log_likelihood = self._log_likelihood + stride_log_likelihood(
                dh_m, K_GRID_M, stride_riser_counts(dh_m, length_m))
        self.strides += 1
        return self.estimate_m

    @property
    def estimating(self) -> bool:
        """Return whether K is estimated (no file's height, a prior of non-zero width)."""
        return self.known_m is None and self.prior_sigma_m > 0.0

    @property
    def estimate_m(self) -> float:
        """Return the riser height: the file's, else the posterior's maximum (or the prior)."""
        return self.estimate_with(None)

    def estimate_with(self, more_log_likelihood=None) -> float:
        """Return the estimate with the log likelihood of more strides (an open flight)."""
        if self.known_m is not None:
            return self.known_m
        if not self.estimating:
            return self.prior_m
        if self.strides == 0 and more_log_likelihood is None:
            return self._prior_in_use[0]
        return grid_peak_m(K_GRID_M, self.log_posterior(more_log_likelihood))

    def log_posterior(self, more_log_likelihood=None) -> np.ndarray:
        """
        Return the normalised log posterior over :data:`K_GRID_M` (with more strides if given).

        log p(K | dh) = log p(K) + sum_i log p(dh_i | K) - log sum_K' (...)
        """
        terms = log_prior(K_GRID_M, *self._prior_in_use) + self._log_likelihood
        if more_log_likelihood is not None:
            terms = terms + more_log_likelihood
        return terms - log_sum_exp(terms)

    def commit(self, log_likelihood: np.ndarray, strides: int):
        """Add the summed log likelihood of ``strides`` strides (a finished flight)."""
        if self.estimating:
            self._log_likelihood = self._log_likelihood + log_likelihood
        self.strides += int(strides)


def grid_peak_m(grid_m: np.ndarray, log_posterior: np.ndarray) -> float:
    """
    Return the maximum of a log posterior sampled on an even grid, between its grid points.

    With l_-, l_0, l_+ the log posterior at the grid's maximum K_i and its neighbours, step d,
    the parabola through them peaks at

        K* = K_i + d (l_- - l_+) / (2 (l_- - 2 l_0 + l_+)),   |K* - K_i| <= d / 2

    (the bound holds because l_0 is the largest of the three; K_i itself at the grid's ends, or
    where the three are equal). The grid's 1 mm would otherwise round K by up to 0.5 mm, 2 cm
    over a 40-riser climb (doc/riser_height_notebook.md, "K between the grid's points").
    """
    i = int(np.argmax(log_posterior))
    if not 0 < i < len(grid_m) - 1:
        return float(grid_m[i])
    below, peak, above = log_posterior[i - 1:i + 2]
    curvature = below - 2.0 * peak + above
    if not curvature < 0.0:
        return float(grid_m[i])
    return float(grid_m[i] + 0.5 * (below - above) / curvature * (grid_m[i + 1] - grid_m[i]))


def log_sum_exp(terms: np.ndarray) -> float:
    """Return log sum_i exp(t_i), computed without overflow."""
    top = float(np.max(terms))
    return top + math.log(float(np.sum(np.exp(terms - top))))


def _check_riser(name: str, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) \
            or not 0.10 <= value <= 0.25:
        raise ValueError(f'RiserHeightEstimator {name} must be a riser height in '
                         f'[0.10, 0.25] m, got {value!r}')


def known_riser_height_m(building) -> Optional[float]:
    """
    Riser height a building file gives for the whole building, else None (then estimated).

    The building-wide ``step_height_m`` when every stairwell resolves to it, or the height all
    stairwells give alike; None when stairwells differ or some give none (which stairwell a
    flight is in is not known here).
    """
    if building is None:
        return None
    wells = {entry.stairwell for entry in building.stairs}
    heights = {building.riser_height_m(well) for well in wells} if wells else {
        building.riser_height_m()}
    return heights.pop() if len(heights) == 1 else None
