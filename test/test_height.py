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

"""Tests of the stair mode (eq. 13), height quantisation (eq. 14), floor index and tracker."""

from anfis_elevation_ros import Anfis
from anfis_elevation_ros.core.anfis import grid_partition
from anfis_elevation_ros.core.building import building_from_dict
from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.floors import floor_map_for, FloorSettler
from anfis_elevation_ros.core.height import (
    bridged_step_count, CycleEstimate, ElevationParams, ElevationTracker, FEATURE_NAMES,
    floor_index, HEIGHT_CHANGE, quantised_height_step, quantised_step_count, round_half_away,
    stair_mode)
import numpy as np
import pytest


FIXED_K = {'step_height_sigma_m': 0.0}
KNOWN_3M_STOREYS = {'floor_height_m': 3.0, 'floor_height_min_m': 3.0, 'floor_height_max_m': 3.0,
                    'lobby_height_max_m': 0.0}
"""Riser height taken as known (no online estimate): eq. 14 as the patent has it."""


class ScriptedModel:
    """Stand-in for the ANFIS: returns a scripted output per call and records its inputs."""

    n_inputs = len(FEATURE_NAMES)

    def __init__(self, outputs):
        self.outputs = list(outputs)
        self.seen = []

    def predict(self, x):
        self.seen.append(np.array(x))
        return np.array([self.outputs[len(self.seen) - 1]])


def _features(dh_m):
    features = np.zeros(len(FEATURE_NAMES))
    features[:5] = [dh_m / 2.0, abs(dh_m) / 3.0, 0.0, abs(dh_m) + 0.02, 0.3]
    features[HEIGHT_CHANGE] = dh_m
    return features


# ------------------------------------------------------------------------------ eq. 13

EQ13_TABLE = [   # (y, sigma_th, C)
    (0.9, 0.5, 1), (0.5000001, 0.5, 1), (0.5, 0.5, 0), (0.0, 0.5, 0), (-0.5, 0.5, 0),
    (-0.5000001, 0.5, -1), (-3.0, 0.5, -1), (0.0, 0.0, 0), (1e-12, 0.0, 1), (-1e-12, 0.0, -1),
    (1.0, 1.0, 0), (1.01, 1.0, 1)]


def test_stair_mode_table_including_boundaries():
    for y, threshold, expected in EQ13_TABLE:
        mode = stair_mode(y, threshold)
        assert mode == expected and isinstance(mode, int), (y, threshold)


def test_stair_mode_is_vectorised():
    y = np.array([row[0] for row in EQ13_TABLE if row[1] == 0.5]).reshape(-1, 1)
    expected = [row[2] for row in EQ13_TABLE if row[1] == 0.5]
    modes = stair_mode(y, 0.5)
    assert modes.shape == y.shape and modes.dtype == np.int64
    assert modes.ravel().tolist() == expected


def test_stair_mode_rejects_nan_and_negative_threshold():
    with pytest.raises(ValueError, match='NaN'):
        stair_mode(np.array([0.1, np.nan]), 0.5)
    with pytest.raises(ValueError, match='threshold'):
        stair_mode(0.1, -0.5)


# ------------------------------------------------------------------------------ eq. 14

EQ14_TABLE = [   # (C, dh m, K m, expected h_i - h_i-1 m), worked by hand
    (1, 0.16, 0.15, 0.15),     # round(1.07) = 1
    (1, 0.31, 0.15, 0.30),     # round(2.07) = 2
    (1, 0.05, 0.15, 0.15),     # round(0.33) = 0 -> max(1, 0) = 1: stairs climb at least a step
    (-1, -0.46, 0.15, -0.45),  # round(3.07) = 3, sign from C
    (-1, 0.02, 0.17, -0.17),   # sign comes from the mode, not from dh
    (0, 0.30, 0.15, 0.0),      # level: no change whatever dh says
    (0, -0.9, 0.17, 0.0),
    (1, 0.375, 0.25, 0.5),     # |dh| / K = 1.5 exactly: half rounds away from zero -> 2
    (1, 0.625, 0.25, 0.75),    # 2.5 exactly -> 3 (round-half-even would give 2)
]


def test_quantised_height_step_table():
    for mode, dh, step, expected in EQ14_TABLE:
        # 1e-12 m: K * n is one float product, off from the decimal value by < 1 ulp.
        assert quantised_height_step(mode, dh, step) == pytest.approx(expected, abs=1e-12), \
            (mode, dh, step)
        assert isinstance(quantised_step_count(mode, dh, step), int)


def test_quantised_height_step_is_vectorised():
    rows = [row for row in EQ14_TABLE if row[2] == 0.15]
    modes = np.array([row[0] for row in rows])
    dh = np.array([row[1] for row in rows])
    np.testing.assert_allclose(quantised_height_step(modes, dh, 0.15), [row[3] for row in rows],
                               rtol=0.0, atol=1e-12)
    assert quantised_step_count(modes, dh, 0.15).tolist() == [1, 2, 1, -3, 0]


def test_round_half_away_from_zero():
    values = np.array([-2.5, -1.5, -0.5, -0.49, 0.0, 0.49, 0.5, 1.5, 2.5])
    np.testing.assert_array_equal(round_half_away(values), [-3, -2, -1, 0, 0, 0, 1, 2, 3])


# ------------------------------------------------------------------------------ floor index

