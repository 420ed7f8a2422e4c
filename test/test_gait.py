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

"""Gait-cycle segmentation and the five features, eq. (8)-(12)."""

import math

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.frames import rpy_to_dcm
from anfis_elevation_ros.core.gait import (
    feature_index, foot_inclination, GaitParams, GaitSegmenter, height_features,
    landing_height_correction, max_relative_pitch, MountingEstimator)
import numpy as np
import pytest

RATE_HZ = 100.0


def test_height_features_hand_computed():
    h = np.array([0.1, 0.3, 0.2])
    mean = 0.2
    std = math.sqrt(((0.1 - mean) ** 2 + (0.3 - mean) ** 2 + 0.0) / 3)
    assert np.allclose(height_features(h), [mean, std, 0.2, 0.3])
    assert height_features(np.array([-0.05, -0.4, -0.17]))[3] == pytest.approx(0.4)


def test_inclination_is_toe_up_positive():
    # REP 103: a positive pitch about y (left) lowers the nose, so toe-up is pitch -theta.
    for theta in (-0.6, 0.0, 0.3):
        up_b = rpy_to_dcm(0.0, -theta, 0.7)[2, :]
        assert foot_inclination(up_b, np.array([1.0, 0.0, 0.0])) == pytest.approx(theta)


def test_pitch_is_relative_to_stance_so_a_tilted_mount_does_not_bias_it():
    forward_b = np.array([1.0, 0.0, 0.0])
    stance_up_b = rpy_to_dcm(0.0, -0.2, 0.0)[2, :]  # mounted 0.2 rad toe-up at rest
    swing_up_b = np.array([rpy_to_dcm(0.0, -0.2 - a, 0.0)[2, :] for a in (0.1, 0.35, -0.5)])
    assert max_relative_pitch(swing_up_b, stance_up_b, forward_b) == pytest.approx(0.35)


def run_segmenter(heights, stance, params=GaitParams(), gaps=None, zupt_dx=None):
    segmenter = GaitSegmenter(params, RATE_HZ, MountingEstimator(params, np.eye(3)))
    cycles = []
    for k, (h, still) in enumerate(zip(heights, stance)):
        cycle = segmenter.update(k * 10_000_000, still, np.array([0.01 * k, 0.0, h]), np.eye(3),
                                 np.array([0.0, 0.0, 9.81]), np.zeros(3), np.zeros(3),
                                 gap=bool(gaps is not None and gaps[k]),
                                 zupt_dx=None if zupt_dx is None else zupt_dx[k])
        if cycle is not None:
            cycles.append(cycle)
    return cycles


def step_up(swing_samples, rise_m):
    swing = rise_m * np.sin(np.linspace(0, np.pi / 2, swing_samples))
    heights = np.concatenate([np.zeros(20), swing, np.full(20, rise_m)])
    stance = np.concatenate([np.ones(20), np.zeros(swing_samples), np.ones(20)]).astype(bool)
    return heights, stance


def test_a_stride_makes_one_cycle_closed_by_its_first_stance_sample():
    heights, stance = step_up(50, 0.17)
    cycles = run_segmenter(heights, stance)
    assert len(cycles) == 1
    cycle = cycles[0]
    assert cycle.stamp_ns == 70 * 10_000_000 and cycle.start_stamp_ns == 19 * 10_000_000
    assert cycle.valid and cycle.height_change_m == pytest.approx(0.17)
    assert cycle.features[3] == pytest.approx(0.17)
    assert np.allclose(cycle.pos_n, [0.7, 0.0, 0.17])


def test_landing_height_correction_keeps_what_the_swing_explains():
    # Walk 519 (consumer): +0.388 m at a landing whose vertical velocity moved 0.011 m/s.
    assert landing_height_correction(0.388, 0.011, 0.81) == pytest.approx(0.011 * 0.81)
    assert landing_height_correction(0.388, -0.011, 0.81) == pytest.approx(0.011 * 0.81)
    assert landing_height_correction(-0.3, 0.1, 1.0) == pytest.approx(-0.1)
    assert landing_height_correction(-0.05, 0.2, 0.5) == pytest.approx(-0.05)
    assert landing_height_correction(0.02, 0.0, 0.5) == 0.0


