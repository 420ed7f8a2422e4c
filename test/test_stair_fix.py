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
The stair-position correction in the core (seed 003, eq. 2, 17-21), without ROS.

Association (nearest entry, eq. 18 threshold, direction table, floor), the EKF position update
against a hand-computed case, buildings without stairs or start, the exactly-once rule of
``PositionFixQueue`` across a restart (state file), and a replay of a short walk in which the
correction moves the track towards the database.
"""

from dataclasses import replace
import math

from anfis_elevation_ros.core import ekf
from anfis_elevation_ros.core.building import Building, Floor, StairEntry, Start
from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.navigator import FootNavigator, TrackPoint
from anfis_elevation_ros.core.params import load_model, load_pipeline_params
from anfis_elevation_ros.core.position_fix import PositionFixQueue
from anfis_elevation_ros.core.stair_database import association_threshold_m, CorrectionRequest
from anfis_elevation_ros.core.stair_database import nearest_entry, StairDatabase
from anfis_elevation_ros.core.stair_database import stair_monitor_for, StairEntryMonitor
from anfis_elevation_ros.core.state import load_state, NavigationState, save_state
from anfis_elevation_ros.tools.replay import replay_recording
from live_support import write_linear_model
import numpy as np
import pytest
from stair_support import simulate_stair_walk, stair_walk_building, STEP_HEIGHT_M

UP, LEVEL, DOWN = 1, 0, -1
FLOORS = (Floor(0, 0.0), Floor(1, 3.2))
START = Start(x_m=0.0, y_m=0.0, floor=0, heading_deg=0.0)


def entry(stairwell, floor, direction, x_m, y_m):
    """Return a database entry."""
    return StairEntry(stairwell=stairwell, floor=floor, direction=direction, x_m=x_m, y_m=y_m)


def monitor_for(*entries, ratio=0.03):
    """Return a StairEntryMonitor of a building with these entries."""
    return StairEntryMonitor(StairDatabase(entries), ratio)


def walk_then_enter(monitor, level_xy, stair_xy, mode=UP, floor=0):
    """Feed level cycles along level_xy, then one stair cycle at stair_xy; return its request."""
    for k, (x, y) in enumerate(level_xy):
        assert monitor.update(k + 1, k * 10**9, x, y, True, LEVEL, floor) is None
    n = len(level_xy)
    return monitor.update(n + 1, n * 10**9, *stair_xy, True, mode, floor + (mode > 0))


def straight_walk(length_m, n=20):
    """Level cycles along +x from the origin to length_m."""
    return [(length_m * k / n, 0.0) for k in range(n + 1)]


# -- association, eq. (17)-(18) ------------------------------------------------------------------

def test_nearest_entry_is_the_closest_and_an_empty_table_has_none():
    positions = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 1.0]])
    assert nearest_entry(positions, (9.0, 0.8)) == (2, pytest.approx(math.hypot(1.0, 0.2)))
    assert nearest_entry(np.zeros((0, 2)), (1.0, 1.0)) == (None, math.inf)


def test_the_nearest_entry_of_the_table_is_associated():
    monitor = monitor_for(entry('A', 0, UP, 100.0, 0.3), entry('B', 0, UP, 101.5, 0.0),
                          entry('C', 0, UP, 0.0, 50.0))
    request = walk_then_enter(monitor, straight_walk(100.0), (100.2, 0.0))
    assert request.stairwell == 'A' and request.floor == 0 and request.direction == UP
    assert (request.entry_x_m, request.entry_y_m) == (100.0, 0.3)
    assert np.allclose(request.innovation_xy, [-0.2, 0.3])   # P_database - P_xy
    assert request.cycle_index == 22 and request.stamp_ns == 21 * 10**9
    assert monitor.counters['stair_fix_accepted'] == 1 and monitor.distance_m == 0.0


def test_threshold_is_the_ratio_of_the_distance_walked():
    assert association_threshold_m(100.0, 0.03) == pytest.approx(3.0)
    # 100 m walked (+0.2 m into the stairs): th_st = 3.006 m. Just inside, then just outside.
    inside = monitor_for(entry('A', 0, UP, 100.2, 2.99))
    assert walk_then_enter(inside, straight_walk(100.0), (100.2, 0.0)) is not None
    outside = monitor_for(entry('A', 0, UP, 100.2, 3.02))
    assert walk_then_enter(outside, straight_walk(100.0), (100.2, 0.0)) is None
    assert outside.refused_far == 1 and outside.accepted == 0
    assert outside.last_threshold_m == pytest.approx(3.006)
    # After an accepted correction the distance starts again: 1 m later th_st is 0.03 m.
    walk_then_enter(inside, [(100.2, 0.0), (101.2, 0.0)], (101.2, 0.0), mode=DOWN, floor=1)
    assert inside.last_threshold_m == pytest.approx(0.03)


def test_an_entry_of_the_other_direction_is_never_used():
    # Going up next to an entry going down: the up table is empty, or its entry is far.
    down_only = monitor_for(entry('A', 0, DOWN, 50.0, 0.0))
    assert walk_then_enter(down_only, straight_walk(50.0), (50.0, 0.0)) is None
    assert down_only.refused_no_entry == 1
    both = monitor_for(entry('A', 0, DOWN, 50.0, 0.0), entry('B', 0, UP, 0.0, 40.0))
    assert walk_then_enter(both, straight_walk(50.0), (50.0, 0.0)) is None
    assert both.refused_far == 1 and both.last_distance_m == pytest.approx(math.hypot(50, 40))


def test_an_entry_on_another_floor_is_never_used():
    # The same place one floor up (stairwells stack): walking on floor 0, the entry of floor 1
    # does not count; walking on floor 1, it does.
    monitor = monitor_for(entry('A', 1, UP, 50.0, 0.0))
    assert walk_then_enter(monitor, straight_walk(50.0), (50.0, 0.0), floor=0) is None
    assert monitor.refused_no_entry == 1
    monitor = monitor_for(entry('A', 1, UP, 50.0, 0.0))
    assert walk_then_enter(monitor, straight_walk(50.0), (50.0, 0.0), floor=1) is not None


def test_only_the_first_stair_cycle_after_level_walking_is_an_entry():
    monitor = monitor_for(entry('A', 0, UP, 50.0, 0.0))
    assert walk_then_enter(monitor, straight_walk(50.0), (50.0, 0.0)) is not None
    # Further stair cycles, an invalid cycle, and stairs after stairs: no entry.
    assert monitor.update(30, 30 * 10**9, 50.3, 0.0, True, UP, 1) is None
    assert monitor.update(31, 31 * 10**9, 50.6, 0.0, False, LEVEL, 1) is None
    assert monitor.update(32, 32 * 10**9, 50.9, 0.0, True, UP, 1) is None
    assert monitor.entries == 1
    # An invalid cycle between level and stairs does not hide the entry (it is not classified).
    monitor = monitor_for(entry('A', 0, UP, 50.0, 0.0))
    for k, (x, y) in enumerate(straight_walk(50.0)):
        monitor.update(k + 1, k * 10**9, x, y, True, LEVEL, 0)
    assert monitor.update(40, 40 * 10**9, 50.0, 0.0, False, LEVEL, 0) is None
    assert monitor.update(41, 41 * 10**9, 50.1, 0.0, True, UP, 1) is not None


def test_buildings_without_stairs_or_start_correct_nothing():
    stairs = (entry('A', 0, UP, 5.0, 0.0),)
    assert stair_monitor_for(None, 0.03) is None
    assert stair_monitor_for(Building('b', FLOORS, start=START), 0.03) is None
    # Stairs but no start: the track is not in the building's frame.
    assert stair_monitor_for(Building('b', FLOORS, stairs=stairs), 0.03) is None
    assert stair_monitor_for(Building('b', FLOORS, stairs=stairs, start=START), 0.03) \
        is not None


def test_a_request_with_a_bad_position_or_direction_is_refused():
    good = {'cycle_index': 1, 'stamp_ns': 5, 'x_m': 0.0, 'y_m': 0.0, 'entry_x_m': 1.0,
            'entry_y_m': 1.0, 'stairwell': 'A', 'floor': 0, 'direction': 1}
    CorrectionRequest(**good)
    with pytest.raises(InputError, match='non-finite'):
        CorrectionRequest(**{**good, 'entry_x_m': math.nan})
    with pytest.raises(InputError, match='direction'):
        CorrectionRequest(**{**good, 'direction': 0})


# -- the EKF update, eq. (2), (19)-(21) ----------------------------------------------------------

def test_position_correction_matches_the_hand_computed_update():
    # Position variance 0.25 m^2 on x and y, yaw variance 0.04 rad^2, cov(x, yaw) = 0.01;
    # sigma 0.3 m. S = diag(0.34, 0.34); K_x = 0.25 / 0.34, K_yaw = 0.01 / 0.34 on the x row.
    yaw = ekf.ATT.start + 2
    P = np.eye(15) * 1e-4
    P[0, 0] = P[1, 1] = 0.25
    P[yaw, yaw] = 0.04
    P[0, yaw] = P[yaw, 0] = 0.01
    dx, P_new, nis = ekf.position_correction(P, np.array([1.0, -0.5]), 0.3)
    assert dx[0] == pytest.approx(0.25 / 0.34) and dx[1] == pytest.approx(-0.5 * 0.25 / 0.34)
    assert dx[yaw] == pytest.approx(0.01 / 0.34)
    assert np.allclose(np.delete(dx, [0, 1, yaw]), 0.0)
    assert P_new[0, 0] == pytest.approx(0.25 * 0.09 / 0.34)
    assert P_new[1, 1] == pytest.approx(0.25 * 0.09 / 0.34)
    assert P_new[yaw, yaw] == pytest.approx(0.04 - 0.01 ** 2 / 0.34)
    assert P_new[0, yaw] == pytest.approx(0.01 * 0.09 / 0.34)
    assert nis == pytest.approx((1.0 + 0.25) / 0.34)
    assert np.allclose(P_new, P_new.T) and np.all(np.linalg.eigvalsh(P_new) > 0.0)


# -- exactly once, across a restart ---------------------------------------------------------------

class RecordingNavigator:
    """Stands in for FootNavigator: records the position updates it is given."""

    def __init__(self):
        self.updates = []

    def correct_position(self, innovation_xy, sigma_m):
        """Record the update; return a NIS."""
        self.updates.append(tuple(innovation_xy))
        return 1.0


def request_at(stamp_s):
    """Return a request made by the cycle stamped stamp_s."""
    return CorrectionRequest(cycle_index=7, stamp_ns=int(stamp_s * 1e9), x_m=1.0, y_m=2.0,
                             entry_x_m=1.5, entry_y_m=2.0, stairwell='A', floor=0, direction=1)


def step(queue, navigator, stamp_s, stance=True):
    """One navigated sample through the queue; return the requests applied at it."""
    point = TrackPoint(int(round(stamp_s * 1e9)), np.zeros(3), np.array([1.0, 0, 0, 0]), stance)
    return queue.after_step(navigator, point)


def test_a_request_is_applied_once_at_the_first_stance_after_the_delay():
    queue, navigator = PositionFixQueue(0.5, 0.3), RecordingNavigator()
    assert queue.submit(request_at(10.0)) == 'queued'
    assert step(queue, navigator, 10.4) == []
    assert step(queue, navigator, 10.6, stance=False) == []     # due, but in a swing
    assert len(step(queue, navigator, 10.7)) == 1                 # the first stance after
    assert navigator.updates == [(0.5, 0.0)]
    assert step(queue, navigator, 10.8) == []
    assert queue.submit(request_at(10.0)) == 'duplicate'
    step(queue, navigator, 11.0)
    assert len(navigator.updates) == 1
    # A request that comes after its sample was processed is applied late, and counted.
    assert queue.submit(request_at(10.2)) == 'late'
    assert len(step(queue, navigator, 11.1)) == 1 and queue.late == 1


def test_restart_in_the_middle_of_a_correction_never_applies_it_twice(tmp_path):
    """Kill after the fix, or before it, or at the cycle's own sample: applied exactly once."""
    def run_until_killed(kill_after_s):
        queue, navigator = PositionFixQueue(0.5, 0.3), RecordingNavigator()
        queue.submit(request_at(10.0))
        saved = None
        for stamp_s, closes_cycle in ((10.55, False), (10.6, True), (10.7, False),
                                      (11.6, True)):
            if stamp_s > kill_after_s:
                break
            step(queue, navigator, stamp_s)
            if closes_cycle:       # the IMU node saves its state with each cycle
                saved = NavigationState(
                    stamp_ns=int(stamp_s * 1e9), wall_time_s=0.0, source_id='imu', x_m=0.0,
                    y_m=0.0, z_m=0.0, heading_rad=0.0, filter_ok=True, cycles=1,
                    stride_period_s=1.0, walk_id=1, map_frame=True,
                    stair_fixes=queue.applied_before(int(round(stamp_s * 1e9))))
                save_state(tmp_path / 'imu.json', saved)
        return navigator

    def resume_and_receive_history():
        state = load_state(tmp_path / 'imu.json', NavigationState)
        queue, navigator = PositionFixQueue(0.5, 0.3), RecordingNavigator()
        queue.submit(request_at(10.0))      # transient-local history, before the first sample
        queue.restore(state.stair_fixes)
        step(queue, navigator, 20.0)
        step(queue, navigator, 20.1)
        return navigator, queue

    # Applied at 10.55 s, saved at the cycle of 10.6 s, killed: the saved position holds it.
    before = run_until_killed(10.65)
    after, queue = resume_and_receive_history()
    assert len(before.updates) == 1 and after.updates == [] and queue.duplicates == 1
    # Applied at the very sample that closes the cycle (its position is from before the
    # update): the saved state does not hold it, so the resumed node applies it, once.
    (tmp_path / 'imu.json').unlink()
    queue, navigator = PositionFixQueue(0.5, 0.3), RecordingNavigator()
    queue.submit(request_at(10.0))
    step(queue, navigator, 10.6)
    assert len(navigator.updates) == 1 and queue.applied_before(int(10.6e9)) == []
    save_state(tmp_path / 'imu.json', NavigationState(
        stamp_ns=int(10.6e9), wall_time_s=0.0, source_id='imu', x_m=0.0, y_m=0.0, z_m=0.0,
        heading_rad=0.0, filter_ok=True, cycles=1, stride_period_s=1.0, walk_id=1,
        stair_fixes=queue.applied_before(int(10.6e9))))
    after, queue = resume_and_receive_history()
    assert len(after.updates) == 1
    # Killed before the fix, with a state of an earlier cycle: applied once after the resume.
    (tmp_path / 'imu.json').unlink()
    save_state(tmp_path / 'imu.json', NavigationState(
        stamp_ns=int(9.6e9), wall_time_s=0.0, source_id='imu', x_m=0.0, y_m=0.0, z_m=0.0,
        heading_rad=0.0, filter_ok=True, cycles=1, stride_period_s=1.0, walk_id=1))
    after, queue = resume_and_receive_history()
    assert len(after.updates) == 1 and queue.late == 0