def test_floor_index_at_boundaries():
    # Exactly half a storey counts as the next floor away from the start (round half away).
    table = [(0.0, 0), (1.49, 0), (1.5, 1), (-1.5, -1), (-1.49, 0), (4.49, 1), (4.5, 2),
             (7.5, 3), (-7.5, -3), (3.0, 1), (-3.0, -1)]
    for height, expected in table:
        floor = floor_index(height, 3.0, 0)
        assert floor == expected and isinstance(floor, int), height
    assert floor_index(1.5, 3.0, 2) == 3
    assert floor_index(-1.5, 3.0, -1) == -2
    heights = np.array([row[0] for row in table])
    assert floor_index(heights, 3.0, 4).tolist() == [row[1] + 4 for row in table]


# ------------------------------------------------------------------------------ parameters

@pytest.mark.parametrize('field, value', [
    ('step_height_m', 0.09), ('step_height_m', 0.26), ('step_height_m', float('nan')),
    ('mode_threshold', -1.1), ('mode_threshold', 1.1), ('floor_height_m', 1.9),
    ('floor_height_m', float('inf')), ('start_floor', 1.0), ('start_floor', True),
    ('start_height_m', float('nan')), ('step_height_m', '0.17'),
    ('floor_height_min_m', 1.9), ('floor_height_max_m', 2.7),    # below the lowest storey
    ('floor_height_max_m', float('nan')), ('lobby_height_max_m', -0.1)])
def test_elevation_params_reject_out_of_range(field, value):
    with pytest.raises(ValueError, match=field):
        ElevationParams(**{field: value})


def test_elevation_params_defaults_and_limits():
    params = ElevationParams()
    assert (params.step_height_m, params.mode_threshold, params.floor_height_m,
            params.start_floor, params.start_height_m) == (0.17, -1.0, 3.0, 0, 0.0)
    ElevationParams(step_height_m=0.10, mode_threshold=0.0, floor_height_m=2.0)
    ElevationParams(step_height_m=0.25, mode_threshold=1.0, start_floor=-2)


def test_negative_mode_threshold_takes_the_models_own():
    model = ScriptedModel([0.42, 0.42])
    assert ElevationTracker(model, ElevationParams()).mode_threshold == 0.5    # none stored
    model.metadata_ = {'mode_threshold': 0.4}
    tracker = ElevationTracker(model, ElevationParams())
    assert tracker.mode_threshold == 0.4
    assert tracker.update(1, _features(0.16), 0.0, 0.0).mode == 1             # 0.42 >= 0.4
    assert ElevationTracker(model, ElevationParams(mode_threshold=0.5)).update(
        1, _features(0.16), 0.0, 0.0).mode == 0                                # the parameter
    model.metadata_ = {'mode_threshold': 'high'}
    with pytest.raises(ValueError, match='mode_threshold'):
        ElevationTracker(model, ElevationParams())


# ------------------------------------------------------------------------------ tracker

def test_tracker_follows_a_scripted_sequence():
    outputs = [0.9, 0.9, 0.1, -0.8, -0.7, 0.6]
    dh = [0.16, 0.31, 0.02, -0.46, -0.05, 0.14]
    model = ScriptedModel(outputs)
    tracker = ElevationTracker(model, ElevationParams(step_height_m=0.15, **FIXED_K))
    estimates = [tracker.update(100 + i, _features(d), float(i), -float(i))
                 for i, d in enumerate(dh)]
    # The fifth, called down, climbed 0.33 risers: level (height_checked_mode), where eq. 14
    # alone would count max(1, round(0.33)) = 1 riser.
    assert [e.mode for e in estimates] == [1, 1, 0, -1, 0, 1]
    # Hand-computed: +0.15, +0.30, 0, -0.45, 0, +0.15.
    np.testing.assert_allclose([e.height_m for e in estimates],
                               [0.15, 0.45, 0.45, 0.0, 0.0, 0.15], rtol=0.0, atol=1e-12)
    assert estimates[3] == CycleEstimate(stamp_ns=103, mode=-1, height_m=estimates[3].height_m,
                                         floor=0, x_m=3.0, y_m=-3.0, anfis_output=-0.8,
                                         floor_certain=False, step_height_m=0.15)
    assert estimates[4].anfis_output == -0.7
    assert (tracker.stair_calls_overruled, tracker.level_calls_overruled) == (1, 0)
    assert tracker.height_m == estimates[-1].height_m
    assert model.seen[0].shape == (1, len(FEATURE_NAMES))


def test_tracker_counts_whole_steps_and_changes_floor_when_settled():
    params = ElevationParams(step_height_m=0.15, start_floor=2, **FIXED_K,
                             **KNOWN_3M_STOREYS)
    tracker = ElevationTracker(ScriptedModel([1.0] * 20 + [0.0] * 2), params)
    assert (tracker.floor, tracker.floor_certain) == (2, True)
    climb = [tracker.update(i, _features(0.15), 0.0, 0.0) for i in range(20)]
    # On the stairs the floor stays the last settled one, not certain (10 steps = 1.50 m is
    # half a storey: the method's round(h / H) would flick to floor 3 there).
    assert {(e.floor, e.floor_certain) for e in climb} == {(2, False)}
    assert tracker.height_m == 20 * 0.15                      # integer steps: no drift
    level = tracker.update(20, _features(0.0), 0.0, 0.0)
    assert (level.floor, level.floor_certain, tracker.floor) == (3, True, 3)
    assert level.step_height_m == 0.15


