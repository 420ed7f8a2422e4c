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
The command centre's alarms: what raises one, and the rule that clears it.

Four causes, evaluated per responder from the times the incident model keeps:

- ``no_motion`` (man down): a pre-alarm after ``no_motion_prealarm_s`` without motion, the
  alarm at ``no_motion_alarm_s`` (Scott/Draeger PASS devices: about 20 s and 12 s later).
  Motion is a gait cycle (a new ``elevation`` message) or a move of the foot of more than
  ``motion_threshold_m`` from where it last moved. While contact is lost this cause is not
  evaluated: ``lost_contact`` says what is known.
- ``lost_contact``: no tracking message (elevation, floor, floor_certain, stair mode, pose)
  from the responder for ``lost_contact_s``; once tracking has begun (a pose or a gait cycle),
  diagnostics alone do not count (a body computer whose IMU is silent keeps reporting them).
- ``diagnostics_error``: one of the responder's diagnostics statuses is at ERROR.
- ``floor_unknown``: the floor has been uncertain (``floor_certain`` False) for
  ``floor_unknown_s`` since the last stair cycle (the classifier calls every floor uncertain
  while on the stairs, about 25 s a storey: a climb of several storeys is not an alarm).

An alarm clears only when it has been acknowledged and its cause is gone; acknowledging while
the cause persists keeps it on the board (acknowledged). One exception, as on a PASS device:
a no-motion *pre-alarm* that has not become an alarm clears by itself when the responder
moves. A pre-alarm that escalates needs a new acknowledgement.

Public API: :class:`AlarmParams`, :class:`Alarm`, :func:`no_motion_level`, ``KINDS``,
``PRIORITY``.
"""

from dataclasses import dataclass, fields
from typing import Optional

from ..core.validation import check_positive

NO_MOTION = 'no_motion'
LOST_CONTACT = 'lost_contact'
DIAGNOSTICS_ERROR = 'diagnostics_error'
FLOOR_UNKNOWN = 'floor_unknown'
KINDS = (NO_MOTION, LOST_CONTACT, DIAGNOSTICS_ERROR, FLOOR_UNKNOWN)
TITLES = {NO_MOTION: 'No motion (man down)', LOST_CONTACT: 'Lost contact',
          DIAGNOSTICS_ERROR: 'Sensor error', FLOOR_UNKNOWN: 'Floor unknown'}

PRE_ALARM = 'pre-alarm'
ALARM = 'alarm'

# Roster order: the lower, the higher up the list (the page sorts by it, it never ranks).
PRIORITY = {'unacknowledged alarm': 0, 'unacknowledged pre-alarm': 1, 'acknowledged alarm': 2,
            'acknowledged pre-alarm': 3, 'none': 4}


@dataclass(frozen=True)
class AlarmParams:
    """
    Alarm timers and thresholds of the command centre.

    Attributes
    ----------
    no_motion_prealarm_s : s without motion before the man-down pre-alarm (PASS devices: 20 s).
    no_motion_alarm_s : s without motion before the man-down alarm (PASS devices: about 30 s).
    motion_threshold_m : a move of the foot larger than this from where it last moved is motion,
        m (0.3 m: above the few centimetres a still foot's ZUPT-aided track wanders, below
        half a stride).
    lost_contact_s : s without a tracking message from a responder before lost contact
        (the track comes at 2 Hz, ``foot_odom_throttle``: 10 s is many missed messages, not
        one radio fade).
    floor_unknown_s : s with the floor uncertain after the last stair cycle before the
        floor-unknown alarm (settling on a floor takes one to three level cycles).

    """

    no_motion_prealarm_s: float = 20.0
    no_motion_alarm_s: float = 30.0
    motion_threshold_m: float = 0.3
    lost_contact_s: float = 10.0
    floor_unknown_s: float = 30.0

    def __post_init__(self):
        """Refuse a value that is not a positive finite number, or alarm before pre-alarm."""
        for field in fields(self):
            check_positive(f'AlarmParams.{field.name}', getattr(self, field.name))
        if self.no_motion_alarm_s < self.no_motion_prealarm_s:
            raise ValueError(f'AlarmParams.no_motion_alarm_s ({self.no_motion_alarm_s}) must not '
                             f'be less than no_motion_prealarm_s ({self.no_motion_prealarm_s})')


@dataclass
class Alarm:
    """
    One alarm of one responder, from raised to cleared.

    Attributes
    ----------
    alarm_id : unique within the incident ('A1', 'A2', ...).
    responder : namespace of the responder ('/ff1').
    kind : one of KINDS.
    severity : 'alarm', or 'pre-alarm' (no_motion before it escalates).
    text : what the commander reads.
    raised_unix_s : wall-clock time it was raised, s since 1970.
    cause_active : whether its cause is still present.
    acknowledged_by : who acknowledged it, or None.
    acknowledged_unix_s : when, or None.

    """

    alarm_id: str
    responder: str
    kind: str
    severity: str
    text: str
    raised_unix_s: float
    cause_active: bool = True
    acknowledged_by: Optional[str] = None
    acknowledged_unix_s: Optional[float] = None

    @property
    def acknowledged(self) -> bool:
        """Tell whether someone has acknowledged it (at its current severity)."""
        return self.acknowledged_by is not None

    @property
    def clears(self) -> bool:
        """
        Tell whether it is over: acknowledged and its cause gone.

        A pre-alarm whose cause is gone clears unacknowledged (the responder moved).
        """
        if self.cause_active:
            return False
        return self.acknowledged or self.severity == PRE_ALARM

    @property
    def priority(self) -> int:
        """Rank in the roster (PRIORITY): unacknowledged alarms first."""
        state = 'acknowledged' if self.acknowledged else 'unacknowledged'
        return PRIORITY[f'{state} {self.severity}']

    def to_dict(self) -> dict:
        """Return the JSON form of /api/state's ``alarms[]``."""
        return {'id': self.alarm_id, 'kind': self.kind, 'severity': self.severity,
                'title': TITLES[self.kind], 'text': self.text,
                'raised_unix_s': self.raised_unix_s, 'cause_active': self.cause_active,
                'acknowledged': self.acknowledged, 'acknowledged_by': self.acknowledged_by,
                'acknowledged_unix_s': self.acknowledged_unix_s}


def no_motion_level(still_s: float, params: AlarmParams) -> Optional[str]:
    """
    Man-down level after ``still_s`` seconds without motion.

    level = 'alarm' if still_s >= no_motion_alarm_s, 'pre-alarm' if still_s >=
    no_motion_prealarm_s, else None.
    """
    if still_s >= params.no_motion_alarm_s:
        return ALARM
    if still_s >= params.no_motion_prealarm_s:
        return PRE_ALARM
    return None


__all__ = ['Alarm', 'AlarmParams', 'ALARM', 'DIAGNOSTICS_ERROR', 'FLOOR_UNKNOWN', 'KINDS',
           'LOST_CONTACT', 'NO_MOTION', 'no_motion_level', 'PRE_ALARM', 'PRIORITY', 'TITLES']
