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
    load_state, resumable_state, save_state, STATE_FORMAT, TrackingState)
import pytest

STATE = TrackingState(stamp_ns=1_700_000_000_000_000_000, wall_time_s=1000.0,
                      imu_id='/imu/data:imu_link', height_m=3.4, floor=1, x_m=1.5, y_m=-2.0,
                      z_m=3.3, heading_rad=0.7)


def test_round_trip_with_owner_only_permissions(tmp_path):
    path = tmp_path / 'state' / 'imu_node.json'
    save_state(path, STATE)
    assert load_state(path) == STATE
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o600
    assert [p.name for p in path.parent.iterdir()] == ['imu_node.json']  # no temporary left


def test_a_failed_write_leaves_the_previous_state(tmp_path, monkeypatch):
    path = tmp_path / 'imu_node.json'
    save_state(path, STATE)

    def broken_dump(*args, **kwargs):
        raise OSError('disk full')
    monkeypatch.setattr(json, 'dump', broken_dump)
    with pytest.raises(OSError):
        save_state(path, TrackingState(**{**STATE.__dict__, 'floor': 5}))
    monkeypatch.undo()
    assert load_state(path) == STATE
    assert len(list(tmp_path.iterdir())) == 1


@pytest.mark.parametrize('content', ['', '{', '[]', '{"format": "x", "version": 1}',
                                     json.dumps({'format': STATE_FORMAT, 'version': 2}),
                                     json.dumps({'format': STATE_FORMAT, 'version': 1,
                                                 'floor': 1}),
                                     json.dumps({'format': STATE_FORMAT, 'version': 1,
                                                 **{**STATE.__dict__, 'height_m': 'NaN'}}),
                                     json.dumps({'format': STATE_FORMAT, 'version': 1,
                                                 **{**STATE.__dict__, 'floor': 1.5}})])
def test_corrupt_files_raise_input_error(tmp_path, content):
    path = tmp_path / 'state.json'
    path.write_text(content)
    with pytest.raises(InputError):
        load_state(path)


def test_nan_height_is_refused_at_construction():
    with pytest.raises(InputError, match='height_m'):
        TrackingState(**{**STATE.__dict__, 'height_m': float('nan')})


def test_resume_only_fresh_state_of_the_same_imu(tmp_path):
    path = tmp_path / 'state.json'
    state, reason = resumable_state(path, STATE.imu_id, 60.0, now_s=1010.0)
    assert state is None and 'no state file' in reason
    save_state(path, STATE)
    state, reason = resumable_state(path, STATE.imu_id, 60.0, now_s=1010.0)
    assert state == STATE and reason.startswith('resuming')
    assert resumable_state(path, STATE.imu_id, 60.0, now_s=1100.0)[0] is None  # too old
    assert resumable_state(path, STATE.imu_id, 60.0, now_s=900.0)[0] is None  # from the future
    assert resumable_state(path, '/imu/other:imu_link', 60.0, now_s=1010.0)[0] is None
