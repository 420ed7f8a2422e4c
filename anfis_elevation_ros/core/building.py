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
The building file: what an incident's pre-plan knows about a building (format version 1).

One YAML file (format ``anfis_elevation_ros/building``, documented in the README) gives the
floors with the elevation of their walking surface and, optionally, their outline, a riser
height, the stair-position database of seeds 001/003 (the first step of every stair entry,
per floor and direction), the entrance and the corridor directions. Frame: the building's
``map`` frame, ENU metres.

The file is data, never code: it is read with ``yaml.SafeLoader`` (duplicate keys refused), at
most ``MAX_BUILDING_BYTES``, and every key is checked; an unknown or bad key is refused with
one line that names it, and nothing is half-loaded (the ``Building`` is built only from a
fully checked file).

Public API: :func:`load_building`, :func:`load_building_file`, :func:`building_from_dict`,
:func:`building_to_dict`, :func:`save_building`, :class:`Building`, :class:`Floor`,
:class:`StairEntry`, :class:`Start`.
"""

from dataclasses import dataclass
import math
import numbers
from pathlib import Path
from typing import Optional

import numpy as np
import yaml

from .errors import InputError

BUILDING_FORMAT = 'anfis_elevation_ros/building'
BUILDING_VERSION = 1
MAX_BUILDING_BYTES = 1_000_000
MAX_FLOORS = 500
MAX_STAIR_ENTRIES = 10_000
MAX_OUTLINE_POINTS = 10_000
MIN_STOREY_M = 1.0          # closer floors cannot be told apart by a foot's height
STEP_HEIGHT_RANGE_M = (0.10, 0.25)
DIRECTIONS = {'up': 1, 'down': -1}

_TOP_KEYS = {'format', 'version', 'name', 'floors', 'step_height_m', 'stairs', 'start',
             'dominant_directions_deg'}
_FLOOR_KEYS = {'index', 'elevation_m', 'name', 'outline'}
_STAIR_KEYS = {'stairwell', 'floor', 'direction', 'x_m', 'y_m', 'step_height_m'}
_START_KEYS = {'x_m', 'y_m', 'floor', 'heading_deg'}


@dataclass(frozen=True)
class Floor:
    """
    One floor of the building.

    Attributes
    ----------
    index : the floor's number as the building counts it (may be negative).
    elevation_m : height of its walking surface in the map frame, m.
    name : shown on the map ('' when the file gives none).
    outline : ((x, y), ...) polygon of its walls in the map frame, m, or () when not given.

    """

    index: int
    elevation_m: float
    name: str = ''
    outline: tuple = ()


@dataclass(frozen=True)
class StairEntry:
    """
    One entry of the stair-position database (seeds 001/003): the first step met there.

    Attributes
    ----------
    stairwell : name shared by the entries of one stairwell.
    floor : index of the floor the entry lies on.
    direction : +1 if entering the stairs here goes up, -1 if down.
    x_m, y_m : centre of the first step, map frame, m.
    step_height_m : this stairwell's riser height, m, or None.

    """

    stairwell: str
    floor: int
    direction: int
    x_m: float
    y_m: float
    step_height_m: Optional[float] = None


@dataclass(frozen=True)
class Start:
    """Where responders enter: the first stance (map frame, m), its floor and heading (deg)."""

    x_m: float
    y_m: float
    floor: int
    heading_deg: float


@dataclass(frozen=True)
class Building:
    """
    A checked building file; build it with :func:`load_building` or :func:`building_from_dict`.

    Attributes
    ----------
    name : shown on the map ('' when not given).
    floors : tuple of Floor, by increasing index (and so by increasing elevation).
    step_height_m : riser height where a stairwell gives none, m, or None (then estimated).
    stairs : tuple of StairEntry, in file order.
    start : Start or None.
    dominant_directions_deg : corridor directions, deg counter-clockwise from +x, modulo 90,
        in [0, 90); () when not given.
    source : the file it was read from ('' for a dict).

    """

    name: str
    floors: tuple
    step_height_m: Optional[float] = None
    stairs: tuple = ()
    start: Optional[Start] = None
    dominant_directions_deg: tuple = ()
    source: str = ''

    def floor(self, index: int) -> Floor:
        """Return the floor with this index; InputError if the building has none."""
        for floor in self.floors:
            if floor.index == index:
                return floor
        raise InputError(f'{self._where()}: no floor with index {index} (floors: '
                         f'{", ".join(str(f.index) for f in self.floors)})')

    def has_floor(self, index: int) -> bool:
        """Tell whether a floor of this index exists."""
        return any(floor.index == index for floor in self.floors)

    @property
    def indices(self) -> np.ndarray:
        """(F,) int64 floor indices, increasing."""
        return np.array([f.index for f in self.floors], dtype=np.int64)

    @property
    def elevations_m(self) -> np.ndarray:
        """(F,) floor elevations in the map frame, m, increasing."""
        return np.array([f.elevation_m for f in self.floors])

    def nearest_floor(self, elevation_m: float) -> tuple:
        """
        Floor whose walking surface is nearest an elevation: (index, elevation_m - E_floor).

        floor = argmin_f |z - E_f|, z in the map frame (ties go to the lower floor).
        """
        elevations = self.elevations_m
        k = int(np.argmin(np.abs(elevations - elevation_m)))
        return int(self.floors[k].index), float(elevation_m - elevations[k])

    def stair_table(self, floor: int, direction: int) -> tuple:
        """
        Return one table of the database: the entries on ``floor`` going ``direction`` (+1/-1).

        Seed 003 keeps two tables, entries going up and entries going down; this is one of them
        restricted to one floor.
        """
        return tuple(e for e in self.stairs if e.floor == floor and e.direction == direction)

    def riser_height_m(self, stairwell: Optional[str] = None) -> Optional[float]:
        """
        Riser height the file gives for a stairwell, else the building's, else None.

        A stairwell's height is the ``step_height_m`` of any of its entries (the first given).
        """
        if stairwell is not None:
            for entry in self.stairs:
                if entry.stairwell == stairwell and entry.step_height_m is not None:
                    return entry.step_height_m
        return self.step_height_m

    def _where(self) -> str:
        return self.source or 'building'


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses a key given twice in one mapping (YAML keeps the last silently)."""

    def construct_mapping(self, node, deep=False):
        """Construct a mapping, refusing duplicate keys."""
        seen = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None, None, f'key {key!r} is given twice', key_node.start_mark)
            seen.add(key)
        return super().construct_mapping(node, deep=deep)


