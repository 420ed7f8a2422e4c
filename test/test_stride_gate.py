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

"""The stride gate: one gait-cycle stance between two swings, relaxed stances, mid-swing dips."""

import math

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.core.stride_gate import (
    initial_state, LATE_AGE, PERIOD_S, samples_to_relaxed_stance, stride_gate_update,
    StrideGateParams)
from anfis_elevation_ros.sim import Segment, simulate_walk
from anfis_elevation_ros.tools.gdin_hallway import GYRO_RANGE_RPS
from gdin_support import gdin_walk
import numpy as np
import pytest

RATE_HZ = 100.0
GAMMA = 1.0e7
PARAMS = StrideGateParams(enabled=True, relaxed_factor=3.0, relaxed_floor=0.0,
                          refractory_fraction=0.7,
                          swing_level=1e9, swing_arm_s=0.05, confirm_s=0.05, late_stances=True)


# The error covariance of a filter sure of its velocity to 0.05 m/s (a ZUPT's NIS: |v|^2 / 0.005)
P_SURE = np.eye(15) * 0.05 ** 2


def run(statistics, shoe_stance, params=PARAMS):
    """Return the gate's flags for each sample and its final state."""
    flags, _, state = run_with_ages(statistics, shoe_stance, params)
    return flags, state


def run_with_ages(statistics, shoe_stance, params=PARAMS, vel_n=np.zeros(3), P=P_SURE,
                  young_max_nis=600.0):
    """Return the flags, the sample each late stance names (-1 elsewhere), the final state."""
    state, config = initial_state(), params.config(RATE_HZ)
    flags, late = [], []
    for k, (t, s) in enumerate(zip(statistics, shoe_stance)):
        flags.append(stride_gate_update(state, config, t, GAMMA, s, vel_n, P, young_max_nis))
        late.append(k - int(state[LATE_AGE]) if flags[-1] & 8 else -1)
    return np.array(flags), np.array(late), state


def stride(stance, swing_s=0.5, stance_s=0.5, dip=None):
    """
    Return one stride at 100 Hz.

    A swing (1e10), with a 3-sample dip to ``dip`` in its middle, then a stance whose
    statistic falls to 0.9 ``stance`` in its middle and rises again to 1.35 ``stance`` (SHOE
    stance where below GAMMA).
    """
    swing = np.full(int(swing_s * RATE_HZ), 1e10)
    if dip is not None:
        middle = len(swing) // 2
        swing[middle:middle + 3] = dip
    n = int(stance_s * RATE_HZ)
    rest = 0.9 * stance * (1.0 + 0.5 * np.abs(np.arange(n) - n // 2) / (n // 2))
    return np.concatenate((swing, rest))


def strides_with_a_dip(swing_samples, dip, value, count):
    """Return a stand of 0.5 s, then strides: a swing with ``value`` at ``dip``, a stance."""
    swing = np.full(swing_samples, 1e10)
    swing[dip] = value
    return np.concatenate([np.full(50, 1e5)] + [swing, np.full(50, 1e6)] * count)


def cycles_opened(flags):
    """Return the number of gait stances that follow a sample that was none."""
    return len(np.flatnonzero((flags & 2 == 2) & np.r_[True, flags[:-1] & 2 == 0]))


def test_a_shoe_stance_after_a_swing_opens_a_cycle_and_stays_one():
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(1e6) for _ in range(3)])
    flags, _ = run(statistics, statistics < GAMMA)
    assert np.all((flags & 1 == 1) == (statistics < GAMMA))
    # gait stance on every stance sample (no swing inside a stance), ZUPT everywhere stance
    assert np.all((flags & 2 == 2) == (statistics < GAMMA))
    assert not np.any(flags & 4)
    openings = np.flatnonzero(np.diff((flags & 2 == 2).astype(int)) == 1)
    assert len(openings) == 3


def test_a_stance_above_gamma_is_found_at_its_stillest_sample_after_confirmation():
    # The stance never goes below gamma (2e7 > 1e7) but is below 3 gamma.
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(2e7) for _ in range(4)])
    flags, state = run(statistics, statistics < GAMMA)
    relaxed = np.flatnonzero(flags & 4)
    assert len(relaxed) == 4
    assert np.all(flags[relaxed] == 1 + 2 + 4)
    # 5 samples (confirm_s = 0.05 s) after each stance's stillest sample (0.9 x 2e7).
    minima = np.flatnonzero(statistics == 0.9 * 2e7)
    assert np.array_equal(relaxed, minima + 5)
    assert state[PERIOD_S] == pytest.approx(1.0)   # strides of 1 s


