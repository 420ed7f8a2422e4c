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

"""Online riser height: synthetic flights with unknown risers per stride, a wrong prior, noise."""

from anfis_elevation_ros.core.riser_height import allowed_riser_counts, K_GRID_M, log_prior
from anfis_elevation_ros.core.riser_height import RiserHeightEstimator, stride_log_likelihood
import numpy as np
import pytest

TREAD_M = 0.28


def flight(k_m, counts, rng, noise_m=0.004, direction=1):
    """(dh, length) per stride of a flight with the given risers per stride."""
    counts = np.asarray(counts)
    dh = direction * counts * k_m + rng.normal(0.0, noise_m, len(counts))
    return dh, counts * TREAD_M * (1.0 + rng.normal(0.0, 0.03, len(counts)))


@pytest.mark.parametrize('k_m', [0.14, 0.155, 0.17, 0.19])
@pytest.mark.parametrize('prior_m', [0.13, 0.21])
def test_mixed_risers_per_stride_and_a_wrong_prior(k_m, prior_m):
    rng = np.random.default_rng(int(k_m * 1000) + int(prior_m * 1000))
    estimator = RiserHeightEstimator(prior_m)
    counts = rng.choice([1, 2, 3], size=9, p=[0.3, 0.5, 0.2])
    for dh, length in zip(*flight(k_m, counts, rng)):
        estimator.add(dh, length)
    # 4 mm noise over ~17 risers: sigma of K about 0.7 mm, plus half the 1 mm grid.
    assert abs(estimator.estimate_m - k_m) <= 0.0026
    assert estimator.strides == 9


def test_descending_flights_estimate_the_same_height():
    rng = np.random.default_rng(4)
    estimator = RiserHeightEstimator(0.17)
    for dh, length in zip(*flight(0.15, [2] * 9, rng, direction=-1)):
        estimator.add(dh, length)
    assert abs(estimator.estimate_m - 0.15) <= 0.002


def test_two_risers_of_0_195_are_not_three_of_0_13():
    # |dh| = 0.39 m fits n = 2 at 0.195 m and n = 3 at 0.13 m; the stride length decides.
    for counts, k_m in (([2] * 8, 0.195), ([3] * 8, 0.13)):
        estimator = RiserHeightEstimator(0.17)
        for _ in counts:
            estimator.add(0.39, counts[0] * TREAD_M)
        assert estimator.estimate_m == pytest.approx(k_m, abs=0.0015)


def test_before_stairs_the_prior_and_with_a_file_the_files_height():
    assert RiserHeightEstimator(0.17).estimate_m == 0.17
    known = RiserHeightEstimator(0.17, known_m=0.152)
    for dh in (0.36, 0.35, 0.37):
        known.add(dh, 0.56)
    assert known.estimate_m == 0.152


def test_reset_forgets_the_strides():
    estimator = RiserHeightEstimator(0.17)
    for _ in range(6):
        estimator.add(0.30, 0.56)
    assert estimator.estimate_m == pytest.approx(0.15)
    estimator.reset()
    assert estimator.strides == 0 and estimator.estimate_m == 0.17


def test_equation_functions():
    assert K_GRID_M[0] == 0.13 and K_GRID_M[-1] == 0.21 and len(K_GRID_M) == 81
    prior = log_prior(K_GRID_M, 0.17)
    assert K_GRID_M[np.argmax(prior)] == pytest.approx(0.17)
    assert allowed_riser_counts(0.56).tolist() == [False, True, False, False]
    assert allowed_riser_counts(None).all() and allowed_riser_counts(5.0).all()
    likelihood = stride_log_likelihood(0.34, K_GRID_M, allowed_riser_counts(0.56))
    assert K_GRID_M[np.argmax(likelihood)] == pytest.approx(0.17)


@pytest.mark.parametrize('bad', [0.05, 0.3, float('nan'), True, '0.17'])
def test_bad_heights_are_refused(bad):
    with pytest.raises(ValueError, match='riser height'):
        RiserHeightEstimator(bad)
    with pytest.raises(ValueError, match='riser height'):
        RiserHeightEstimator(0.17, known_m=bad)


def test_a_non_finite_stride_is_refused():
    with pytest.raises(ValueError, match='finite'):
        RiserHeightEstimator(0.17).add(float('nan'))