def test_tracker_with_a_real_anfis_of_known_consequents():
    # Every rule says y = dh / 0.17, so the network output is exactly that (the normalised
    # strengths sum to 1); the mode then follows |dh| > 0.085 m.
    universe = np.array([[-1.0, 1.0]] * 5)
    consequents = np.zeros((243, 6))
    consequents[:, HEIGHT_CHANGE] = 1.0 / 0.17
    model = Anfis.from_params(grid_partition(universe, 3, 'triangle'), consequents, universe)
    tracker = ElevationTracker(model, ElevationParams(**FIXED_K))
    dh = [0.18, 0.17, 0.05, -0.35, -0.09]
    estimates = [tracker.update(i, _features(d), 0.0, 0.0) for i, d in enumerate(dh)]
    np.testing.assert_allclose([e.anfis_output for e in estimates], np.array(dh) / 0.17,
                               rtol=1e-12)
    assert [e.mode for e in estimates] == [1, 1, 0, -1, -1]
    np.testing.assert_allclose([e.height_m for e in estimates],
                               [0.17, 0.34, 0.34, 0.0, -0.17], rtol=0.0, atol=1e-12)


def test_tracker_rejects_bad_cycles_and_keeps_its_state():
    tracker = ElevationTracker(ScriptedModel([1.0, 1.0]), ElevationParams())
    tracker.update(0, _features(0.17), 0.0, 0.0)
    height = tracker.height_m
    bad = _features(0.17)
    bad[1] = np.nan
    shape = rf'\({len(FEATURE_NAMES)},\)'
    for features, x_m, match in [(bad, 0.0, 'not finite'), (np.ones(4), 0.0, shape),
                                 (np.ones((1, 5)), 0.0, shape), (['a'] * 5, 0.0, 'numbers'),
                                 (_features(0.17), float('inf'), 'position')]:
        with pytest.raises(InputError, match=match):
            tracker.update(1, features, x_m, 0.0)
    assert tracker.height_m == height


def test_tracker_restores_height_after_a_restart():
    params = ElevationParams(step_height_m=0.15, start_height_m=0.3, **FIXED_K)
    tracker = ElevationTracker(ScriptedModel([1.0, -1.0]), params)
    assert tracker.height_m == 0.3
    resumed = ElevationTracker(ScriptedModel([1.0]), params, height_m=4.2)
    assert resumed.update(0, _features(0.16), 0.0, 0.0).height_m == pytest.approx(4.35, abs=1e-12)
    assert resumed.floor == 1
    resumed.reset(-3.0)
    assert resumed.height_m == -3.0 and resumed.floor == -1
    resumed.reset()
    assert resumed.height_m == 0.3
    with pytest.raises(ValueError, match='height_m'):
        resumed.reset(float('nan'))
    with pytest.raises(ValueError, match='4 inputs'):
        ElevationTracker(Anfis(4), params)


# ------------------------------------------------------------------------------ lost cycles

@pytest.mark.parametrize('before, steps, after, lost, expected', [
    (1, 2, 1, 1, 2), (1, 2, 1, 3, 6), (-1, -1, -1, 2, -2), (1, 2, 0, 1, 0), (0, 0, 1, 1, 0),
    (-1, -2, 1, 1, 0), (0, 0, 0, 4, 0)])
def test_bridged_step_count_table(before, steps, after, lost, expected):
    assert bridged_step_count(before, steps, after, lost) == expected


def test_invalid_cycles_inside_a_flight_are_bridged():
    """Up, two invalid, up: the two lost cycles climbed as the one before (2 steps each)."""
    model = ScriptedModel([0.9, 0.9, 0.1])
    tracker = ElevationTracker(model, ElevationParams(step_height_m=0.15, **FIXED_K))
    first = tracker.update(0, _features(0.30), 0.0, 0.0)
    lost = [tracker.update(k, None, 0.0, 0.0, valid=False) for k in (1, 2)]
    assert [e.mode for e in lost] == [0, 0] and all(np.isnan(e.anfis_output) for e in lost)
    assert [e.height_m for e in lost] == [first.height_m] * 2      # nothing until it is known
    after = tracker.update(3, _features(0.31), 0.0, 0.0)
    assert after.bridged_steps == 4
    assert after.height_m == pytest.approx(0.30 + 0.60 + 0.30, abs=1e-12)
    assert (tracker.bridged_cycles, tracker.unbridged_cycles) == (2, 0)
    level = tracker.update(4, _features(0.0), 0.0, 0.0)
    assert level.bridged_steps == 0 and len(model.seen) == 3     # invalid ones not classified


def test_invalid_cycles_at_the_end_of_a_flight_add_nothing():
    tracker = ElevationTracker(ScriptedModel([0.9, 0.0]),
                               ElevationParams(step_height_m=0.15, **FIXED_K))
    tracker.update(0, _features(0.30), 0.0, 0.0)
    tracker.update(1, None, float('nan'), 0.0, valid=False)     # a lost cycle: no checks
    after = tracker.update(2, _features(0.0), 0.0, 0.0)
    assert after.bridged_steps == 0 and after.height_m == pytest.approx(0.30, abs=1e-12)
    assert (tracker.bridged_cycles, tracker.unbridged_cycles) == (0, 1)


def test_new_parameters_mid_run_keep_height_and_pending_cycles():
    """A live parameter change between a lost cycle and the next keeps the bridging."""
    tracker = ElevationTracker(ScriptedModel([0.9] * 6),
                               ElevationParams(step_height_m=0.15, **FIXED_K))
    for k in range(5):
        tracker.update(k, _features(0.30), 0.0, 0.0)               # 2 steps each: 1.50 m
    tracker.update(5, None, 0.0, 0.0, valid=False)
    tracker.set_params(ElevationParams(step_height_m=0.17, floor_height_m=2.0, start_floor=3,
                                       **FIXED_K))
    assert tracker.height_m == pytest.approx(1.50, abs=1e-12)
    assert tracker.floor == 4                                      # 3 + round(1.50 / 2.0)
    after = tracker.update(6, _features(0.34), 0.0, 0.0)
    # The lost cycle climbed as the one before (2 steps), now of the new height 0.17 m.
    assert after.bridged_steps == 2
    assert after.height_m == pytest.approx(1.50 + 2 * 0.17 + 2 * 0.17, abs=1e-12)
    assert (tracker.bridged_cycles, tracker.unbridged_cycles) == (1, 0)
    with pytest.raises(ValueError):
        tracker.set_params({'step_height_m': 0.17})


