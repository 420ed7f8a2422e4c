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

"""Tests of the foot-IMU simulator: physics, truth bookkeeping, scenarios, IMU error presets."""

import dataclasses
import math

from anfis_elevation_ros import sim
from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.frames import rpy_to_dcm
from anfis_elevation_ros.core.strapdown import strapdown
from anfis_elevation_ros.sim import motion
from anfis_elevation_ros.sim.plan import STAND_S
import numpy as np
import pytest

G = 9.80665
DEG = math.pi / 180.0

# About 10 s with every kind of motion: turn while walking, stairs up (2 steps per stride),
# turn on the spot, stairs down (1 step per stride), a level stride.
PHYSICS_WALK = (sim.Segment.level(2, turn_deg=60.0), sim.Segment.stairs(4, +1),
                sim.Segment.turn(-90.0), sim.Segment.stairs(2, -1, steps_per_stride=1),
                sim.Segment.level(1))
STILL_GAIT = sim.GaitParams(stance_sway_rps=(0.0, 0.0), stand_sway_rps=(0.0, 0.0))


def quat_to_dcm_batch(q):
    """(N, 3, 3) rotation matrices of (N, 4) unit quaternions [w, x, y, z]."""
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def ideal_strapdown_errors(rate_hz, mounting_rpy_deg=(10.0, -25.0, 40.0)):
    """Max position (m) and attitude (rad) error of free strapdown on the ideal preset."""
    # The foot still on the ground: the sway's rate steps at the stance's ends (sim.sway) are
    # a first-order error of any integrator, which is not what this measures.
    walk = sim.simulate_walk(PHYSICS_WALK, rng=np.random.default_rng(5), rate_hz=rate_hz,
                             imu='ideal', mounting_rpy_deg=mounting_rpy_deg,
                             initial_stand_s=2.0, final_stand_s=0.5, gait=STILL_GAIT)
    quat, _, pos = strapdown(walk.quat_nb[0], walk.vel_n[0], walk.pos_n[0], walk.stamp_ns,
                             walk.acc_b, walk.gyr_b, gravity_mps2=walk.gravity_mps2)
    pos_err = np.linalg.norm(pos - walk.pos_n, axis=1).max()
    att_err = 2 * np.arccos(np.clip(np.abs(np.sum(quat * walk.quat_nb, axis=1)), 0, 1)).max()
    return walk, pos_err, att_err


def test_ideal_imu_strapdown_reproduces_truth():
    walk, pos_err_400, att_err_400 = ideal_strapdown_errors(400.0)
    assert 9.0 < walk.duration_s < 12.0
    assert walk.strides.mode.tolist().count(1) == 2 and walk.strides.mode.tolist().count(-1) == 2
    # The only error left is the integrator's: its trapezoidal rule is second order and these
    # swings are fast (rates to 10 rad/s, touch-down pulses of 2-6 g over 20-40 ms): measured
    # 2.2 cm / 0.014 deg at 400 Hz. A sign or frame error in the signals would give metres and
    # whole degrees.
    assert pos_err_400 < 0.04
    assert att_err_400 < 0.03 * DEG
    # Exact signals make the error shrink as dt^2 (a ratio of 4 per halving of dt); an error in
    # the signals themselves would not shrink with the sample rate.
    _, pos_err_200, att_err_200 = ideal_strapdown_errors(200.0)
    assert 3.0 < pos_err_200 / pos_err_400 < 5.5
    assert 3.0 < att_err_200 / att_err_400 < 5.5


def test_ideal_signals_match_attitude_and_velocity_derivatives():
    # Independent of the strapdown code: the truth sampled at 2 kHz.
    # (The sway's rate steps at the stance's ends: test_a_foot_on_the_ground_sways_about_the_imu.)
    walk = sim.simulate_walk(PHYSICS_WALK, rng=np.random.default_rng(2), rate_hz=2000.0,
                             imu='ideal', mounting_rpy_deg=(180.0, 0.0, 0.0), gait=STILL_GAIT)
    dt = 1.0 / walk.rate_hz
    C = quat_to_dcm_batch(walk.quat_nb)
    acc_n = np.einsum('nij,nj->ni', C, walk.acc_b) - [0.0, 0.0, G]     # a_n = C_nb f_b + g_n
    # Velocity increments over two samples against Simpson's rule of the accelerations the
    # IMU reports. Between knots every translation chain is a quintic in time, so its
    # acceleration is a cubic and Simpson's rule is exact (measured 4e-14 m/s); an interval
    # across a knot, where the jerk jumps, errs by ~dt^2 * jump (measured 4e-4 m/s at the
    # touch-down pulses). A frame or sign error would give ~dt * 10 m/s^2 = 1e-2 m/s.
    simpson = dt / 3.0 * (acc_n[:-2] + 4.0 * acc_n[1:-1] + acc_n[2:])
    err = np.linalg.norm(walk.vel_n[2:] - walk.vel_n[:-2] - simpson, axis=1)
    assert np.percentile(err, 99) < 1e-9
    assert err.max() < 2e-3
    # Body rate from the attitude increment: C_k^T C_(k+1) ~ I + [w x] dt (error ~ dt^2 w'').
    dC = np.einsum('nji,njk->nik', C[:-1], C[1:])
    w_b = np.stack([dC[:, 2, 1] - dC[:, 1, 2], dC[:, 0, 2] - dC[:, 2, 0],
                    dC[:, 1, 0] - dC[:, 0, 1]], -1) / (2 * dt)
    w_mid = 0.5 * (walk.gyr_b[:-1] + walk.gyr_b[1:])
    # Second order in dt (measured 4e-3 rad/s at 2 kHz, where the roll stops at foot flat)
    # against peaks of 10 rad/s.
    assert np.abs(w_b - w_mid).max() < 0.01


