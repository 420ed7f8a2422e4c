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

"""Command-centre alarms on a fake clock: exact times, acknowledgement, clearing, the log."""

from anfis_elevation_ros.command_centre.alarms import AlarmParams
from anfis_elevation_ros.command_centre.incident import Incident
from command_centre_support import FakeClock
import pytest

FF1 = '/ff1'
STEP_S = 0.5


def make_incident():
    clock = FakeClock()
    wall = FakeClock(1_800_000_000.0)
    return Incident(clock=clock, wall_clock=wall), clock


def alarms_of(incident, rid=FF1):
    responder = next(r for r in incident.snapshot()['responders'] if r['id'] == rid)
    return {a['kind']: a for a in responder['alarms']}


def stand_still_until(incident, clock, end_s, x_m=1.0, y_m=2.0, watch='no_motion'):
    """Send a pose at one place every STEP_S up to end_s; return {severity: first time seen}."""
    first_seen = {}
    while clock.t <= end_s + 1e-9:
        incident.update_pose(FF1, int(clock.t * 1e9), x_m, y_m, 0.0, 90.0, 0.5)
        incident.tick()
        alarm = alarms_of(incident).get(watch)
        if alarm is not None:
            first_seen.setdefault(alarm['severity'], clock.t)
        clock.t = round(clock.t + STEP_S, 6)
    return first_seen


def events(incident, event=None):
    rows = [e for e in incident.snapshot()['log'] if e['responder'] == FF1]
    return [(e['event'], e['kind'], e['severity']) for e in rows
            if event is None or e['event'] == event]


def test_no_motion_prealarm_at_20_s_and_alarm_at_30_s():
    incident, clock = make_incident()
    first_seen = stand_still_until(incident, clock, 40.0)
    assert first_seen == {'pre-alarm': 20.0, 'alarm': 30.0}
    assert events(incident, 'raised') == [('raised', 'no_motion', 'pre-alarm'),
                                          ('raised', 'no_motion', 'alarm')]


def test_no_motion_times_follow_the_parameters():
    clock = FakeClock()
    incident = Incident(params=AlarmParams(no_motion_prealarm_s=5.0, no_motion_alarm_s=8.0),
                        clock=clock)
    assert stand_still_until(incident, clock, 12.0) == {'pre-alarm': 5.0, 'alarm': 8.0}


def test_small_wander_is_not_motion_but_a_step_is():
    incident, clock = make_incident()
    stand_still_until(incident, clock, 15.0)
    # A ZUPT-aided still foot wanders a few centimetres: no reset of the timer.
    first_seen = stand_still_until(incident, clock, 20.0, x_m=1.1)
    assert first_seen == {'pre-alarm': 20.0}
    # A step of 1 m: motion; the unacknowledged pre-alarm clears by itself (PASS behaviour).
    incident.update_pose(FF1, int(clock.t * 1e9), 2.0, 2.0, 0.0, 90.0, 0.5)
    incident.tick()
    assert 'no_motion' not in alarms_of(incident)
    assert events(incident)[-1] == ('cleared', 'no_motion', 'pre-alarm')


def test_a_gait_cycle_is_motion():
    incident, clock = make_incident()
    stand_still_until(incident, clock, 25.0)
    assert alarms_of(incident)['no_motion']['severity'] == 'pre-alarm'
    incident.update_elevation(FF1, 123, 1.0, 2.0, 0.0)
    incident.tick()
    assert 'no_motion' not in alarms_of(incident)
    # The same elevation message again (a transient-local re-delivery) is not a new cycle.
    clock.t = 46.0
    incident.update_elevation(FF1, 123, 1.0, 2.0, 0.0)
    incident.tick()
    assert alarms_of(incident)['no_motion']['severity'] == 'pre-alarm'


def test_alarm_acknowledged_while_the_cause_persists_stays_until_the_responder_moves():
    incident, clock = make_incident()
    stand_still_until(incident, clock, 31.0)
    alarm = alarms_of(incident)['no_motion']
    assert (alarm['severity'], alarm['acknowledged']) == ('alarm', False)
    assert incident.acknowledge(alarm['id'], 'IC Smith')
    stand_still_until(incident, clock, 60.0)
    alarm = alarms_of(incident)['no_motion']
    assert alarm['acknowledged'] and alarm['acknowledged_by'] == 'IC Smith'
    assert alarm['cause_active']
    incident.update_pose(FF1, int(clock.t * 1e9), 5.0, 2.0, 0.0, 90.0, 0.5)
    incident.tick()
    assert 'no_motion' not in alarms_of(incident)
    assert events(incident)[-3:] == [('raised', 'no_motion', 'alarm'),
                                     ('acknowledged', 'no_motion', 'alarm'),
                                     ('cleared', 'no_motion', 'alarm')]


