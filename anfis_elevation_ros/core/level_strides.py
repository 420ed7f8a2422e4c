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
What the level strides say about the raw INS height: its slope error and its stride noise.

On a level stride the true height change is 0, so what the INS reads there is its error. Two
parts of it matter to the riser height (``core/riser_height.py``):

- the slope (:class:`LevelSlope`, :func:`level_slope`): a misaligned accelerometer turns
  forward metres into height, c m per m, which stair strides must have taken off before their
  risers are counted;
- the stride noise (:func:`stride_noise_sigma`): what the slope leaves of a level stride, the
  sigma with which a stair stride's height is weighed.

Public API: :class:`LevelSlope`, :func:`level_slope`, :func:`stride_noise_sigma` and the
constants below.
"""

import math
from typing import Optional

import numpy as np

STRIDE_SIGMA_M = 0.01
"""
Noise sigma of one stride's raw height change, m: before the level strides measure it, and
the widest they set (:func:`stride_noise_sigma`).
"""

NOISE_STRIDES = 32
"""Level strides behind the stride noise estimate (:func:`stride_noise_sigma`)."""

MIN_NOISE_STRIDES = 8
"""Fewer level strides than this say too little: :data:`STRIDE_SIGMA_M` is used."""

NOISE_SIGMA_FACTOR = 2.0
"""sigma = this x the level strides' scatter: flights of one stair read a few % apart too."""

MIN_STRIDE_SIGMA_M = 0.001
"""Narrowest stride noise, m: the riser height grid's step (``riser_height.K_GRID_M``)."""

SLOPE_STRIDES = 8
"""
Level strides behind the slope correction (:class:`LevelSlope`): the latest only, because the
slope moves during a walk as the filter's tilt and accelerometer bias estimates move (random
walk 67, consumer IMU: -0.03 m/m for 14 strides, about 0 after a turn on the spot; with the
last 64, K came out 0.132 m for 0.1405 m). Chosen from 8, 16 and 64 on random walks 14-20 and
51-80 (doc/riser_height_notebook.md, "The slope over the last 8 level strides").
"""

MIN_SLOPE_STRIDES = 4
"""
Fewer level strides than this give no slope (0): the median of two or three is one stride's
word, and the MaD left foot's two level strides before its stairs (one of them already
climbing 0.2 m) said 0.105 m/m, which took its K to the grid's floor
(doc/riser_height_notebook.md, "no slope from fewer than 4 level strides").
"""

SLOPE_MIN_LENGTH_M = 0.5
"""Shorter level strides (turns, shuffles) say little about the slope, m."""


class LevelSlope:
    """
    Height error of the raw INS per horizontal metre, learnt from level strides.

    A misaligned accelerometer (a cross-axis term) turns forward motion into a height error
    per forward metre, which no zero-velocity update sees (constant for a fixed tilt error,
    but the filter's tilt and bias estimates move during a walk); it makes
    strides up look taller than strides down by 2 c L. On level strides the true height change
    is 0, so (:func:`level_slope`) c = median_i dh_i / L_i over the last :data:`SLOPE_STRIDES`
    level strides of at least :data:`SLOPE_MIN_LENGTH_M` (0 before :data:`MIN_SLOPE_STRIDES`
    of them); a stair stride is then corrected
    to dh - c L before K is estimated and its risers counted. What the slope leaves of a level
    stride, dh - c L, is the INS's stride height noise on this sensor and gait
    (:func:`stride_noise_sigma`, :attr:`stride_sigma_m`).
    """

    def __init__(self):
        self._ratios = []
        self._residuals = []

    def add_level(self, dh_m: float, length_m: Optional[float]):
        """Take a level stride's raw height change and horizontal length, m."""
        if length_m is not None and length_m >= SLOPE_MIN_LENGTH_M and math.isfinite(dh_m):
            # The slope before this stride, once there is one: the residual is out of sample
            # (a residual with no slope taken off is a consumer IMU's 2-28 mm/m, not noise).
            if len(self._ratios) >= MIN_SLOPE_STRIDES:
                self._residuals = (self._residuals + [self.corrected(dh_m, length_m)])[
                    -NOISE_STRIDES:]
            self._ratios = (self._ratios + [dh_m / length_m])[-SLOPE_STRIDES:]

    @property
    def slope(self) -> float:
        """Return c, m of height per m of stride (0 before :data:`MIN_SLOPE_STRIDES`)."""
        return level_slope(self._ratios)

    @property
    def stride_sigma_m(self) -> float:
        """Return the stride height noise sigma, m (:func:`stride_noise_sigma`)."""
        return stride_noise_sigma(self._residuals)

    def corrected(self, dh_m: float, length_m: Optional[float]) -> float:
        """Return a stair stride's height change without the slope error, dh - c L, m."""
        return dh_m if length_m is None else dh_m - self.slope * length_m


def level_slope(ratios) -> float:
    """
    Height error per horizontal metre from level strides.

    c = median_i (dh_i / L_i)      (0 with fewer than :data:`MIN_SLOPE_STRIDES` strides)
    """
    return float(np.median(ratios)) if len(ratios) >= MIN_SLOPE_STRIDES else 0.0


def stride_noise_sigma(residuals) -> float:
    """
    Noise sigma of a stride's raw height change, from level strides (true change 0).

    sigma = min(sigma_0, max(sigma_min, f 1.4826 median_i |dh_i - c L_i|))

    over the last :data:`NOISE_STRIDES` level strides, c the slope before stride i
    (:class:`LevelSlope`); 1.4826 median |r| is the standard deviation of Gaussian r, robust
    to a stair stride called level. f = :data:`NOISE_SIGMA_FACTOR`; sigma_min =
    :data:`MIN_STRIDE_SIGMA_M`; sigma_0 = :data:`STRIDE_SIGMA_M`, also the answer with fewer
    than :data:`MIN_NOISE_STRIDES` residuals. The level strides can show that a sensor is
    better than sigma_0 assumes (a simulated tactical IMU scatters by 2 mm: then stairs whose
    risers are 5 mm apart are told apart), not that it is worse: a wider sigma let flights
    of different riser heights share one K in the simulator, and the real feet that scatter
    by 9-68 mm have no height truth to say what a wider sigma would do
    (doc/riser_height_notebook.md, "the stride noise from the level strides").
    """
    if len(residuals) < MIN_NOISE_STRIDES:
        return STRIDE_SIGMA_M
    scatter_m = 1.4826 * float(np.median(np.abs(residuals)))
    return min(STRIDE_SIGMA_M, max(MIN_STRIDE_SIGMA_M, NOISE_SIGMA_FACTOR * scatter_m))