# ------------------------------------------------------------------------------ riser height K

TREAD_M = 0.28


class Walker:
    """Feeds a tracker strides of known risers: level strides, stair strides, positions."""

    def __init__(self, tracker, model, rng):
        self.tracker, self.model, self.rng = tracker, model, rng
        self.x_m, self.stamp = 0.0, 0
        self.true_height_m = 0.0

    def stride(self, mode, risers=0, k_m=0.0, length_m=1.4, noise_m=0.004):
        self.model.outputs.append(float(mode))
        self.x_m += length_m if mode == 0 else risers * TREAD_M
        dh_m = mode * risers * k_m + self.rng.normal(0.0, noise_m)
        self.true_height_m += mode * risers * k_m
        self.stamp += 1
        return self.tracker.update(self.stamp, _features(dh_m), self.x_m, 0.0)

    def flight(self, mode, counts, k_m):
        return [self.stride(mode, n, k_m) for n in counts]


def _walker(params, seed=0, building=None):
    model = ScriptedModel([])
    return Walker(ElevationTracker(model, params, building=building), model,
                  np.random.default_rng(seed))


@pytest.mark.parametrize('k_m, prior_m', [(0.14, 0.19), (0.15, 0.17), (0.19, 0.14),
                                          (0.165, 0.17)])
def test_estimated_riser_height_ends_a_flight_at_whole_risers_of_the_truth(k_m, prior_m):
    """Mixed 1-3 risers per stride, a wrong prior: the flight ends at n_total K, and back."""
    walker = _walker(ElevationParams(step_height_m=prior_m), seed=int(k_m * 1000))
    counts = walker.rng.choice([1, 2, 3], size=10, p=[0.3, 0.5, 0.2])
    walker.stride(0)
    up = walker.flight(1, counts, k_m)
    assert abs(up[-1].step_height_m - k_m) <= 0.0015
    # The flight's heights were corrected forward: the end is n_total risers of the estimate.
    assert up[-1].height_m == pytest.approx(counts.sum() * up[-1].step_height_m, abs=1e-9)
    assert abs(up[-1].height_m - walker.true_height_m) <= 0.03
    walker.stride(0)
    down = walker.flight(-1, counts[::-1], k_m)
    level = walker.stride(0)
    assert down[-1].height_m == pytest.approx(0.0, abs=1e-9)      # same stairwell, same K
    assert level.height_m == pytest.approx(0.0, abs=1e-9)


def test_a_second_staircase_of_another_riser_height_gets_its_own_estimate():
    walker = _walker(ElevationParams(step_height_m=0.17))
    walker.stride(0)
    walker.flight(1, [2] * 9, 0.15)
    for _ in range(5):
        walker.stride(0)
    second = walker.flight(1, [2] * 9, 0.19)
    walker.stride(0)
    assert walker.tracker.risers.stairwells == 2
    assert second[-1].step_height_m == pytest.approx(0.19, abs=0.0015)
    assert walker.tracker.height_m == pytest.approx(walker.true_height_m, abs=0.04)


def test_the_building_files_riser_height_is_used_exactly():
    tree = {'format': 'anfis_elevation_ros/building', 'version': 1, 'step_height_m': 0.16,
            'floors': [{'index': 0, 'elevation_m': 0.0}, {'index': 1, 'elevation_m': 2.88}]}
    walker = _walker(ElevationParams(step_height_m=0.17), building=building_from_dict(tree))
    flight = walker.flight(1, [2] * 9, 0.16)
    assert {e.step_height_m for e in flight} == {0.16}
    assert [e.height_m for e in flight] == pytest.approx([0.32 * (i + 1) for i in range(9)],
                                                         abs=1e-12)
    level = walker.stride(0)
    assert (level.floor, level.floor_certain) == (1, True)


