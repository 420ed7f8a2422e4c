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
Stair-position database and the association of stair entries, seeds 001/003 (eq. 17-18).

The building file's ``stairs`` give the centre of the first step of every stair entry. Seed 003
keeps them in two tables, entries going up and entries going down; :class:`StairDatabase` keeps
one table per floor and direction. On the first stair cycle after level walking (stair mode
SR(k-1) = level, SR(k) = up or down) :class:`StairEntryMonitor` takes the nearest entry of the
matching table on the current floor (eq. 17) and accepts it when it is closer than
th_st = ratio x the distance walked since the last correction (eq. 18): the position error of a
ZUPT filter grows with the distance walked, about 1-3 % of it. An accepted association becomes a
:class:`CorrectionRequest`, which the IMU side applies as a horizontal position measurement in
the EKF (``ekf.position_correction``, eq. 2 and 19-21, scheduled by ``core/position_fix.py``).

Which point of the walk is the entry: the cycle's position, i.e. the foot at the first stance
of its stair stride, the first stance on the stairs. The database gives the centre of the first
step met; with two steps per stride the instrumented foot lands on the first or the second step,
so the measurement's standard deviation (``BuildingAidParams.stair_fix_sigma_m``, 0.3 m) covers
one tread.

The stairs need the building's ``start`` (the track in the building's frame, ``map_frame.py``):
a building with stairs and no start corrects nothing.

Public API: :class:`BuildingAidParams`, :class:`StairDatabase`, :class:`CorrectionRequest`,
:class:`StairEntryMonitor`, :func:`stair_monitor_for`, :func:`association_threshold_m`,
:func:`nearest_entry`.

References
----------
[1] Seed 003: stair-scene recognition for foot-mounted pedestrian navigation, eq. (2) position
    error measurement, (17) nearest stair entry, (18) threshold th_st, (19)-(21) Kalman update.

