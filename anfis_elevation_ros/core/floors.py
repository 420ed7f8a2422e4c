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
The floor a quantised height stands on, changed only when the height settles there.

Floors come from the building file's elevations when there is one (storeys of any height, a
taller lobby), else from one storey height H and the start floor. Heights are relative to the
start floor's walking surface (0 at the first stance, plus ``start_height_m``).

Without a building file nobody knows the storeys, so H is only a guess: a height of 12 m is
floor 4 of 3 m storeys and floor 3 of 4 m ones. With no floor walked to go by (below), a
floor is then certain only where every building with storeys in a plausible range
[H_min, H_max] (and a ground storey, the lobby, up to L_max) puts the same floor
(:meth:`FloorMap.candidates`), and the height is also within the tolerance of the guess's
elevation (:meth:`FloorMap.place`), after a level stretch (a landing can be at a floor's
height); elsewhere the floor is the guess of H, not certain, and
:attr:`FloorSettler.floor_range` says which floors the height can be on.

Floors walked narrow the rest. The start floor, and every floor made certain on a level
stretch, is an anchor: each storey between it and another floor is again H_min..H_max (the
lobby up to L_max), so the floors a height can be on are also those its height above the
anchor allows, and a floor is certain where the anchors leave it alone
(:meth:`FloorSettler.candidates`). One storey from an anchor is 2.3-5.0 m and two are 5.1 m
or more (tolerance 0.5 m), so the floor next to an anchor is certain whatever the storeys.
A landing walked round can be at any height a floor could have (two thirds up a storey of
three flights is a storey's height above the floor below, or 3 m above the start), so where
the storeys are not known a floor is certain only once its level stretch has gone more than
:data:`LANDING_REACH_M` from where the stairs ended.
The guess of H stood guard against a height error; the errors that reach half a storey are
climbs nobody saw, so the anchors are forgotten where cycles were lost next to stairs
(:meth:`FloorSettler.forget_anchors`), and until a floor is certain again the guess of H
stands guard as before.

Settle rule (our choice; the method rounds h / H at every cycle, which flickers on landings and
mid-flight): the floor changes only at a level cycle whose height lies within a tolerance of a
floor's elevation, or after a level stretch (:func:`settled_floor`). While on stairs, on a
landing between floors, or level but off every floor, the floor is not certain.
Certainty lives in one place, :attr:`FloorSettler.certain`, so that other doubts (a restart's
outage) can join it.

Rounding. "round" in eq. 14 and in the floor index rounds halves away from zero
(:func:`round_half_away`): 1.5 -> 2, -1.5 -> -2, 0.5 -> 1, -0.5 -> -1. Exact halves are rare with
real data; this choice treats going up and going down alike around the start floor, which numpy's
and Python's round-half-to-even would not (0.5 -> 0 but 1.5 -> 2).

Public API: :class:`FloorMap`, :func:`floor_map_for`, :func:`settled_floor`,
:class:`FloorSettler`, :func:`floor_index`, :func:`round_half_away`.
"""

from dataclasses import dataclass, replace
import math
from typing import Optional

import numpy as np

MODE_LEVEL = 0

LEVEL_STRETCH_CYCLES = 3
"""Consecutive level cycles that make a level stretch (a landing turn takes 1-2)."""

LANDING_REACH_M = 3.0
"""How far a level stretch may go from the stairs and still be on a landing, m (a landing is
about a stair's width deep, 1-2.5 m): without known storeys only a stretch that went further
is made certain (and becomes a floor walked)."""


def round_half_away(value):
    """
    Round to the nearest integer, halves away from zero (1.5 -> 2, -0.5 -> -1).

    round(v) = sign(v) * floor(|v| + 1/2)

    Parameters
    ----------
    value : float or array
        Values to round.

    Returns
    -------
    Float or array of the same shape holding whole numbers.

    """
    return np.sign(value) * np.floor(np.abs(value) + 0.5)


def _int_result(value, scalar: bool):
    """Return a Python int for scalar input, an int64 array otherwise."""
    result = np.asarray(value).astype(np.int64)
    return int(result) if scalar else result


def floor_index(height_m, floor_height_m: float, start_floor: int = 0):
    """
    Floor reached at a height, step S8.

    floor = start_floor + round(h / H)      (round halves away from zero: h = H/2 is one floor up)

    Parameters
    ----------
    height_m : float or array
        Height h above the start point, m.
    floor_height_m : float > 0
        Storey height H, m.
    start_floor : int
        Floor of the start point.

    Returns
    -------
    int (scalar height) or int64 array.

    """
    floors = round_half_away(np.asarray(height_m, dtype=float) / floor_height_m)
    return _int_result(start_floor + floors, np.ndim(height_m) == 0)


@dataclass(frozen=True)
class FloorMap:
    """
    Where the floors are, relative to the start floor's walking surface.

    Attributes
    ----------
    start_floor : int, the floor of the first stance.
    storey_m : float, storey height H (used when ``indices`` is empty), m.
    indices : tuple of int, the building's floors (empty: uniform storeys of ``storey_m``).
    elevations_m : tuple of float, their elevations minus the start floor's, m.
    storey_range_m : (H_min, H_max), the storeys' plausible heights without a building, m.
    lobby_max_m : float, L_max, how tall the ground storey (floor 0 to 1) can be, m (below
        H_max: no taller than the others).

    """

    start_floor: int
    storey_m: float = 3.0
    indices: tuple = ()
    elevations_m: tuple = ()
    storey_range_m: tuple = (3.0, 3.0)
    lobby_max_m: float = 0.0

    def nearest(self, height_m: float) -> tuple:
        """
        Return the floor nearest a height and the height's offset from it, (floor, h - E_f).

        floor = argmin_f |h - E_f|, E_f = E_f,file - E_start,file with a building, else
        floor = start_floor + round(h / H) and E_f = (floor - start_floor) H.
        """
        if not self.indices:
            floor = floor_index(height_m, self.storey_m, self.start_floor)
            return floor, height_m - (floor - self.start_floor) * self.storey_m
        k = int(np.argmin(np.abs(np.asarray(self.elevations_m) - height_m)))
        return self.indices[k], height_m - self.elevations_m[k]

    @property
    def storeys_known(self) -> bool:
        """Return whether the floors' elevations are known: a building file, or storeys of H."""
        h_min, h_max = self.storey_range_m
        return bool(self.indices) or (h_min == h_max and self.lobby_max_m <= h_max)

    def place(self, height_m: float, tolerance_m: float) -> tuple:
        """
        Return the floor a height is taken to be on and whether it is sure: (f, sure).

        The nearest floor f (:meth:`nearest`; without a building file the guess of H, moved
        into the candidates C(h) when they are not empty), sure when |h - E_f| <= tol and,
        without a building file, C(h) = {f}: both the guess of H and every plausible storey
        height put h on f. The first alone is wrong in most buildings (storeys other than H);
        the second alone cannot see a height error (floor 1 holds 2.3-5.1 m).
        """
        floor, offset_m = self.nearest(height_m)
        sure = abs(offset_m) <= tolerance_m
        if self.indices:
            return floor, sure
        floors = self.candidates(height_m, tolerance_m)
        if floors is None:
            return floor, False
        lowest, highest = floors
        return min(max(floor, lowest), highest), sure and lowest == highest == floor

    def seen_from(self, floor: int) -> 'FloorMap':
        """Return the same storeys seen from another floor (heights above that floor's)."""
        return replace(self, start_floor=int(floor))

    def elevation_range_m(self, floor: int) -> tuple:
        """
        Return the lowest and highest elevation a floor can have without a building file, m.

        Floor f is n = |f - f_0| storeys from the start floor f_0, each of H_min..H_max but the
        ground storey (between floors 0 and 1, when crossed), which may be up to
        L = max(L_max, H_max):

            E_f in sign(f - f_0) [n H_min, n H_max + (L - H_max) [lobby crossed]]

        """
        low_floor, high_floor = sorted((int(floor), self.start_floor))
        storeys = high_floor - low_floor
        h_min, h_max = self.storey_range_m
        lobby_m = max(self.lobby_max_m, h_max) if low_floor <= 0 < high_floor else h_max
        shortest, tallest = storeys * h_min, storeys * h_max + lobby_m - h_max
        return (shortest, tallest) if floor >= self.start_floor else (-tallest, -shortest)

    def candidates(self, height_m: float, tolerance_m: float) -> Optional[tuple]:
        """
        Return the floors a height can be on, within the tolerance: (lowest, highest), or None.

        C(h) = {f : E_f,min - tol <= h <= E_f,max + tol}, an interval of floors; with a
        building file the floor nearest h alone, if h is within tol of it. None between two
        floors' ranges (a landing, a mezzanine).
        """
        if self.indices:
            floor, offset_m = self.nearest(height_m)
            return (floor, floor) if abs(offset_m) <= tolerance_m else None
        h_min, h_max = self.storey_range_m
        side = 1 if height_m >= 0.0 else -1
        inside = []
        for storeys in range(max(0, int(abs(height_m) // max(h_max, self.lobby_max_m)) - 1),
                             int(abs(height_m) // h_min) + 2):
            floor = self.start_floor + side * storeys
            low_m, high_m = self.elevation_range_m(floor)
            if low_m - tolerance_m <= height_m <= high_m + tolerance_m:
                inside.append(floor)
        return (min(inside), max(inside)) if inside else None


def floor_map_for(building, start_floor: int, storey_m: float,
                  storey_range_m: Optional[tuple] = None, lobby_max_m: float = 0.0) -> FloorMap:
    """
    Return the floors of a building (None: storeys of about ``storey_m``) seen from the start.

    The start floor is the building's ``start.floor`` when it has one, else ``start_floor``.
    Without a building the storeys may be anywhere in ``storey_range_m`` (None: exactly
    ``storey_m``), widened to hold ``storey_m``, and the ground storey up to ``lobby_max_m``.

    Raises
    ------
    ValueError : the start floor is not one of the building's floors.

    """
    if building is None:
        low_m, high_m = storey_range_m if storey_range_m is not None else (storey_m, storey_m)
        return FloorMap(start_floor=int(start_floor), storey_m=float(storey_m),
                        storey_range_m=(float(min(low_m, storey_m)),
                                        float(max(high_m, storey_m))),
                        lobby_max_m=float(lobby_max_m))
    if building.start is not None:
        start_floor = building.start.floor
    if not building.has_floor(start_floor):
        raise ValueError(f'elevation.start_floor {start_floor} is not a floor of the building '
                         f'{building.source or building.name!r} (floors '
                         f'{", ".join(str(f.index) for f in building.floors)})')
    base = building.floor(start_floor).elevation_m
    return FloorMap(start_floor=int(start_floor), storey_m=float(storey_m),
                    indices=tuple(int(f.index) for f in building.floors),
                    elevations_m=tuple(float(f.elevation_m - base) for f in building.floors))


def settled_floor(floor: int, level_cycles: int, place: int, sure: bool,
                  settle_cycles: int = 1) -> tuple:
    """
    Floor after a gait cycle, and whether it is certain: the settle rule.

    on_floor_i = (L_i >= L_settle and sure_i)
    floor_i = place_i if on_floor_i or L_i >= L_stretch else floor_{i-1};  certain_i = on_floor_i

    L_i counts the consecutive level cycles up to this one (0 on stairs); (place_i, sure_i)
    from :meth:`FloorMap.place` at the cycle's height: sure when the height can be on that
    floor alone (within the tolerance of its elevation). L_settle (``settle_cycles``) is 1
    where the floors' elevations are known, :data:`LEVEL_STRETCH_CYCLES` where the storeys
    are not (a landing can be at a floor's height there). A level stretch of
    :data:`LEVEL_STRETCH_CYCLES` off every floor (a mezzanine, a height error beyond the
    tolerance, storeys unlike ``floor_height_m``, a height that several floors could have
    without a building file) moves to that floor, uncertain; a landing turn (1-2 cycles)
    between floors does not.

    Parameters
    ----------
    floor : int
        Floor before the cycle.
    level_cycles : int
        L_i.
    place, sure : int, bool
        From :meth:`FloorMap.place`.
    settle_cycles : int
        L_settle.

    Returns
    -------
    (int, bool).

    """
    on_floor = level_cycles >= max(1, settle_cycles) and sure
    moved = on_floor or level_cycles >= LEVEL_STRETCH_CYCLES
    return (int(place) if moved else int(floor)), bool(on_floor)


class FloorSettler:
    """
    The floor of successive gait cycles under the settle rule (:func:`settled_floor`).

    Parameters
    ----------
    floor_map : FloorMap
        Where the floors are.
    tolerance_m : float > 0
        How far from a floor's elevation a level height may be and still settle on it, m.
    height_m : float
        Height at the start (or at a resume): the floor it is on (:meth:`FloorMap.place`),
        certain if it can be on no other.

    """

    def __init__(self, floor_map: FloorMap, tolerance_m: float, height_m: float):
        if not (isinstance(tolerance_m, (int, float)) and math.isfinite(tolerance_m)
                and tolerance_m > 0):
            raise ValueError(f'floor tolerance must be a number > 0 m, got {tolerance_m!r}')
        self.tolerance_m = float(tolerance_m)
        self.level_cycles = 0
        self.reach_m = 0.0
        self._last_xy = self._stretch_xy = None
        self.rebase(floor_map, height_m)

    def rebase(self, floor_map: FloorMap, height_m: float, certain: Optional[bool] = None):
        """Take new floors (a parameter change): the floor nearest the height, its anchor."""
        self.floor_map = floor_map
        self.height_m = float(height_m)
        self.floor, sure = floor_map.place(height_m, self.tolerance_m)
        self.certain = sure if certain is None else (certain and sure)
        self.anchors = {}
        self._anchor()

    def _anchor(self):
        """Take a certain floor for an anchor (storeys unknown): a floor walked at its height."""
        if self.certain and not self.floor_map.storeys_known:
            self.anchors[self.floor] = self.height_m

    def forget_anchors(self):
        """Forget the floors walked: a climb may have gone unseen (lost cycles by the stairs)."""
        self.anchors = {}

    def candidates(self, height_m: float) -> Optional[tuple]:
        """
        Return the floors a height can be on, given the floors walked: (lowest, highest) or None.

        I(h) = C(h) & C_a1(h - h_a1) & C_a2(h - h_a2) & ...

        C (:meth:`FloorMap.candidates`) from the start floor, C_a the same storeys seen from an
        anchor a, a floor made certain on a level stretch at height h_a, since the anchors
        were last forgotten (:meth:`FloorMap.seen_from`). None when empty: a height off every
        floor, or one the anchors disagree on (a height error).
        """
        floors = self.floor_map.candidates(height_m, self.tolerance_m)
        for floor, anchor_m in self.anchors.items():
            if floors is None:
                break
            seen = self.floor_map.seen_from(floor).candidates(height_m - anchor_m,
                                                              self.tolerance_m)
            if seen is None:
                return None
            floors = (max(floors[0], seen[0]), min(floors[1], seen[1]))
            if floors[0] > floors[1]:
                return None
        return floors

    def _place(self, height_m: float) -> tuple:
        """
        Return the floor a height is taken to be on and whether it is sure: (f, sure).

        :meth:`FloorMap.place` where the storeys are known. Where they are not, sure only once
        the level stretch has left the stairs (:data:`LANDING_REACH_M`: a landing walked round
        can be at any height a floor could have), and then: without anchors as
        :meth:`FloorMap.place`; with them the same floor moved into I(h) (:meth:`candidates`),
        sure when I(h) is one floor (the floors walked stand for the guess of H).
        """
        floor, sure = self.floor_map.place(height_m, self.tolerance_m)
        if self.floor_map.storeys_known:
            return floor, sure
        walked_off = self.reach_m > LANDING_REACH_M
        if not self.anchors:
            return floor, sure and walked_off
        floors = self.candidates(height_m)
        if floors is None:
            return floor, False
        lowest, highest = floors
        return min(max(floor, lowest), highest), lowest == highest and walked_off

    def _walk(self, xy: Optional[tuple], level: bool):
        """
        Follow how far the level stretch has gone from where the stairs ended, m.

        reach = max over the stretch's cycles of |p_i - p_0|, p_0 the position at its start.
        """
        if not level:
            self._stretch_xy, self.reach_m = None, 0.0
        elif xy is not None:
            if self._stretch_xy is None:
                self._stretch_xy = self._last_xy if self._last_xy is not None else xy
            self.reach_m = max(self.reach_m, math.dist(xy, self._stretch_xy))
        if xy is not None:
            self._last_xy = xy

    def update(self, height_m: float, mode: Optional[int], xy: Optional[tuple] = None) -> int:
        """
        Apply the settle rule to a cycle's height and mode; return the floor.

        ``mode`` None is an invalid (unclassified) cycle: it extends a level stretch already
        begun (a few lost samples on a corridor) but starts none (not after stairs). ``xy``
        is the cycle's end position, m (None: not known, the stretch is not followed).
        """
        if mode is None:
            if not self.level_cycles:
                self._walk(xy, False)
                return self.floor
            mode = MODE_LEVEL
        self.level_cycles = self.level_cycles + 1 if mode == MODE_LEVEL else 0
        self._walk(xy, mode == MODE_LEVEL)
        self.height_m = float(height_m)
        place, sure = self._place(height_m)
        settle_cycles = 1 if self.floor_map.storeys_known else LEVEL_STRETCH_CYCLES
        self.floor, self.certain = settled_floor(self.floor, self.level_cycles, place, sure,
                                                 settle_cycles)
        self._anchor()
        return self.floor

    @property
    def floor_range(self) -> Optional[tuple]:
        """
        Return the floors the height can be on, (lowest, highest), or None when not known.

        (floor, floor) while certain. On a level stretch (:data:`LEVEL_STRETCH_CYCLES`) that
        is not: the candidates I(h) (:meth:`candidates`; without a building file a height
        several floors could have, or one floor by the floors walked while the stretch is
        still near the stairs). None on the stairs, on a landing turn, and where no floor
        fits (a mezzanine, a height off every floor of the file, anchors that disagree); and
        for one floor when no floor walked says so (no anchors: after lost cycles by the
        stairs the height may be wrong, and one floor that the guess of H does not confirm is
        what lost stair strides give, so no floor is offered).
        """
        if self.certain:
            return self.floor, self.floor
        if self.level_cycles < LEVEL_STRETCH_CYCLES:
            return None
        floors = self.candidates(self.height_m)
        if floors is not None and floors[0] == floors[1] and not self.anchors:
            return None
        return floors