def load_building(path) -> Building:
    """
    Read and check a building file.

    Parameters
    ----------
    path : str or Path
        The YAML file.

    Returns
    -------
    Building.

    Raises
    ------
    InputError : a missing, unreadable, oversized or invalid file, or any bad key; the one-line
        message names the file and the key.

    """
    path = Path(path)
    where = str(path)
    try:
        with open(path, 'rb') as stream:
            data = stream.read(MAX_BUILDING_BYTES + 1)
    except OSError as err:
        raise InputError(f'{where}: cannot read the building file ({err.strerror or err})') \
            from None
    if len(data) > MAX_BUILDING_BYTES:
        raise InputError(f'{where}: larger than {MAX_BUILDING_BYTES} bytes; not a building file')
    try:
        tree = yaml.load(data.decode('utf-8'), Loader=_UniqueKeyLoader)
    except UnicodeDecodeError:
        raise InputError(f'{where}: not UTF-8 text; not a building file') from None
    except yaml.YAMLError as err:
        mark = getattr(err, 'problem_mark', None)
        at = f' (line {mark.line + 1})' if mark is not None else ''
        problem = getattr(err, 'problem', None) or str(err).splitlines()[0]
        raise InputError(f'{where}: invalid YAML{at}: {problem}') from None
    return building_from_dict(tree, where)


def load_building_file(building_file) -> Optional[Building]:
    """Load the building a ``building_file`` parameter names; None for '' (no building)."""
    return load_building(Path(building_file).expanduser()) if str(building_file) else None


def building_from_dict(tree, where: str = 'building') -> Building:
    """
    Check a parsed building file (a dict as YAML gives it) and build the Building.

    Raises
    ------
    InputError : the first bad key, named as ``where: key: problem``.

    """
    if not isinstance(tree, dict):
        raise InputError(f'{where}: a building file is a YAML mapping with format, version and '
                         f'floors; got {type(tree).__name__}')
    _check_keys(tree, _TOP_KEYS, where, '')
    if tree.get('format') != BUILDING_FORMAT:
        raise InputError(f'{where}: format: must be {BUILDING_FORMAT!r}, got '
                         f'{tree.get("format")!r}')
    version = tree.get('version')
    if isinstance(version, bool) or version != BUILDING_VERSION:
        raise InputError(f'{where}: version: must be {BUILDING_VERSION}, got {version!r} '
                         '(a newer file needs a newer anfis_elevation_ros)')
    name = _optional_text(tree, 'name', where, '')
    floors = _floors(tree.get('floors'), where)
    indices = {f.index for f in floors}
    step_height_m = None
    if tree.get('step_height_m') is not None:
        step_height_m = _number(tree['step_height_m'], where, 'step_height_m',
                                *STEP_HEIGHT_RANGE_M)
    stairs = _stairs(tree.get('stairs'), indices, where)
    start = _start(tree.get('start'), indices, where)
    directions = _directions(tree.get('dominant_directions_deg'), where)
    return Building(name=name, floors=floors, step_height_m=step_height_m, stairs=stairs,
                    start=start, dominant_directions_deg=directions, source=where)