"""

from dataclasses import dataclass
import math
from typing import Optional

import numpy as np

from .errors import InputError
from .height import MODE_LEVEL
from .validation import check_range


@dataclass(frozen=True)
class BuildingAidParams:
    """
    How the building file aids the track (map frame and stair-position correction).

    Attributes
    ----------
    align_strides : strides whose overall direction is taken as the building's
        ``start.heading_deg`` (the map frame is fixed after them).
    stair_fix_ratio : eq. (18), th_st = ratio x distance walked since the last correction
        (seed 003: 0.03, a ZUPT filter's error is 1-3 % of the distance).
    stair_fix_sigma_m : standard deviation of the stair-entry position measurement, m (one
        tread: the foot lands on the first or second step).
    stair_fix_delay_s : a correction is applied at the first stance sample at least this much
        sensor time after its gait cycle (longer than the classifier's latency, so live and
        replay apply it at the same sample).

    """

    align_strides: int = 3
    stair_fix_ratio: float = 0.03
    stair_fix_sigma_m: float = 0.3
    stair_fix_delay_s: float = 0.5

    def __post_init__(self):
        check_range('align_strides', self.align_strides, 1, 50)
        check_range('stair_fix_ratio', self.stair_fix_ratio, 0.0, 1.0)
        check_range('stair_fix_sigma_m', self.stair_fix_sigma_m, 0.01, 10.0)
        check_range('stair_fix_delay_s', self.stair_fix_delay_s, 0.05, 10.0)


@dataclass(frozen=True)
class CorrectionRequest:
    """
    An accepted stair-entry association: what the IMU side needs to apply it once.

    Attributes
    ----------
    cycle_index : index of the gait cycle that entered the stairs (for logs).
    stamp_ns : its stamp (sensor time, ns): the request's identity, and the time it is due from.
    x_m, y_m : the cycle's position, map frame, m.
    entry_x_m, entry_y_m : the database entry's position, map frame, m.
    stairwell : the entry's stairwell.
    floor : the floor it lies on.
    direction : +1 up, -1 down.

    """

    cycle_index: int
    stamp_ns: int
    x_m: float
    y_m: float
    entry_x_m: float
    entry_y_m: float
    stairwell: str
    floor: int
    direction: int

    def __post_init__(self):
        values = (self.x_m, self.y_m, self.entry_x_m, self.entry_y_m)
        if not all(math.isfinite(v) for v in values):
            raise InputError(f'correction request of cycle {self.cycle_index} has a non-finite '
                             'position')
        if self.direction not in (-1, 1):
            raise InputError(f'correction request direction {self.direction} is not +1 or -1')

    @property
    def innovation_xy(self) -> np.ndarray:
        """(2,) P_database - P_xy, m: the position error the measurement says (eq. 2 negated)."""
        return np.array([self.entry_x_m - self.x_m, self.entry_y_m - self.y_m])


class StairDatabase:
    """
    The stair entries of a building, one table per floor and direction (seed 003's two tables).

    Parameters
    ----------
    stairs : sequence of building.StairEntry

    """

    def __init__(self, stairs):
        tables = {}
        for entry in stairs:
            tables.setdefault((entry.floor, entry.direction), []).append(entry)
        self._tables = {key: (tuple(entries),
                              np.array([(e.x_m, e.y_m) for e in entries], dtype=float))
                        for key, entries in tables.items()}

    def table(self, floor: int, direction: int) -> tuple:
        """Return (entries, (K, 2) positions) of one floor and direction; K may be 0."""
        return self._tables.get((floor, direction), ((), np.zeros((0, 2))))

    def __len__(self):
        return sum(len(entries) for entries, _ in self._tables.values())


def association_threshold_m(distance_walked_m: float, ratio: float) -> float:
    """
    Association threshold, seed 003 eq. (18): th_st = ratio * L.

    L is the horizontal distance walked since the last correction (since the start before the
    first), m; ratio 0.03.
    """
    return ratio * distance_walked_m


def nearest_entry(positions_xy: np.ndarray, pos_xy) -> tuple:
    """
    Nearest entry of a table, seed 003 eq. (17): k = argmin_j ||P_xy - P_j||.

    Parameters
    ----------
    positions_xy : (K, 2) array
        Entry positions, m.
    pos_xy : (2,) array
        Position of the foot, m.

    Returns
    -------
    (k, distance_m), or (None, inf) for an empty table.

    """
    if len(positions_xy) == 0:
        return None, math.inf
    distances = np.hypot(positions_xy[:, 0] - pos_xy[0], positions_xy[:, 1] - pos_xy[1])
    k = int(np.argmin(distances))
    return k, float(distances[k])


class StairEntryMonitor:
    """
    Watches the classified gait cycles for stair entries and associates them (eq. 17-18).

    ``update`` takes every gait cycle in order (after the classifier) and returns a
    ``CorrectionRequest`` when the cycle enters stairs from level walking and the nearest
    entry of the matching table on the floor of the level walking is within th_st.

    Counters: ``entries`` (stair entries seen), ``accepted``, ``refused_far`` (nearest entry
    beyond th_st), ``refused_no_entry`` (no entry on that floor in that direction).

    Parameters
    ----------
    database : StairDatabase
    ratio : float
        eq. (18).

    """

    def __init__(self, database: StairDatabase, ratio: float):
        self._database = database
        self._ratio = ratio
        self._mode = None            # stair mode of the last valid cycle
        self._floor = None           # and its floor
        self._last_xy = None
        self.distance_m = 0.0        # walked since the last accepted correction
        self.entries = 0
        self.accepted = 0
        self.refused_far = 0
        self.refused_no_entry = 0
        self.last_distance_m = math.nan
        self.last_threshold_m = math.nan
        self.last_stamp_ns = None    # of the last stair entry

    def update(self, cycle_index: int, stamp_ns: int, x_m: float, y_m: float, valid: bool,
               mode: int, floor: int) -> Optional[CorrectionRequest]:
        """
        Take one gait cycle; return the correction request it makes, or None.

        The cycle's index and stamp, its position (map frame, m), valid (False: not
        classified, it only adds distance), its stair mode (eq. 13) and the floor after it.

        """
        if self._last_xy is not None:
            self.distance_m += math.hypot(x_m - self._last_xy[0], y_m - self._last_xy[1])
        self._last_xy = (x_m, y_m)
        if not valid:
            return None
        entering = self._mode == MODE_LEVEL and mode != MODE_LEVEL
        level_floor = self._floor
        self._mode, self._floor = mode, floor
        if not entering:
            return None
        self.entries += 1
        self.last_stamp_ns = int(stamp_ns)
        entries, positions = self._database.table(level_floor, mode)
        k, distance_m = nearest_entry(positions, (x_m, y_m))
        threshold_m = association_threshold_m(self.distance_m, self._ratio)
        self.last_distance_m, self.last_threshold_m = distance_m, threshold_m
        if k is None:
            self.refused_no_entry += 1
            return None
        if not distance_m < threshold_m:
            self.refused_far += 1
            return None
        self.accepted += 1
        self.distance_m = 0.0
        entry = entries[k]
        return CorrectionRequest(cycle_index=int(cycle_index), stamp_ns=int(stamp_ns),
                                 x_m=float(x_m), y_m=float(y_m), entry_x_m=entry.x_m,
                                 entry_y_m=entry.y_m, stairwell=entry.stairwell,
                                 floor=entry.floor, direction=entry.direction)

    @property
    def counters(self) -> dict:
        """Return the association counters, for diagnostics."""
        return {'stair_entries': self.entries, 'stair_fix_accepted': self.accepted,
                'stair_fix_refused_far': self.refused_far,
                'stair_fix_refused_no_entry': self.refused_no_entry,
                'distance_since_fix_m': self.distance_m}


def stair_monitor_for(building, ratio: float) -> Optional[StairEntryMonitor]:
    """
    Return the StairEntryMonitor of a building, or None when it cannot correct anything.

    None without a building, without ``stairs``, or without ``start`` (the track is then not in
    the building's frame, and the database's positions mean nothing to it).
    """
    if building is None or not building.stairs or building.start is None:
        return None
    return StairEntryMonitor(StairDatabase(building.stairs), ratio)


__all__ = ['association_threshold_m', 'BuildingAidParams', 'CorrectionRequest',
           'nearest_entry', 'StairDatabase', 'StairEntryMonitor',
           'stair_monitor_for']