def test_alarm_whose_cause_went_stays_until_acknowledged():
    incident, clock = make_incident()
    stand_still_until(incident, clock, 31.0)
    incident.update_pose(FF1, int(clock.t * 1e9), 5.0, 2.0, 0.0, 90.0, 0.5)
    clock.t += 60
    incident.update_pose(FF1, int(clock.t * 1e9), 9.0, 2.0, 0.0, 90.0, 0.5)
    incident.tick()
    alarm = alarms_of(incident)['no_motion']
    assert (alarm['cause_active'], alarm['acknowledged']) == (False, False)
    assert incident.acknowledge(alarm['id'], 'IC')
    assert 'no_motion' not in alarms_of(incident)
    assert not incident.acknowledge(alarm['id'], 'IC')     # it is gone


def test_acknowledged_prealarm_that_escalates_needs_a_new_acknowledgement():
    incident, clock = make_incident()
    stand_still_until(incident, clock, 21.0)
    alarm = alarms_of(incident)['no_motion']
    assert incident.acknowledge(alarm['id'], 'IC')
    assert alarms_of(incident)['no_motion']['acknowledged']
    stand_still_until(incident, clock, 30.0)
    alarm = alarms_of(incident)['no_motion']
    assert (alarm['severity'], alarm['acknowledged']) == ('alarm', False)


def test_lost_contact_at_lost_contact_s_and_cleared_by_a_message_and_an_ack():
    incident, clock = make_incident()
    incident.update_pose(FF1, 0, 1.0, 2.0, 0.0, 90.0, 0.5)
    first = None
    while clock.t < 15.0:
        clock.t = round(clock.t + 0.1, 6)
        incident.tick()
        if first is None and 'lost_contact' in alarms_of(incident):
            first = clock.t
    assert first == 10.0
    # No news is not "no motion": no man-down alarm from a silent responder.
    clock.t = 25.0
    incident.tick()
    assert set(alarms_of(incident)) == {'lost_contact'}
    incident.update_elevation(FF1, 5, 3.0, 2.0, 0.0)
    incident.tick()
    alarm = alarms_of(incident)['lost_contact']
    assert not alarm['cause_active']
    assert incident.acknowledge(alarm['id'], 'IC')
    assert 'lost_contact' not in alarms_of(incident)
    assert [e[0] for e in events(incident) if e[1] == 'lost_contact'] == \
        ['raised', 'acknowledged', 'cleared']


def test_diagnostics_error_raises_at_once_and_clears_when_ok_and_acknowledged():
    incident, clock = make_incident()
    incident.update_diagnostics(FF1, 0, '/ff1/imu_node: IMU input', 'receiving 200 Hz')
    incident.tick()
    assert alarms_of(incident) == {}
    incident.update_diagnostics(FF1, 2, '/ff1/imu_node: IMU input', 'no IMU message for 2 s')
    alarm = alarms_of(incident)['diagnostics_error']
    assert 'no IMU message' in alarm['text']
    snapshot = incident.snapshot()['responders'][0]
    assert snapshot['data_quality'] == 'ERROR'
    incident.update_diagnostics(FF1, 0, '/ff1/imu_node: IMU input', 'receiving 200 Hz')
    assert alarms_of(incident)['diagnostics_error']['cause_active'] is False
    incident.acknowledge(alarm['id'], 'IC')
    assert alarms_of(incident) == {}


def test_floor_unknown_after_floor_unknown_s():
    incident, clock = make_incident()
    incident.update_floor(FF1, 2)
    incident.update_floor_certain(FF1, False)
    first_seen = stand_still_until(incident, clock, 29.5, watch='floor_unknown')
    assert first_seen == {}
    clock.t = 30.0
    incident.update_floor_certain(FF1, False)       # still uncertain: the timer runs on
    assert alarms_of(incident)['floor_unknown']['severity'] == 'alarm'
    incident.update_floor_certain(FF1, True)
    assert alarms_of(incident)['floor_unknown']['cause_active'] is False


def test_a_floor_range_is_no_floor_unknown_alarm_until_it_is_lost():
    # No building file: settled at 12 m, floor 3 or 4. The tracker is not lost; the storeys
    # are unknown, and the page shows the range.
    incident, clock = make_incident()
    incident.update_floor(FF1, 4)
    incident.update_floor_certain(FF1, False)
    incident.update_floor_range(FF1, [3, 4])
    assert stand_still_until(incident, clock, 60.0, watch='floor_unknown') == {}
    incident.update_floor_range(FF1, [])            # the height in doubt (an outage)
    clock.t = 61.0
    incident.tick()
    assert alarms_of(incident)['floor_unknown']['severity'] == 'alarm'