def test_a_fresh_track_refuses_the_requests_of_an_earlier_walk():
    queue, navigator = PositionFixQueue(0.5, 0.3), RecordingNavigator()
    assert queue.submit(request_at(10.0)) == 'queued'     # history, before the first sample
    queue.refuse_before(int(50e9))
    assert queue.submit(request_at(20.0)) == 'stale'
    step(queue, navigator, 60.0)
    assert navigator.updates == [] and queue.stale == 2


def test_state_stair_fixes_are_checked():
    fields = {'stamp_ns': 1, 'wall_time_s': 0.0, 'source_id': 'imu', 'x_m': 0.0, 'y_m': 0.0,
              'z_m': 0.0, 'heading_rad': 0.0, 'filter_ok': True, 'cycles': 1,
              'stride_period_s': 1.0, 'walk_id': 1}
    assert NavigationState(**fields).stair_fixes == []
    with pytest.raises(InputError, match='stair_fixes'):
        NavigationState(**fields, stair_fixes=[1.5])
    with pytest.raises(InputError, match='stair_fixes'):
        NavigationState(**fields, stair_fixes=[True])


def test_a_resumed_filter_keeps_its_uncertainty_for_the_next_correction(stair_walk):
    # Position sigma 0.5 m (trace), so 0.25 / 3 m^2 per axis: K = 0.0833 / (0.0833 + 0.09).
    walk = stair_walk[0]
    recording = walk.to_recording()
    moves = []
    for sigmas in (None, (0.5, 0.05)):
        navigator = FootNavigator(start_pos_n=(1.0, 2.0, 0.0), start_sigmas=sigmas)
        k = 0
        while not navigator.initialised:
            navigator.step(int(recording.stamp_ns[k]), recording.acc_b[k], recording.gyr_b[k])
            k += 1
        [(point, _)] = navigator.step(int(recording.stamp_ns[k]), recording.acc_b[k],
                                      recording.gyr_b[k])
        navigator.correct_position(np.array([0.4, 0.0]), 0.3)
        [(after, _)] = navigator.step(int(recording.stamp_ns[k + 1]), recording.acc_b[k + 1],
                                      recording.gyr_b[k + 1])
        moves.append(after.pos_n[0] - point.pos_n[0])
    assert abs(moves[0]) < 1e-3          # a fresh start: the position is known
    gain = (0.25 / 3 + 1e-8) / (0.25 / 3 + 1e-8 + 0.09)
    assert moves[1] == pytest.approx(0.4 * gain, abs=2e-3)
    with pytest.raises(InputError, match='start sigmas'):
        FootNavigator(start_sigmas=(math.nan, 0.0))