def test_knot_chains_have_exact_derivatives_and_never_dwell():
    # A chain with extrema, a monotone knot and a knot with given derivatives, as swings use.
    knots = motion._knots((0.0, 0.0), (0.3, -0.6), (0.6, 0.1, None), (0.8, 0.5),
                          (0.9, 0.45, -1.0, -20.0), (1.0, 0.0))
    u, y, v, a = knots
    assert v[0] == a[0] == v[-1] == a[-1] == 0.0                    # at rest at both ends
    assert v[1] == 0.0 and a[1] == pytest.approx(2 * (0.7 / 0.3 + 2.0) / 0.6)   # extremum
    assert v[2] == pytest.approx(1.5 / (0.7 / (0.7 / 0.3) + 0.8 / 2.0))  # harmonic mean
    assert (v[4], a[4]) == (-1.0, -20.0)                            # as given
    t = np.linspace(0.0, 1.0, 200_001)
    duration_s = 0.5
    p, dp, ddp = sim.knot_profile(t, u, y, duration_s, v, a)
    h = (t[1] - t[0]) * duration_s
    # Values and derivatives at the knots are the ones given.
    at_knots = np.searchsorted(t, u)
    assert np.allclose(p[at_knots], y, atol=1e-12)
    assert np.allclose(dp[at_knots] * duration_s, v, atol=1e-9)
    # dp, ddp are the derivatives of p and dp (central differences, error ~h^2 * jerk').
    assert np.abs(np.gradient(p, h)[1:-1] - dp[1:-1]).max() < 1e-5
    assert np.abs(np.gradient(dp, h)[1:-1] - ddp[1:-1]).max() < 2e-2 * np.abs(ddp).max()
    # The rate passes through zero at the extremum (u = 0.3) with a slope (a[1] above) instead
    # of lingering: around it, it is below 5 % of its peak for 6.8 % of the time, against
    # 12.4 % for a minimum-jerk chain through the same knots (zero slope and curvature at
    # every knot: 30 w^2 (1 - w)^2 grows from zero as w^2).
    near = (t > 0.15) & (t < 0.45)
    _, dp_mj, _ = sim.knot_profile(t, u, y, duration_s)
    slow, slow_mj = (np.mean(np.abs(d[near]) < 0.05 * np.abs(d[near]).max()) for d in (dp, dp_mj))
    assert slow < 0.6 * slow_mj


def test_the_swinging_foot_is_never_imu_still_while_it_moves():
    # A foot that moves without rotating and with |f| = g looks to any inertial zero-velocity
    # detector like a foot at rest (SHOE, Skog et al. 2010). A resting foot reads |w| within
    # the gyro noise and a slight sway (< 0.1 rad/s) and |f| = g within the accelerometer
    # noise (< 0.05 m/s^2 for a consumer part at 200 Hz). So wherever the foot moves faster than
    # 0.3 m/s the IMU must read |w| > 0.5 rad/s or ||f| - g| > 1 m/s^2: five and twenty times
    # those levels; with pyshoe's weights 0.5 rad/s alone puts the SHOE statistic at 3e7,
    # above the navigator's thresholds. Real feet do so (on the MaD stairs the least |w| in
    # mid-swing has a median of 1 rad/s). The old simulator failed on 3 % of such samples
    # (|w| 0.09 rad/s at 3 m/s in 3-4 step stair strides). All gaits and all steps per stride:
    segments = sim.random_walk(240.0, np.random.default_rng(21),
                               steps_per_stride_weights=(1, 1, 1, 1))
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(21), rate_hz=200.0,
                             imu='ideal')
    assert set(walk.strides.n_steps.tolist()) == {0, 1, 2, 3, 4}
    speed = np.linalg.norm(walk.vel_n, axis=1)
    rate = np.linalg.norm(walk.gyr_b, axis=1)
    off_g = np.abs(np.linalg.norm(walk.acc_b, axis=1) - G)
    moving = speed > 0.3
    assert moving.sum() > 5000
    still_looking = moving & (rate <= 0.5) & (off_g <= 1.0)
    assert not np.any(still_looking), np.flatnonzero(still_looking)[:10]
    # With a margin: the roll keeps |w| near 0.8 rad/s where the pitch turns (measured 1.45).
    assert np.min(np.maximum(rate / 0.5, off_g / 1.0)[moving]) > 1.3


def test_swing_rates_and_touch_down_impacts_are_those_of_a_real_foot():
    segments = sim.random_walk(240.0, np.random.default_rng(22),
                               steps_per_stride_weights=(1, 1, 1, 1))
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(22), rate_hz=200.0,
                             imu='ideal')
    s = walk.strides
    walking = np.array([segments[k].kind != 'turn' for k in s.segment_index])
    peak_rate = np.empty(len(s))
    landing_g = np.empty(len(s))
    for i in range(len(s)):
        swing = (walk.stamp_ns >= s.swing_start_ns[i]) & (walk.stamp_ns < s.stamp_ns[i])
        peak_rate[i] = np.abs(walk.gyr_b[swing, 1]).max()             # pitch rate, b = f
        end = np.searchsorted(walk.stamp_ns, s.stamp_ns[i])
        landing = slice(end - int(0.15 * walk.rate_hz), end)           # touch-down, foot flat
        landing_g[i] = np.linalg.norm(walk.acc_b[landing], axis=1).max() / G
    level, stairs = walking & (s.mode == 0), s.mode != 0
    # Peak pitch rates of real feet: 5-8 rad/s walking on the level, 2-5 rad/s on stairs.
    assert 5.0 < np.median(peak_rate[level]) < 8.0
    assert 2.0 < np.median(peak_rate[stairs]) < 5.0
    assert peak_rate[walking].min() > 1.5                             # measured 2.1
    # Every touch-down is an impact of a few g (measured 2.1-6.6 g), not a soft landing.
    assert landing_g[walking].min() > 1.8
    assert landing_g[walking].max() < 8.0


