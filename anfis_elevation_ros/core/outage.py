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
An outage (a node restarted, gait cycles never received): what it hid, and the floor's doubt.

Our policy (the method does not cover restarts):

- The gait cycles lost in an outage are counted from the sensor time it lasted and the stride
  period saved before it (:func:`outage_cycle_count`). The IMU node publishes them as invalid
  cycles flagged ``outage``; the tracker bridges them like any run of invalid cycles: when the
  stair mode on both sides agrees, each lost cycle climbed the risers of the stride before
  (``core/height.py``, ``bridged_step_count``), so the risers missed are
  n_lost x risers per stride.
- A bridge is a guess from time alone: beyond :data:`MAX_CERTAIN_OUTAGE_CYCLES` lost cycles, or
  when the modes on both sides differ (the flight ended or began in the outage), the climb is
  unknown and the floor is in doubt (:func:`outage_leaves_doubt`, :class:`FloorDoubt`).
- A doubt carries the most the outage could have climbed or descended
  (:func:`max_unobserved_climb`: every lost cycle a stride of stairs). It clears at the next
  level stretch (:data:`LEVEL_STRETCH_CYCLES` level cycles in a row) when exactly one floor of
  the building file is within that reach of the height: the height is then that floor's
  (:func:`snapped_floor_height`). Otherwise, and always without a building file, the floor
  stays uncertain: the outputs never claim a floor the outage may have changed.

Public API: :func:`outage_cycle_count`, :func:`outage_leaves_doubt`,
:func:`max_unobserved_climb`, :func:`snapped_floor_height`, :class:`FloorDoubt`,
:data:`MAX_CERTAIN_OUTAGE_CYCLES`, :data:`LEVEL_STRETCH_CYCLES`, :data:`UNKNOWN_CLIMB_M`.
"""

from typing import Optional

import numpy as np

MAX_CERTAIN_OUTAGE_CYCLES = 3
"""Lost cycles up to which a bridged outage leaves the floor certain: beyond, a count from
time alone may be off (the stride period drifts, the walker may have stopped or turned)."""

LEVEL_STRETCH_CYCLES = 4
"""Level cycles in a row that make a level stretch (a landing between flights has 1-2)."""

MIN_RISERS_PER_STRIDE = 2
"""Risers a lost stride may climb at least in the reach of an outage (the usual two; more when
the stride before the outage climbed more)."""

UNKNOWN_CLIMB_M = 10000.0
"""The reach of a doubt whose motion is not bounded (the IMU node started a new walk)."""

MAX_OUTAGE_CYCLES = 1000
"""Most cycles one outage may count (``resume_max_gap_s`` bounds the gap: 3600 s at most)."""


def outage_cycle_count(gap_s: float, stride_period_s: float) -> int:
    """
    Count the gait cycles lost in an outage, from the sensor time it lasted.

    n_lost = round((t_first - t_saved) / T_stride)

    t_saved is the stamp of the last cycle before the outage, t_first the first stance of the
    restarted node (navigation starts there, so the stride ending at it is lost too), T_stride
    the stride period before the outage.

    Parameters
    ----------
    gap_s : float
        t_first - t_saved, s.
    stride_period_s : float > 0
        T_stride, s.

    Raises
    ------
    ValueError : a stride period that is not > 0.

    """
    if not stride_period_s > 0.0:
        raise ValueError(f'stride_period_s must be > 0, got {stride_period_s!r}')
    lost = int(np.floor(gap_s / stride_period_s + 0.5))
    return min(MAX_OUTAGE_CYCLES, max(0, lost))


def outage_leaves_doubt(lost_cycles: int, mode_before: int, mode_after: int) -> bool:
    """
    Say whether the cycles lost in an outage leave the floor uncertain.

    doubt  <=>  n_lost > MAX_CERTAIN_OUTAGE_CYCLES  or  C_before != C_after

    A short outage with the same stair mode on both sides is bridged on stairs, and adds
    nothing on level ground (a flight between two level stretches takes more strides).
    """
    return lost_cycles > MAX_CERTAIN_OUTAGE_CYCLES or mode_before != mode_after


def max_unobserved_climb(lost_cycles: int, risers_before: int, step_height_m: float) -> float:
    """
    Return the most an outage could have climbed (or descended), m.

    dh_max = n_lost * max(MIN_RISERS_PER_STRIDE, r_before) * K

    Parameters
    ----------
    lost_cycles : int
        n_lost.
    risers_before : int
        r_before, risers of the last stair stride before the outage (0 if level).
    step_height_m : float
        Riser height K, m.

    """
    return float(lost_cycles * max(MIN_RISERS_PER_STRIDE, abs(int(risers_before)))
                 * step_height_m)


def snapped_floor_height(height_m: float, floor_heights_m, reach_m: float) -> Optional[float]:
    """
    Return the floor a level stretch stands on after a doubt, if one alone is within reach.

    F = {f : |h - E_f| <= reach};  h <- E_f if F = {f}

    Parameters
    ----------
    height_m : float
        Quantised height of the level stretch, m.
    floor_heights_m : sequence of float
        Elevations of the building's floors relative to the start floor, m (none: no building).
    reach_m : float
        How far the true height may be from ``height_m`` (:func:`max_unobserved_climb` plus a
        riser of slack), m.

    """
    heights = np.asarray(floor_heights_m, dtype=float)
    within = heights[np.abs(heights - height_m) <= reach_m]
    return float(within[0]) if within.size == 1 else None


class FloorDoubt:
    """
    Whether an outage left the floor in doubt, why, and how often.

    Parameters
    ----------
    reason : str
        Why the floor is in doubt at the start ('' for no doubt, e.g. a resumed state's).
    reach_m : float
        How far from the height the true one may be (the doubts' climbs added), m.

    """

    def __init__(self, reason: str = '', reach_m: float = 0.0):
        self.reason = str(reason)
        self.reach_m = float(reach_m) if reason else 0.0
        self.doubts = int(bool(reason))

    @property
    def certain(self) -> bool:
        """Return False while the floor is in doubt."""
        return not self.reason

    def doubt(self, reason: str, climb_m: float = UNKNOWN_CLIMB_M):
        """Doubt the floor from now on, for this reason; the height may be off by climb_m more."""
        self.reason = reason or 'unobserved motion'
        self.reach_m = min(UNKNOWN_CLIMB_M, self.reach_m + float(climb_m))
        self.doubts += 1

    def clear(self):
        """Know the floor again."""
        self.reason = ''
        self.reach_m = 0.0