@pytest.mark.parametrize('dpos_z, dvel_z, rise_m, height_change_m', [
    (0.388, 0.011, 0.0, 0.011 * 0.51),   # it takes back 0.39 m from before: a level stride
    (0.03, 0.12, 0.17, 0.2),             # the swing's own error corrected: all of it counts
])
def test_a_landing_counts_only_the_correction_its_swing_explains(dpos_z, dvel_z, rise_m,
                                                                 height_change_m):
    heights, stance = step_up(50, rise_m)
    heights[70:] += dpos_z       # the closing sample's ZUPT moved the track by dpos_z
    zupt_dx = np.zeros((len(heights), 6))
    zupt_dx[70] = [0.0, 0.0, dpos_z, 0.0, 0.0, dvel_z]
    cycle, = run_segmenter(heights, stance, zupt_dx=zupt_dx)     # a swing of 0.51 s
    assert cycle.height_change_m == pytest.approx(height_change_m)
    assert cycle.pos_n[2] == pytest.approx(rise_m + dpos_z)    # the absolute height moves


def run_with_late_stance(heights, stance, late_at, age, dpos, dvel, max_slope):
    """Segment a walk along x (1 cm a sample) with a late stance found at one sample."""
    segmenter = GaitSegmenter(GaitParams(), RATE_HZ, MountingEstimator(GaitParams(), np.eye(3)))
    cycles = []
    for k, (h, still) in enumerate(zip(heights, stance)):
        cycle = segmenter.update(k * 10_000_000, still, np.array([0.01 * k, 0.0, h]), np.eye(3),
                                 np.zeros(3), np.zeros(3), np.zeros(3))
        if k == late_at:
            late = segmenter.late_stance(age, dpos, dvel, max_slope)
            cycle = cycle if late is None else late
        if cycle is not None:
            cycles.append(cycle)
    return cycles


def test_a_late_stance_on_stairs_is_carried_back_to_the_samples_since_it_and_cuts_nothing():
    # One swing (samples 20-119) over two strides up 0.34 m; at sample 99 a late stance 30
    # samples back (sample 69, 0.5 m from the stance, 0.17 m up: a slope of 0.34) was found and
    # its ZUPT moved the position by dpos and the velocity by dvel: sample j, t_j before 99, by
    # dpos - dvel t_j (the height) and dvel (the velocity).
    heights = np.concatenate([np.zeros(20), np.linspace(0.0, 0.34, 100), np.full(20, 0.34)])
    stance = np.concatenate([np.ones(20), np.zeros(100), np.ones(20)]).astype(bool)
    dpos, dvel = np.array([0.0, 0.0, 0.01]), np.array([0.5, 0.0, 0.02])
    cycles = run_with_late_stance(heights, stance, 99, 30, dpos, dvel, 0.2)
    assert len(cycles) == 1 and cycles[0].start_stamp_ns == 19 * 10_000_000
    held = heights[20:121].copy()                 # the swing and the closing stance sample
    held[69 - 20:99 - 20] += 0.01 - 0.02 * (99 - np.arange(69, 99)) / RATE_HZ
    features = cycles[0].features
    assert features[feature_index(['mean_height_m'])[0]] == pytest.approx(np.mean(held))
    assert features[feature_index(['max_horizontal_speed_mps'])[0]] == pytest.approx(0.5)


def test_a_late_stance_on_level_ground_closes_the_cycle_there():
    # The same swing on level ground, each stride's foot lifted 0.1 m: the late stance at
    # sample 69 closes a cycle there; the next one starts from it, its heights from its
    # corrected height; with no slope allowed the swing stays one cycle.
    lift = 0.1 * np.sin(np.linspace(0.0, 2.0 * np.pi, 100)) ** 2
    heights = np.concatenate([np.zeros(20), lift, np.zeros(20)])
    stance = np.concatenate([np.ones(20), np.zeros(100), np.ones(20)]).astype(bool)
    dpos, dvel = np.array([0.02, 0.0, 0.01]), np.array([0.1, 0.0, 0.02])
    first, second = run_with_late_stance(heights, stance, 99, 30, dpos, dvel, 0.2)
    assert (first.start_stamp_ns, first.stamp_ns) == (19 * 10_000_000, 69 * 10_000_000)
    assert (second.start_stamp_ns, second.stamp_ns) == (69 * 10_000_000, 120 * 10_000_000)
    correction = dpos - dvel * ((99 - np.arange(69, 99)) / RATE_HZ)[:, None]
    assert first.pos_n == pytest.approx([0.69 + correction[0][0], 0.0,
                                         heights[69] + correction[0][2]])
    corrected = heights[69:121].copy()
    corrected[:30] += correction[:, 2]
    mean_height = feature_index(['mean_height_m'])[0]
    assert second.features[mean_height] == pytest.approx(np.mean(corrected[1:] - corrected[0]))
    assert len(run_with_late_stance(heights, stance, 99, 30, dpos, dvel, 0.0)) == 1


