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

"""Saturation recovery of a clipped gyro: the fit, the per-sample stage, the navigator's feed."""

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.gyro_rail import fill_rail_run, GyroRailParams, GyroRailStage
from anfis_elevation_ros.core.imu_data import ImuRecording
from anfis_elevation_ros.core.input_gate import InputGate
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.core.params import load_pipeline_params
from anfis_elevation_ros.sim import Segment, simulate_walk
from anfis_elevation_ros.tools.replay import navigated_samples
import numpy as np
import pytest

RATE_HZ = 200.0
RAIL_RPS = 8.55
ON = GyroRailParams(enabled=True)
OFF = GyroRailParams(enabled=False)


def swing_peak(t_s, peak_rps=12.0, width_s=0.04):
    """Return a swing's smooth rate peak on 1 rad/s (a Gaussian), rad/s."""
    return 1.0 + (peak_rps - 1.0) * np.exp(-0.5 * (t_s / width_s) ** 2)


def stamps_ns(n):
    return np.arange(n, dtype=np.int64) * int(1e9 / RATE_HZ)


def test_a_clipped_peak_gets_its_rotation_back():
    t_s = np.arange(-0.3, 0.3, 1.0 / RATE_HZ)
    true = swing_peak(t_s)
    clipped = np.minimum(true, RAIL_RPS)
    filled = fill_rail_run(t_s, clipped, RAIL_RPS, 2, 2)
    lost_deg = np.degrees(np.trapezoid(true - clipped, t_s))
    error_deg = np.degrees(np.trapezoid(filled - true, t_s))
    # 13 samples at the rail lose 8.8 deg; the quadratic through 2 samples each side leaves
    # -1.7 deg (measured): within 2.5 deg, a quarter of the loss.
    assert np.sum(clipped >= RAIL_RPS) == 13 and lost_deg == pytest.approx(8.8, abs=0.1)
    assert abs(error_deg) < 2.5 and abs(error_deg) < 0.25 * lost_deg
    assert np.all(filled[clipped < RAIL_RPS] == clipped[clipped < RAIL_RPS])
    assert np.all(filled >= clipped)
    # Never below the rail, on either side of it.
    assert np.all(fill_rail_run(t_s, -clipped, RAIL_RPS, 2, 2) == -filled)
    flat = np.where(clipped >= RAIL_RPS, RAIL_RPS, 0.0)        # a fit that stays under it
    assert np.all(fill_rail_run(t_s, flat, RAIL_RPS, 2, 2)[clipped >= RAIL_RPS] == RAIL_RPS)


def test_a_run_at_either_end_of_the_record_is_left_as_it_is():
    t_s = np.arange(-0.3, 0.3, 1.0 / RATE_HZ)
    clipped = np.minimum(swing_peak(t_s), RAIL_RPS)
    at_rail = np.flatnonzero(clipped >= RAIL_RPS)
    starts_clipped = clipped[at_rail[0] + 1:]
    ends_clipped = clipped[:at_rail[-1]]
    assert fill_rail_run(t_s[at_rail[0] + 1:], starts_clipped, RAIL_RPS, 2, 2) is starts_clipped
    assert fill_rail_run(t_s[:at_rail[-1]], ends_clipped, RAIL_RPS, 2, 2) is ends_clipped


def push_all(stage, gyr_b):
    """Push rates along x; return the released samples and how many were held after each."""
    released, held = [], []
    for stamp_ns, rate in zip(stamps_ns(len(gyr_b)).tolist(), gyr_b):
        released += stage.push(stamp_ns, np.zeros(3), np.array([rate, 0.0, 0.0]))
        held.append(stage.holding)
    return released, held


def test_the_stage_holds_only_while_the_gyro_clips_and_releases_every_sample_in_order():
    t_s = np.arange(-0.3, 0.3, 1.0 / RATE_HZ)
    clipped = np.minimum(swing_peak(t_s), RAIL_RPS)
    stage = GyroRailStage(RAIL_RPS, ON)
    released, held = push_all(stage, clipped)
    at_rail = clipped >= RAIL_RPS
    # Held from the first rail sample to the second clear one after the run: 13 + 2 samples,
    # a latency of 2 samples after the run (10 ms at 200 Hz).
    assert max(held) == 14 and np.sum(np.array(held) > 0) == 14
    assert [s for s, _, _, _ in released] == stamps_ns(len(clipped)).tolist()
    rebuilt = np.array([g[0] for _, _, g, _ in released])
    assert np.allclose(rebuilt, fill_rail_run(t_s - t_s[0], clipped, RAIL_RPS, 2, 2),
                       rtol=0.0, atol=1e-12)
    assert stage.filled_samples == np.sum(rebuilt != clipped) and stage.filled_samples > 10
    assert np.all(rebuilt[~at_rail] == clipped[~at_rail])
    # A record that starts at the rail: held, then released as it came (nothing before it).
    starts_clipped = clipped[np.flatnonzero(at_rail)[-1] - 2:]
    stage = GyroRailStage(RAIL_RPS, ON)
    released, held = push_all(stage, starts_clipped)
    assert held[:4] == [1, 2, 3, 4] and held[4] == 0
    assert np.array_equal([g[0] for _, _, g, _ in released], starts_clipped)