def test_a_relaxed_stance_whose_zupt_is_implausible_is_no_stance():
    # Random walk 524: a foot dropping down a 4-riser stride at 2.3 m/s without turning looks
    # still; as a young SHOE stance, its ZUPT's NIS (here 2^2 / (0.05^2 + 0.02^2) = 1379)
    # refuses it, and the refusal is flagged (16) for the diagnostics. The refused minimum
    # stays the gate's: the next strides' stances, no lower, are no relaxed stances either.
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(2e7) for _ in range(4)])
    falling = np.array([0.0, 0.0, -2.0])
    flags, _, _ = run_with_ages(statistics, statistics < GAMMA, vel_n=falling)
    assert not np.any(flags & 4) and np.count_nonzero(flags == 16) == 1
    # A lower statistic after the refusal is examined again (and refused again at that speed).
    lower = np.concatenate([statistics, stride(1.5e7)])
    flags, _, _ = run_with_ages(lower, lower < GAMMA, vel_n=np.array([0.0, 0.0, -2.0]))
    assert np.count_nonzero(flags == 16) == 2 and not np.any(flags & 4)
    # Slower (NIS 31), or with the young-stance rule off (0), it is a stance.
    for vel_n, young_max_nis in ((np.array([0.0, 0.0, -0.3]), 600.0), (falling, 0.0)):
        flags, _, _ = run_with_ages(statistics, statistics < GAMMA, vel_n=vel_n,
                                    young_max_nis=young_max_nis)
        assert np.count_nonzero(flags & 4) == 4 and not np.any(flags & 16)


def test_the_relaxed_stance_is_foreseen_by_a_countdown():
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(2e7) for _ in range(2)])
    state, config = initial_state(), PARAMS.config(RATE_HZ)
    foreseen, relaxed = [], []
    for k, t in enumerate(statistics):
        if stride_gate_update(state, config, t, GAMMA, t < GAMMA, np.zeros(3), P_SURE, 600.0) & 4:
            relaxed.append(k)
        foreseen.append(samples_to_relaxed_stance(state, config, GAMMA))
    assert len(relaxed) == 2
    for k in relaxed:
        assert foreseen[k - 5:k] == [5, 4, 3, 2, 1] and foreseen[k] == -1


def test_a_stance_far_above_gamma_is_refused():
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(4e7) for _ in range(3)])
    flags, _ = run(statistics, statistics < GAMMA)
    assert np.all(flags[:50] == 3)             # the stand before the walk
    assert not np.any(flags[50:] & 7)          # no ZUPT (late stances: below)


def test_a_brief_dip_followed_by_the_impact_is_refused():
    # A 2-sample dip (1.5e7, below 3 gamma) just before the heel strike: 5 samples later, at
    # the confirming sample, the statistic is the impact's (1e10), not a stance's.
    swing = np.full(100, 1e10)
    swing[60:62] = 1.5e7
    statistics = np.concatenate([np.full(50, 1e5), swing])
    flags, _ = run(statistics, statistics < GAMMA)
    assert not np.any(flags[50:])


def test_the_relaxed_floor_takes_stances_above_the_relative_bound():
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(4e7) for _ in range(3)])
    params = StrideGateParams(enabled=True, relaxed_floor=5e7, swing_arm_s=0.05,
                              confirm_s=0.05)
    flags, _ = run(statistics, statistics < GAMMA, params)
    assert len(np.flatnonzero(flags & 4)) == 3


def test_a_mid_swing_dip_below_the_bound_is_refused_inside_the_refractory_period():
    # Strides of 1 s; the dip comes 0.25 s after the swing starts, 0.45 s after the last
    # stance opened: inside 0.7 x the stride period. Its value (1.5e7) is below the stance's.
    # (The first swing after a stand has no last opening to count from: no dip in it.)
    strides = [stride(2e7)] + [stride(2e7, dip=1.5e7) for _ in range(4)]
    statistics = np.concatenate([np.full(50, 1e5)] + strides)
    flags, _ = run(statistics, statistics < GAMMA)
    relaxed = np.flatnonzero(flags & 4)
    minima = np.flatnonzero(statistics == 0.9 * 2e7)
    assert np.array_equal(relaxed, minima + 5)


