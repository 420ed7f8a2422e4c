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

"""The command-centre model: responders by namespace, floors, tracks, bad input, bounded memory."""

import math
import threading

from anfis_elevation_ros.command_centre import incident as incident_module
from anfis_elevation_ros.command_centre.incident import Incident
from anfis_elevation_ros.core.building import building_from_dict
from command_centre_support import FakeClock
import pytest

BUILDING = building_from_dict({
    'format': 'anfis_elevation_ros/building', 'version': 1, 'name': 'Tower',
    'floors': [{'index': 0, 'elevation_m': 0.0, 'name': 'Ground',
                'outline': [[0, 0], [30, 0], [30, 20], [0, 20]]},
               {'index': 1, 'elevation_m': 3.0}, {'index': 2, 'elevation_m': 6.0}],
    'stairs': [{'stairwell': 'A', 'floor': 0, 'direction': 'up', 'x_m': 5.0, 'y_m': 2.0}]})


def feed(incident, rid, floor, x_m=1.0, y_m=2.0, certain=True, stamp_ns=1):
    incident.update_pose(rid, stamp_ns, x_m, y_m, 3.0 * floor, 45.0, 0.8)
    incident.update_elevation(rid, stamp_ns, x_m, y_m, 3.0 * floor)
    incident.update_floor(rid, floor)
    incident.update_floor_certain(rid, certain)
    incident.update_mode(rid, 1)


def test_responders_fields_and_floor_counts():
    clock = FakeClock()
    incident = Incident(BUILDING, clock=clock)
    feed(incident, '/ff1', 0)
    feed(incident, '/ff2', 2)
    feed(incident, '/crew/ff3', 2, certain=False)
    clock.t = 1.5
    state = incident.snapshot()
    by_id = {r['id']: r for r in state['responders']}
    assert set(by_id) == {'/ff1', '/ff2', '/crew/ff3'}
    ff2 = by_id['/ff2']
    assert (ff2['floor'], ff2['floor_certain'], ff2['mode']) == (2, True, 1)
    assert (ff2['x_m'], ff2['y_m'], ff2['z_m']) == (1.0, 2.0, 6.0)
    assert (ff2['heading_deg'], ff2['sigma_xy_m']) == (45.0, 0.8)
    assert ff2['last_update_age_s'] == 1.5
    assert ff2['data_quality'] == 'unknown' and ff2['alarms'] == []
    # A crumb at first contact (floor not yet known) and one when the floor came.
    assert ff2['track'] == [[1.0, 2.0, None, None], [1.0, 2.0, 6.0, 2]]
    assert by_id['/crew/ff3']['floor_certain'] is False
    floors = {f['index']: f for f in state['floors']}
    assert [f['index'] for f in state['floors']] == [2, 1, 0]
    assert (floors[2]['responders'], floors[2]['uncertain'], floors[0]['responders'],
            floors[1]['responders']) == (2, 1, 1, 0)
    assert sum(f['responders'] for f in state['floors']) == 3
    assert floors[0]['name'] == 'Ground'
    assert state['building']['floors'][0]['outline'] == [[0, 0], [30, 0], [30, 20], [0, 20]]
    assert state['building']['stairs'][0]['direction'] == 1


def test_stamps_of_the_latest_message_and_of_the_latest_elevation():
    incident = Incident(clock=FakeClock())
    incident.update_elevation('/ff1', 1_000_000_000, 1.0, 2.0, 0.0)
    incident.update_pose('/ff1', 1_500_000_000, 1.1, 2.0, 0.0, 0.0, 0.5)
    ff1 = incident.snapshot()['responders'][0]
    assert (ff1['stamp_unix_s'], ff1['elevation_stamp_unix_s']) == (1.5, 1.0)


def test_floor_not_in_the_building_is_listed_and_without_building_the_seen_floors():
    incident = Incident(clock=FakeClock())
    feed(incident, '/ff1', -1)
    feed(incident, '/ff2', 3)
    assert [(f['index'], f['responders']) for f in incident.snapshot()['floors']] == \
        [(3, 1), (-1, 1)]
    assert incident.snapshot()['building'] is None


