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
(:data:`K_GRID_M`, 0.13-0.21 m in 1 mm steps):

    log p(K | dh) = log p(K) + sum_i log sum_n pi(n | L_i) N(|dh_i|; n K, sigma^2)

with a weak Gaussian prior p(K) around ``elevation.step_height_m`` (:func:`log_prior`), a
mixture over the riser count per stride (:func:`stride_log_likelihood`) and the counts a
stride's horizontal length L_i allows (:func:`allowed_riser_counts`: one tread is
:data:`TREAD_RANGE_M`). Sub-harmonics: on this grid K/2 never fits (2 x 0.13 > 0.21), but 2
risers of 0.195 m look like 3 of 0.13 m; the stride length tells them apart, and
pi(n) prefers the smaller count (:data:`RISER_COUNT_PRIOR`). A riser height the building
file gives replaces the estimate (:class:`RiserHeightEstimator` with ``known_m``).

Public API: :func:`log_prior`, :func:`allowed_riser_counts`, :func:`stride_log_likelihood`,
:class:`RiserHeightEstimator`, :data:`K_GRID_M`.

References
----------
[1] Patent CN111649742A, eq. (14): the height is a whole number of risers K.

"""

import math
import numbers
from typing import Optional

import numpy as np

K_GRID_M = np.round(np.arange(0.130, 0.2105, 0.001), 3)
"""Riser heights searched, m: building codes allow about 0.14-0.20 m."""

MAX_RISERS = 4
"""At most this many risers in one stride."""

RISER_COUNT_PRIOR = np.array([0.4, 0.4, 0.15, 0.05])
"""pi(n), n = 1..4: step-to and alternating gaits are common, skipping steps is rare."""

TREAD_RANGE_M = (0.20, 0.38)
"""Horizontal depth of one tread, m (codes: 0.22-0.35 m, margin for INS length errors)."""

STRIDE_SIGMA_M = 0.01
"""Noise sigma of one stride's raw height change, m (simulator: 1-5 mm rms, tails 2 cm)."""

PRIOR_SIGMA_M = 0.02
"""Sigma of the prior around ``elevation.step_height_m``, m: weak, a few strides override it."""


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


def allowed_riser_counts(length_m: Optional[float]) -> np.ndarray:
    """
    Riser counts a stride of horizontal length L can have: n T_min <= L <= n T_max.

    n in {1..MAX_RISERS} with T_min = TREAD_RANGE_M[0], T_max = TREAD_RANGE_M[1]; None or a
    length that allows none (a landing stride, an INS error) allows every n.

    Returns
    -------
    (MAX_RISERS,) bool array, entry n-1 for n risers.

    """
    counts = np.arange(1, MAX_RISERS + 1)
    if length_m is None or not math.isfinite(length_m):
        return np.ones(MAX_RISERS, dtype=bool)
    low, high = TREAD_RANGE_M
    allowed = (counts * low <= length_m) & (length_m <= counts * high)
    return allowed if allowed.any() else np.ones(MAX_RISERS, dtype=bool)


def stride_log_likelihood(dh_m: float, k_grid_m: np.ndarray, allowed=None,
                          sigma_m: float = STRIDE_SIGMA_M) -> np.ndarray:
    """
    Log likelihood of one stair stride's raw height change for each riser height.

    log p(dh | K) = log sum_{n allowed} pi(n) N(|dh|; n K, sigma^2)

    Parameters
    ----------
    dh_m : float
        Raw height change of the stride, m (its sign is the direction).
    k_grid_m : (G,) array
        Riser heights K, m.
    allowed : (MAX_RISERS,) bool array or None
        From :func:`allowed_riser_counts`; None allows every count.
    sigma_m : float
        Noise sigma, m.

    Returns
    -------
    (G,) array.

    """
    counts = np.arange(1, MAX_RISERS + 1)
    weights = RISER_COUNT_PRIOR * (np.ones(MAX_RISERS, bool) if allowed is None else allowed)
    z = (abs(dh_m) - counts[None, :] * np.asarray(k_grid_m)[:, None]) / sigma_m
    terms = np.log(np.maximum(weights, 1e-300))[None, :] - 0.5 * z ** 2
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

    Attributes
    ----------
    strides : int, stair strides in the current estimate.

    """

    def __init__(self, prior_m: float, known_m: Optional[float] = None):
        for name, value in (('prior_m', prior_m), ('known_m', known_m)):
            if value is None and name == 'known_m':
                continue
            if isinstance(value, bool) or not isinstance(value, numbers.Real) \
                    or not 0.10 <= value <= 0.25:
                raise ValueError(f'RiserHeightEstimator {name} must be a riser height in '
                                 f'[0.10, 0.25] m, got {value!r}')
        self.prior_m = float(prior_m)
        self.known_m = None if known_m is None else float(known_m)
        self.reset()

    def reset(self, prior_m: Optional[float] = None):
        """Forget the strides (a new stairwell); optionally move the prior's centre."""
        if prior_m is not None:
            self.prior_m = float(prior_m)
        self._log_posterior = log_prior(K_GRID_M, self.prior_m)
        self.strides = 0

    def add(self, dh_m: float, length_m: Optional[float] = None) -> float:
        """Take one stair stride's raw height change (m) and length (m); return the estimate."""
        if not math.isfinite(dh_m):
            raise ValueError(f'RiserHeightEstimator.add: dh_m must be finite, got {dh_m!r}')
        if self.known_m is None:
            self._log_posterior = self._log_posterior + stride_log_likelihood(
                dh_m, K_GRID_M, allowed_riser_counts(length_m))
        self.strides += 1
        return self.estimate_m

    @property
    def estimate_m(self) -> float:
        """Return the riser height: the file's, else the posterior's maximum (or the prior)."""
        if self.known_m is not None:
            return self.known_m
        if self.strides == 0:
            return self.prior_m
        return float(K_GRID_M[int(np.argmax(self._log_posterior))])