def test_a_hover_mid_swing_after_a_long_stance_is_no_stance():
    # Stairs (x-io's spiral stairs): stances of 0.5 s, swings of 0.6 s in which the foot
    # hovers over the next step for 0.1 s. 0.7 of the 1.1 s stride period after a stance
    # began falls in that hover; counted from the stance's end it does not.
    statistics = strides_with_a_dip(60, slice(25, 35), 1.5e7, 6)
    flags, _ = run(statistics, statistics < GAMMA)
    assert not np.any(flags & 4)
    assert cycles_opened(flags) == 1 + 6          # the stand, then one cycle a stride


def test_a_stance_too_shaky_for_a_relaxed_one_is_found_after_the_fact_between_two_swings():
    # Stances at 4e7 (above 3 gamma, refused as relaxed stances, test above): when the next
    # swing has armed and no stance follows within half the time from the last stance to the
    # minimum, the minimum was the stance: a late stance (flag 8, its ZUPT late) names its
    # sample.
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(4e7) for _ in range(4)])
    flags, late, _ = run_with_ages(statistics, statistics < GAMMA)
    found = late[late >= 0]
    minima = np.flatnonzero(statistics == 0.9 * 4e7)
    assert np.array_equal(found, minima[:3])      # the last stance has no swing after it
    assert np.all(flags[late >= 0] == 8)
    # found 0.5 x (minimum - last stance) after the minimum: 75 samples after the stand's
    # end for the first, then strides of 1 s
    assert np.array_equal(np.flatnonzero(late >= 0) - found, [38, 50, 50])
    off = StrideGateParams(**{**PARAMS.__dict__, 'late_stances': False})
    assert not np.any(run(statistics, statistics < GAMMA, off)[0] & 8)


def test_a_late_stance_whose_foot_moves_beyond_the_filters_doubt_is_refused():
    # The same strides, the INS velocity at the minima 0.9 m/s: NIS 0.81 / (0.05^2 + 0.05^2)
    # = 162 passes the bound of 200; at 1.1 m/s (242) the foot was still moving. A filter
    # unsure of its velocity (1 m/s) takes 1.1 m/s for its own error.
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(4e7) for _ in range(4)])

    def late_stances(speed, P=P_SURE):
        flags = run_with_ages(statistics, statistics < GAMMA, vel_n=np.array([0.0, 0.0, speed]),
                              P=P)[0]
        return np.count_nonzero(flags & 8)
    assert late_stances(0.9) == 3
    assert late_stances(1.1) == 0
    assert late_stances(1.1, np.eye(15)) == 3


def test_a_dip_late_in_the_swing_followed_soon_by_a_stance_is_no_late_stance():
    # A swing of 1.2 s with a dip (5e8 < the swing level) 0.9 s after the last stance: the
    # swing resumes, but the stance comes 0.3 s after the dip, under half of 0.9 s.
    statistics = strides_with_a_dip(120, slice(85, 88), 5e8, 4)
    flags, _ = run(statistics, statistics < GAMMA)
    assert not np.any(flags & 8)
    assert cycles_opened(flags) == 1 + 4


def test_a_stance_broken_briefly_continues_and_after_a_long_break_opens_no_cycle():
    statistics = np.concatenate([np.full(50, 1e5), stride(1e6), np.full(80, 1e6)])
    statistics[-75:-65] = 1e8          # 0.1 s of movement, no swing: the same stance
    statistics[-50:-20] = 1e8          # 0.3 s of movement, no swing: no new gait cycle
    flags, _ = run(statistics, statistics < GAMMA)
    assert np.all(flags[-65:-50] == 3)
    assert np.all(flags[-20:] == 1)    # ZUPT, not a gait stance


def test_disabled_gate_is_the_shoe_decision():
    statistics = np.concatenate([np.full(50, 1e5)] + [stride(2e7, dip=1.5e7) for _ in range(3)])
    shoe = statistics < GAMMA
    flags, _ = run(statistics, shoe, StrideGateParams(enabled=False))
    assert np.array_equal(flags, np.where(shoe, 3, 0))


def test_nan_statistic_while_the_window_fills_is_no_stance():
    flags, _ = run(np.full(20, math.nan), np.zeros(20, bool))
    assert not np.any(flags)


@pytest.mark.parametrize('field, value', [
    ('relaxed_factor', 0.5), ('refractory_fraction', 1.5), ('swing_level', 0.0),
    ('confirm_s', 1.0), ('relaxed_sigma_mps', 0.0), ('relaxed_floor', -1.0),
    ('current_factor', 0.5), ('max_break_s', 2.0), ('late_balance', -0.1),
    ('late_sigma_mps', 0.0), ('late_max_nis', -1.0)])