def test_a_responder_in_doubt_may_be_on_every_floor_of_its_range():
    """Floor 3 or 4 (storeys unknown): counted on 4, possible on 3, until the floor is sure."""
    incident = Incident(clock=FakeClock())
    feed(incident, '/ff1', 4, certain=False)
    incident.update_floor_range('/ff1', [3, 4])
    feed(incident, '/ff2', 2)
    incident.update_floor_range('/ff2', [2, 2])

    def counts():
        return [(f['index'], f['responders'], f['uncertain'], f['possible'])
                for f in incident.snapshot()['floors']]

    assert counts() == [(4, 1, 1, 0), (3, 0, 0, 1), (2, 1, 0, 0)]
    incident.update_floor_range('/ff1', [-50, 50])      # says nothing about any one floor
    assert counts() == [(4, 1, 1, 0), (2, 1, 0, 0)]
    incident.update_floor_range('/ff1', [3, 4])
    incident.update_floor_certain('/ff1', True)
    assert counts() == [(4, 1, 0, 0), (2, 1, 0, 0)]


def test_roster_sorted_by_alarm_priority():
    clock = FakeClock()
    incident = Incident(clock=clock)
    for rid in ('/a', '/b', '/c'):
        feed(incident, rid, 0)
    incident.update_diagnostics('/c', 2, '/c/imu_node: IMU input', 'lost')
    assert [r['id'] for r in incident.snapshot()['responders']] == ['/c', '/a', '/b']


@pytest.mark.parametrize('call', [
    lambda i: i.update_pose('/ff2', 1, math.nan, 0.0, 0.0, 0.0, 0.5),
    lambda i: i.update_pose('/ff2', 1, 0.0, 0.0, 0.0, math.inf, 0.5),
    lambda i: i.update_pose('/ff2', 1, 0.0, 0.0, 0.0, 0.0, -1.0),
    lambda i: i.update_pose('/ff2', 'x', 0.0, 0.0, 0.0, 0.0, None),
    lambda i: i.update_elevation('/ff2', 1, 0.0, None, 0.0),
    lambda i: i.update_floor('/ff2', 1.5),
    lambda i: i.update_floor('/ff2', True),
    lambda i: i.update_floor_certain('/ff2', 1),
    lambda i: i.update_mode('/ff2', 2),
    lambda i: i.update_floor_range('/ff2', [3]),
    lambda i: i.update_floor_range('/ff2', [4, 3]),
    lambda i: i.update_floor_range('/ff2', [3, 4.0]),
    lambda i: i.update_floor_range('/ff2', 3),
    lambda i: i.update_diagnostics('/ff2', 7, 'n', 'm'),
    lambda i: i.update_diagnostics('/ff2', 0, None, 'm'),
    lambda i: i.update_pose('ff2', 1, 0.0, 0.0, 0.0, 0.0, 0.5),
    lambda i: i.update_pose('/ff 2', 1, 0.0, 0.0, 0.0, 0.0, 0.5),
    lambda i: i.update_pose(None, 1, 0.0, 0.0, 0.0, 0.0, 0.5),
])
def test_bad_input_is_counted_and_changes_nothing(call):
    incident = Incident(clock=FakeClock())
    feed(incident, '/ff1', 1)
    feed(incident, '/ff2', 2, x_m=4.0)
    before = incident.snapshot()
    call(incident)
    after = incident.snapshot()
    assert sum(after['rejected'].values()) == 1
    assert after['responders'] == before['responders']
    assert after['seq'] == before['seq']


def test_heading_wraps_and_sigma_may_be_unknown():
    incident = Incident(clock=FakeClock())
    incident.update_pose('/ff1', 1, 0.0, 0.0, 0.0, -90.0, None)
    r = incident.snapshot()['responders'][0]
    assert (r['heading_deg'], r['sigma_xy_m']) == (270.0, None)


def test_track_is_a_bounded_ring_of_crumbs_half_a_metre_apart():
    incident = Incident(clock=FakeClock())
    for k in range(10):                           # 1 cm apart: one crumb
        incident.update_pose('/ff1', k, 0.01 * k, 0.0, 0.0, 0.0, 0.5)
    assert len(incident.snapshot()['responders'][0]['track']) == 1
    points = incident_module.TRACK_POINTS
    for k in range(3 * points):                   # 1 m apart: one crumb each
        incident.update_pose('/ff1', 100 + k, 1.0 + k, 0.0, 0.0, 0.0, 0.5)
    track = incident.snapshot()['responders'][0]['track']
    assert len(track) == points
    assert track[-1][0] == 3.0 * points


