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

"""What the level strides say: the slope error of the raw INS height and its stride noise."""

from anfis_elevation_ros.core.level_strides import level_slope, LevelSlope
from anfis_elevation_ros.core.level_strides import stride_noise_sigma, STRIDE_SIGMA_M
import numpy as np
import pytest


def test_level_slope_is_the_median_height_per_metre():
    assert level_slope([]) == 0.0 and level_slope([0.1, 0.1, 0.1]) == 0.0
    slope = LevelSlope()
    for dh in (0.028, 0.030, 0.5, 0.026):           # one glitch: the median ignores it
        slope.add_level(dh, 1.4)
    slope.add_level(0.2, 0.3)                       # too short to say anything
    assert slope.slope == pytest.approx(0.029 / 1.4 * 1.0, rel=0.05)
    assert slope.corrected(0.30 + 0.56 * slope.slope, 0.56) == pytest.approx(0.30)
    assert slope.corrected(0.31, None) == 0.31
    # The slope follows the walk: 14 strides at -0.03 m/m, then 9 at 0 (random walk 67,
    # consumer IMU, where the filter's tilt estimate moved after a turn on the spot).
    for dh in [-0.042] * 14 + [0.0] * 9:
        slope.add_level(dh, 1.4)
    assert slope.slope == 0.0


def test_a_slope_needs_four_level_strides():
    # The MaD left foot: two level strides before the stairs, one of them already climbing.
    slope = LevelSlope()
    for dh in (0.02, 0.2, 0.03):
        slope.add_level(dh, 1.0)
        assert slope.slope == 0.0 and slope.corrected(0.3, 0.6) == 0.3
    slope.add_level(0.01, 1.0)
    assert slope.slope == pytest.approx(0.025)


def test_the_stride_noise_is_what_the_slope_leaves_of_level_strides():
    assert stride_noise_sigma([0.01] * 7) == STRIDE_SIGMA_M     # too few to say
    # 1.4826 median |r| is the sigma of Gaussian residuals; f = 2 of it.
    residuals = np.random.default_rng(3).normal(0.0, 0.004, 2000)
    assert stride_noise_sigma(residuals) == pytest.approx(2 * 0.004, rel=0.05)
    assert stride_noise_sigma([0.0] * 8) == 0.001                # never below the grid step
    assert stride_noise_sigma([0.05] * 8) == STRIDE_SIGMA_M      # nor above the default
    slope = LevelSlope()
    assert slope.stride_sigma_m == STRIDE_SIGMA_M
    rng = np.random.default_rng(5)
    for dh in 0.02 * 1.4 + rng.normal(0.0, 0.003, 40):          # slope 0.02 m/m, 3 mm noise
        slope.add_level(dh, 1.4)
    assert slope.stride_sigma_m == pytest.approx(2 * 0.003, rel=0.3)
    for dh in 0.02 * 1.4 + rng.normal(0.0, 0.0045, 40):         # a noisier sensor: the last 32
        slope.add_level(dh, 1.4)
    assert slope.stride_sigma_m == pytest.approx(2 * 0.0045, rel=0.3)