def test_a_flights_first_stride_called_level_is_recovered_when_the_flight_shows():
    """The classifier calls the first stride of a flight down level: its risers still count."""
    tree = {'format': 'anfis_elevation_ros/building', 'version': 1, 'step_height_m': 0.17,
            'floors': [{'index': 0, 'elevation_m': 0.0}, {'index': 1, 'elevation_m': 3.06}]}
    walker = _walker(ElevationParams(), building=building_from_dict(tree))
    for _ in range(3):
        walker.stride(0)
    walker.model.outputs.append(0.0)                # the model says level ...
    walker.x_m += TREAD_M
    walker.true_height_m -= 0.17                    # ... but the stride went down a riser
    missed = walker.tracker.update(99, _features(-0.171), walker.x_m, 0.0)
    assert missed.height_m == 0.0
    flight = walker.flight(-1, [1] * 8, 0.17)
    assert flight[0].height_m == pytest.approx(-0.34, abs=1e-9)      # both strides counted
    assert flight[-1].height_m == pytest.approx(walker.true_height_m, abs=1e-9)
    assert walker.tracker.recovered_strides == 1
    # A level stride that reads a few centimetres (noise, a kerb) before a flight is level.
    before = walker.tracker.height_m
    walker.stride(0)
    walker.model.outputs.append(0.0)
    walker.x_m += 1.4
    walker.tracker.update(199, _features(0.04), walker.x_m, 0.0)     # 0.24 K: level
    walker.flight(1, [2] * 2, 0.17)
    assert walker.tracker.height_m == pytest.approx(before + 0.68, abs=1e-9)
    # Nor is a landing turn that reads 0.2 m (an INS glitch), the next flight going on back.
    walker.model.outputs.append(0.0)
    walker.tracker.update(299, _features(0.2), walker.x_m, 0.7)
    walker.model.outputs.append(1.0)
    walker.tracker.update(300, _features(0.34), walker.x_m - 0.56, 0.7)
    assert walker.tracker.height_m == pytest.approx(before + 1.02, abs=1e-9)
    # Nor a straight one that read 0.15 m where the flight's strides read 0.34 m (a glitch).
    walker.stride(0)
    walker.model.outputs.append(0.0)
    walker.tracker.update(399, _features(0.15), walker.x_m - 1.4, 0.7)
    walker.model.outputs.append(1.0)
    walker.tracker.update(400, _features(0.34), walker.x_m - 1.96, 0.7)
    assert walker.tracker.height_m == pytest.approx(before + 1.36, abs=1e-9)
    assert walker.tracker.recovered_strides == 1


def test_a_stride_called_level_that_climbed_two_risers_over_two_treads_is_counted_at_once():
    """Random walk 19 (consumer): the first stride down a flight called level, 2 risers."""
    walker = _walker(ElevationParams())
    for _ in range(3):
        walker.stride(0)
    walker.model.outputs.append(0.0)                # the model says level ...
    walker.x_m += 2 * TREAD_M
    walker.true_height_m -= 0.34                    # ... the stride went down two risers
    first = walker.tracker.update(99, _features(-0.342), walker.x_m, 0.0)
    assert first.mode == -1
    assert first.height_m == pytest.approx(-2 * first.step_height_m, abs=1e-12)   # 2 risers
    assert first.anfis_output == 0.0                # the classifier's own output is kept
    flight = walker.flight(-1, [2] * 8, 0.17)
    assert flight[-1].height_m / flight[-1].step_height_m == pytest.approx(-18, abs=1e-9)
    assert (walker.tracker.level_calls_overruled, walker.tracker.recovered_strides) == (1, 0)
    # A level stride of 1.4 m that reads 0.36 m (two risers, but no stairs are that long).
    walker.stride(0)
    walker.model.outputs.append(0.0)
    walker.x_m += 1.4
    level = walker.tracker.update(199, _features(0.36), walker.x_m, 0.0)
    assert (level.mode, level.height_m) == (0, flight[-1].height_m)
    assert walker.tracker.level_calls_overruled == 1


def test_a_landing_stride_called_level_after_a_flight_stays_level_whatever_it_read():
    """
    The seed replica, consumer IMU at 100 Hz, tilted mount: the level stride onto the landing.

    It read -0.46 m over 0.67 m (the filter booking, in the landing's turn, the height error
    the misalignment had built up); the classifier said level, and the stride's geometry, which
    took it for three risers down, left the height 0.45 m low for the rest of the walk.
    """
    walker = _walker(ElevationParams(step_height_m=0.15, **FIXED_K))
    for _ in range(8):
        walker.stride(0)
    flight = walker.flight(-1, [2] * 9, 0.15)
    walker.model.outputs.append(0.0)                # the model says level ...
    walker.x_m += 0.67
    walker.stamp += 1
    landing = walker.tracker.update(walker.stamp, _features(-0.457), walker.x_m, 0.0)
    assert landing.mode == 0                        # ... and the stride's geometry agrees
    assert landing.height_m == flight[-1].height_m
    assert flight[-1].height_m == pytest.approx(walker.true_height_m, abs=1e-9)
    assert walker.tracker.level_calls_overruled == 0
    walker.stride(0)
    after = walker.flight(-1, [2] * 9, 0.15)
    assert after[-1].height_m == pytest.approx(walker.true_height_m, abs=1e-9)
    assert walker.tracker.recovered_strides == 0


def test_a_flights_long_first_stride_from_the_floor_counts_the_risers_it_climbed():
    """
    Random walk 81 (consumer): the first stride up a flight went 0.91 m and one riser.

    It read 0.216 m (1.3 risers of the 0.17 m prior); counted within the risers its length
    fits as a stair stride (3-4 treads), it was three: 0.36 m high for the rest of the walk.
    From the floor before the stairs, only L >= n T_min holds.
    """
    walker = _walker(ElevationParams())
    for _ in range(8):
        walker.stride(0)
    walker.model.outputs.append(1.0)
    walker.x_m += 0.91
    walker.true_height_m += 0.15
    walker.stamp += 1
    first = walker.tracker.update(walker.stamp, _features(0.216), walker.x_m, 0.0)
    assert first.height_m == pytest.approx(first.step_height_m, abs=1e-12)      # one riser
    flight = walker.flight(1, [1] * 10, 0.15)
    assert flight[-1].height_m == pytest.approx(11 * flight[-1].step_height_m, abs=1e-12)
    assert abs(flight[-1].height_m - walker.true_height_m) < 0.05


