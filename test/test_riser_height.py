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

from anfis_elevation_ros.core.riser_height import allowed_riser_counts, grid_peak_m
from anfis_elevation_ros.core.riser_height import height_checked_mode
from anfis_elevation_ros.core.riser_height import K_GRID_M, log_prior
from anfis_elevation_ros.core.riser_height import riser_count_bounds, RiserHeightEstimator
from anfis_elevation_ros.core.riser_height import stride_log_likelihood, stride_riser_counts
from anfis_elevation_ros.core.stair_steps import flight_riser_count, FlightStrides
from anfis_elevation_ros.core.stairwells import StairwellRiserHeights
import numpy as np
import pytest

TREAD_M = 0.28


def counted(risers):
    """
    Return a flight counted once: the same risers at any K.

    One stride whose height says nothing (0 m, no whole count) and whose length allows exactly
    abs(risers) risers, of the flight's sign.
    """
    n = abs(risers)
    return FlightStrides.of_flight(1 if risers >= 0 else -1, [0.0], [1], [(n, n)])


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
    assert estimator.estimate_m == pytest.approx(0.15, abs=0.0005)    # the prior pulls a little
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


def test_the_estimate_lies_between_the_grids_points():
    """Random walk 399 (consumer): stairs of 0.1475 m; the 1 mm grid gives 0.147 or 0.148."""
    parabola = -((K_GRID_M - 0.1475) / 0.002) ** 2
    assert grid_peak_m(K_GRID_M, parabola) == pytest.approx(0.1475, abs=1e-9)
    assert grid_peak_m(K_GRID_M, -((K_GRID_M - 0.125) / 0.002) ** 2) == 0.13   # the grid's end
    assert grid_peak_m(K_GRID_M, np.zeros(len(K_GRID_M))) == 0.13                # flat: no peak
    estimator = RiserHeightEstimator(0.17)
    for _ in range(40):                 # one riser a stride, 0.1475 m, no noise
        estimator.add(0.1475, 0.28)
    assert estimator.estimate_m == pytest.approx(0.1475, abs=0.0002)
    sigma = 0.004                       # the stride noise of the level strides
    stairwells = StairwellRiserHeights(0.17)
    stairwells.start_flight((0.0, 0.0), -1, 0.0)
    for _ in range(40):
        stairwells.add(-0.1475, 0.28, (0.0, 0.0), sigma)
    assert stairwells.estimate_m == pytest.approx(0.1475, abs=0.0002)


@pytest.mark.parametrize('bad', [0.05, 0.3, float('nan'), True, '0.17'])
def test_bad_heights_are_refused(bad):
    with pytest.raises(ValueError, match='riser height'):
        RiserHeightEstimator(bad)
    with pytest.raises(ValueError, match='riser height'):
        RiserHeightEstimator(0.17, known_m=bad)


def test_a_non_finite_stride_is_refused():
    with pytest.raises(ValueError, match='finite'):
        RiserHeightEstimator(0.17).add(float('nan'))


def test_riser_count_bounds_follow_the_stride_length():
    assert riser_count_bounds(0.56) == (2, 2)
    assert riser_count_bounds(0.84) == (3, 4)
    assert riser_count_bounds(0.28) == (1, 1)
    for unknown in (None, float('nan'), 5.0, 0.05):
        assert riser_count_bounds(unknown)[0] == 1 and riser_count_bounds(unknown)[1] > 100
    # A flight's first stride starts on the floor before the stairs: at most L / T_min risers.
    assert riser_count_bounds(0.91, from_level=True)[1] > 100            # 1..4: any
    assert riser_count_bounds(0.56, from_level=True) == (1, 2)
    assert riser_count_bounds(0.28, from_level=True) == (1, 1)
    assert allowed_riser_counts(0.91, from_level=True).tolist() == [True] * 4
    assert allowed_riser_counts(0.50, from_level=True).tolist() == [True, True, False, False]