@pytest.mark.parametrize('mounting', [(0.0, 0.0, 0.0), (180.0, 0.0, 0.0), (30.0, -20.0, 75.0)])
def test_at_rest_the_imu_reads_gravity_rotated_by_the_mounting(mounting):
    walk = sim.simulate_walk(PHYSICS_WALK, rng=np.random.default_rng(0), rate_hz=100.0,
                             imu='ideal', mounting_rpy_deg=mounting, gait=STILL_GAIT)
    C_fb = rpy_to_dcm(*(a * DEG for a in mounting))
    expected = C_fb.T @ [0.0, 0.0, G]              # f_b = C_bf C_fn [0, 0, g], foot flat
    # Every stance sample (start, on the stairs, after turns) has the foot flat and still.
    assert np.allclose(walk.acc_b[walk.stance], expected, atol=1e-9, rtol=0)
    assert np.all(walk.gyr_b[walk.stance] == 0.0)
    # The first sample's attitude is the mounting itself (foot level, heading 0).
    assert np.allclose(quat_to_dcm_batch(walk.quat_nb[:1])[0], C_fb, atol=1e-12)
    assert np.all(walk.pos_n[0] == 0.0)
    if mounting == (180.0, 0.0, 0.0):
        assert np.allclose(walk.acc_b[0], [0.0, 0.0, -G])   # pyshoe-like z down


def test_a_foot_on_the_ground_sways_about_the_imu():
    gait = sim.GaitParams()
    walk = sim.simulate_walk(sim.sample_walk(), rng=np.random.default_rng(3), rate_hz=200.0,
                             imu='ideal', gait=gait)
    rate = np.abs(walk.gyr_b)
    # The first stand (3 s) sways within stand_sway_rps; the walking stances within
    # stance_sway_rps (per axis; three axes at most sqrt(3) times it).
    first_swing = np.argmax(~walk.stance)
    assert 0.005 < rate[:first_swing].max() <= gait.stand_sway_rps[1]
    runs = np.flatnonzero(np.diff(np.r_[0, walk.stance.astype(int), 0]))
    walking = np.zeros_like(walk.stance)
    for start, end in zip(runs[::2], runs[1::2]):
        walking[start:end] = (end - start) / walk.rate_hz < STAND_S
    assert walking.sum() > 0.2 * walk.stance.sum()
    assert rate[walking].max() <= gait.stance_sway_rps[1]
    # Walking stances are not still for a zero angular rate update at 0.02 rad/s: most
    # 25 ms windows hold a rate above it.
    window = 5
    peak = np.max([np.roll(rate.max(axis=1), k) for k in range(window)], axis=0)
    assert np.mean(peak[walking] > 0.02) > 0.8
    # The IMU stays in place: position and velocity as without the sway.
    still = sim.simulate_walk(sim.sample_walk(), rng=np.random.default_rng(3), rate_hz=200.0,
                              imu='ideal', gait=STILL_GAIT)
    assert np.array_equal(walk.pos_n, still.pos_n) and np.array_equal(walk.vel_n, still.vel_n)
    assert np.array_equal(walk.stance, still.stance)
    # The rates are the attitude's: C_k^T C_(k+1) ~ I + [w x] dt inside the stances.
    fine = sim.simulate_walk(sim.sample_walk(), rng=np.random.default_rng(3), rate_hz=2000.0,
                             imu='ideal', gait=gait)
    C = quat_to_dcm_batch(fine.quat_nb)
    dC = np.einsum('nji,njk->nik', C[:-1], C[1:])
    w_b = np.stack([dC[:, 2, 1] - dC[:, 1, 2], dC[:, 0, 2] - dC[:, 2, 0],
                    dC[:, 1, 0] - dC[:, 0, 1]], -1) * (fine.rate_hz / 2.0)
    inside = fine.stance[:-2] & fine.stance[1:-1] & fine.stance[2:]
    w_mid = 0.5 * (fine.gyr_b[:-1] + fine.gyr_b[1:])
    assert np.abs(w_b - w_mid)[:-1][inside].max() < 1e-4


def test_stance_samples_have_zero_truth_velocity_and_swings_move():
    walk = sim.simulate_walk(sim.sample_walk(), rng=np.random.default_rng(3), rate_hz=200.0,
                             imu='ideal')
    assert np.all(walk.vel_n[walk.stance] == 0.0)
    moving = ~walk.stance
    assert np.all(np.linalg.norm(walk.vel_n[moving], axis=1) > 0.0)
    # Stance is foot flat and still for 35-50 % of each stride plus the stops: about half.
    assert 0.4 < walk.stance.mean() < 0.7
    # Position is constant through each stance run.
    jumps = np.linalg.norm(np.diff(walk.pos_n, axis=0), axis=1)
    assert np.all(jumps[walk.stance[1:] & walk.stance[:-1]] == 0.0)


