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

"""Persisted tracking state: atomic 0600 writes, strict reads, freshness and IMU identity."""

import json
import os
import stat

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.state import (
    ElevationState, is_walk_id, load_state, MAX_WALK_ID, NavigationState, new_walk_id,
    resumable_state, save_state, state_file, STATE_FORMAT, STATE_VERSION, walk_continues)
import pytest

STATE = NavigationState(stamp_ns=1_700_000_000_000_000_000, wall_time_s=1000.0,
                        source_id='/imu/data:imu_link', x_m=1.5, y_m=-2.0, z_m=3.3,
                        heading_rad=0.7, filter_ok=True, cycles=42,
                        stride_period_s=1.1, walk_id=12345)
ELEVATION = ElevationState(stamp_ns=1_700_000_000_000_000_000, wall_time_s=1000.0,
                           source_id='/gait_cycle', height_m=3.4, floor=1, cycle_index=42,
                           walk_id=12345, step_height_m=0.153, riser_strides=17,
                           last_mode=1, last_abs_dh_m=0.31, floor_doubt='5 cycles unobserved')


@pytest.mark.parametrize('state', [STATE, ELEVATION])
def test_round_trip_with_owner_only_permissions(tmp_path, state):
    path = tmp_path / 'state' / 'imu_node.json'
    save_state(path, state)
    assert load_state(path, type(state)) == state
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o600
    assert stat.S_IMODE(os.stat(path.parent).st_mode) == 0o700
    assert [p.name for p in path.parent.iterdir()] == ['imu_node.json']  # no temporary left


def test_a_state_of_the_other_kind_is_refused(tmp_path):
    path = tmp_path / 'classifier_node.json'
    save_state(path, ELEVATION)
    with pytest.raises(InputError, match='NavigationState'):
        load_state(path, NavigationState)


def test_a_failed_write_leaves_the_previous_state(tmp_path, monkeypatch):
    path = tmp_path / 'imu_node.json'
    save_state(path, STATE)

    def broken_dump(*args, **kwargs):
        raise OSError('disk full')
    monkeypatch.setattr(json, 'dump', broken_dump)
    with pytest.raises(OSError):
        save_state(path, NavigationState(**{**STATE.__dict__, 'cycles': 43}))
    monkeypatch.undo()
    assert load_state(path, NavigationState) == STATE
    assert len(list(tmp_path.iterdir())) == 1


def _document(**changes):
    return json.dumps({'format': STATE_FORMAT, 'version': STATE_VERSION,
                       'kind': 'NavigationState', **{**STATE.__dict__, **changes}})


@pytest.mark.parametrize('content', ['', '{', '[]', '{"format": "x", "version": 1}',
                                     '[' * 100000,
                                     json.dumps({'format': STATE_FORMAT, 'version': 1}),
                                     json.dumps({'format': STATE_FORMAT,
                                                 'version': STATE_VERSION,
                                                 'kind': 'NavigationState', 'cycles': 1}),
                                     _document(x_m='NaN'), _document(cycles=1.5),
                                     _document(filter_ok=1), _document(source_id=7),
                                     _document(walk_id=0), _document(walk_id=2 ** 31),
                                     _document(walk_id=True), _document(walk_id=3.0),
                                     _document(extra=1)])
def test_corrupt_files_raise_input_error(tmp_path, content):
    path = tmp_path / 'state.json'
    path.write_text(content)
    with pytest.raises(InputError):
        load_state(path, NavigationState)


def test_nan_position_is_refused_at_construction():
    with pytest.raises(InputError, match='x_m'):
        NavigationState(**{**STATE.__dict__, 'x_m': float('nan')})


def test_resume_only_fresh_state_of_the_same_source(tmp_path):
    path = tmp_path / 'state.json'
    state, reason = resumable_state(path, NavigationState, STATE.source_id, 60.0, now_s=1010.0)
    assert state is None and 'no state file' in reason
    save_state(path, STATE)
    state, reason = resumable_state(path, NavigationState, STATE.source_id, 60.0, now_s=1010.0)
    assert state == STATE and reason.startswith('resuming')
    assert resumable_state(path, NavigationState, STATE.source_id, 60.0,
                           now_s=1100.0)[0] is None  # too old
    assert resumable_state(path, NavigationState, STATE.source_id, 60.0,
                           now_s=900.0)[0] is None  # from the future
    assert resumable_state(path, NavigationState, '/imu/other:imu_link', 60.0,
                           now_s=1010.0)[0] is None


def test_state_file_names_follow_the_node_and_ros_home(monkeypatch):
    monkeypatch.setenv('ROS_HOME', '/tmp/rh')
    assert str(state_file('', '/imu_node')) == '/tmp/rh/anfis_elevation_ros/imu_node.state.json'
    assert str(state_file('/var/x', '/left_boot/imu_node')) == \
        '/var/x/left_boot.imu_node.state.json'


T0 = 1_700_000_000_000_000_000


@pytest.mark.parametrize('gap_s, continues, words', [
    (1.5, True, 'continue the saved state after 1.5 s'), (30.0, True, 'after 30.0 s'),
    (0.0, False, 'before'), (-40.0, False, '40.0 s before'),
    (30.5, False, 'resume_max_gap_s = 30 s'), (3600.0, False, '3600.0 s after')])
def test_resume_only_when_the_sensor_stamps_continue(gap_s, continues, words):
    """Not earlier (a replay, a reset clock), not far later (another walk): a restart only."""
    ok, why = walk_continues(T0, T0 + int(gap_s * 1e9), 30.0)
    assert ok is continues and words in why


def test_walk_ids_are_random_and_in_range():
    ids = [new_walk_id() for _ in range(200)]
    assert len(set(ids)) > 190 and all(is_walk_id(i) for i in ids)
    assert not any(is_walk_id(v) for v in (0, MAX_WALK_ID + 1, True, 5.0, '5'))


def test_a_version_2_elevation_state_is_refused_with_the_reason(tmp_path):
    path = tmp_path / 'classifier.state.json'
    old = {k: v for k, v in ELEVATION.__dict__.items()
           if k not in ('step_height_m', 'riser_strides')}
    path.write_text(json.dumps({'format': STATE_FORMAT, 'version': 2,
                                'kind': 'ElevationState', **old}))
    state, reason = resumable_state(path, ElevationState, '/gait_cycle', 60.0, now_s=1010.0)
    assert state is None and 'version 2' in reason and 'reads version' in reason


@pytest.mark.parametrize('changes', [{'step_height_m': 0.3}, {'step_height_m': float('nan')},
                                     {'riser_strides': -1}, {'riser_strides': 2.0}])
def test_a_bad_riser_height_in_a_state_is_refused(changes):
    with pytest.raises(InputError, match='step_height_m|riser_strides'):
        ElevationState(**{**ELEVATION.__dict__, **changes})


@pytest.mark.parametrize('changes', [{'last_mode': 2}, {'last_abs_dh_m': -0.1},
                                     {'last_abs_dh_m': float('inf')}, {'floor_doubt': 7},
                                     {'floor_doubt': 'x' * 501}, {'last_mode': True}])
def test_a_bad_outage_field_of_an_elevation_state_is_refused(changes):
    with pytest.raises(InputError):
        ElevationState(**{**ELEVATION.__dict__, **changes})
