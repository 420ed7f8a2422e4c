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
Walk plans of the tools and benchmarks.

The seed's building walk, a tower walk, random training walks, the bundled sample walk.

Public API: ``building_walk``, ``tower_walk``, ``tower_floor_elevations_m``, ``random_walk``,
``sample_walk``, ``nominal_duration_s``.
"""

import math
from typing import NamedTuple

import numpy as np

from .motion import draw_uniform, segment_strides
from .plan import DEFAULT_FINAL_STAND_S, DEFAULT_INITIAL_STAND_S, DEFAULT_TREAD_M, GaitParams
from .plan import Segment
from ..core.errors import InputError
from ..core.validation import check_range


def nominal_duration_s(segments, gait: GaitParams = GaitParams(),
                       step_height_m: float = 0.17) -> float:
    """
    Return the expected duration of the segments alone (mid-range stride times), s.

    Excludes simulate_walk's initial and final stands.
    """
    total = 0.0
    for seg in segments:
        if seg.kind == 'stand':
            total += seg.duration_s
            continue
        for n_steps, *_ in segment_strides(seg, step_height_m):
            if seg.kind == 'level':
                total += sum(gait.level_stride_s) / 2
            elif seg.kind == 'turn':
                total += sum(gait.turn_stride_s) / 2
            else:
                total += (sum(gait.stair_stride_base_s)
                          + n_steps * sum(gait.stair_stride_per_step_s)) / 2
    return total


def building_walk(*, step_height_m: float = 0.15, steps_per_flight: int = 18,
                  steps_per_stride: int = 2, total_duration_s: float = 640.0,
                  gait: GaitParams = GaitParams()) -> tuple:
    """
    Plan the issue's seed replica: down two flights, a long level walk, back up the stairs.

    Plan: start upstairs (walk 20 strides to the stairwell, stand 10 s), down 2 flights of
    ``steps_per_flight`` steps of ``step_height_m`` with a 180 deg landing turn, about 500 s of
    level walking in out-and-back corridor legs with turns while walking, turns on the spot and
    stops, then turn round and back up both flights, walk 20 strides and stand. The level part
    is sized so that the walk, with simulate_walk's default stands, lasts about
    ``total_duration_s`` (640 s: 36 steps x 0.15 m = 5.4 m down and up).

    Returns
    -------
    tuple of Segment, for simulate_walk.

    """
    check_range('total_duration_s', total_duration_s, 200.0, 1e5)
    flight = {'steps_per_stride': steps_per_stride, 'step_height_m': step_height_m}
    down = (Segment.stairs(steps_per_flight, -1, **flight),
            Segment.level(2, turn_deg=180.0, stride_length_m=0.7),
            Segment.stairs(steps_per_flight, -1, **flight))
    up = (Segment.turn(180.0),
          Segment.stairs(steps_per_flight, +1, **flight),
          Segment.level(2, turn_deg=-180.0, stride_length_m=0.7),
          Segment.stairs(steps_per_flight, +1, **flight))
    head = (Segment.level(20), Segment.stand(10.0)) + down
    tail = up + (Segment.level(20), Segment.stand(5.0))
    block = (Segment.level(20), Segment.level(3, turn_deg=90.0), Segment.level(12),
             Segment.stand(8.0), Segment.turn(180.0), Segment.level(12),
             Segment.level(3, turn_deg=-90.0), Segment.level(20), Segment.stand(12.0),
             Segment.turn(-180.0))
    budget = (total_duration_s - DEFAULT_INITIAL_STAND_S - DEFAULT_FINAL_STAND_S
              - nominal_duration_s(head + tail, gait))
    middle = ()
    while nominal_duration_s(middle + block, gait) <= budget:
        middle += block
    stride_s = sum(gait.level_stride_s) / 2
    rest = budget - nominal_duration_s(middle, gait)
    if rest >= 2 * stride_s:
        # Out and back along the same corridor for the remaining time.
        half = int((rest - 2 * sum(gait.turn_stride_s)) / (2 * stride_s))
        if half >= 1:
            middle += (Segment.level(half), Segment.turn(180.0), Segment.level(half),
                       Segment.turn(180.0))
    return head + middle + tail


def tower_floor_elevations_m(storey_steps, step_height_m: float) -> np.ndarray:
    """
    Return the elevation of each floor of a tower (floor 0 at 0 m), m.

    E_0 = 0, E_f = K * sum_{j < f} storey_steps[j]: a storey of s steps of riser K is s K high.
    """
    return step_height_m * np.concatenate([[0], np.cumsum(storey_steps)]).astype(float)


def tower_walk(route, *, storey_steps=(26, 18, 18, 18, 18), step_height_m: float = 0.17,
               steps_per_stride: int = 2, level_strides: int = 12) -> tuple:
    """
    Plan a walk through a tower with one stairwell: floor to floor by ``route``.

    Floor f to f + 1 is two straight flights of ``storey_steps[f] / 2`` steps (the first one
    takes the odd step) with a 180 deg landing turn between them; on every floor of the route
    the walker leaves the stairwell, walks ``level_strides`` strides along a corridor, turns
    round and walks back. A lobby taller than the other storeys has more steps
    (``storey_steps[0]``). The floors' elevations are :func:`tower_floor_elevations_m`.

    Parameters
    ----------
    route : sequence of int
        Floors visited in order, starting with 0 (e.g. (0, 4, 1, 3, 0)); each in
        [0, len(storey_steps)].
    storey_steps : sequence of int
        Steps from floor f to floor f + 1, each in [4, 60].
    step_height_m : float
        Riser height K, m.
    steps_per_stride : int
        Steps climbed per stride, 1..4.
    level_strides : int
        Strides along the corridor, each way, on each floor of the route.

    Returns
    -------
    tuple of Segment, for simulate_walk.

    """
    route = [int(f) for f in route]
    top = len(storey_steps)
    if not route or route[0] != 0 or any(not 0 <= f <= top for f in route):
        raise InputError(f'tower_walk route={route} must start at floor 0 and stay in [0, {top}]')
    for steps in storey_steps:
        check_range('tower_walk storey_steps[]', steps, 4, 60)
    check_range('tower_walk level_strides', level_strides, 1, 1000)
    flight = {'steps_per_stride': steps_per_stride, 'step_height_m': step_height_m}
    corridor = (Segment.level(level_strides), Segment.turn(180.0), Segment.level(level_strides),
                Segment.turn(180.0))
    segments = list(corridor)
    floor = 0
    for target in route[1:]:
        while floor != target:
            direction = 1 if target > floor else -1
            steps = storey_steps[floor if direction > 0 else floor - 1]
            segments += [Segment.level(1),
                         Segment.stairs(steps - steps // 2, direction, **flight),
                         Segment.level(2, turn_deg=180.0, stride_length_m=0.7),
                         Segment.stairs(steps // 2, direction, **flight)]
            floor += direction
            segments += [Segment.turn(180.0)] if floor == target else [
                Segment.level(2, turn_deg=180.0, stride_length_m=0.7)]
        segments += corridor
    return tuple(segments)


def random_walk(duration_s: float, rng: np.random.Generator, *,
                step_height_range_m: tuple = (0.14, 0.19),
                steps_per_stride_weights: tuple = (0.35, 0.5, 0.1, 0.05),
                max_floors: int = 3, gait: GaitParams = GaitParams(),
                tread_range_m: tuple = (DEFAULT_TREAD_M, DEFAULT_TREAD_M)) -> tuple:
    """
    Plan a random mixture of level walking, stair flights, turns and stops (training data).

    The building's stairs are drawn first, once per storey (floors f to f + 1, f in
    [-``max_floors``, ``max_floors`` - 1], from the lowest up; ``_draw_staircase``): its
    riser height from ``step_height_range_m`` (storeys may differ), its steps per flight,
    6-20, its flights, two with a landing turn (probability 0.6) or one, and where it is: the
    foot of its first flight within 10 m of the start in plan, the heading up it (a multiple
    of 90 deg) and the side of its landing turn. Then activities are drawn until the nominal
    duration reaches ``duration_s`` (minus simulate_walk's default stands): level walks of
    3-15 strides of one length drawn from ``gait.level_stride_length_m`` (straight or turning
    up to 180 deg), a storey of stairs up or down, turns on the spot of 45-180 deg and stops
    of 2-10 s. To take a storey's stairs the wearer turns on the spot towards their foot (going
    up) or head (going down), walks there in a straight line (strides of at most 1.5 m) and
    turns on the spot to face up or down them; the flights are the storey's own whenever it is
    walked, the wearer's steps per stride 1..4 drawn per traversal with
    ``steps_per_stride_weights``, so going down retraces the way up. The plan knows its
    position from the nominal stride lengths (``_advance_nominal``); simulate_walk jitters
    given stride lengths (``GaitParams.stride_length_jitter``, 3 % of each stride), so a
    storey's flights start where the plan puts them to within that jitter summed over the
    strides walked since the plan's start (about 0.5 m after 10 minutes). The floor stays
    within +-``max_floors`` storeys of the start.

    Each storey's tread depth is drawn from ``tread_range_m`` (``_draw_treads``), apart from
    its riser height, so 2R + G need not obey a building code.

    Returns
    -------
    tuple of Segment, for simulate_walk (its duration is within a few strides of duration_s).

    """
    check_range('duration_s', duration_s, 5.0, 1e6)
    if not isinstance(rng, np.random.Generator):
        raise InputError(f'rng must be a numpy.random.Generator, got {type(rng).__name__}')
    low, high = step_height_range_m
    check_range('step_height_range_m[0]', low, 0.05, 0.30)
    check_range('step_height_range_m[1]', high, low, 0.30)
    weights = np.asarray(steps_per_stride_weights, dtype=float)
    if weights.shape != (4,) or np.any(weights < 0) or weights.sum() <= 0:
        raise InputError(f'steps_per_stride_weights={steps_per_stride_weights} must be 4 '
                         'non-negative weights for 1, 2, 3, 4 steps per stride')
    weights = weights / weights.sum()
    check_range('max_floors', max_floors, 1, 100)
    check_range('tread_range_m[0]', tread_range_m[0], 0.15, 0.50)
    check_range('tread_range_m[1]', tread_range_m[1], tread_range_m[0], 0.50)
    budget = duration_s - DEFAULT_INITIAL_STAND_S - DEFAULT_FINAL_STAND_S
    floors = range(-max_floors, max_floors)
    treads = _draw_treads(rng, tread_range_m, len(floors))
    storeys = {f: _draw_staircase(rng, (low, high), tread) for f, tread in zip(floors, treads)}
    segments = []
    elapsed = 0.0
    floor = 0
    xy, yaw = np.zeros(2), 0.0
    while elapsed < budget:
        activity = rng.choice(4, p=(0.4, 0.3, 0.15, 0.15))
        if activity == 0:
            turn = float(rng.choice((0.0, 0.0, 0.0, 45.0, 90.0, 180.0))) * rng.choice((-1, 1))
            n = int(rng.integers(3, 16))
            new = [Segment.level(n, turn_deg=turn if abs(turn) <= 60.0 * n else 0.0,
                                 stride_length_m=draw_uniform(rng, gait.level_stride_length_m))]
        elif activity == 1:
            direction = int(rng.choice((-1, 1)))
            if abs(floor + direction) > max_floors:
                direction = -direction
            stairs = storeys[min(floor, floor + direction)]
            per_stride = int(rng.choice(4, p=weights)) + 1
            start_xy, start_yaw = _stair_start(stairs, direction)
            new = (_walk_to(xy, yaw, start_xy, start_yaw)
                   + _stair_flights(stairs, direction, per_stride))
            floor += direction
        elif activity == 2:
            new = [Segment.turn(draw_uniform(rng, (45.0, 180.0)) * rng.choice((-1, 1)))]
        else:
            new = [Segment.stand(draw_uniform(rng, (2.0, 10.0)))]
        segments.extend(new)
        xy, yaw = _advance_nominal(xy, yaw, new)
        elapsed += nominal_duration_s(new, gait)
    return tuple(segments)


class _Staircase(NamedTuple):
    """
    One storey's stairs in a random_walk building.

    ``foot_xy_m`` is the start of the first flight going up, facing ``up_yaw_rad`` (ENU,
    from east, counter-clockwise); two flights are joined by a 180 deg landing turn to the
    ``landing_side`` (+1 left, -1 right, going up).
    """

    step_height_m: float
    tread_m: float
    steps_per_flight: int
    flights: int
    foot_xy_m: tuple
    up_yaw_rad: float
    landing_side: float


def _draw_treads(rng: np.random.Generator, tread_range_m: tuple, storeys: int) -> list:
    """
    Draw each storey's tread depth, m, from a generator spawned from ``rng``.

    Spawning leaves ``rng``'s own draws as they are, so a walk with treads drawn is the
    default walk (one tread everywhere) with other treads.
    """
    low, high = tread_range_m
    if low == high:
        return [float(low)] * storeys
    tread_rng = rng.spawn(1)[0]
    return [draw_uniform(tread_rng, tread_range_m) for _ in range(storeys)]


def _draw_staircase(rng: np.random.Generator, step_height_range_m: tuple,
                    tread_m: float) -> _Staircase:
    """Draw one storey's stairs: riser height, steps per flight, flights, place and heading."""
    step_height_m = draw_uniform(rng, step_height_range_m)
    steps = int(rng.integers(6, 21))
    flights = 2 if rng.uniform() < 0.6 else 1
    foot = (draw_uniform(rng, (-10.0, 10.0)), draw_uniform(rng, (-10.0, 10.0)))
    up_yaw = 0.5 * math.pi * int(rng.integers(4))
    side = float(rng.choice((-1.0, 1.0)))
    return _Staircase(step_height_m, tread_m, steps, flights, foot, up_yaw, side)