def test_a_single_floor_in_doubt_is_no_floor_unknown_alarm_either():
    # Floor 2 by the floors walked, the level stretch still near the stairs (a landing can be
    # at a floor's height): the page shows 'Floor 2?'. After lost stair strides the classifier
    # gives no range (test_height.py), and the alarm comes as for the outage above.
    incident, clock = make_incident()
    incident.update_floor(FF1, 2)
    incident.update_floor_certain(FF1, False)
    incident.update_floor_range(FF1, [2, 2])
    assert stand_still_until(incident, clock, 60.0, watch='floor_unknown') == {}


def test_floor_unknown_counts_from_the_last_stair_cycle():
    # A climb of several storeys keeps the floor uncertain for minutes: not an alarm.
    incident, clock = make_incident()
    incident.update_floor(FF1, 0)
    incident.update_floor_certain(FF1, False)
    for t in range(1, 120):
        clock.t = float(t)
        incident.update_mode(FF1, 1)
        incident.update_pose(FF1, t * 10**9, t * 0.5, 0.0, t * 0.1, 0.0, 0.3)
        incident.tick()
        assert 'floor_unknown' not in alarms_of(incident), t
    clock.t = 120.0
    incident.update_mode(FF1, 0)            # the last stair cycle was at 119 s
    clock.t = 148.5
    incident.update_pose(FF1, 148 * 10**9, 80.0, 0.0, 12.0, 0.0, 0.3)
    incident.tick()
    assert 'floor_unknown' not in alarms_of(incident)
    clock.t = 149.0
    incident.tick()
    assert alarms_of(incident)['floor_unknown']['severity'] == 'alarm'


def test_diagnostics_alone_do_not_keep_contact():
    # The IMU went silent (or the bag ended): the nodes still report every second.
    incident, clock = make_incident()
    incident.update_pose(FF1, 0, 1.0, 2.0, 0.0, 90.0, 0.5)
    while clock.t < 9.0:
        clock.t = round(clock.t + 1.0, 6)
        incident.update_diagnostics(FF1, 3, '/ff1/imu_node: IMU input', 'no IMU messages')
        incident.tick()
        assert 'lost_contact' not in alarms_of(incident), clock.t
    clock.t = 10.0
    incident.update_diagnostics(FF1, 3, '/ff1/imu_node: IMU input', 'no IMU messages')
    assert alarms_of(incident)['lost_contact']['severity'] == 'alarm'


def test_diagnostics_keep_contact_before_tracking_begins():
    # A body computer starting up: its nodes report before the first pose comes.
    incident, clock = make_incident()
    for t in range(1, 16):
        clock.t = float(t)
        incident.update_diagnostics(FF1, 0, '/ff1/imu_node: IMU input', 'waiting')
        incident.tick()
        assert 'lost_contact' not in alarms_of(incident), t


def test_every_log_entry_has_its_time():
    """Each log entry (and CSV row) carries the wall-clock time of its own event."""
    clock = FakeClock()
    wall = FakeClock(1_800_000_000.0)           # the wall clock runs with the monotonic one
    incident = Incident(clock=clock, wall_clock=lambda: wall.t + clock.t)
    stand_still_until(incident, clock, 31.0)    # joined at 0 s, pre-alarm at 20 s, alarm at 30 s
    wall.t += 3628.75                           # the commander acknowledges an hour later
    incident.acknowledge(alarms_of(incident)['no_motion']['id'], 'IC')
    log = incident.snapshot()['log']
    assert [e['event'] for e in log] == ['joined', 'raised', 'raised', 'acknowledged']
    assert [e['time_unix_s'] for e in log] == [1_800_000_000.0, 1_800_000_020.0,
                                               1_800_000_030.0, 1_800_003_660.25]
    assert [e['time_utc'] for e in log] == ['2027-01-15T08:00:00Z', '2027-01-15T08:00:20Z',
                                            '2027-01-15T08:00:30Z', '2027-01-15T09:01:00Z']
    csv_lines = incident.log_csv().splitlines()
    assert csv_lines[0].startswith('seq,time_utc,time_unix_s,responder,event,alarm_id')
    assert len(csv_lines) == 5 and ',acknowledged,' in csv_lines[-1]
    assert [line.split(',')[1:3] for line in csv_lines[1:]] == [
        [e['time_utc'], str(e['time_unix_s'])] for e in log]


@pytest.mark.parametrize('kwargs', [{'no_motion_prealarm_s': 0}, {'lost_contact_s': -1},
                                    {'no_motion_alarm_s': float('nan')},
                                    {'no_motion_prealarm_s': 30, 'no_motion_alarm_s': 20},
                                    {'floor_unknown_s': True}])
def test_bad_alarm_parameters_are_refused(kwargs):
    with pytest.raises(ValueError, match='AlarmParams'):
        AlarmParams(**kwargs)