def test_stride_truth_heights_add_up_to_the_stairs():
    segments = (sim.Segment.stairs(7, +1, steps_per_stride=3, step_height_m=0.16),
                sim.Segment.level(2, turn_deg=180.0),
                sim.Segment.stairs(5, +1, steps_per_stride=1, step_height_m=0.19),
                sim.Segment.stand(3.0),
                sim.Segment.stairs(9, -1, steps_per_stride=4),
                sim.Segment.level(3))
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(4), rate_hz=100.0,
                             imu='ideal', step_height_m=0.14)
    s = walk.strides
    expected_total = 7 * 0.16 + 5 * 0.19 - 9 * 0.14
    assert math.isclose(s.height_change_m.sum(), expected_total, abs_tol=1e-12)
    assert math.isclose(walk.pos_n[-1, 2], expected_total, abs_tol=1e-12)
    assert np.allclose(s.height_m, np.cumsum(s.height_change_m), atol=1e-12)
    assert s.n_steps.tolist() == [3, 3, 1, 0, 0, 1, 1, 1, 1, 1, 4, 4, 1, 0, 0, 0]
    assert s.mode.tolist() == [1, 1, 1, 0, 0, 1, 1, 1, 1, 1, -1, -1, -1, 0, 0, 0]
    assert np.allclose(np.abs(s.height_change_m), s.n_steps * s.step_height_m, atol=1e-12)
    assert np.all(np.sign(s.height_change_m) == s.mode)
    assert s.segment_index.tolist() == [0, 0, 0, 1, 1, 2, 2, 2, 2, 2, 4, 4, 4, 5, 5, 5]
    # stamp_ns is the first stance sample after the swing; swing_start_ns the first moving one.
    index = np.searchsorted(walk.stamp_ns, s.stamp_ns)
    assert np.all(walk.stance[index]) and not np.any(walk.stance[index - 1])
    start = np.searchsorted(walk.stamp_ns, s.swing_start_ns)
    assert not np.any(walk.stance[start]) and np.all(walk.stance[start - 1])
    assert np.allclose(walk.pos_n[index], s.end_pos_n, atol=1e-12)
    assert np.allclose(walk.pos_n[start - 1], s.start_pos_n, atol=1e-12)
    # Flights move one tread (0.28 m) per step along the heading.
    flight = s.mode != 0
    run = np.linalg.norm(s.end_pos_n[flight, :2] - s.start_pos_n[flight, :2], axis=1)
    assert np.allclose(run, 0.28 * s.n_steps[flight], atol=1e-12)
    assert math.isclose(s.heading_change_rad[3:5].sum(), math.pi, abs_tol=1e-12)


def test_building_walk_matches_the_issue_description():
    segments = sim.building_walk()
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(7), rate_hz=100.0,
                             imu='ideal')
    s = walk.strides
    down, up = s.mode == -1, s.mode == 1
    assert s.n_steps[down].sum() == 36 and s.n_steps[up].sum() == 36
    assert np.allclose(s.step_height_m[down | up], 0.15)
    assert math.isclose(walk.pos_n[:, 2].min(), -5.4, abs_tol=1e-9)    # 36 x 0.15 m down
    assert math.isclose(walk.pos_n[-1, 2], 0.0, abs_tol=1e-9)          # and back up
    # Two flights of 18 each way, down first, joined by a 180 deg landing turn.
    flights = [seg for seg in segments if seg.kind == 'stairs']
    assert [(f.direction, f.n_steps) for f in flights] == [(-1, 18)] * 2 + [(1, 18)] * 2
    assert np.flatnonzero(down).max() < np.flatnonzero(up).min()
    # About 640 s in all (stride times are random: +-3 %) and about 500 s between the flights.
    assert 620.0 < walk.duration_s < 660.0
    level_s = (s.swing_start_ns[np.flatnonzero(up)[0]] - s.stamp_ns[np.flatnonzero(down)[-1]])
    assert 470.0 < level_s * 1e-9 < 530.0
    kinds = {seg.kind for seg in segments}
    assert kinds == {'level', 'stairs', 'turn', 'stand'}
    assert any(seg.kind == 'level' and seg.turn_deg != 0.0 for seg in segments)


def test_random_walk_varies_with_the_seed_and_spans_the_gait_ranges():
    plans = [sim.random_walk(300.0, np.random.default_rng(seed)) for seed in range(6)]
    assert plans[0] != plans[1]
    assert plans[0] == sim.random_walk(300.0, np.random.default_rng(0))
    flights = [seg for plan in plans for seg in plan if seg.kind == 'stairs']
    heights = np.array([f.step_height_m for f in flights])
    assert np.all((heights >= 0.14) & (heights <= 0.19)) and np.ptp(heights) > 0.03
    per_stride = np.array([f.steps_per_stride for f in flights])
    assert set(per_stride) <= {1, 2, 3, 4}
    assert np.mean(per_stride <= 2) > 0.6                    # mostly 1-2 steps per stride
    assert {f.direction for f in flights} == {-1, 1}
    walk = sim.simulate_walk(plans[2], rng=np.random.default_rng(2), rate_hz=100.0,
                             imu='ideal')
    # Planned with mid-range stride times; it overshoots by at most one activity.
    assert 270.0 < walk.duration_s < 360.0
    with pytest.raises(InputError, match='steps_per_stride_weights'):
        sim.random_walk(60.0, np.random.default_rng(0), steps_per_stride_weights=(1, 1))


def _storey_traversals(segments) -> list:
    """(lower floor, flights) of each stair traversal of a random_walk plan, in order."""
    traversals, floor = [], 0
    for i, seg in enumerate(segments):
        if seg.kind != 'stairs':
            continue
        landing = segments[i - 1]
        if landing.kind == 'level' and landing.stride_length_m == 0.7 and traversals:
            traversals[-1][1].append(seg)                    # the next flight after a landing
            continue
        if traversals:
            floor += traversals[-1][1][0].direction
        traversals.append((min(floor, floor + seg.direction), [seg]))
    return traversals


def test_random_walk_stairs_are_the_buildings_one_geometry_per_storey():
    # The stairs between floors f and f + 1 are the same whenever and whichever way they are
    # walked (riser height, steps per flight, flights); storeys differ from each other.
    traversals = _storey_traversals(sim.random_walk(1800.0, np.random.default_rng(5)))
    geometry, walked = {}, {}
    for lower, flights in traversals:
        shape = (flights[0].step_height_m, flights[0].n_steps, len(flights))
        assert all((f.step_height_m, f.n_steps) == shape[:2] for f in flights)
        assert geometry.setdefault(lower, shape) == shape, (lower, shape, geometry[lower])
        walked.setdefault(lower, set()).add(flights[0].direction)
        assert abs(lower) <= 3 and -3 <= lower + 1 <= 3
    assert any(len(d) == 2 for d in walked.values())          # a storey walked up and down
    assert len({shape[0] for shape in geometry.values()}) == len(geometry) > 2
    per_stride = {f.steps_per_stride for _, flights in traversals for f in flights}
    assert len(per_stride) > 1                                # the wearer's choice varies