def building_to_dict(building: Building) -> dict:
    """
    Return the file form of a Building (what :func:`building_from_dict` reads back equal).

    Optional keys the building does not have are left out.
    """
    tree = {'format': BUILDING_FORMAT, 'version': BUILDING_VERSION}
    if building.name:
        tree['name'] = building.name
    tree['floors'] = []
    for floor in building.floors:
        item = {'index': floor.index, 'elevation_m': floor.elevation_m}
        if floor.name:
            item['name'] = floor.name
        if floor.outline:
            item['outline'] = [list(point) for point in floor.outline]
        tree['floors'].append(item)
    if building.step_height_m is not None:
        tree['step_height_m'] = building.step_height_m
    if building.stairs:
        names = {value: key for key, value in DIRECTIONS.items()}
        tree['stairs'] = [{'stairwell': e.stairwell, 'floor': e.floor,
                           'direction': names[e.direction], 'x_m': e.x_m, 'y_m': e.y_m,
                           **({} if e.step_height_m is None
                              else {'step_height_m': e.step_height_m})}
                          for e in building.stairs]
    if building.start is not None:
        start = building.start
        tree['start'] = {'x_m': start.x_m, 'y_m': start.y_m, 'floor': start.floor,
                         'heading_deg': start.heading_deg}
    if building.dominant_directions_deg:
        tree['dominant_directions_deg'] = list(building.dominant_directions_deg)
    return tree


def save_building(path, building: Building) -> None:
    """Write a building file (YAML) that :func:`load_building` reads back equal."""
    text = yaml.safe_dump(building_to_dict(building), sort_keys=False,
                          default_flow_style=None)
    Path(path).write_text(text, encoding='utf-8')


# -- checks -----------------------------------------------------------------------------------

def _check_keys(mapping: dict, known: set, where: str, path: str):
    for key in mapping:
        if key not in known:
            raise InputError(f'{where}: {path}{key}: unknown key (known: '
                             f'{", ".join(sorted(known))})')


def _number(value, where: str, key: str, low: float = -math.inf, high: float = math.inf) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) \
            or not math.isfinite(value):
        raise InputError(f'{where}: {key}: must be a finite number, got {value!r}')
    if not low <= value <= high:
        raise InputError(f'{where}: {key}: {value} is outside [{low}, {high}]')
    return float(value)


def _integer(value, where: str, key: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) \
            or not -10_000 <= value <= 10_000:
        raise InputError(f'{where}: {key}: must be a whole number in [-10000, 10000], got '
                         f'{value!r}')
    return int(value)


def _optional_text(mapping: dict, key: str, where: str, path: str) -> str:
    value = mapping.get(key)
    if value is None:
        return ''
    if not isinstance(value, str) or len(value) > 200:
        raise InputError(f'{where}: {path}{key}: must be text of at most 200 characters, got '
                         f'{value!r:.60}')
    return value


def _list(value, where: str, key: str, limit: int, required: bool) -> list:
    if value is None and not required:
        return []
    if not isinstance(value, list) or (required and not value):
        what = 'a list of at least one item' if required else 'a list'
        raise InputError(f'{where}: {key}: must be {what}, got {value!r:.60}')
    if len(value) > limit:
        raise InputError(f'{where}: {key}: more than {limit} items')
    return value


def _mapping(value, where: str, key: str) -> dict:
    if not isinstance(value, dict):
        raise InputError(f'{where}: {key}: must be a mapping, got {value!r:.60}')
    return value


def _required(mapping: dict, key: str, where: str, path: str):
    if key not in mapping:
        raise InputError(f'{where}: {path}{key}: required key is missing')
    return mapping[key]


