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

from dataclasses import dataclass
import math
from typing import Optional

import numpy as np

MODE_LEVEL = 0

LEVEL_STRETCH_CYCLES = 3
"""Consecutive level cycles that make a level stretch (a landing turn takes 1-2)."""


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

    """

    start_floor: int
    storey_m: float = 3.0
    indices: tuple = ()
    elevations_m: tuple = ()

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


def floor_map_for(building, start_floor: int, storey_m: float) -> FloorMap:
    """
    Return the floors of a building (None: uniform storeys) seen from the start floor.

    The start floor is the building's ``start.floor`` when it has one, else ``start_floor``.

    Raises
    ------
    ValueError : the start floor is not one of the building's floors.

    """
    if building is None:
        return FloorMap(start_floor=int(start_floor), storey_m=float(storey_m))
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


def settled_floor(floor: int, level_cycles: int, nearest: int, offset_m: float,
                  tolerance_m: float) -> tuple:
    """
    Floor after a gait cycle, and whether it is certain: the settle rule.

    on_floor_i = (L_i >= 1 and |h_i - E_nearest| <= tol)
    floor_i = nearest if on_floor_i or L_i >= L_stretch else floor_{i-1};  certain_i = on_floor_i

    L_i counts the consecutive level cycles up to this one (0 on stairs). A level stretch of
    :data:`LEVEL_STRETCH_CYCLES` off every floor (a mezzanine, a height error beyond the
    tolerance, storeys unlike ``floor_height_m``) moves to the nearest floor, uncertain; a
    landing turn (1-2 cycles) between floors does not.

    Parameters
    ----------
    floor : int
        Floor before the cycle.
    level_cycles : int
        L_i.
    nearest, offset_m : int, float
        From :meth:`FloorMap.nearest` at the cycle's height.
    tolerance_m : float
        tol, m.

    Returns
    -------
    (int, bool).

    """
    on_floor = level_cycles >= 1 and abs(offset_m) <= tolerance_m
    moved = on_floor or level_cycles >= LEVEL_STRETCH_CYCLES
    return (int(nearest) if moved else int(floor)), bool(on_floor)


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
        Height at the start (or at a resume): the floor nearest it, certain if within the
        tolerance.

    """

    def __init__(self, floor_map: FloorMap, tolerance_m: float, height_m: float):
        if not (isinstance(tolerance_m, (int, float)) and math.isfinite(tolerance_m)
                and tolerance_m > 0):
            raise ValueError(f'floor tolerance must be a number > 0 m, got {tolerance_m!r}')
        self.tolerance_m = float(tolerance_m)
        self.level_cycles = 0
        self.rebase(floor_map, height_m)

    def rebase(self, floor_map: FloorMap, height_m: float, certain: Optional[bool] = None):
        """Take new floors (a parameter change): the floor nearest the height."""
        self.floor_map = floor_map
        self.floor, offset_m = floor_map.nearest(height_m)
        within = abs(offset_m) <= self.tolerance_m
        self.certain = within if certain is None else (certain and within)

    def update(self, height_m: float, mode: Optional[int]) -> int:
        """
        Apply the settle rule to a cycle's height and mode; return the floor.

        ``mode`` None is an invalid (unclassified) cycle: it extends a level stretch already
        begun (a few lost samples on a corridor) but starts none (not after stairs).
        """
        if mode is None:
            if not self.level_cycles:
                return self.floor
            mode = MODE_LEVEL
        self.level_cycles = self.level_cycles + 1 if mode == MODE_LEVEL else 0
        nearest, offset_m = self.floor_map.nearest(height_m)
        self.floor, self.certain = settled_floor(self.floor, self.level_cycles, nearest,
                                                 offset_m, self.tolerance_m)
        return self.floor