def test_random_walk_treads_per_storey_leave_the_rest_of_the_walk_as_it_was():
    default = sim.random_walk(600.0, np.random.default_rng(5))
    treads = sim.random_walk(600.0, np.random.default_rng(5), tread_range_m=(0.22, 0.36))
    assert {seg.tread_m for seg in default if seg.kind == 'stairs'} == {0.28}

    def without_treads(plan):
        return [(seg.kind, seg.n_steps, seg.step_height_m, seg.steps_per_stride) for seg in plan]

    assert without_treads(treads) == without_treads(default)
    by_storey = {}
    for lower, flights in _storey_traversals(treads):
        by_storey.setdefault(lower, set()).update(f.tread_m for f in flights)
    assert all(len(tread) == 1 for tread in by_storey.values())     # one tread a storey
    drawn = set().union(*by_storey.values())
    assert len(drawn) > 2 and all(0.22 <= tread <= 0.36 for tread in drawn)
    with pytest.raises(InputError, match='tread_range_m'):
        sim.random_walk(60.0, np.random.default_rng(0), tread_range_m=(0.3, 0.2))


def _stair_traversals(segments, strides) -> list:
    """(direction, start xy, end xy, lower floor height) of each storey walked, from the truth."""
    on_stairs = np.array([segments[k].kind == 'stairs' or (
        segments[k].kind == 'level' and segments[k].stride_length_m == 0.7)
        for k in strides.segment_index])
    traversals, i = [], 0
    while i < len(strides):
        if not on_stairs[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(strides) and on_stairs[j + 1]:
            j += 1
        start, end = strides.start_pos_n[i], strides.end_pos_n[j]
        traversals.append((int(strides.mode[i]), start[:2], end[:2], min(start[2], end[2])))
        i = j + 1
    return traversals


def test_random_walk_takes_each_storeys_stairs_where_they_are():
    # In a building a storey's stairs stay where they are: every way up starts at their foot
    # and every way down at their head, and going down retraces the way up to the foot.
    # simulate_walk jitters each given stride length by 3 %, so the truth agrees with the
    # plan to within that jitter summed over the walk (measured: 0.65 m from the mean here).
    segments = sim.random_walk(600.0, np.random.default_rng(17))
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(17), rate_hz=100.0,
                             imu='ideal')
    feet, heads = {}, {}
    for direction, start, end, lower in _stair_traversals(segments, walk.strides):
        foot, head = (start, end) if direction > 0 else (end, start)
        feet.setdefault(round(lower, 1), []).append(foot)
        heads.setdefault(round(lower, 1), []).append(head)
    walked_often = [lower for lower, at in feet.items() if len(at) >= 4]
    assert len(walked_often) >= 2
    for places in (feet, heads):
        for at in places.values():
            assert np.max(np.linalg.norm(np.array(at) - np.mean(at, axis=0), axis=1)) < 1.0
    # Different storeys have their stairs in different places (drawn within 10 m).
    centres = np.array([np.mean(at, axis=0) for at in feet.values()])
    assert np.ptp(centres, axis=0).max() > 3.0


def test_sample_walk_is_a_short_demo_up_and_down():
    walk = sim.simulate_walk(sim.sample_walk(), rng=np.random.default_rng(1), rate_hz=100.0,
                             imu='ideal')
    assert 60.0 < walk.duration_s < 90.0
    assert math.isclose(walk.strides.height_m.max(), 14 * 0.17, abs_tol=1e-9)
    assert math.isclose(walk.pos_n[-1, 2], 0.0, abs_tol=1e-9)
    # The navigator levels itself at rest first: at least 2 s of stance.
    assert np.all(walk.stance[:int(2.0 * walk.rate_hz) + 1])
    assert np.all(walk.stance[-int(1.0 * walk.rate_hz):])


def test_foot_elevation_follows_the_gait_of_each_mode():
    walk = sim.simulate_walk(PHYSICS_WALK, rng=np.random.default_rng(8), rate_hz=200.0,
                             imu='ideal')
    # Elevation of the foot's x axis (toe up positive); with identity mounting b = f.
    toe_z = quat_to_dcm_batch(walk.quat_nb)[:, 2, 0]
    elevation_deg = np.degrees(np.arcsin(toe_z))
    s = walk.strides
    gait = sim.GaitParams()
    checked = set()
    for i in range(len(s)):
        swing = (walk.stamp_ns >= s.swing_start_ns[i]) & (walk.stamp_ns < s.stamp_ns[i])
        e = elevation_deg[swing]
        early, late = e[:len(e) // 2], e[int(0.75 * len(e)):]
        scale = min(1.0, 0.4 + 0.3 * s.n_steps[i])       # step-to strides roll the foot less
        if s.mode[i] == 0 and s.n_steps[i] == 0 and np.any(s.start_pos_n[i] != s.end_pos_n[i]):
            # Toe-off -30..-50 deg, toe up +10..+20 at heel strike.
            assert gait.level_toe_off_deg[0] <= e.min() < gait.level_toe_off_deg[1] + 1
            assert gait.level_landing_deg[0] - 1 < e.max() <= gait.level_landing_deg[1]
            checked.add(0)
        elif s.mode[i] == 1:
            # Toe-off, toe up over the nose, forefoot first.
            assert scale * gait.up_toe_off_deg[0] <= early.min() < scale * gait.up_toe_off_deg[1]
            assert scale * gait.up_mid_swing_deg[0] < e.max() <= scale * gait.up_mid_swing_deg[1]
            assert gait.up_landing_deg[0] <= late.min() < gait.up_landing_deg[1]
            checked.add(1)
        elif s.mode[i] == -1:
            # Toe-off, toe up over the nose, toe lands first.
            assert scale * gait.down_toe_off_deg[0] <= early.min()
            assert scale * gait.down_mid_swing_deg[0] < e.max()
            assert e.max() <= scale * gait.down_mid_swing_deg[1]
            assert scale * gait.down_landing_deg[0] <= late.min()
            assert late.min() < scale * gait.down_landing_deg[1]
            checked.add(-1)
    assert checked == {-1, 0, 1}                          # each mode's gait was checked


def _sole_margin(walk, imu_height_m=0.07, toe_m=0.12, heel_m=0.10, tread_m=0.28):
    """Min over swing samples of the sole's height above the stair surface, per flight stride."""
    C = quat_to_dcm_batch(walk.quat_nb)
    sole_f = np.array([[x, 0.0, -imu_height_m] for x in np.linspace(-heel_m, toe_m, 9)])
    s = walk.strides
    margins = []
    for i in np.flatnonzero(s.mode != 0):
        swing = (walk.stamp_ns >= s.swing_start_ns[i]) & (walk.stamp_ns <= s.stamp_ns[i])
        points = walk.pos_n[swing, None, :] + np.einsum('nij,pj->npi', C[swing], sole_f)
        ahead = s.end_pos_n[i, :2] - s.start_pos_n[i, :2]
        ahead /= np.linalg.norm(ahead)
        along = (points[..., :2] - s.start_pos_n[i, :2]) @ ahead
        # Tread j (0 = the start tread) spans along in [(j - 1/2), (j + 1/2)] treads.
        j = np.clip(np.floor(along / tread_m + 0.5), 0, s.n_steps[i])
        surface = s.start_pos_n[i, 2] - imu_height_m + s.mode[i] * j * s.step_height_m[i]
        margins.append((points[..., 2] - surface).min())
    return np.array(margins)


def test_the_swinging_foot_clears_the_stair_noses():
    segments = []
    for n in (1, 2, 3, 4):
        for k in (0.14, 0.19):
            segments += [sim.Segment.stairs(2 * n, +1, steps_per_stride=n, step_height_m=k),
                         sim.Segment.stairs(2 * n, -1, steps_per_stride=n, step_height_m=k)]
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(9), rate_hz=200.0,
                             imu='ideal')
    margins = _sole_margin(walk)
    assert len(margins) == 32
    # A rigid 22 cm sole 7 cm under the IMU never goes into the stairs (1 mm for rounding at
    # the contact points: the sole touches the tread at the start and end of each swing).
    assert margins.min() > -1e-3


