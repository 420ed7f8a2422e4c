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
The incident: every responder's latest floor, position, track, data quality and alarms.

One :class:`Incident` is the command centre's single source of truth. The ROS node feeds it
(one ``update_*`` call per message, the responder named by its namespace) and calls
:meth:`Incident.tick` a few times a second for the timers; the web server reads
:meth:`Incident.snapshot` (``/api/state``) and :meth:`Incident.events_since` (the push
stream) and writes acknowledgements, evacuation and roll call. Every public method takes one
lock, so the two sides may run in different threads.

A bad value (non-finite number, wrong type, unknown mode, a namespace that is not one) is
refused and counted by reason (``rejected`` in the snapshot); it never raises and never
touches what is known of that responder or any other.

Memory is bounded whatever runs for how long: at most ``MAX_RESPONDERS`` responders, a
breadcrumb ring of ``TRACK_POINTS`` per responder (one crumb per ``TRACK_SPACING_M`` moved),
``MAX_DIAGNOSTICS`` statuses per responder and a log of ``MAX_LOG_ENTRIES`` entries.

Public API: :class:`Incident`, ``TRACK_POINTS``, ``MAX_RESPONDERS``.
"""

import collections
import math
import re
import threading
import time

from . import alarms as al
from .incident_log import IncidentLog
from .responder import QUALITY, Responder

MAX_RESPONDERS = 500
TRACK_POINTS = 600          # 300 m of breadcrumbs at TRACK_SPACING_M
TRACK_SPACING_M = 0.5
MAX_DIAGNOSTICS = 16        # statuses per responder (one per node; more is a misconfiguration)
MAX_TEXT = 200
MAX_POSSIBLE_FLOORS = 10    # a range wider than this says nothing about any one floor
_NAMESPACE = re.compile(r'^(/[A-Za-z][A-Za-z0-9_]*)+$')


class Incident:
    """
    Responders, alarms and the log of one incident; thread-safe.

    Parameters
    ----------
    building : core.building.Building or None
        Floors (index, elevation, name, outline) and stairs for the map; None for a grid.
    params : AlarmParams
        Alarm timers.
    clock : callable returning s
        Monotonic clock for ages and timers (a fake one in tests).
    wall_clock : callable returning s since 1970
        Times written to the log and shown to the commander.

    """

    def __init__(self, building=None, params: al.AlarmParams = al.AlarmParams(),
                 clock=time.monotonic, wall_clock=time.time):
        self._building = building
        self._params = params
        self._clock = clock
        self._wall_clock = wall_clock
        self._lock = threading.Lock()
        self._changed = threading.Condition(self._lock)
        self._responders = {}
        self._seq = 0
        self._log = IncidentLog()
        self._rejected = collections.Counter()
        self._next_alarm = 1
        self._evacuation = None
        self._roll_call = None

    # -- feeds ----------------------------------------------------------------------------

    def update_elevation(self, responder: str, stamp_ns: int, x_m: float, y_m: float,
                         z_m: float) -> None:
        """Take one ``elevation`` message (one gait cycle: motion); z is the quantised height."""
        with self._lock:
            if not _is_int(stamp_ns) or not _finite(x_m, y_m, z_m):
                return self._reject('elevation: non-finite position or bad stamp')
            r = self._responder(responder)
            if r is None:
                return
            now = self._clock()
            if r.elevation_stamp_ns != int(stamp_ns):
                r.elevation_stamp_ns = r.stamp_ns = int(stamp_ns)
                r.moved(now, float(x_m), float(y_m))
            r.z_m = float(z_m)
            if r.pose_stamp_ns is None:
                r.x_m, r.y_m = float(x_m), float(y_m)
            self._updated(r, now, crumb=True)

    def update_floor(self, responder: str, floor: int) -> None:
        """Take one ``floor`` message (the floor index)."""
        with self._lock:
            if not _is_int(floor) or abs(floor) > 10_000:
                return self._reject('floor: not a floor index')
            r = self._responder(responder)
            if r is None:
                return
            r.floor = int(floor)
            self._updated(r, self._clock(), crumb=True)

    def update_floor_certain(self, responder: str, certain: bool) -> None:
        """Take one ``floor_certain`` message; the floor shows as 'Floor ?' while False."""
        with self._lock:
            if not isinstance(certain, bool):
                return self._reject('floor_certain: not a bool')
            r = self._responder(responder)
            if r is None:
                return
            now = self._clock()
            if certain:
                r.uncertain_since = None
            elif r.floor_certain:
                r.uncertain_since = now
            r.floor_certain = certain
            self._updated(r, now)

    def update_floor_range(self, responder: str, floors) -> None:
        """
        Take one ``floor_range`` message: [lowest, highest] floor the height can be on, or [].

        A floor in doubt with a range (a height several floors could have, no building file;
        or a floor the floors walked give, near the stairs) is shown as that range and raises
        no ``floor_unknown`` alarm: the tracker is not lost (:func:`_range_known`).
        """
        with self._lock:
            if not isinstance(floors, (list, tuple)) or len(floors) not in (0, 2) \
                    or not all(_is_int(f) and abs(f) <= 10_000 for f in floors) \
                    or (floors and floors[0] > floors[1]):
                return self._reject('floor_range: not [] or [lowest, highest]')
            r = self._responder(responder)
            if r is None:
                return
            r.floor_range = (int(floors[0]), int(floors[1])) if floors else None
            self._updated(r, self._clock())

    def update_mode(self, responder: str, mode: int) -> None:
        """Take one ``stair_mode`` message: -1 down, 0 level, +1 up."""
        with self._lock:
            if not _is_int(mode) or mode not in (-1, 0, 1):
                return self._reject('stair_mode: not -1, 0 or +1')
            r = self._responder(responder)
            if r is None:
                return
            r.mode = int(mode)
            now = self._clock()
            if r.mode != 0 and r.uncertain_since is not None:
                # On the stairs the floor is known to be changing: the floor-unknown timer
                # counts from the last stair cycle, so a long climb raises no alarm.
                r.uncertain_since = now
            self._updated(r, now)

    def update_pose(self, responder: str, stamp_ns: int, x_m, y_m, z_m, heading_deg: float,
                    sigma_xy_m) -> None:
        """
        Take one ``foot_odom`` message: position (map frame, m), heading and its uncertainty.

        heading_deg is the yaw, degrees counter-clockwise from +x (east), REP 103;
        sigma_xy_m the 1-sigma horizontal position error, m, or None when unknown. z_m (the raw
        EKF height) is not shown: the quantised height of ``elevation`` is.
        """
        with self._lock:
            if not _is_int(stamp_ns) or not _finite(x_m, y_m, z_m, heading_deg):
                return self._reject('foot_odom: non-finite pose or bad stamp')
            if sigma_xy_m is not None and (not _finite(sigma_xy_m) or sigma_xy_m < 0):
                return self._reject('foot_odom: bad position sigma')
            r = self._responder(responder)
            if r is None:
                return
            now = self._clock()
            r.pose_stamp_ns = r.stamp_ns = int(stamp_ns)
            r.x_m, r.y_m = float(x_m), float(y_m)
            r.heading_deg = float(heading_deg) % 360.0
            r.sigma_xy_m = None if sigma_xy_m is None else float(sigma_xy_m)
            if r.moved_from_anchor(self._params.motion_threshold_m):
                r.moved(now, r.x_m, r.y_m)
            self._updated(r, now, crumb=True)

    def update_diagnostics(self, responder: str, level: int, name: str, message: str) -> None:
        """Take one diagnostics status of the responder: 0 OK, 1 WARN, 2 ERROR, 3 STALE."""
        with self._lock:
            if not _is_int(level) or level not in QUALITY or not isinstance(name, str) \
                    or not isinstance(message, str):
                return self._reject('diagnostics: bad level, name or message')
            r = self._responder(responder)
            if r is None:
                return
            if name not in r.diagnostics and len(r.diagnostics) >= MAX_DIAGNOSTICS:
                return self._reject('diagnostics: too many status names')
            r.diagnostics[name[:MAX_TEXT]] = (int(level), message[:MAX_TEXT])
            # Once tracking has begun (a pose or a gait cycle), diagnostics are not contact: a
            # body computer whose IMU went silent still reports them every second, and its
            # responder is lost all the same. Before, they are the only sign of a starting node.
            now = self._clock()
            if r.stamp_ns is None:
                self._updated(r, now)
            else:
                self._bump(r)
                self._evaluate(r, now)

    def tick(self) -> None:
        """Evaluate the timers (no motion, lost contact, floor unknown) of every responder."""
        with self._lock:
            now = self._clock()
            for r in self._responders.values():
                self._evaluate(r, now)

    # -- reads and writes -----------------------------------------------------------------

    def snapshot(self) -> dict:
        """Return the state of the incident as ``/api/state`` documents it (README)."""
        with self._lock:
            now = self._clock()
            responders = sorted(self._responders.values(), key=lambda r: (r.priority, r.rid))
            return {
                'seq': self._seq,
                'time_unix_s': self._wall_clock(),
                'building': _building_dict(self._building),
                'floors': self._floors(),
                'responders': [r.to_dict(now, track=True) for r in responders],
                'evacuation': self._evacuation,
                'roll_call': self._roll_call,
                'log': self._log.latest(200),
                'rejected': dict(self._rejected),
                'params': _params_dict(self._params),
                'track_max_points': TRACK_POINTS,
            }

    def events_since(self, seq: int) -> tuple:
        """
        Return what changed after ``seq``: ``(current_seq, events)``, for the push stream.

        Events: ``{'type': 'responder', 'responder': {...}, 'track_append': [...]}`` per
        responder changed (its /api/state entry without the track, plus the crumbs laid since
        ``seq``), ``{'type': 'log', 'entry': {...}}`` per log entry, ``{'type': 'incident',
        'floors': [...], 'evacuation': ..., 'roll_call': ...}`` when anything changed, and
        ``{'type': 'reset'}`` alone when ``seq`` is older than the log remembers (refetch
        /api/state).
        """
        with self._lock:
            if not _is_int(seq) or seq < 0:
                seq = 0
            if seq >= self._seq:
                return self._seq, []
            entries = self._log.since(seq)
            if entries is None:
                return self._seq, [{'type': 'reset'}]
            now = self._clock()
            events = [{'type': 'responder', 'responder': r.to_dict(now, track=False),
                       'track_append': r.track_since(seq)}
                      for r in self._responders.values() if r.changed_seq > seq]
            events.extend({'type': 'log', 'entry': e} for e in entries)
            events.append({'type': 'incident', 'floors': self._floors(),
                           'evacuation': self._evacuation, 'roll_call': self._roll_call,
                           'rejected': dict(self._rejected)})
            return self._seq, events

    def wait_for_change(self, seq: int, timeout_s: float) -> int:
        """Block until the incident changes after ``seq`` or ``timeout_s`` passes; return seq."""
        with self._changed:
            self._changed.wait_for(lambda: self._seq > seq, timeout=timeout_s)
            return self._seq

    def acknowledge(self, alarm_id: str, by: str) -> bool:
        """Acknowledge an alarm; False if no active alarm has this id."""
        with self._lock:
            for r in self._responders.values():
                alarm = r.alarms.get(alarm_id) if isinstance(alarm_id, str) else None
                if alarm is None:
                    continue
                if not alarm.acknowledged:
                    alarm.acknowledged_by = _who(by)
                    alarm.acknowledged_unix_s = self._wall_clock()
                    self._record(r.rid, 'acknowledged', alarm,
                                 f'{al.TITLES[alarm.kind]} {alarm.severity} acknowledged by '
                                 f'{alarm.acknowledged_by}', alarm.acknowledged_by)
                self._evaluate(r, self._clock())
                self._bump(r)
                return True
            return False

    def evacuate(self, by: str) -> None:
        """Order the evacuation of the building (logged; the page shows it until the end)."""
        with self._lock:
            who = _who(by)
            self._evacuation = {'ordered_unix_s': self._wall_clock(), 'by': who}
            self._record('', 'evacuation', None, f'Evacuation ordered by {who}; '
                         f'{len(self._responders)} responders inside', who)
            self._bump()

    def roll_call(self, by: str) -> None:
        """Take a roll call: log one line per responder with floor, last contact and alarms."""
        with self._lock:
            who = _who(by)
            now = self._clock()
            self._roll_call = {'taken_unix_s': self._wall_clock(), 'by': who,
                               'responders': len(self._responders)}
            self._record('', 'roll call', None, f'Roll call by {who}: '
                         f'{len(self._responders)} responders', who)
            for r in sorted(self._responders.values(), key=lambda r: r.rid):
                state = r.to_dict(now, track=False)
                floor = _floor_text(state)
                active = ', '.join(a['title'] for a in state['alarms']) or 'no alarm'
                self._record(r.rid, 'roll call', None,
                             f'{floor}, last contact {state["last_update_age_s"]:.0f} s ago, '
                             f'{active}')
            self._bump()

    def log_csv(self) -> str:
        """Return the whole incident log as CSV (time, responder, event, alarm, by, text)."""
        with self._lock:
            return self._log.csv()

    # -- inside the lock ------------------------------------------------------------------

    def _reject(self, reason: str) -> None:
        self._rejected[reason] += 1

    def _responder(self, rid):
        if not isinstance(rid, str) or len(rid) > MAX_TEXT or not _NAMESPACE.match(rid):
            self._reject('responder: not a namespace such as /ff1')
            return None
        r = self._responders.get(rid)
        if r is None:
            if len(self._responders) >= MAX_RESPONDERS:
                self._reject(f'responder: more than {MAX_RESPONDERS} responders')
                return None
            r = Responder(rid, self._clock(), TRACK_POINTS)
            self._responders[rid] = r
            self._record(rid, 'joined', None, f'{rid} joined the incident')
        return r

    def _updated(self, r: Responder, now: float, crumb: bool = False) -> None:
        r.last_update = now
        self._bump(r)
        if crumb:
            r.lay_crumb(self._seq, TRACK_SPACING_M)
        self._evaluate(r, now)

    def _bump(self, r: Responder = None) -> None:
        self._seq += 1
        if r is not None:
            r.changed_seq = self._seq
        self._changed.notify_all()

    def _evaluate(self, r: Responder, now: float) -> None:
        """Raise, escalate and clear the responder's alarms for the time ``now``."""
        p = self._params
        lost = now - r.last_update >= p.lost_contact_s
        causes = {
            al.LOST_CONTACT: (al.ALARM, f'no message for {now - r.last_update:.0f} s')
            if lost else None,
            al.DIAGNOSTICS_ERROR: _diagnostics_cause(r.diagnostics),
            al.FLOOR_UNKNOWN: (al.ALARM, f'floor uncertain for {now - r.uncertain_since:.0f} s')
            if r.uncertain_since is not None and not _range_known(r.floor_range)
            and now - r.uncertain_since >= p.floor_unknown_s else None,
        }
        level = None if lost else al.no_motion_level(now - r.last_motion, p)
        still = r.alarm_of(al.NO_MOTION)
        if lost and still is not None:
            level = still.severity      # no news is not motion: keep the level it had
        causes[al.NO_MOTION] = None if level is None else \
            (level, f'no motion for {now - r.last_motion:.0f} s')
        for kind, cause in causes.items():
            self._apply(r, kind, cause)

    def _apply(self, r: Responder, kind: str, cause) -> None:
        alarm = r.alarm_of(kind)
        if cause is None:
            if alarm is not None and alarm.cause_active:
                alarm.cause_active = False
                self._bump(r)
            if alarm is not None and alarm.clears:
                del r.alarms[alarm.alarm_id]
                self._record(r.rid, 'cleared', alarm, f'{al.TITLES[kind]} cleared')
                self._bump(r)
            return
        severity, text = cause
        if alarm is None:
            alarm = al.Alarm(f'A{self._next_alarm}', r.rid, kind, severity, text,
                             self._wall_clock())
            self._next_alarm += 1
            r.alarms[alarm.alarm_id] = alarm
            self._record(r.rid, 'raised', alarm, f'{al.TITLES[kind]} {severity}: {text}')
            self._bump(r)
            return
        if not alarm.cause_active:
            alarm.cause_active = True
            self._record(r.rid, 'cause returned', alarm, f'{al.TITLES[kind]}: {text}')
        if severity == al.ALARM and alarm.severity == al.PRE_ALARM:
            alarm.severity = al.ALARM
            alarm.text = text
            alarm.acknowledged_by = alarm.acknowledged_unix_s = None
            self._record(r.rid, 'raised', alarm, f'{al.TITLES[kind]} {severity}: {text}')

    def _record(self, rid: str, event: str, alarm, text: str, by: str = None) -> None:
        self._seq += 1
        self._log.append(self._seq, self._wall_clock(), rid, event, alarm, text, by)
        if rid in self._responders:
            self._responders[rid].changed_seq = self._seq
        self._changed.notify_all()

    def _floors(self) -> list:
        """
        Floors of the building (or seen) with responder counts and active alarms.

        A responder counts on its floor; one whose floor is in doubt with a range of floors
        (no building file) also counts as ``possible`` on the range's other floors, so that a
        floor's button tells who may be there.
        """
        floors = {}
        if self._building is not None:
            for f in self._building.floors:
                floors[f.index] = {'index': f.index, 'name': f.name,
                                   'elevation_m': f.elevation_m}
        placed = [(r, _possible_floors(r)) for r in self._responders.values()
                  if r.floor is not None]
        for r, possible in placed:
            for index in [r.floor] + possible:
                floors.setdefault(index, {'index': index, 'name': '', 'elevation_m': None})
        for f in floors.values():
            f.update(responders=0, uncertain=0, possible=0, alarms=0)
        for r, possible in placed:
            f = floors[r.floor]
            f['responders'] += 1
            f['uncertain'] += not r.floor_certain
            f['alarms'] += sum(a.severity == al.ALARM for a in r.alarms.values())
            for index in possible:
                floors[index]['possible'] += 1
        return [floors[k] for k in sorted(floors, reverse=True)]


