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
A walk like seed 003's experiment, and the building file that goes with it.

Seed 003 walked about 1,100 m through two floors with four stairwells each and corrected the
track at the stair entries. Here: a rectangular corridor of ``CORRIDOR_M`` on each floor
with a stairwell at each corner (A, B, C, D, counter-clockwise from the entrance). Every
stairwell is a switchback: a flight, a 180 deg landing turn, a flight, so the walk comes out on
the other floor next to where it went in. Each leg walks one whole corridor loop, then on to
the next stairwell to use; the eight stair transitions use each of the eight entries (four up
from floor 0, four down from floor 1) once.

:func:`seed003_building` writes the building file from the simulated truth: every entry at the
first stance of the walk on its stairs (the first step the foot meets), ``start`` at the first
stance and the direction of the first strides, in a map frame placed and turned away from the
simulator's frame (so that the map transform is exercised). ``unknown`` leaves the entries of one
stairwell out: the walk then goes through a stairwell the database does not know.

The IMU is ``SEED003_IMU``: tactical-grade noise, with a gyro bias instability that makes the
plain ZUPT filter drift about 1 % of the distance walked, as the seed's plain filter did (11.45 m
mean error over 1,100 m).

Public API: :func:`seed003_walk`, :func:`seed003_building`, :data:`SEED003_IMU`,
:data:`STAIRWELLS`, :func:`map_from_sim`.
"""

from dataclasses import replace
import math

import numpy as np

from .imu_errors import IMU_PRESETS
from .plan import DEG, Segment
from ..core.building import Building, Floor, StairEntry, Start

CORRIDOR_M = (34.0, 11.0)        # the rectangle's sides: along the entrance's heading, across
STRIDE_M = 1.35
STEPS = 10                       # per flight; two flights a storey
STEP_HEIGHT_M = 0.16
STOREY_M = 2 * STEPS * STEP_HEIGHT_M
STAIRWELLS = ('A', 'B', 'C', 'D')  # at corners 0..3, counter-clockwise from the entrance
# The stair transitions: (stairwell, direction); up from floor 0, down from floor 1.
TRANSITIONS = (('B', 1), ('C', -1), ('D', 1), ('A', -1), ('C', 1), ('B', -1), ('A', 1),
               ('D', -1))
MAP_OFFSET_M = (12.3, 4.1)         # where the entrance is in the building's map frame
MAP_HEADING_DEG = 90.0             # direction of the first strides in the map frame

SEED003_IMU = replace(IMU_PRESETS['tactical'], name='seed003',
                      gyr_bias_sigma_rps=150.0 / 3600.0 * DEG,
                      gyr_bias_walk_rps_rts=150.0 / 3600.0 * DEG / math.sqrt(600.0))


def _leg(n_edges: int, first_edge: int) -> list:
    """Walk n_edges corridor sides from a corner, turning left at each corner reached."""
    segments = []
    for k in range(n_edges):
        side = CORRIDOR_M[(first_edge + k) % 2]
        segments.append(Segment.level(max(1, round(side / STRIDE_M)), stride_length_m=STRIDE_M))
        segments.append(Segment.turn(90.0))
    return segments


def _switchback(direction: int) -> list:
    """One stairwell: flight, 180 deg landing turn, flight, then face along the corridor."""
    flight = {'steps_per_stride': 2, 'step_height_m': STEP_HEIGHT_M}
    return [Segment.stairs(STEPS, direction, **flight),
            Segment.level(2, turn_deg=180.0, stride_length_m=0.7),
            Segment.stairs(STEPS, direction, **flight),
            Segment.turn(-90.0)]


def seed003_walk() -> tuple:
    """
    Plan the walk: (segments, transitions); a transition: (segment, stairwell, floor, +-1).

    The walk starts at corner A facing along the long side. Each transition: one whole loop
    of the corridor, then the sides to the stairwell to use, then the switchback. About 1,150 m.
    """
    segments = [Segment.stand(2.0)]
    transitions = []
    corner, floor = 0, 0
    for stairwell, direction in TRANSITIONS:
        target = STAIRWELLS.index(stairwell)
        edges = 4 + (target - corner) % 4
        segments += _leg(edges, corner)
        # The last turn of a leg faces the next side; the stairs go straight on from the corner.
        segments.pop()
        transitions.append((len(segments), stairwell, floor, direction))
        segments += _switchback(direction)
        corner, floor = target, floor + direction
    segments += _leg(1, corner)[:1] + [Segment.stand(3.0)]
    return tuple(segments), tuple(transitions)


def map_from_sim(pos_sim) -> np.ndarray:
    """Return the (N, 2) map-frame x, y of simulator positions (N, >=2), as the file says."""
    pos = np.atleast_2d(np.asarray(pos_sim, dtype=float))[:, :2]
    c, s = math.cos(MAP_HEADING_DEG * DEG), math.sin(MAP_HEADING_DEG * DEG)
    return np.column_stack((MAP_OFFSET_M[0] + c * pos[:, 0] - s * pos[:, 1],
                            MAP_OFFSET_M[1] + s * pos[:, 0] + c * pos[:, 1]))


def seed003_building(walk, transitions, unknown: str = '') -> Building:
    """
    Return the building file of a simulated seed-003 walk: floors, stair entries, start.

    ``walk`` is the SimulatedWalk (its stride truth places the entries), ``transitions``
    come from seed003_walk, ``unknown`` names a stairwell to leave out ('' for none).

    """
    strides = walk.strides
    stairs = []
    for segment_index, stairwell, floor, direction in transitions:
        if stairwell == unknown:
            continue
        first = int(np.flatnonzero(strides.segment_index == segment_index)[0])
        x, y = map_from_sim(strides.end_pos_n[first])[0]
        stairs.append(StairEntry(stairwell=stairwell, floor=floor, direction=direction,
                                 x_m=float(x), y_m=float(y), step_height_m=STEP_HEIGHT_M))
    return Building(name='seed 003 replica', floors=(Floor(0, 0.0, 'ground'),
                                                     Floor(1, STOREY_M, 'first')),
                    step_height_m=STEP_HEIGHT_M, stairs=tuple(stairs),
                    start=Start(x_m=MAP_OFFSET_M[0], y_m=MAP_OFFSET_M[1], floor=0,
                                heading_deg=MAP_HEADING_DEG))


__all__ = ['map_from_sim', 'SEED003_IMU', 'seed003_building', 'seed003_walk', 'STAIRWELLS']