def test_same_seed_same_walk_and_other_seed_differs():
    def run(seed, imu='consumer'):
        return sim.simulate_walk(sim.sample_walk(), rng=np.random.default_rng(seed),
                                 rate_hz=100.0, imu=imu)
    a, b, c = run(11), run(11), run(12)
    for name in ('stamp_ns', 'acc_b', 'gyr_b', 'pos_n', 'quat_nb', 'stance'):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.array_equal(a.strides.stamp_ns, b.strides.stamp_ns)
    assert not np.array_equal(a.pos_n, c.pos_n)
    assert not np.array_equal(a.acc_b, c.acc_b)
    # The gait and the IMU errors draw from separate streams: same trajectory for any preset.
    ideal = run(11, imu='ideal')
    assert np.array_equal(ideal.pos_n, a.pos_n) and not np.array_equal(ideal.acc_b, a.acc_b)


@pytest.mark.parametrize('rate_hz', [100.0, 200.0, 400.0])
def test_stamps_are_regular_from_the_epoch(rate_hz):
    walk = sim.simulate_walk((sim.Segment.level(1),), rng=np.random.default_rng(0),
                             rate_hz=rate_hz, imu='ideal')
    assert walk.stamp_ns.dtype == np.int64 and walk.stamp_ns[0] == sim.EPOCH_NS
    assert np.all(np.diff(walk.stamp_ns) == round(1e9 / rate_hz))
    recording = walk.to_recording('left_foot_imu')
    assert recording.frame_id == 'left_foot_imu'
    assert math.isclose(recording.rate_hz, rate_hz)
    assert np.array_equal(recording.acc_b, walk.acc_b)


# ----------------------------------------------------------------------------------------------
# IMU error presets
# ----------------------------------------------------------------------------------------------

def test_interval_means_keep_the_velocity_change_of_a_touch_down():
    # A touch-down lasts 40-80 ms, a few samples at 100 Hz: instantaneous samples of it alias.
    # Strapdown from the truth at the start of each swing to its end, where the true velocity
    # is zero; the means over the sample intervals keep the increments.
    means = sim.ImuErrorModel(name='means', interval_mean=True)
    assert not means.is_ideal and not sim.IMU_PRESETS['ideal'].interval_mean
    assert sim.IMU_PRESETS['tactical'].interval_mean and sim.IMU_PRESETS['consumer'].interval_mean
    end_speed = {}
    for model in ('ideal', means):
        walk = sim.simulate_walk(PHYSICS_WALK * 2, rng=np.random.default_rng(5), rate_hz=100.0,
                                 imu=model, gait=STILL_GAIT)
        s = walk.strides
        speeds = []
        for i in range(len(s)):
            k0 = np.searchsorted(walk.stamp_ns, s.swing_start_ns[i]) - 1
            k1 = np.searchsorted(walk.stamp_ns, s.stamp_ns[i]) + 1
            _, vel, _ = strapdown(walk.quat_nb[k0], walk.vel_n[k0], walk.pos_n[k0],
                                  walk.stamp_ns[k0:k1], walk.acc_b[k0:k1], walk.gyr_b[k0:k1],
                                  gravity_mps2=walk.gravity_mps2)
            speeds.append(np.linalg.norm(vel[-1]))
        end_speed[getattr(model, 'name', model)] = np.sqrt(np.mean(np.square(speeds)))
        # Away from the swings the readings are exact either way: gravity, no rotation.
        rest = walk.stance & np.roll(walk.stance, 1) & np.roll(walk.stance, -1)
        assert np.allclose(walk.acc_b[rest], [0.0, 0.0, G], atol=1e-12)
        assert np.all(walk.gyr_b[rest] == 0.0)
    # RMS over the 16 swings, measured: 0.024 m/s from samples, 0.011 m/s from means (what is
    # left is the integrator's: 100 Hz against rates of 10 rad/s).
    assert end_speed['ideal'] > 0.015
    assert end_speed['means'] < 0.6 * end_speed['ideal']