@pytest.mark.parametrize('rise_m, cycles', [(0.0, 3), (0.34, 2)])
def test_a_late_stance_after_a_stair_stride_closes_no_cycle(rise_m, cycles):
    # A first stride 0.5 m long that rises rise_m, then the level two-stride swing above with
    # its late stance: closed after a level stride, not after a stair stride (the foot of a
    # flight, where HuGaDB's cut cycles were called wrong).
    lift = 0.1 * np.sin(np.linspace(0.0, 2.0 * np.pi, 100)) ** 2
    heights = np.concatenate([np.zeros(20), np.linspace(0.0, rise_m, 50), np.full(20, rise_m),
                              rise_m + lift, np.full(20, rise_m)])
    stance = np.concatenate([np.ones(20), np.zeros(50), np.ones(20), np.zeros(100),
                             np.ones(20)]).astype(bool)
    found = run_with_late_stance(heights, stance, 169, 30, np.zeros(3), np.zeros(3), 0.2)
    assert len(found) == cycles


def test_a_late_stance_outside_a_swing_or_the_held_samples_corrects_nothing():
    heights, stance = step_up(50, 0.17)

    def cycle(late_at):
        segmenter = GaitSegmenter(GaitParams(), RATE_HZ,
                                  MountingEstimator(GaitParams(), np.eye(3)))
        for k, (h, still) in enumerate(zip(heights, stance)):
            closed = segmenter.update(k * 10_000_000, still, np.array([0.01 * k, 0.0, h]),
                                      np.eye(3), np.zeros(3), np.zeros(3), np.zeros(3))
            if k in late_at:
                assert segmenter.late_stance(late_at[k], np.ones(3), np.ones(3), 0.0) is None
            if closed is not None:
                return closed.features
    plain = cycle({})
    assert cycle({10: 2}) == pytest.approx(plain)           # in the stand before the walk
    assert cycle({30: 20}) == pytest.approx(plain)          # reaching back before the swing
    assert cycle({40: 5}) != pytest.approx(plain)           # inside it


def test_short_swings_are_no_cycle_and_long_ones_are_invalid():
    assert run_segmenter(*step_up(10, 0.0)) == []  # 0.1 s < min_swing_s
    long_cycles = run_segmenter(*step_up(300, 0.17))  # 3 s > max_swing_s
    assert len(long_cycles) == 1 and not long_cycles[0].valid


def test_a_gap_in_the_swing_invalidates_the_cycle():
    heights, stance = step_up(50, 0.17)
    gaps = np.zeros(len(heights), bool)
    gaps[40] = True
    assert not run_segmenter(heights, stance, gaps=gaps)[0].valid


def test_automatic_mounting_learns_the_forward_axis_from_strides():
    params = GaitParams(mounting_strides=3)
    estimator = MountingEstimator(params)
    C_nb = rpy_to_dcm(0.3, 0.1, 1.0)  # body axes rotated from the navigation frame
    forward_b = C_nb.T @ np.array([math.cos(0.4), math.sin(0.4), 0.0])
    for _ in range(3):
        used = estimator.forward_for_cycle(np.array([math.cos(0.4), math.sin(0.4), 0.2]), C_nb)
    assert estimator.fixed and np.allclose(used, forward_b)
    # Once learnt, a turn on the spot (no stride) keeps the axis.
    assert np.allclose(estimator.forward_for_cycle(np.zeros(3), C_nb), forward_b)


@pytest.mark.parametrize('kwargs', [{'min_swing_s': 3.0}, {'max_swing_s': 20.0},
                                    {'min_stride_m': 0.0}, {'mounting_strides': 0}])
def test_bad_gait_parameters_raise(kwargs):
    with pytest.raises(InputError):
        GaitParams(**kwargs)