def test_out_of_range_parameters_are_refused(field, value):
    with pytest.raises(InputError, match=field):
        StrideGateParams(**{field: value})


def test_max_period_below_min_period_is_refused():
    with pytest.raises(InputError, match='max_period_s'):
        StrideGateParams(min_period_s=1.0, max_period_s=0.5)


def test_the_gate_cuts_no_extra_cycle_on_clean_simulated_stances():
    """
    On a simulated walk whose every stance SHOE sees, the gate adds nothing: same cycles.

    With the gate and without it the navigator finds one cycle per simulated stride, at the
    same stamps and with the same features, and the gate counts no relaxed or late stance (it
    neither cuts a stride in two at a mid-swing dip nor merges two).
    """
    segments = (Segment.level(4), Segment.stairs(8, +1, steps_per_stride=2), Segment.level(2))
    w = simulate_walk(segments, rng=np.random.default_rng(11), rate_hz=200.0, imu='tactical',
                      step_height_m=0.17)
    runs = {}
    for enabled in (True, False):
        navigator = FootNavigator(NavigatorParams(stride_gate=StrideGateParams(enabled=enabled)))
        _, cycles = navigator.run(w.stamp_ns, w.acc_b, w.gyr_b)
        runs[enabled] = cycles, navigator.status
    (gated, status), (shoe_only, status_without) = runs[True], runs[False]
    assert len(gated) == len(shoe_only) == len(w.strides.stamp_ns)
    assert all(c.valid for c in gated)
    assert [c.stamp_ns for c in gated] == [c.stamp_ns for c in shoe_only]
    assert all(np.array_equal(a.features, b.features) for a, b in zip(gated, shoe_only))
    assert (status.relaxed_stances, status.late_stances, status.late_cycles) == (0, 0, 0)
    assert status.stance_samples == status_without.stance_samples


def gdin_cycles(walk, gate):
    """Return the cycles of a gdin walk with a stride gate, and the navigator's status."""
    recording = walk.recording
    navigator = FootNavigator(NavigatorParams(gyro_range_rps=GYRO_RANGE_RPS, stride_gate=gate))
    _, cycles = navigator.run(recording.stamp_ns, recording.acc_b, recording.gyr_b)
    return len(cycles), navigator.status


def test_the_gate_finds_the_strides_shoe_merges_on_a_real_brisk_walk_and_counts_them():
    # gdin walk 32 (80 m of corridors, 61 strides): measured 59 cycles without the gate (two
    # stances never still enough for SHOE), 61 with it, the relaxed stances counted.
    walk = gdin_walk(32)
    without, status_without = gdin_cycles(walk, StrideGateParams(enabled=False))
    with_gate, status = gdin_cycles(walk, StrideGateParams(enabled=True))
    assert without < walk.n_strides and status_without.relaxed_stances == 0
    assert with_gate == walk.n_strides and status.relaxed_stances > 0


@pytest.mark.parametrize('number', [34, 38])
def test_late_stances_find_the_strides_no_stance_rule_finds_on_real_walks_and_close_them(number):
    # gdin walks 34 (24 strides) and 38 (60): measured 23 and 57 cycles with relaxed stances
    # alone (a gentle first step, and on 38 two stances too shaky for a relaxed one); the late
    # stances find those 1 and 3, apply their ZUPTs late and, on this level ground, close a
    # cycle at each; with no slope allowed they close none.
    walk = gdin_walk(number)
    without, status_without = gdin_cycles(walk, StrideGateParams(late_stances=False))
    with_late, status = gdin_cycles(walk, StrideGateParams(late_stances=True))
    kept, status_kept = gdin_cycles(walk, StrideGateParams(late_max_slope=0.0))
    assert without < walk.n_strides and status_without.late_stances == 0
    assert with_late == walk.n_strides
    assert status.late_stances == status.late_cycles == walk.n_strides - without
    assert kept == without and status_kept.late_stances == status.late_stances
    assert status_kept.late_cycles == 0


def test_late_stances_close_every_stride_of_a_run_no_stance_stills():
    # gdin walk 35: a 3 s run (about 5 strides) with no stance, its gyro at the rail; measured
    # 24 of 28 strides as cycles without the cut, one 14.6 m cycle over the run.
    walk = gdin_walk(35)
    cycles, status = gdin_cycles(walk, StrideGateParams())
    assert cycles == walk.n_strides and status.late_cycles == 4