def _possible_floors(r: Responder) -> list:
    """Return the floors a responder in doubt may be on besides its floor (its range's)."""
    if r.floor is None or r.floor_certain or r.floor_range is None:
        return []
    lowest, highest = r.floor_range
    if highest - lowest >= MAX_POSSIBLE_FLOORS:
        return []
    return [f for f in range(lowest, highest + 1) if f != r.floor]


def _range_known(floors) -> bool:
    """
    Return whether a floor range says where a floor in doubt is: the tracker is not lost.

    The classifier publishes a range only where it knows one: the floors a height can be on
    without a building file (several, the storeys unknown; or one, by the floors walked, on a
    level stretch still near the stairs). After a climb nobody saw it publishes none (``[]``),
    and that is the ``floor_unknown`` alarm.
    """
    return floors is not None


def _floor_text(state: dict) -> str:
    """Return a responder's floor as the page shows it: 'Floor 2', 'Floor 2\u20133?', 'Floor ?'."""
    floors = state['floor_range']
    if state['floor'] is None or not (state['floor_certain'] or floors):
        return 'Floor ?'
    if state['floor_certain']:
        return f'Floor {state["floor"]}'
    return f'Floor {floors[0]}' + (f'\u2013{floors[1]}' if floors[1] != floors[0] else '') + '?'


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _finite(*values) -> bool:
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
               for v in values)


def _who(by) -> str:
    text = str(by).strip()[:64] if isinstance(by, str) else ''
    return text or 'command'


def _diagnostics_cause(diagnostics: dict):
    errors = [f'{name}: {message}' for name, (level, message) in diagnostics.items()
              if level == 2]
    return (al.ALARM, '; '.join(sorted(errors))[:MAX_TEXT]) if errors else None


def _building_dict(building):
    if building is None:
        return None
    return {'name': building.name,
            'floors': [{'index': f.index, 'name': f.name, 'elevation_m': f.elevation_m,
                        'outline': [list(p) for p in f.outline]} for f in building.floors],
            'stairs': [{'stairwell': s.stairwell, 'floor': s.floor, 'direction': s.direction,
                        'x_m': s.x_m, 'y_m': s.y_m} for s in building.stairs]}


def _params_dict(params: al.AlarmParams) -> dict:
    return {name: getattr(params, name) for name in params.__dataclass_fields__}


__all__ = ['Incident', 'MAX_RESPONDERS', 'TRACK_POINTS', 'TRACK_SPACING_M']