def _stair_flights(stairs: _Staircase, direction: int, steps_per_stride: int = 2) -> list:
    """
    Return the segments of one traversal of a storey's stairs, up (+1) or down (-1).

    Going down takes the flights in reverse with the landing turn to the other side, so it
    retraces the way up.
    """
    side = stairs.landing_side * direction
    segments = []
    for j in range(stairs.flights):
        if j:
            segments.append(Segment.level(2, turn_deg=180.0 * side, stride_length_m=0.7))
        segments.append(Segment.stairs(stairs.steps_per_flight, direction,
                                       steps_per_stride=steps_per_stride,
                                       step_height_m=stairs.step_height_m,
                                       tread_m=stairs.tread_m))
    return segments


def _stair_start(stairs: _Staircase, direction: int) -> tuple:
    """
    Return where a traversal of the stairs starts: (xy in m, heading in rad).

    Up: the foot, facing up the stairs. Down: the head (where the way up ends, nominal
    stride lengths), facing back the way the last flight up came.
    """
    foot = np.asarray(stairs.foot_xy_m, dtype=float)
    if direction > 0:
        return foot, stairs.up_yaw_rad
    head, yaw = _advance_nominal(foot, stairs.up_yaw_rad, _stair_flights(stairs, +1))
    return head, yaw + math.pi


