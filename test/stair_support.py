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
A short walk through a switchback stairwell, up and back down, and its building file.

About 50 s: 5 level strides from the entrance, up a switchback (two flights of 10 steps), 5
strides along the upper corridor and back, down the same stairwell, 4 strides. Two stair
entries from level walking (floor 0 going up, floor 1 going down), at positions the building
file gives ``offset_m`` away from the truth, so that the correction visibly moves the track.
The map frame is ``sim/seed003.py``'s (entrance at (12.3, 4.1), first strides along +y).
"""

from anfis_elevation_ros.core.building import Building, Floor, StairEntry, Start
from anfis_elevation_ros.sim import Segment, simulate_walk
from anfis_elevation_ros.sim.seed003 import map_from_sim, MAP_HEADING_DEG, MAP_OFFSET_M
import numpy as np

STEPS = 10
STEP_HEIGHT_M = 0.16
STRIDE_M = 1.35


def _switchback(direction: int) -> list:
    flight = {'steps_per_stride': 2, 'step_height_m': STEP_HEIGHT_M}
    return [Segment.stairs(STEPS, direction, **flight),
            Segment.level(2, turn_deg=180.0, stride_length_m=0.7),
            Segment.stairs(STEPS, direction, **flight)]


def stair_walk_segments() -> tuple:
    """Return (segments, entries): entries are (segment index, floor, direction)."""
    segments = [Segment.level(5, stride_length_m=STRIDE_M)]
    entries = [(len(segments), 0, 1)]
    segments += _switchback(1)
    segments += [Segment.level(5, stride_length_m=STRIDE_M), Segment.turn(180.0),
                 Segment.level(5, stride_length_m=STRIDE_M), Segment.turn(180.0)]
    entries.append((len(segments), 1, -1))
    segments += _switchback(-1) + [Segment.level(4, stride_length_m=STRIDE_M)]
    return segments, entries


def simulate_stair_walk(seed: int = 3, rate_hz: float = 100.0, imu='tactical'):
    """Simulate the walk; return (SimulatedWalk, entries)."""
    segments, entries = stair_walk_segments()
    walk = simulate_walk(segments, rng=np.random.default_rng(seed), rate_hz=rate_hz, imu=imu,
                         step_height_m=STEP_HEIGHT_M)
    return walk, entries


def stair_walk_building(walk, entries, offset_m=(0.4, -0.3), stairs: bool = True,
                        directions_deg=()) -> Building:
    """Return the building of the walk: floors, entrance, the two entries (or none), corridors."""
    strides = walk.strides
    table = []
    for segment_index, floor, direction in entries if stairs else ():
        first = int(np.flatnonzero(strides.segment_index == segment_index)[0])
        x, y = map_from_sim(strides.end_pos_n[first])[0]
        table.append(StairEntry(stairwell='A', floor=floor, direction=direction,
                                x_m=float(x + offset_m[0]), y_m=float(y + offset_m[1])))
    return Building(name='stair walk', floors=(Floor(0, 0.0), Floor(1, 2 * STEPS * STEP_HEIGHT_M)),
                    step_height_m=STEP_HEIGHT_M, stairs=tuple(table),
                    start=Start(x_m=MAP_OFFSET_M[0], y_m=MAP_OFFSET_M[1], floor=0,
                                heading_deg=MAP_HEADING_DEG),
                    dominant_directions_deg=tuple(directions_deg))
