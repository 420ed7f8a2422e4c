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
Three simulated responders in a three-storey tower: the command-centre demo and tests.

The tower has one stairwell, floors 0, 1 and 2, ``STOREY_STEPS`` risers of ``STEP_HEIGHT_M``
per storey (3.06 m: floors at 0, 3.06 and 6.12 m; without the tower's building file, which
:func:`tower_building` gives, the nodes could not tell floor 2 from floor 1 of a taller
lobby). Each responder walks a :func:`~.scenarios.tower_walk` route with short corridors and
then stands still for ``final_stand_s``:

- ``/ff1`` climbs to floor 1,
- ``/ff2`` climbs to floor 2,
- ``/ff3`` stays on floor 0 and stands still for a long time (the man-down case).

Public API: ``ResponderPlan``, ``RESPONDERS``, ``simulate_responder``, ``tower_building``.
"""

from dataclasses import dataclass

import numpy as np

from .scenarios import tower_floor_elevations_m, tower_walk
from .walk import simulate_walk
from ..core.building import Building, Floor

STOREY_STEPS = (18, 18)
STEP_HEIGHT_M = 0.17
LEVEL_STRIDES = 3
OUTLINE_MARGIN_M = 3.0


@dataclass(frozen=True)
class ResponderPlan:
    """
    One simulated responder.

    Attributes
    ----------
    namespace : the responder's ROS namespace (its id on the map).
    route : floors visited in order, from floor 0 (tower_walk).
    final_stand_s : time standing still at the end of the walk, s.
    seed : random seed of the gait and IMU errors.

    """

    namespace: str
    route: tuple
    final_stand_s: float
    seed: int

    @property
    def final_floor(self) -> int:
        """Return the floor the responder ends on."""
        return self.route[-1]


# Final stands chosen so that the three walks end within a few seconds of each other.
RESPONDERS = (ResponderPlan('/ff1', (0, 1), 15.0, 11),
              ResponderPlan('/ff2', (0, 2), 4.0, 12),
              ResponderPlan('/ff3', (0,), 45.0, 13))


def simulate_responder(plan: ResponderPlan, rate_hz: float = 100.0, imu: str = 'tactical'):
    """Simulate one responder's walk; return the SimulatedWalk."""
    segments = tower_walk(plan.route, storey_steps=STOREY_STEPS, step_height_m=STEP_HEIGHT_M,
                          level_strides=LEVEL_STRIDES)
    return simulate_walk(segments, rng=np.random.default_rng(plan.seed), rate_hz=rate_hz,
                         imu=imu, step_height_m=STEP_HEIGHT_M, final_stand_s=plan.final_stand_s)


def tower_building(walks) -> Building:
    """
    Return the tower's building file: its floors and, as their outline, a box round the walks.

    The outline is in the responders' frame (x, y relative to each walk's first position, as
    the nodes publish them without a ``start`` in the file), ``OUTLINE_MARGIN_M`` beyond the
    farthest point any walk reached.
    """
    xy = np.vstack([walk.pos_n[:, :2] - walk.pos_n[0, :2] for walk in walks])
    (x0, y0), (x1, y1) = xy.min(axis=0) - OUTLINE_MARGIN_M, xy.max(axis=0) + OUTLINE_MARGIN_M
    outline = tuple((round(float(x), 1), round(float(y), 1))
                    for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1)))
    elevations = tower_floor_elevations_m(STOREY_STEPS, STEP_HEIGHT_M)
    floors = tuple(Floor(index, round(float(z), 3), 'Ground' if index == 0 else f'Floor {index}',
                         outline) for index, z in enumerate(elevations))
    return Building(name='Simulated tower', floors=floors, step_height_m=STEP_HEIGHT_M)


__all__ = ['ResponderPlan', 'RESPONDERS', 'simulate_responder', 'tower_building']