def test_a_stride_length_that_no_riser_height_fits_is_not_believed():
    # The length allows counts whose riser height is on the grid: they stand.
    assert stride_riser_counts(0.30, 0.56).tolist() == [False, True, False, False]
    assert stride_riser_counts(0.50, 0.84).tolist() == [False, False, True, True]
    # Random walk 398 (consumer), strides of 2 risers of 0.149 m out of a landing's turn whose
    # INS lengths allow one riser of 0.30 m, or three or four of 0.10 m or less: any count.
    assert stride_riser_counts(0.300, 0.378, from_level=True).all()
    assert stride_riser_counts(0.295, 0.88).all()
    # Walk 361: 3 risers of 0.159 m onto the floor, read 1.31 m long (four risers at least).
    assert stride_riser_counts(0.471, 1.305).all()
    # Within three sigma of the grid's edge a count still fits: 0.43 m is two of 0.215 m.
    assert not stride_riser_counts(0.43, 0.56, sigma_m=0.01).all()


def test_a_flight_out_of_a_landings_turn_joins_the_stairwell_its_heights_fit():
    # Random walk 398 (consumer, 2026-12-07): a stairwell of 0.147 m risers, another of
    # 0.187 m; a flight of 2-riser strides of 0.149 m whose first three strides read 0.38,
    # 0.88 and 0.81 m long. Held to their lengths they fit no riser height, the evidence tied
    # and the flight went to the 0.187 m stairwell (a height 0.38 m off).
    wells = StairwellRiserHeights(0.17)
    for dh, length, count in ((0.294, 0.56, 9), (0.374, 0.57, 4)):
        wells.start_flight()
        for _ in range(count):
            wells.add(dh, length)
        wells.end_flight(counted(2 * count))
    assert wells.stairwells == 2
    wells.start_flight((30.0, 30.0), -1, -10.0)
    for dh, length, from_level in ((-0.300, 0.378, True), (-0.295, 0.88, False),
                                   (-0.291, 0.806, False)):
        wells.add(dh, length, from_level=from_level)
        assert wells.estimate_m == pytest.approx(0.147, abs=0.002)


def test_a_flight_counts_a_sure_height_whatever_the_stride_length_says():
    # Random walk 11 (tactical): 1-riser strides of 0.166 m, one of which the INS reads 0.46 m
    # long (bounds (2, 2)); the height is sure, so the flight climbs 6 risers, not 7.
    k_m = 0.1656
    lows, highs = zip(*[riser_count_bounds(length) for length in [0.28] * 5 + [0.46]])
    assert (lows[-1], highs[-1]) == (2, 2)
    dh = [0.166, 0.165, 0.166, 0.164, 0.166, 0.165]
    assert flight_riser_count(1, dh, [1] * 6, k_m, lows, highs) == 6
    # Half a riser off (an INS glitch after a landing turn): the length decides, as before.
    dh[-1] = 0.25
    assert flight_riser_count(-1, dh, [1] * 6, k_m, lows, highs) == -7
    lows, highs = zip(*[riser_count_bounds(0.28)] * 6)
    assert flight_riser_count(1, dh, [1] * 6, k_m, lows, highs) == 6