def test_the_slope_learnt_on_level_strides_corrects_stair_strides():
    """A misaligned IMU: +20 mm per metre walked; strides up look taller, down shorter."""
    walker = _walker(ElevationParams(step_height_m=0.17))
    slope = 0.02

    def stride(mode, risers=0, length_m=1.4):
        walker.model.outputs.append(float(mode))
        length = length_m if mode == 0 else risers * TREAD_M
        walker.x_m += length
        walker.stamp += 1
        dh_m = mode * risers * 0.15 + slope * length
        return walker.tracker.update(walker.stamp, _features(dh_m), walker.x_m, 0.0)

    for _ in range(6):
        stride(0)
    up = [stride(1, 2) for _ in range(9)]
    assert up[-1].step_height_m == pytest.approx(0.15, abs=0.001)
    assert walker.tracker.slope.slope == pytest.approx(slope)


@pytest.mark.parametrize('level_noise_m, expected_wells', [(0.001, 2), (0.015, 1)])
def test_stairs_6_mm_apart_are_told_apart_on_a_sensor_whose_level_strides_say_it_can(
        level_noise_m, expected_wells):
    """
    Tell two storeys' stairs, risers 0.149 and 0.155 m, apart (random walk 116).

    The level strides' scatter sets the stride noise (at most the default 10 mm): 1 mm of
    scatter tells the stairs apart, 15 mm does not.
    """
    walker = _walker(ElevationParams(step_height_m=0.17), seed=2)
    for k_m in (0.149, 0.155):
        for _ in range(12):
            walker.stride(0, noise_m=level_noise_m)
        for _ in range(16):
            walker.stride(1, 1, k_m, noise_m=0.001)
    walker.stride(0, noise_m=level_noise_m)
    assert walker.tracker.risers.stairwells == expected_wells
    if expected_wells == 2:     # one stairwell would be 16 x 3 mm off
        assert walker.tracker.height_m == pytest.approx(walker.true_height_m, abs=0.01)


# ------------------------------------------------------------------------------ floors

def test_the_floor_changes_only_when_the_height_settles_no_flicker():
    """Two flights with a landing at half a storey: no floor change until the level floor."""
    params = ElevationParams(step_height_m=0.15, **FIXED_K, **KNOWN_3M_STOREYS)
    walker = _walker(params)
    walker.stride(0)
    seen = [(e.floor, e.floor_certain) for e in walker.flight(1, [2] * 5, 0.15)]   # 1.50 m
    seen += [(e.floor, e.floor_certain) for e in (walker.stride(0, length_m=0.7),
                                                  walker.stride(0, length_m=0.7))]
    seen += [(e.floor, e.floor_certain) for e in walker.flight(1, [2] * 5, 0.15)]  # 3.00 m
    assert set(seen) == {(0, False)}                  # stairs and the mid-storey landing
    assert [(e.floor, e.floor_certain) for e in (walker.stride(0), walker.stride(0))] == [
        (1, True), (1, True)]


def test_floors_from_a_building_with_a_taller_lobby_and_its_start():
    tree = {'format': 'anfis_elevation_ros/building', 'version': 1,
            'floors': [{'index': -1, 'elevation_m': -3.0}, {'index': 0, 'elevation_m': 0.0},
                       {'index': 1, 'elevation_m': 4.5}, {'index': 2, 'elevation_m': 7.5}],
            'start': {'x_m': 0.0, 'y_m': 0.0, 'floor': 0, 'heading_deg': 0.0}}
    params = ElevationParams(step_height_m=0.15, start_floor=5, **FIXED_K)   # file's start wins
    walker = _walker(params, building=building_from_dict(tree))
    assert (walker.tracker.floor, walker.tracker.floor_certain) == (0, True)
    walker.flight(1, [2] * 15, 0.15)                                          # 4.50 m
    assert walker.stride(0).floor == 1      # uniform 3 m storeys would say 2 (4.5 / 3 = 1.5)
    walker.flight(1, [2] * 10, 0.15)
    assert walker.stride(0).floor == 2
    walker.flight(-1, [2] * 25, 0.15)
    walker.flight(-1, [2] * 10, 0.15)
    assert (walker.stride(0).floor, walker.tracker.height_m) == (-1, pytest.approx(-3.0))
    del tree['start']
    with pytest.raises(ValueError, match='start_floor 5 is not a floor'):
        ElevationTracker(ScriptedModel([]), params, building=building_from_dict(tree))


def test_level_but_off_every_floor_is_not_certain_and_keeps_the_floor():
    tracker = ElevationTracker(ScriptedModel([1.0] * 8 + [0.0]),
                               ElevationParams(step_height_m=0.15, **FIXED_K))
    for i in range(8):
        tracker.update(i, _features(0.15), 0.0, 0.0)                       # 1.20 m
    level = tracker.update(8, _features(0.0), 0.0, 0.0)
    assert (level.floor, level.floor_certain) == (0, False)


def test_a_resumed_estimate_carries_on():
    walker = _walker(ElevationParams(step_height_m=0.17))
    walker.flight(1, [2] * 9, 0.15)
    walker.stride(0)
    saved_k, saved_strides = walker.tracker.step_height_m, walker.tracker.risers.strides
    assert (saved_k, saved_strides) == (pytest.approx(0.15, abs=0.0015), 9)
    resumed = _walker(ElevationParams(step_height_m=0.17))
    resumed.tracker.reset(walker.tracker.height_m)
    resumed.tracker.risers.resume(saved_k, saved_strides)
    assert resumed.tracker.step_height_m == saved_k
    first = resumed.flight(1, [1], 0.15)[0]       # one ambiguous stride does not undo it
    assert first.step_height_m == pytest.approx(saved_k, abs=0.001)