def test_interval_means_are_second_order_means():
    # Mean of x(t) = (t^3, t, 1) over [t_k - dt/2, t_k + dt/2]: exactly (t^3 + t dt^2 / 4, t, 1);
    # the midpoint rule on S sub-intervals misses t dt^2 / (4 S^2) of the cubic's.
    t = np.linspace(-1.0, 2.0, 7)
    dt_s, sub = 0.2, 8

    def signals(times):
        return (np.stack([times ** 3, times, np.ones_like(times)], axis=-1),)

    (mean,) = sim.interval_means(signals, t, dt_s, sub_samples=sub, chunk=3)
    exact = t ** 3 + t * dt_s ** 2 / 4
    assert np.allclose(mean[:, 0], exact - t * dt_s ** 2 / (4 * sub ** 2), atol=1e-12)
    assert np.allclose(mean[:, 1:], np.stack([t, np.ones_like(t)], -1), atol=1e-12)


def _static_readings(model, rate_hz, n, seed):
    acc = np.tile([0.0, 0.0, G], (n, 1))
    gyr = np.zeros((n, 3))
    return sim.apply_imu_errors(acc, gyr, rate_hz, model, np.random.default_rng(seed))


@pytest.mark.parametrize('preset', ['tactical', 'consumer'])
def test_white_noise_matches_the_preset_density(preset):
    model = sim.IMU_PRESETS[preset]
    rate_hz = 200.0
    acc, gyr = _static_readings(model, rate_hz, 20_000, seed=1)
    gyr_std, acc_std = model.noise_std(rate_hz)
    t = np.arange(len(acc))
    for measured, spec in ((acc, acc_std), (gyr, gyr_std)):
        # Remove bias and the slow bias walk (a line per axis) before taking the std.
        residual = measured - np.polynomial.polynomial.polyval(
            t, np.polynomial.polynomial.polyfit(t, measured, 1)).T
        # 60 000 samples estimate a std to 0.3 %; 10 % leaves room for quantisation (0.05 %).
        assert np.allclose(residual.std(axis=0), spec, rtol=0.10), (preset, spec)
    if preset == 'consumer':
        # MPU-9250: 0.01 deg/s/sqrt(Hz) and 300 ug/sqrt(Hz) -> 0.141 deg/s and 4.2 mg at 200 Hz.
        assert math.isclose(gyr_std, math.radians(0.01) * math.sqrt(200.0))
        assert math.isclose(acc_std, 300e-6 * G * math.sqrt(200.0))


def test_turn_on_bias_scale_factor_and_misalignment_match_the_preset():
    model = sim.IMU_PRESETS['consumer']
    seeds = range(300)
    bias_acc, bias_gyr, m_acc, m_gyr = [], [], [], []
    for seed in seeds:
        acc, gyr = sim.apply_imu_errors(np.zeros((100, 3)), np.zeros((100, 3)), 200.0, model,
                                        np.random.default_rng(seed))
        bias_acc.append(acc.mean(axis=0))
        bias_gyr.append(gyr.mean(axis=0))
        # Same seed, opposite inputs: bias, walk and noise cancel in the difference, leaving
        # the matrix (I + M) of scale factor and misalignment.
        a, w = 100.0, 20.0
        plus = sim.apply_imu_errors(a * np.eye(3), w * np.eye(3), 200.0, model,
                                    np.random.default_rng(seed))
        minus = sim.apply_imu_errors(-a * np.eye(3), -w * np.eye(3), 200.0, model,
                                     np.random.default_rng(seed))
        m_acc.append((plus[0] - minus[0]).T / (2 * a) - np.eye(3))
        m_gyr.append((plus[1] - minus[1]).T / (2 * w) - np.eye(3))
    off = ~np.eye(3, dtype=bool)
    # 900 (diagonal) or 1800 (off-diagonal) draws estimate a std to 2.4 % / 1.7 %: 10 % is 4 sigma.
    assert math.isclose(np.std(bias_acc), model.acc_bias_sigma_mps2, rel_tol=0.10)
    assert math.isclose(np.std(bias_gyr), model.gyr_bias_sigma_rps, rel_tol=0.10)
    assert math.isclose(np.std(np.array(m_acc)[:, np.eye(3, dtype=bool)]), 0.005, rel_tol=0.10)
    assert math.isclose(np.std(np.array(m_gyr)[:, np.eye(3, dtype=bool)]), 0.005, rel_tol=0.10)
    assert math.isclose(np.std(np.array(m_acc)[:, off]), 0.5 * DEG, rel_tol=0.10)
    assert math.isclose(np.std(np.array(m_gyr)[:, off]), 0.5 * DEG, rel_tol=0.10)
    # Consumer turn-on bias is 30 mg and 0.5 deg/s (1 sigma).
    assert math.isclose(model.acc_bias_sigma_mps2, 0.030 * G)
    assert math.isclose(model.gyr_bias_sigma_rps, 0.5 * DEG)


def test_bias_walk_grows_with_the_square_root_of_time():
    consumer = sim.IMU_PRESETS['consumer']
    walk_only = sim.ImuErrorModel(gyr_bias_walk_rps_rts=consumer.gyr_bias_walk_rps_rts,
                                  acc_bias_walk_mps2_rts=consumer.acc_bias_walk_mps2_rts)
    ends_acc, ends_gyr = [], []
    for seed in range(300):
        acc, gyr = _static_readings(walk_only, 100.0, 1000, seed)   # 10 s
        ends_acc.append(acc[-1] - [0.0, 0.0, G])
        ends_gyr.append(gyr[-1])
    # std after 10 s = walk * sqrt(10 s); 900 draws: 2.4 % std error, 10 % tolerance.
    expected = math.sqrt(10.0)
    assert math.isclose(np.std(ends_acc), consumer.acc_bias_walk_mps2_rts * expected,
                        rel_tol=0.10)
    assert math.isclose(np.std(ends_gyr), consumer.gyr_bias_walk_rps_rts * expected,
                        rel_tol=0.10)