def test_the_classifiers_mode_is_checked_against_the_strides_geometry():
    k_m = 0.179
    # Two or more whole risers over as many treads are stairs whatever the classifier said.
    assert height_checked_mode(0, -0.373, 0.567, k_m, 0) == -1     # random walk 19, consumer
    assert height_checked_mode(0, 0.54, 0.84, k_m, 0) == 1         # 3 risers, 3 treads
    assert height_checked_mode(0, 0.70, 1.40, k_m, 0) == 1         # 4 risers, the most
    # One riser is not sure (a kerb, a ramp, a glitch): the classifier's call stands.
    assert height_checked_mode(0, 0.22, 0.30, k_m, 0) == 0
    # A length no stairs of that many risers have: a level stride, or strides merged in a run.
    assert height_checked_mode(0, 0.36, 1.30, k_m, 0) == 0
    assert height_checked_mode(0, 0.36, 0.30, k_m, 0) == 0
    assert height_checked_mode(0, 0.36, None, k_m, 0) == 0
    assert height_checked_mode(0, 1.31, 14.6, k_m, 0) == 0         # gdin walk 35's run
    assert height_checked_mode(0, 1.00, 1.50, k_m, 0) == 0         # 6 risers: beyond 4
    # A stair call on a stride that climbed less than half a riser is level (x-io's straight
    # walk: level strides of 1.44 m called down, which eq. 14 counted as 4 risers each).
    assert height_checked_mode(-1, -0.021, 1.44, k_m, 0) == 0
    assert height_checked_mode(1, 0.089, 0.77, k_m, 0) == 0
    assert height_checked_mode(1, 0.09, 1.44, k_m, 0) == 1         # half a riser: a riser
    # ... not on a stride of two treads or less: a flight's first or last, half on a landing.
    assert height_checked_mode(1, 0.03, 0.76, k_m, 0) == 1
    assert height_checked_mode(1, 0.03, None, k_m, 0) == 1
    assert height_checked_mode(-1, 0.20, 0.30, k_m, 0) == -1     # a riser, the other way: as said
    # After a stair stride a level call stands: the replica's consumer IMU (100 Hz, tilted
    # mount) read -0.46 m on the level stride onto a landing, counted as three risers down.
    assert height_checked_mode(0, -0.457, 0.67, 0.15, -1) == 0
    assert height_checked_mode(0, -0.457, 0.67, 0.15, 0) == -1   # after level: a flight's first
    assert height_checked_mode(0, 0.54, 0.84, k_m, 1) == 0
    assert height_checked_mode(-1, -0.021, 1.44, k_m, -1) == 0     # the first line as before


@pytest.mark.parametrize('sigma_m, expected_wells', [(0.004, 2), (0.01, 1)])
def test_how_far_apart_two_stairs_must_be_follows_the_stride_noise(sigma_m, expected_wells):
    # Two storeys' stairs 6 mm apart (random walk 116): a sensor whose strides scatter by
    # 2 mm tells them apart, one at the default sigma (10 mm) cannot.
    wells = StairwellRiserHeights(0.17)
    rng = np.random.default_rng(11)
    for k_m in (0.149, 0.155):
        wells.start_flight()
        for dh, length in zip(*flight(k_m, [1] * 16, rng, noise_m=0.001)):
            wells.add(dh, length, sigma_m=sigma_m)
        wells.end_flight(counted(16))
    assert wells.stairwells == expected_wells


def test_flights_of_one_riser_height_share_a_stairwell_another_gets_its_own():
    wells = StairwellRiserHeights(0.17)
    rng = np.random.default_rng(9)
    for k_m, expected_wells in ((0.15, 1), (0.15, 1), (0.19, 2), (0.151, 2)):
        wells.start_flight()
        for dh, length in zip(*flight(k_m, [2] * 6, rng)):
            wells.add(dh, length)
        assert wells.estimate_m == pytest.approx(k_m, abs=0.002)
        wells.end_flight(counted(12))
        assert wells.stairwells == expected_wells
    # N_w risers per stairwell with the latest K_w: 3 x 12 risers of ~0.15, 12 of ~0.19.
    assert wells.climbed_m == pytest.approx(36 * 0.15 + 12 * 0.19, abs=0.06)
    wells.forget_climbs()
    assert wells.climbed_m == 0.0


def test_a_resumed_estimate_is_a_narrow_prior():
    estimator = RiserHeightEstimator(0.17)
    estimator.resume(0.152, 20)
    assert estimator.estimate_m == 0.152 and estimator.strides == 20
    estimator.add(0.33, 0.56)                        # one stride of 0.165 m does not undo it
    assert estimator.estimate_m == pytest.approx(0.152, abs=0.002)
    fixed = RiserHeightEstimator(0.17, prior_sigma_m=0.0)
    fixed.add(0.30, 0.56)
    assert not fixed.estimating and fixed.estimate_m == 0.17


def test_a_flight_back_down_the_same_stairs_joins_them_whatever_its_strides_say():
    """Up strides read 0.174 m, down strides 0.153 m (cross-axis errors): one stairwell."""
    wells = StairwellRiserHeights(0.17)
    wells.start_flight((0.0, 0.0), 1)
    for i in range(7):
        wells.add(0.348, 0.56, (0.56 * (i + 1), 0.0))
    wells.end_flight(counted(14))
    wells.start_flight((4.0, 0.5), -1)               # turned round at the top
    for i in range(7):
        wells.add(-0.306, 0.56, (4.0 - 0.56 * (i + 1), 0.5))
    wells.end_flight(counted(-14))
    assert wells.stairwells == 1 and wells.climbed_m == 0.0
    wells.start_flight((30.0, 0.0), -1)              # far away, same strides: evidence decides
    wells.add(-0.306, 0.56, (30.5, 0.0))
    wells.end_flight(counted(-2))
    assert wells.stairwells == 2


