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
One responder as the command centre knows them: latest values, motion, breadcrumbs, alarms.

Plain state with no lock and no clock of its own: :class:`~.incident.Incident` owns the lock
and passes the time in. The breadcrumb track is a ring (``collections.deque`` with a maximum
length), one crumb each time the responder has moved ``spacing_m`` from the last one or
changed floor, so its memory is bounded however long the incident lasts.
"""

import collections
import math

from . import alarms as al

QUALITY = {0: 'OK', 1: 'WARN', 2: 'ERROR', 3: 'STALE'}
QUALITY_ORDER = (0, 1, 3, 2)       # worst last: ERROR is worse than STALE


class Responder:
    """
    Latest known state of one responder (see ``Incident`` for how it is fed).

    Positions are in the map frame (ENU, m); times are on the incident's monotonic clock, s.
    """

    def __init__(self, rid: str, now: float, track_points: int):
        self.rid = rid
        self.floor = None
        self.floor_certain = True
        self.floor_range = None         # (lowest, highest) floor the height can be on
        self.uncertain_since = None
        self.x_m = self.y_m = self.z_m = None
        self.mode = None
        self.heading_deg = None
        self.sigma_xy_m = None
        self.pose_stamp_ns = None
        self.elevation_stamp_ns = None
        self.stamp_ns = None            # the latest pose or elevation message's stamp
        self.diagnostics = {}
        self.alarms = {}
        self.last_update = now
        self.last_motion = now          # the no-motion timer starts at first contact
        self.anchor = None              # (x, y) where the responder last moved
        self.changed_seq = 0
        self.track = collections.deque(maxlen=track_points)   # (seq, [x, y, z, floor])

    def moved(self, now: float, x_m: float, y_m: float) -> None:
        """Record motion now, at (x, y)."""
        self.last_motion = now
        self.anchor = (x_m, y_m)

    def moved_from_anchor(self, threshold_m: float) -> bool:
        """Tell whether the latest position is more than ``threshold_m`` from the anchor."""
        if self.anchor is None:
            self.anchor = (self.x_m, self.y_m)
            return False
        return math.hypot(self.x_m - self.anchor[0], self.y_m - self.anchor[1]) > threshold_m

    def lay_crumb(self, seq: int, spacing_m: float) -> None:
        """Add a breadcrumb [x, y, z, floor] if the responder moved ``spacing_m`` or floor."""
        if self.x_m is None:
            return
        crumb = [round(self.x_m, 2), round(self.y_m, 2),
                 None if self.z_m is None else round(self.z_m, 2), self.floor]
        if self.track:
            last = self.track[-1][1]
            if last[3] == crumb[3] \
                    and math.hypot(crumb[0] - last[0], crumb[1] - last[1]) < spacing_m:
                return
        self.track.append((seq, crumb))

    def track_since(self, seq: int) -> list:
        """Return the crumbs laid after ``seq``, oldest first."""
        out = []
        for crumb_seq, crumb in reversed(self.track):
            if crumb_seq <= seq:
                break
            out.append(crumb)
        out.reverse()
        return out

    def alarm_of(self, kind: str):
        """Return the responder's alarm of this kind, or None."""
        for alarm in self.alarms.values():
            if alarm.kind == kind:
                return alarm
        return None

    @property
    def priority(self) -> int:
        """Roster rank: that of the responder's most urgent alarm."""
        return min((a.priority for a in self.alarms.values()), default=al.PRIORITY['none'])

    @property
    def data_quality(self) -> str:
        """Worst diagnostics level of the responder: OK, WARN, STALE, ERROR, or 'unknown'."""
        if not self.diagnostics:
            return 'unknown'
        levels = {level for level, _ in self.diagnostics.values()}
        return QUALITY[max(levels, key=QUALITY_ORDER.index)]

    def to_dict(self, now: float, track: bool) -> dict:
        """Return the /api/state ``responders[]`` entry (with the track when ``track``)."""
        alarms = sorted(self.alarms.values(), key=lambda a: (a.priority, a.alarm_id))
        state = {
            'id': self.rid,
            'floor': self.floor,
            'floor_certain': self.floor_certain,
            'floor_range': None if self.floor_range is None else list(self.floor_range),
            'x_m': self.x_m, 'y_m': self.y_m, 'z_m': self.z_m,
            'mode': self.mode,
            'heading_deg': self.heading_deg,
            'sigma_xy_m': self.sigma_xy_m,
            'last_update_age_s': round(now - self.last_update, 3),
            'stamp_unix_s': None if self.stamp_ns is None else self.stamp_ns / 1e9,
            'elevation_stamp_unix_s': (None if self.elevation_stamp_ns is None
                                       else self.elevation_stamp_ns / 1e9),
            'last_motion_age_s': round(now - self.last_motion, 3),
            'data_quality': self.data_quality,
            'diagnostics': [{'name': name, 'level': QUALITY[level], 'message': message}
                            for name, (level, message) in sorted(self.diagnostics.items())],
            'priority': self.priority,
            'alarms': [a.to_dict() for a in alarms],
        }
        if track:
            state['track'] = [crumb for _, crumb in self.track]
        return state