def test_a_level_stretch_off_every_floor_moves_to_the_nearest_uncertain():
    """5.4 m down with 3 m storeys: not a floor, but after a level stretch floor -2, in doubt."""
    walker = _walker(ElevationParams(step_height_m=0.15, **FIXED_K, **KNOWN_3M_STOREYS))
    walker.flight(-1, [2] * 18, 0.15)
    stretch = [walker.stride(0) for _ in range(4)]
    assert [(e.floor, e.floor_certain) for e in stretch] == [
        (0, False), (0, False), (-2, False), (-2, False)]


def test_a_height_settled_on_a_building_floor_takes_its_elevation():
    tree = {'format': 'anfis_elevation_ros/building', 'version': 1,
            'floors': [{'index': 0, 'elevation_m': 0.0}, {'index': 1, 'elevation_m': 2.88}]}
    walker = _walker(ElevationParams(step_height_m=0.15, **FIXED_K),
                     building=building_from_dict(tree))
    walker.flight(1, [1] * 19, 0.15)                          # 2.85 m: 3 cm short of the floor
    level = walker.stride(0)
    assert (level.floor, level.floor_certain, level.height_m) == (1, True, 2.88)
    # Without a file the storeys are a guess: nothing is snapped.
    free = _walker(ElevationParams(step_height_m=0.15, floor_height_m=2.88, **FIXED_K))
    free.flight(1, [1] * 19, 0.15)
    assert free.stride(0).height_m == pytest.approx(2.85, abs=1e-12)