def test_memory_stays_bounded_with_many_responders_and_a_long_incident(monkeypatch):
    """Tracks keep TRACK_POINTS crumbs; the log keeps its bound of entries and counts the rest."""
    monkeypatch.setattr(incident_module, 'TRACK_POINTS', 50)
    log_bound = 300                               # MAX_LOG_ENTRIES, small enough to reach
    monkeypatch.setattr(incident_module.IncidentLog.__init__, '__defaults__', (log_bound,))
    clock = FakeClock()
    incident = Incident(clock=clock)
    for step in range(400):
        clock.t = step * 0.1
        for k in range(50):
            incident.update_pose(f'/ff{k}', step, step * 1.0, k, 0.0, 0.0, 0.5)
        incident.tick()
        if step % 50 == 49:                       # 8 roll calls of 51 entries each
            incident.roll_call('IC')
    state = incident.snapshot()
    assert len(state['responders']) == 50
    assert all(len(r['track']) == 50 for r in state['responders'])
    written = 50 + 8 * 51                         # the joins and the roll calls
    assert len(incident._log._entries) == log_bound
    assert incident._log.dropped == written - log_bound > 0
    # The newest entries are the ones kept: the last roll call's last line is the last entry.
    assert state['log'][-1]['event'] == 'roll call' and state['log'][-1]['responder'] == '/ff9'
    assert len(state['log']) == 200


def test_events_since_sends_changed_responders_new_crumbs_and_log():
    incident = Incident(clock=FakeClock())
    feed(incident, '/ff1', 0)
    feed(incident, '/ff2', 0)
    seq, events = incident.events_since(0)
    assert seq == incident.snapshot()['seq']
    assert {e['responder']['id'] for e in events if e['type'] == 'responder'} == {'/ff1', '/ff2'}
    assert [e['entry']['event'] for e in events if e['type'] == 'log'] == ['joined', 'joined']
    assert events[-1]['type'] == 'incident'
    assert incident.events_since(seq) == (seq, [])
    incident.update_pose('/ff2', 9, 5.0, 2.0, 0.0, 0.0, 0.5)
    seq2, events = incident.events_since(seq)
    assert seq2 > seq
    (changed,) = [e for e in events if e['type'] == 'responder']
    assert changed['responder']['id'] == '/ff2' and 'track' not in changed['responder']
    assert changed['track_append'] == [[5.0, 2.0, 0.0, 0]]


def test_events_since_asks_for_a_reset_when_the_log_dropped_what_was_asked(monkeypatch):
    monkeypatch.setattr(incident_module.IncidentLog.__init__, '__defaults__', (3,))
    incident = Incident(clock=FakeClock())
    for k in range(6):
        incident.update_pose(f'/ff{k}', 1, 0.0, 0.0, 0.0, 0.0, 0.5)
    assert incident.events_since(1)[1] == [{'type': 'reset'}]
    assert incident.log_csv().splitlines()[0] == '# 3 older entries were dropped (log full)'


def test_evacuation_and_roll_call_are_logged():
    clock = FakeClock()
    incident = Incident(clock=clock)
    feed(incident, '/ff1', 2, certain=False)
    clock.t = 4.0
    incident.evacuate('IC Smith')
    incident.roll_call('IC Smith')
    state = incident.snapshot()
    assert state['evacuation']['by'] == 'IC Smith'
    assert state['roll_call']['responders'] == 1
    texts = [e['text'] for e in state['log']]
    assert 'Evacuation ordered by IC Smith; 1 responders inside' in texts
    assert 'Floor ?, last contact 4 s ago, no alarm' in texts
    incident.update_floor_range('/ff1', [1, 2])     # settled where two floors fit
    incident.roll_call('IC Smith')
    assert 'Floor 1\u20132?, last contact 0 s ago, no alarm' in [
        e['text'] for e in incident.snapshot()['log']]
    incident.update_floor('/ff1', -1)
    incident.update_floor_range('/ff1', [-2, -1])   # basements: the dash is no minus sign
    incident.roll_call('IC Smith')
    assert 'Floor -2\u2013-1?, last contact 0 s ago, no alarm' in [
        e['text'] for e in incident.snapshot()['log']]


def test_wait_for_change_wakes_on_an_update():
    incident = Incident(clock=FakeClock())
    seq = incident.snapshot()['seq']
    timer = threading.Timer(0.1, incident.update_floor, ('/ff1', 1))
    timer.start()
    assert incident.wait_for_change(seq, 5.0) > seq
    timer.join()