def test_a_run_longer_than_the_cap_is_released_as_it_came_and_never_stalls():
    t_s = np.arange(-0.4, 0.4, 1.0 / RATE_HZ)
    clipped = np.minimum(swing_peak(t_s, 14.0, 0.1), RAIL_RPS)     # 0.24 s at the rail
    stage = GyroRailStage(RAIL_RPS, ON)
    released, held = push_all(stage, clipped)
    assert max(held) == int(ON.max_run_s * RATE_HZ) + 1
    assert np.array_equal([g[0] for _, _, g, _ in released], clipped)
    assert stage.filled_samples == 0 and stage.long_run_samples == np.sum(clipped >= RAIL_RPS)
    # The record ends during a run: flush releases what is held, as it came.
    stage = GyroRailStage(RAIL_RPS, ON)
    end = int(np.flatnonzero(clipped >= RAIL_RPS)[0]) + 5
    released, held = push_all(stage, clipped[:end])
    assert held[-1] == 5
    released += stage.flush()
    assert np.array_equal([g[0] for _, _, g, _ in released], clipped[:end])


def test_params_are_checked():
    with pytest.raises(InputError, match='rail.fit_order'):
        GyroRailParams(fit_samples=1, fit_order=2)
    with pytest.raises(InputError, match='rail.max_run_s'):
        GyroRailParams(max_run_s=2.0)
    with pytest.raises(InputError, match='rail.range_fraction'):
        GyroRailParams(range_fraction=1.5)


@pytest.fixture(scope='module')
def clipped_walk():
    """Return a simulated walk whose gyro clips in every swing (range 4 rad/s)."""
    w = simulate_walk((Segment.level(6),), rng=np.random.default_rng(5), rate_hz=RATE_HZ,
                      imu='tactical')
    range_rps = 4.0
    rail = 0.99 * range_rps
    assert np.sum(np.abs(w.gyr_b) >= rail) > 100
    return w, np.clip(w.gyr_b, -rail, rail), range_rps


def test_per_sample_feed_equals_batch_and_replay(clipped_walk):
    w, gyr_b, range_rps = clipped_walk
    params = NavigatorParams(gyro_range_rps=range_rps, rail=ON)
    track, cycles = FootNavigator(params).run(w.stamp_ns, w.acc_b, gyr_b)
    live = FootNavigator(params)
    outputs = [out for t, a, g in zip(w.stamp_ns, w.acc_b, gyr_b)
               for out in live.step(int(t), a, g)] + live.flush()
    assert live.status.rail_filled_samples > 100
    assert len(outputs) == len(track) and len(track) > 0.9 * len(w.stamp_ns)
    assert [p.stamp_ns for p, _ in outputs] == [p.stamp_ns for p in track]
    assert all(np.array_equal(a.pos_n, b.pos_n) for a, b in zip(track, (p for p, _ in outputs)))
    live_cycles = [c for _, c in outputs if c is not None]
    assert len(live_cycles) == len(cycles) >= 5
    assert all(np.array_equal(a.features, b.features) for a, b in zip(cycles, live_cycles))
    pipeline = load_pipeline_params()
    replayed = list(navigated_samples(
        ImuRecording(w.stamp_ns, w.acc_b, gyr_b), InputGate(pipeline.gate),
        FootNavigator(params)))
    assert [p.stamp_ns for _, p, _ in replayed] == [p.stamp_ns for p in track]
    assert all(np.array_equal(a.pos_n, p.pos_n) for a, (_, p, _) in zip(track, replayed))


def test_without_a_declared_range_nothing_is_held(clipped_walk):
    w, gyr_b, _ = clipped_walk
    navigator = FootNavigator(NavigatorParams(rail=ON))
    counts = [len(navigator.step(int(t), a, g)) for t, a, g in zip(w.stamp_ns, w.acc_b, gyr_b)]
    assert set(counts[100:]) == {1} and navigator.flush() == []
    assert navigator.status.rail_filled_samples == 0


def test_rebuilt_samples_move_the_track_not_the_stances(clipped_walk):
    # The detector sees the rate as the sensor gave it: the same stances and cycle ends.
    w, gyr_b, range_rps = clipped_walk
    runs = [FootNavigator(NavigatorParams(gyro_range_rps=range_rps, rail=GyroRailParams(
        enabled=enabled))).run(w.stamp_ns, w.acc_b, gyr_b) for enabled in (False, True)]
    (plain_track, plain_cycles), (track, cycles) = runs
    assert [p.stance for p in track] == [p.stance for p in plain_track]
    assert [c.stamp_ns for c in cycles] == [c.stamp_ns for c in plain_cycles]
    moved_m = max(np.linalg.norm(a.pos_n - b.pos_n) for a, b in zip(track, plain_track))
    assert moved_m > 0.01


def test_a_simulated_walk_clipped_at_5_rad_s_ends_where_the_unclipped_one_does():
    # Three 6 m walks (tactical IMU, swing peaks 8 rad/s) clipped at 5 rad/s. Final position
    # error against the simulation's truth, summed (measured): 0.25 m unclipped, 0.43 m
    # clipped with the range declared, 0.25 m with the clipped samples rebuilt.
    errors = np.zeros(3)
    for seed in (5, 6, 7):
        w = simulate_walk((Segment.level(6),), rng=np.random.default_rng(seed), rate_hz=RATE_HZ,
                          imu='tactical')
        clipped = np.clip(w.gyr_b, -0.99 * 5.0, 0.99 * 5.0)
        for k, (gyr_b, params) in enumerate((
                (w.gyr_b, NavigatorParams()),
                (clipped, NavigatorParams(gyro_range_rps=5.0, rail=OFF)),
                (clipped, NavigatorParams(gyro_range_rps=5.0, rail=ON)))):
            track, _ = FootNavigator(params).run(w.stamp_ns, w.acc_b, gyr_b)
            first = len(w.stamp_ns) - len(track)
            errors[k] += np.linalg.norm(track[-1].pos_n - track[0].pos_n
                                        - (w.pos_n[-1] - w.pos_n[first]))
    unclipped, noise_only, rebuilt = errors
    assert rebuilt < 0.7 * noise_only
    assert rebuilt < unclipped + 0.05