@pytest.mark.parametrize('storey_m', [2.8, 3.0, 3.3, 3.6, 4.0, 4.5])
@pytest.mark.parametrize('lobby_m', [None, 4.2, 6.0])
def test_without_a_building_file_no_storey_height_gives_a_wrong_floor_that_is_certain(
        storey_m, lobby_m):
    """Storeys of 2.8-4.5 m, lobby up to 6 m: the floor is right whenever it says certain."""
    k_m = 0.15
    storeys = [lobby_m or storey_m] + [storey_m] * 5
    walker = _walker(ElevationParams(step_height_m=k_m, **FIXED_K))
    true_m = 0.0
    for floor, storey in enumerate(storeys, start=1):
        risers = round(storey / k_m)
        walker.flight(1, [2] * (risers // 2) + [1] * (risers % 2), k_m)
        true_m += risers * k_m
        stretch = [walker.stride(0) for _ in range(4)]
        assert stretch[-1].height_m == pytest.approx(true_m, abs=1e-9)
        assert all(e.floor == floor for e in stretch if e.floor_certain), (floor, true_m)
        if lobby_m != 6.0:      # each floor from the one below (a 6 m lobby: floor 1 or 2)
            assert stretch[-1].floor_certain, (floor, true_m)


def test_without_a_building_file_the_floors_a_height_can_be_on():
    """C(h) = {f : E_f,min - tol <= h <= E_f,max + tol}, storeys 2.8-4.5 m, lobby 6 m."""
    floors = floor_map_for(None, 0, 3.0, (2.8, 4.5), 6.0)
    assert floors.elevation_range_m(0) == (0.0, 0.0)
    assert floors.elevation_range_m(1) == (2.8, 6.0)                  # the lobby
    assert floors.elevation_range_m(3) == pytest.approx((8.4, 15.0))
    assert floors.elevation_range_m(-2) == pytest.approx((-9.0, -5.6))
    assert floors.candidates(12.0, 0.5) == (3, 4)            # 3 of 4 m or 4 of 3 m
    assert floors.place(12.0, 0.5) == (4, False)             # the guess of 3 m, in doubt
    assert floors.place(3.2, 0.5) == (1, True)               # both agree
    assert floors.place(4.9, 0.5) == (1, False)              # floor 1 alone, no 3 m storey
    assert floors.place(5.5, 0.5) == (2, False)              # floor 1 or 2
    assert floors.place(1.5, 0.5) == (1, False)              # between floors: none fits
    assert floors.place(-8.0, 0.5) == (-3, False)            # -2 (of 4 m) or -3
    assert floors.place(-5.8, 0.5) == (-2, True)
    started_on_2 = floor_map_for(None, 2, 3.0, (2.8, 4.5), 6.0)
    assert started_on_2.elevation_range_m(3) == pytest.approx((2.8, 4.5))     # no lobby crossed
    assert started_on_2.elevation_range_m(1) == pytest.approx((-4.5, -2.8))
    assert started_on_2.elevation_range_m(0) == pytest.approx((-10.5, -5.6))  # lobby crossed
    assert started_on_2.elevation_range_m(-1) == pytest.approx((-15.0, -8.4))  # lobby crossed
    known = floor_map_for(None, 0, 3.0)                      # storeys known to be 3 m
    assert known.place(12.0, 0.5) == (4, True)
    assert known.place(13.0, 0.5) == (4, False)
    assert floor_map_for(None, 0, 2.5, (2.8, 4.5)).storey_range_m == (2.5, 4.5)   # holds H


def test_the_floors_walked_narrow_the_floors_a_height_can_be_on():
    """I(h) = C(h) & C_a(h - h_a): floor 1 walked at 4.0 m, storeys 2.8-4.5 m, lobby 6 m."""
    settler = FloorSettler(floor_map_for(None, 0, 3.0, (2.8, 4.5), 6.0), 0.5, 0.0)
    assert settler.anchors == {0: 0.0}                          # the start floor
    assert settler.candidates(8.0) == (2, 3)
    assert [settler.update(4.0, 0, (1.4 * k, 0.0)) for k in range(3)] == [0, 0, 1]
    assert not settler.certain                      # 2.8 m from the stairs: maybe a landing
    assert (settler.update(4.0, 0, (4.2, 0.0)), settler.certain) == (1, True)
    assert settler.anchors == {0: 0.0, 1: 4.0}
    assert settler.candidates(8.0) == (2, 2)                    # one storey above floor 1
    assert settler.candidates(12.0) == (3, 4)                   # two of 4 m or three of 2.7 m
    assert settler.candidates(6.0) is None                      # 2 m above floor 1: no storey
    settler.forget_anchors()
    assert settler.candidates(8.0) == (2, 3)


def _climb_two_storeys_of_4_m(walker, lose=None):
    """Two storeys of 25 risers of 0.16 m, level stretches between; ``lose`` goes unseen."""
    estimates = []
    for storey in range(2):
        for at, risers in enumerate([0] * 4 + [2] * 12 + [1] + [0] * 4):
            if (storey, at) == lose:             # (storey, stride), the stride unobserved
                walker.stamp += 1
                walker.x_m += 0.5
                walker.true_height_m += risers * 0.16
                walker.tracker.update(walker.stamp, _features(0.0), walker.x_m, 0.0,
                                      valid=False)
            else:
                estimates.append(walker.stride(int(risers > 0), risers, 0.16))
    return estimates


def test_the_floors_walked_stand_for_the_storey_height_until_a_climb_goes_unseen():
    """Storeys of 4 m, nobody said: floor 2 is certain from floor 1, not after lost stairs."""
    params = ElevationParams(step_height_m=0.16, **FIXED_K)
    walker = _walker(params)
    last = _climb_two_storeys_of_4_m(walker)[-1]
    assert (last.height_m, last.floor, last.floor_certain) == (pytest.approx(8.0), 2, True)
    kept = _walker(params)                                       # lost on the level: no climb
    assert _climb_two_storeys_of_4_m(kept, lose=(0, 19))[-1].floor_certain
    lost = _walker(params)                                       # lost on the stairs: bridged
    last = _climb_two_storeys_of_4_m(lost, lose=(1, 8))[-1]
    assert last.height_m == pytest.approx(lost.true_height_m) == pytest.approx(8.0)
    assert (last.floor_certain, last.floor_range) == (False, (2, 3))
    # Lost in the first storey: at 4.0 m only floor 1 fits, but no floor walked says so and
    # the guess of 3 m does not either; lost stair strides give such heights: no range.
    lost = _walker(params)
    first = [e for e in _climb_two_storeys_of_4_m(lost, lose=(0, 8))
             if e.height_m == pytest.approx(4.0)][-1]
    assert (first.floor, first.floor_certain, first.floor_range) == (1, False, None)


def test_a_landing_a_storeys_height_above_a_floor_walked_is_no_floor():
    """Storeys of 3.6 m in three flights: the landing at 2.4 m, walked round, is no floor."""
    walker = _walker(ElevationParams(step_height_m=0.15, **FIXED_K))
    for floor in (1, 2):
        for _ in range(4):
            walker.stride(0)                                   # the corridor: 5.6 m
        walker.flight(1, [2] * 4, 0.15)
        walker.stride(0, length_m=0.7)                         # the first landing's turn
        walker.flight(1, [2] * 4, 0.15)
        landing = [walker.stride(0, length_m=0.5) for _ in range(5)]    # round the second
        assert landing[-1].height_m == pytest.approx(3.6 * floor - 1.2)
        assert {e.floor_certain for e in landing} == {False}   # 2.4 m above a floor walked
        walker.flight(1, [2] * 4, 0.15)
        corridor = [walker.stride(0) for _ in range(4)]
        assert (corridor[-1].floor, corridor[-1].floor_certain) == (floor, True)


def test_a_landing_walked_round_at_the_guess_of_3_m_is_no_floor_either():
    """No floors walked (a stride lost on the stairs): the landing 3.0 m up a 4.5 m storey."""
    walker = _walker(ElevationParams(step_height_m=0.15, **FIXED_K))
    for _ in range(4):
        walker.stride(0)
    walker.flight(1, [2] * 2, 0.15)
    walker.stamp += 1                                          # a stride of 2 risers unseen
    walker.tracker.update(walker.stamp, _features(0.0), walker.x_m, 0.0, valid=False)
    walker.flight(1, [2] * 2, 0.15)                            # bridged: 1.5 m
    walker.stride(0, length_m=0.7)
    walker.flight(1, [2] * 5, 0.15)
    landing = [walker.stride(0, length_m=0.5) for _ in range(5)]     # 2.5 m round it
    assert walker.tracker.floors.anchors == {}
    assert landing[-1].height_m == pytest.approx(3.0)
    assert {e.floor_certain for e in landing} == {False}       # the guess alone would say 1


def test_the_floors_a_height_can_be_on_are_published_after_a_level_stretch():
    """Floor range: (f, f) while certain, None on the stairs, C(h) on a level stretch."""
    walker = _walker(ElevationParams(step_height_m=0.15, **FIXED_K))
    assert walker.tracker.floor_range == (0, 0)
    climb = walker.flight(1, [2] * 40, 0.15)                  # 12 m: floor 3 of 4 m, 4 of 3 m
    assert {e.floor_certain for e in climb} == {False}
    assert walker.tracker.floor_range is None
    stretch = [walker.stride(0) for _ in range(3)]
    assert walker.tracker.floor_range == (3, 4)
    assert (stretch[-1].floor, stretch[-1].floor_certain) == (4, False)
    known = _walker(ElevationParams(step_height_m=0.15, **FIXED_K, **KNOWN_3M_STOREYS))
    known.flight(1, [2] * 40, 0.15)
    assert (known.stride(0).floor_certain, known.tracker.floor_range) == (True, (4, 4))