def test_saturation_clips_and_quantisation_rounds_to_the_lsb():
    model = sim.IMU_PRESETS['consumer']
    gyr_lsb = model.gyr_range_rps / 2 ** 15          # 16-bit: 16.4 LSB per deg/s
    acc_lsb = model.acc_range_mps2 / 2 ** 15          # 2048 LSB per g
    assert math.isclose(1.0 / math.degrees(gyr_lsb), 16.384)
    assert math.isclose(G / acc_lsb, 2048.0)
    true_acc = np.array([[300.0, -300.0, 9.8], [0.0, 50.0, -50.0]])
    true_gyr = np.array([[60.0, -60.0, 1.0], [0.0, 20.0, -20.0]])
    acc, gyr = sim.apply_imu_errors(true_acc, true_gyr, 200.0, model,
                                    np.random.default_rng(0))
    assert acc[0, 0] == model.acc_range_mps2 - acc_lsb and acc[0, 1] == -model.acc_range_mps2
    assert gyr[0, 0] == model.gyr_range_rps - gyr_lsb and gyr[0, 1] == -model.gyr_range_rps
    assert np.all(np.abs(acc[1, 1:] - true_acc[1, 1:]) < 2.0)   # in range: not clipped
    assert np.allclose(acc / acc_lsb, np.round(acc / acc_lsb), rtol=0, atol=1e-9)
    assert np.allclose(gyr / gyr_lsb, np.round(gyr / gyr_lsb), rtol=0, atol=1e-9)
    # In a simulated walk: a +-3 g, +-300 deg/s part clips the foot's swing peaks.
    small = sim.ImuErrorModel(acc_range_mps2=3 * G, gyr_range_rps=300 * DEG)
    ideal = sim.simulate_walk(PHYSICS_WALK, rng=np.random.default_rng(3), imu='ideal')
    clipped = sim.simulate_walk(PHYSICS_WALK, rng=np.random.default_rng(3), imu=small)
    assert np.abs(ideal.gyr_b).max() > 300 * DEG and np.abs(ideal.acc_b).max() > 3 * G
    assert np.abs(clipped.gyr_b).max() == 300 * DEG
    assert np.abs(clipped.acc_b).max() == 3 * G


def test_ideal_preset_changes_nothing_and_presets_are_named():
    acc = np.random.default_rng(0).normal(size=(50, 3))
    out_acc, out_gyr = sim.apply_imu_errors(acc, -acc, 200.0, sim.IMU_PRESETS['ideal'],
                                            np.random.default_rng(1))
    assert np.array_equal(out_acc, acc) and np.array_equal(out_gyr, -acc)
    assert sim.imu_error_model('tactical') is sim.IMU_PRESETS['tactical']
    assert sim.IMU_PRESETS['ideal'].is_ideal and not sim.IMU_PRESETS['tactical'].is_ideal
    tactical = sim.IMU_PRESETS['tactical']
    # Tactical: ARW 0.1 deg/sqrt(h), 1 deg/h bias, VRW 0.03 m/s/sqrt(h), 0.5 mg bias.
    assert math.isclose(math.degrees(tactical.gyr_noise_density_rps_rthz) * 60.0, 0.1)
    assert math.isclose(math.degrees(tactical.gyr_bias_sigma_rps) * 3600.0, 1.0)
    assert math.isclose(tactical.acc_noise_density_mps2_rthz * 60.0, 0.03)
    assert math.isclose(tactical.acc_bias_sigma_mps2, 0.5e-3 * G)


# ----------------------------------------------------------------------------------------------
# Bad input
# ----------------------------------------------------------------------------------------------

@pytest.mark.parametrize('make, field', [
    (lambda: sim.Segment.stairs(10, 0), 'direction'),
    (lambda: sim.Segment.stairs(10, 1, steps_per_stride=5), 'steps_per_stride'),
    (lambda: sim.Segment.stairs(10, 1, step_height_m=0.5), 'step_height_m'),
    (lambda: sim.Segment.level(0), 'n_strides'),
    (lambda: sim.Segment.stand(-1.0), 'duration_s'),
    (lambda: sim.Segment('hop'), 'kind'),
    (lambda: sim.GaitParams(level_stride_s=(1.2, 0.9)), 'level_stride_s'),
    (lambda: sim.GaitParams(foot_flat_s=(0.1, 0.3)), 'foot_flat_s'),
    (lambda: sim.GaitParams(level_sink_mps=(0.0, 0.3)), 'level_sink_mps'),
    (lambda: sim.ImuErrorModel(gyr_noise_density_rps_rthz=-1.0), 'gyr_noise_density'),
    (lambda: sim.ImuErrorModel(adc_bits=16), 'adc_bits'),
    (lambda: sim.imu_error_model('navigation-grade'), 'consumer'),
    (lambda: sim.simulate_walk((sim.Segment.level(1),), rng=np.random.default_rng(0),
                               rate_hz=20.0), 'rate_hz'),
    (lambda: sim.simulate_walk((sim.Segment.level(1),), rng=np.random.default_rng(0),
                               initial_stand_s=1.0), 'initial_stand_s'),
    (lambda: sim.simulate_walk((sim.Segment.level(1),), rng=np.random.default_rng(0),
                               mounting_rpy_deg=(0.0, 0.0)), 'mounting_rpy_deg'),
    (lambda: sim.simulate_walk((sim.Segment.level(1),), rng=1), 'Generator'),
    (lambda: sim.simulate_walk((), rng=np.random.default_rng(0)), 'Segment'),
])
def test_bad_parameters_raise_input_error_naming_the_field(make, field):
    with pytest.raises(InputError, match=field):
        make()


def test_segments_and_results_are_frozen():
    segment = sim.Segment.level(3)
    with pytest.raises(dataclasses.FrozenInstanceError):
        segment.n_strides = 4