def test_the_flight_under_the_end_of_another_storeys_stairs_is_not_them():
    """Down from floor 1 to 0 with 0.185 m risers, then up from -1 to 0 (0.152 m) right below."""
    wells = StairwellRiserHeights(0.17)
    wells.start_flight((0.0, 0.0), -1, 3.33)
    for i in range(9):
        wells.add(-0.37, 0.56, (0.56 * (i + 1), 0.0))
    wells.end_flight(counted(-18), 0.0)
    wells.start_flight((4.5, 0.5), 1, -3.04)         # where it ended, but a storey lower
    for i in range(10):
        wells.add(0.304, 0.56, (4.5 - 0.56 * (i + 1), 0.5))
    assert wells.estimate_m == pytest.approx(0.152, abs=0.002)
    wells.end_flight(counted(20), 0.0)
    assert wells.stairwells == 2
    wells.start_flight((5.0, 0.3), 1, 0.0)           # the same stairs back up: joins them
    wells.add(0.30, 0.56, (4.5, 0.3))                 # (a stride of 0.15 m risers: still)
    assert wells.estimate_m == pytest.approx(0.185, abs=0.002)


def test_a_flight_is_counted_again_when_a_later_flight_moves_its_k():
    """Random walk 159: up 4 risers of 0.152 m a stride, read as 3 of 0.203, then back down."""
    wells = StairwellRiserHeights(0.17)
    wells.start_flight((0.0, 0.0), 1, 0.0)
    up = [0.608, 0.610, 0.607]
    for i, dh in enumerate(up):
        wells.add(dh, 1.12, (1.12 * (i + 1), 0.0))
    assert wells.estimate_m == pytest.approx(0.203, abs=0.002)
    wells.end_flight(FlightStrides.of_flight(1, up, [1, 1, 1], [riser_count_bounds(1.12)] * 3),
                     1.82)
    assert wells.climbed_m == pytest.approx(9 * 0.203, abs=0.02)
    # Back down the same stairs one riser a stride: K moves to 0.152 m, and the flight up is
    # 12 risers of it, so the walk ends where it started.
    wells.start_flight((3.4, 0.3), -1, 1.82)
    down = np.full(12, 0.152)
    for i, dh in enumerate(down):
        wells.add(-dh, 0.28, (3.4 - 0.28 * (i + 1), 0.3))
    assert wells.estimate_m == pytest.approx(0.152, abs=0.001)
    wells.end_flight(FlightStrides.of_flight(-1, down, [1] * 12,
                                             [riser_count_bounds(0.28)] * 12), 0.0)
    assert wells.stairwells == 1
    assert wells.climbed_m == pytest.approx(0.0, abs=1e-9)


def test_the_strides_of_many_flights_count_as_each_flight_would():
    """The strides of flights up and down, bridged cycles, bounds: counted as each flight."""
    rng = np.random.default_rng(3)
    flights, total = [], FlightStrides.empty()
    for mode in (1, -1, 1, 1, -1):
        n = int(rng.integers(3, 12))
        dh = rng.uniform(0.12, 0.70, n)
        cycles = rng.integers(1, 3, n)
        bounds = [riser_count_bounds(float(length)) for length in rng.uniform(0.2, 1.5, n)]
        flights.append((mode, dh, cycles, bounds))
        total = total + FlightStrides.of_flight(mode, dh, cycles, bounds)
    assert FlightStrides.empty().risers(0.17) == 0
    for k_m in np.linspace(0.13, 0.21, 17):
        each = sum(flight_riser_count(mode, dh, cycles, k_m, *zip(*bounds))
                   for mode, dh, cycles, bounds in flights)
        assert total.risers(k_m) == each