def _walk_to(xy, yaw: float, goal_xy, goal_yaw: float) -> list:
    """
    Return the segments from (xy, yaw) to (goal_xy, goal_yaw) at nominal stride lengths.

    Turn on the spot towards the goal, walk straight to it in equal strides of at most
    1.5 m (none when it is under 0.2 m away, the shortest stride), turn on the spot to
    ``goal_yaw``; turns under 1 deg are left out.
    """
    segments = []
    offset = np.asarray(goal_xy, dtype=float) - np.asarray(xy, dtype=float)
    distance = float(np.hypot(*offset))
    if distance >= 0.2:
        bearing = math.atan2(offset[1], offset[0])
        segments += _turn_on_the_spot(bearing - yaw)
        n = math.ceil(distance / 1.5)
        segments.append(Segment.level(n, stride_length_m=distance / n))
        yaw = bearing
    return segments + _turn_on_the_spot(goal_yaw - yaw)


def _turn_on_the_spot(angle_rad: float) -> list:
    """Return a turn by the angle wrapped to (-180, 180] deg, or nothing under 1 deg."""
    angle_deg = math.degrees(math.remainder(angle_rad, 2.0 * math.pi))
    return [Segment.turn(angle_deg)] if abs(angle_deg) >= 1.0 else []


def _advance_nominal(xy, yaw: float, segments) -> tuple:
    """
    Return (xy in m, heading in rad) after the segments at their nominal stride lengths.

    Per stride, as simulate_walk moves the foot: psi = yaw + turn / 2,
    xy += length (cos psi, sin psi), yaw += turn. Level strides must have a given length.
    """
    xy = np.array(xy, dtype=float)
    for seg in segments:
        if seg.kind == 'stand':
            continue
        for _, turn, _, length, _, _ in segment_strides(seg, 0.17):
            if length is None:
                raise InputError('advance_nominal needs level segments with stride_length_m')
            heading = yaw + 0.5 * turn
            xy += length * np.array([math.cos(heading), math.sin(heading)])
            yaw += turn
    return xy, yaw


def sample_walk() -> tuple:
    """
    Plan a short demo walk (about 65 s): level, a flight up, turn, the flight down, level.

    Stair segments leave the riser height to simulate_walk's ``step_height_m``.
    """
    return (Segment.level(15),
            Segment.stairs(14, +1),
            Segment.level(1, stride_length_m=0.5),
            Segment.stand(5.0),
            Segment.turn(180.0),
            Segment.stairs(14, -1),
            Segment.level(15),
            Segment.stand(5.0))
