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

"""The SHOE detector, eq. (4), and its adaptive threshold, against hand-computed values."""

import math

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.zupt import (
    adaptive_threshold, GaitIntensity, shoe_statistic, shoe_statistic_trailing, ShoeDetector,
    ZuptParams)
import numpy as np
import pytest

G = 9.80665


def test_statistic_of_a_still_window_is_the_gyro_term_alone():
    acc = np.tile([0.0, 0.0, G], (3, 1))
    gyr = np.tile([0.1, 0.0, 0.0], (3, 1))
    # ||a - g abar/|abar| || = 0, so T = 1/W * sum 0.01 / sigma_w^2 = 0.01 / 0.01^2 = 100.
    assert shoe_statistic(acc, gyr, 1.0, 0.01, G) == pytest.approx(100.0)


def test_statistic_hand_computed_with_accelerations():
    acc = np.array([[0.0, 0.0, 10.0], [0.0, 0.0, 12.0]])
    gyr = np.array([[0.0, 0.0, 0.0], [0.0, 0.2, 0.0]])
    # abar points up; residuals 10 - 9.80665 and 12 - 9.80665 on z; sigma_a = 1, sigma_w = 0.1.
    expected = ((10 - G) ** 2 + (12 - G) ** 2 + 0.04 / 0.01) / 2
    assert shoe_statistic(acc, gyr, 1.0, 0.1, G) == pytest.approx(expected)


def test_live_detector_equals_the_direct_statistic_over_many_wraps():
    rng = np.random.default_rng(1)
    acc = rng.normal(size=(3000, 3)) * 3 + [0.0, 0.0, G]
    gyr = rng.normal(size=(3000, 3))
    params = ZuptParams()
    detector = ShoeDetector(params, 200.0)
    live = [detector.update(a, w) for a, w in zip(acc, gyr)]
    batch = shoe_statistic_trailing(acc, gyr, detector.window, params.sigma_acc_mps2,
                                    params.sigma_gyr_rps)
    assert live[:detector.window - 1] == [None] * (detector.window - 1)
    assert np.allclose(np.array(live[detector.window - 1:], float), batch[detector.window - 1:],
                       rtol=1e-9)


def test_window_is_a_duration_so_it_holds_across_rates():
    params = ZuptParams(window_s=0.025)
    assert [params.window_samples(r) for r in (100.0, 200.0, 400.0)] == [3, 5, 10]


def test_adaptive_threshold_follows_the_power_law_within_bounds():
    params = ZuptParams(threshold=1e7, ref_peak_gyr_rps=6.0, intensity_exponent=4.0,
                        min_threshold=1e5, max_threshold=2e8)
    assert adaptive_threshold(6.0, *params.threshold_law()) == pytest.approx(1e7)
    assert adaptive_threshold(12.0, *params.threshold_law()) == pytest.approx(1.6e8)
    assert adaptive_threshold(30.0, *params.threshold_law()) == 2e8
    assert adaptive_threshold(0.1, *params.threshold_law()) == 1e5


def test_intensity_rises_at_once_and_falls_with_the_median_block_peak():
    params = ZuptParams(ref_peak_gyr_rps=6.0, intensity_block_s=0.5, intensity_blocks=3)
    intensity = GaitIntensity(params, rate_hz=10.0)  # 5 samples per block
    values = []
    for rate in [1, 2, 3, 4, 5, 9, 1, 1, 1, 1, 2, 2, 7, 2, 2, 1, 1, 1, 1, 1]:
        intensity.update(rate)
        values.append(intensity.value)
    # Blocks peak at 5, 9, 7, 1; 9 lifts m at once, block ends set the median.
    assert values == [6, 6, 6, 6, 5, 9, 9, 9, 9, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7]


@pytest.mark.parametrize('field, value', [('window_s', 0.0), ('threshold', -1.0),
                                          ('sigma_gyr_rps', 0.0), ('intensity_blocks', 0),
                                          ('min_threshold', 1e10)])
def test_bad_parameters_raise_naming_the_field(field, value):
    with pytest.raises(InputError, match=field):
        ZuptParams(**{field: value})


def test_default_sigmas_are_pyshoes_vicon_values():
    params = ZuptParams()
    assert params.sigma_acc_mps2 == pytest.approx(0.00098, rel=0.03)
    assert params.sigma_gyr_rps == pytest.approx(8.7266463e-5, rel=1e-6)
    assert math.isclose(ZuptParams().threshold, 1.2e7)