def _floors(value, where: str) -> tuple:
    floors = []
    for k, item in enumerate(_list(value, where, 'floors', MAX_FLOORS, required=True)):
        path = f'floors[{k}].'
        item = _mapping(item, where, path[:-1])
        _check_keys(item, _FLOOR_KEYS, where, path)
        index = _integer(_required(item, 'index', where, path), where, path + 'index')
        elevation = _number(_required(item, 'elevation_m', where, path), where,
                            path + 'elevation_m', -10_000.0, 10_000.0)
        floors.append(Floor(index=index, elevation_m=elevation,
                            name=_optional_text(item, 'name', where, path),
                            outline=_outline(item.get('outline'), where, path + 'outline')))
    floors.sort(key=lambda f: f.index)
    for lower, upper in zip(floors, floors[1:]):
        if upper.index == lower.index:
            raise InputError(f'{where}: floors: index {upper.index} is given twice')
        if upper.elevation_m - lower.elevation_m < MIN_STOREY_M:
            raise InputError(
                f'{where}: floors: floor {upper.index} (elevation_m {upper.elevation_m}) must be '
                f'at least {MIN_STOREY_M} m above floor {lower.index} ({lower.elevation_m}): '
                'elevations increase with the index')
    return tuple(floors)


def _outline(value, where: str, key: str) -> tuple:
    if value is None:
        return ()
    points = _list(value, where, key, MAX_OUTLINE_POINTS, required=True)
    if len(points) < 3:
        raise InputError(f'{where}: {key}: a polygon needs at least 3 points, got {len(points)}')
    outline = []
    for j, point in enumerate(points):
        if not isinstance(point, list) or len(point) != 2:
            raise InputError(f'{where}: {key}[{j}]: must be [x, y] in metres, got {point!r:.60}')
        outline.append(tuple(_number(v, where, f'{key}[{j}]') for v in point))
    return tuple(outline)


def _stairs(value, floor_indices: set, where: str) -> tuple:
    entries = []
    for k, item in enumerate(_list(value, where, 'stairs', MAX_STAIR_ENTRIES, required=False)):
        path = f'stairs[{k}].'
        item = _mapping(item, where, path[:-1])
        _check_keys(item, _STAIR_KEYS, where, path)
        stairwell = _required(item, 'stairwell', where, path)
        if isinstance(stairwell, bool) or not isinstance(stairwell, (str, int)) \
                or not str(stairwell).strip() or len(str(stairwell)) > 100:
            raise InputError(f'{where}: {path}stairwell: must be a name, got {stairwell!r:.60}')
        floor = _integer(_required(item, 'floor', where, path), where, path + 'floor')
        if floor not in floor_indices:
            raise InputError(f'{where}: {path}floor: {floor} is not one of floors[].index')
        direction = _required(item, 'direction', where, path)
        if direction not in DIRECTIONS:
            raise InputError(f"{where}: {path}direction: must be 'up' or 'down', got "
                             f'{direction!r:.60}')
        step = item.get('step_height_m')
        entries.append(StairEntry(
            stairwell=str(stairwell), floor=floor, direction=DIRECTIONS[direction],
            x_m=_number(_required(item, 'x_m', where, path), where, path + 'x_m'),
            y_m=_number(_required(item, 'y_m', where, path), where, path + 'y_m'),
            step_height_m=None if step is None else _number(step, where, path + 'step_height_m',
                                                            *STEP_HEIGHT_RANGE_M)))
    return tuple(entries)


def _start(value, floor_indices: set, where: str) -> Optional[Start]:
    if value is None:
        return None
    item = _mapping(value, where, 'start')
    _check_keys(item, _START_KEYS, where, 'start.')
    floor = _integer(_required(item, 'floor', where, 'start.'), where, 'start.floor')
    if floor not in floor_indices:
        raise InputError(f'{where}: start.floor: {floor} is not one of floors[].index')
    return Start(x_m=_number(_required(item, 'x_m', where, 'start.'), where, 'start.x_m'),
                 y_m=_number(_required(item, 'y_m', where, 'start.'), where, 'start.y_m'),
                 floor=floor,
                 heading_deg=_number(_required(item, 'heading_deg', where, 'start.'), where,
                                     'start.heading_deg', -3600.0, 3600.0))


def _directions(value, where: str) -> tuple:
    angles = _list(value, where, 'dominant_directions_deg', 36, required=False)
    return tuple(sorted({_number(a, where, f'dominant_directions_deg[{k}]') % 90.0
                         for k, a in enumerate(angles)}))


__all__ = ['Building', 'building_from_dict', 'building_to_dict', 'BUILDING_FORMAT',
           'BUILDING_VERSION', 'Floor', 'load_building', 'load_building_file', 'save_building',
           'StairEntry', 'Start']