# -- the whole chain offline ------------------------------------------------------------------

@pytest.fixture(scope='module')
def stair_walk(tmp_path_factory):
    """Give the short stair walk, a known model, and the pipeline parameters (th_st 20 %)."""
    walk, entries = simulate_stair_walk()
    model = load_model(str(write_linear_model(
        tmp_path_factory.mktemp('model') / 'model.json', STEP_HEIGHT_M)))
    pipeline = load_pipeline_params()
    # ZARU off: it learns the z-gyro bias in the walk's stands and leaves the position too
    # certain for the fix to move it as this test measures (with it on the fix moved the
    # resumed position 0.05 m, test_stair_fix_restart.py).
    navigator = replace(pipeline.navigator, heading=replace(pipeline.navigator.heading,
                                                            zaru_enabled=False))
    pipeline = replace(pipeline, navigator=navigator, building_aid=replace(
        pipeline.building_aid, stair_fix_ratio=0.2))
    return walk, entries, model, pipeline


def test_replay_corrects_at_the_entries_and_not_without_stairs(stair_walk):
    walk, entries, model, pipeline = stair_walk
    recording = walk.to_recording()
    plain = replay_recording(recording, pipeline, model,
                             building=stair_walk_building(walk, entries, stairs=False))
    fixed = replay_recording(recording, pipeline, model,
                             building=stair_walk_building(walk, entries))
    assert plain.stair_monitor is None and plain.fixes.applied_count == 0
    assert fixed.stair_monitor.accepted == 2 and fixed.fixes.applied_count == 2
    assert fixed.fixes.late == 0 and fixed.fixes.duplicates == 0
    # The map frame: the walk starts at the entrance, its first strides go along +y.
    first = plain.cycles[1]
    assert abs(first[3] - 12.3) < 0.1 and first[4] > 4.1 + 1.0
    # The database is 0.5 m off the truth, at (+0.4, -0.3): after the first fix the track
    # moves that way; before it, both tracks are the same.
    stamps = [row[0] for row in fixed.cycles]
    first_fix = fixed.fixes.applied_ids[0]
    k = next(i for i, s in enumerate(stamps) if s > first_fix + 5 * 10**8)
    assert [r[3:5] for r in fixed.cycles[:k - 1]] == [r[3:5] for r in plain.cycles[:k - 1]]
    shift = np.subtract(fixed.cycles[k][3:5], plain.cycles[k][3:5])
    assert 0.1 < shift[0] < 0.4 and -0.3 < shift[1] < 0.0


def test_simulate_writes_the_seed003_building(tmp_path, capsys):
    """``simulate --scenario seed003`` writes its building file, without an unknown stairwell."""
    from anfis_elevation_ros.tools.cli import main
    from anfis_elevation_ros.core.building import load_building

    out = tmp_path / 'seed003'
    assert main(['simulate', '--scenario', 'seed003', '--rate-hz', '50', '--unknown-stairwell',
                 'D', '--out', str(out)]) == 0
    building = load_building(out / 'building.yaml')
    assert len(building.stairs) == 6 and 'D' not in {e.stairwell for e in building.stairs}
    assert (building.start.x_m, building.start.y_m, building.start.heading_deg) == \
        (12.3, 4.1, 90.0)
    assert "IMU 'seed003'" in capsys.readouterr().err
    assert main(['simulate', '--scenario', 'sample', '--unknown-stairwell', 'D', '--out',
                 str(tmp_path / 'sample')]) == 1
    assert '--unknown-stairwell applies to --scenario seed003 only' in capsys.readouterr().err
