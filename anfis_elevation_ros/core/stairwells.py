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
Which stairwell a flight is in: one riser height estimate per stairwell.

Successive flights of one stairwell share K (their strides sharpen one estimate,
``core/riser_height.py``); another staircase may have another K. Each flight joins the
stairwell whose posterior explains its strides best, or starts a new one
(:func:`stairwell_evidence`); a flight back down the stairs just climbed joins them whatever
its strides say.

Public API: :class:`StairwellRiserHeights`, :func:`stairwell_evidence`,
:data:`SAME_STAIRS_M`, :data:`SAME_LEVEL_M`.
"""

from dataclasses import dataclass, field
import math
from typing import Optional

import numpy as np

from .level_strides import STRIDE_SIGMA_M
from .riser_height import K_GRID_M, log_sum_exp, PRIOR_SIGMA_M, RiserHeightEstimator
from .riser_height import stride_log_likelihood, stride_riser_counts
from .stair_steps import FlightStrides

SAME_STAIRS_M = 3.0
"""A flight starting this close (m) to where a stairwell's last flight ended is in it."""

SAME_LEVEL_M = 0.5
"""... and at a height this close (m) to that flight's end: not a storey above or below.

Less than half the shortest flight (6 risers of 0.14 m), more than the height error allowed.
"""


@dataclass
class Stairwell:
    """
    One stairwell: its riser height estimate and how its last flight ended.

    Attributes
    ----------
    estimator : the riser height of its flights' strides.
    flights : its finished flights' strides, to count their risers at any K.
    end_xy : (x, y) where its last flight ended, m, or None.
    direction : that flight's direction (+1 up, -1 down; 0 none yet).
    end_height_m : the height it ended at, m, or None.

    """

    estimator: RiserHeightEstimator
    flights: FlightStrides = field(default_factory=FlightStrides.empty)
    end_xy: Optional[tuple] = None
    direction: int = 0
    end_height_m: Optional[float] = None


class StairwellRiserHeights:
    """
    One :class:`RiserHeightEstimator` per stairwell, a flight's stairwell chosen by its strides.

    Successive flights of one stairwell share K (their strides sharpen one estimate); another
    staircase may have another K. Which stairwell a flight is in is not known (no stair
    database here, and the INS position drifts), so each flight goes to the stairwell whose
    riser height best explains its strides so far, or to a new one, by Bayesian evidence
    (:func:`stairwell_evidence`): a stairwell of another K, or a flight of one stair too many,
    is told apart after a stride or two. A flight back the other way that starts within
    :data:`SAME_STAIRS_M` of where a stairwell's last flight ended, and within
    :data:`SAME_LEVEL_M` of its end height (a turn back down the same stairs, not the next
    storey's stairs under them), is in that stairwell whatever its strides say: over a few
    metres the track does not drift, and strides up and down the same stairs can differ by
    10 % (an IMU's cross-axis errors). Each
    stairwell keeps how to count the risers of each of its finished flights, so that the
    height they add is K_w N_w(K_w) with the latest K_w: a later flight that moves K_w
    (strides of one riser settling what strides of four, read as three, left open) counts
    the earlier flights again, stride by stride, at the new K_w.

    Parameters
    ----------
    prior_m, known_m, prior_sigma_m
        As :class:`RiserHeightEstimator`, for every stairwell.

    """

    def __init__(self, prior_m: float, known_m: Optional[float] = None,
                 prior_sigma_m: float = PRIOR_SIGMA_M):
        self._template = RiserHeightEstimator(prior_m, known_m, prior_sigma_m)
        self._wells = []            # Stairwell records
        self._risers_at = {}        # (stairwell, K) -> N_w(K): K moves only during a flight
        self._flight_log_likelihood = None
        self._flight_strides = 0
        self._flight_start_xy = self._flight_end_xy = None
        self._flight_direction = 0
        self._flight_start_height_m = None
        self._index = None          # stairwell of the open (or last) flight; None: a new one

    def start_flight(self, start_xy: Optional[tuple] = None, direction: int = 0,
                     start_height_m: Optional[float] = None):
        """
        Open a flight (+1 up, -1 down) at (x, y) and height, m.

        Its strides are its own until it ends.
        """
        self._flight_log_likelihood = np.zeros(len(K_GRID_M))
        self._flight_strides = 0
        self._flight_start_xy = self._flight_end_xy = start_xy
        self._flight_direction = int(direction)
        self._flight_start_height_m = start_height_m
        self._index = None

    def add(self, dh_m: float, length_m: Optional[float] = None,
            end_xy: Optional[tuple] = None, sigma_m: float = STRIDE_SIGMA_M,
            from_level: bool = False) -> float:
        """
        Add a stride (ending at (x, y), m) to the open flight; return the estimate, m.

        ``sigma_m`` is the stride's height noise (``level_strides.stride_noise_sigma``);
        ``from_level`` says it is the flight's first (:func:`stride_riser_counts`).
        """
        if not math.isfinite(dh_m):
            raise ValueError(f'stair stride dh_m must be finite, got {dh_m!r}')
        if self._flight_log_likelihood is None:
            self.start_flight()
        self._flight_log_likelihood += stride_log_likelihood(
            dh_m, K_GRID_M, stride_riser_counts(dh_m, length_m, from_level, sigma_m), sigma_m)
        self._flight_strides += 1
        self._flight_end_xy = end_xy
        same_stairs = self._stairwell_ending_near(self._flight_start_xy)
        if same_stairs is not None:
            self._index = same_stairs
        elif self._template.estimating:
            evidence = [stairwell_evidence(well.estimator.log_posterior(),
                                           self._flight_log_likelihood) for well in self._wells]
            new = stairwell_evidence(self._template.log_posterior(),
                                     self._flight_log_likelihood)
            best = int(np.argmax(evidence)) if evidence else None
            self._index = best if best is not None and evidence[best] >= new else None
        else:
            self._index = 0 if self._wells else None
        return self.estimate_m

    def end_flight(self, flight: FlightStrides, end_height_m: Optional[float] = None):
        """
        Close the open flight (ending at a height, m): its strides and risers join its well.

        ``flight`` holds its strides as eq. 14 counts them: when a later flight moves its
        stairwell's K, the flight is counted again with it.
        """
        if self._flight_log_likelihood is None or not self._flight_strides:
            self._flight_log_likelihood = None
            return
        if self._index is None:
            self._wells.append(Stairwell(self._new_estimator()))
            self._index = len(self._wells) - 1
        well = self._wells[self._index]
        well.estimator.commit(self._flight_log_likelihood, self._flight_strides)
        well.flights = well.flights + flight
        self._risers_at.clear()
        well.end_xy = self._flight_end_xy
        well.direction = self._flight_direction
        well.end_height_m = end_height_m
        self._flight_log_likelihood = None

    def _new_estimator(self) -> RiserHeightEstimator:
        first = self._template
        return RiserHeightEstimator(first.prior_m, first.known_m, first.prior_sigma_m)

    def _stairwell_ending_near(self, xy: Optional[tuple]) -> Optional[int]:
        """Return the stairwell whose last flight, the other way, ended near (x, y) and height."""
        if xy is None or not self._flight_direction:
            return None
        start_m = self._flight_start_height_m
        for k, well in enumerate(self._wells):
            end_xy, end_m = well.end_xy, well.end_height_m
            if end_xy is not None and well.direction == -self._flight_direction and math.hypot(
                    xy[0] - end_xy[0], xy[1] - end_xy[1]) <= SAME_STAIRS_M and (
                    start_m is None or end_m is None or abs(start_m - end_m) <= SAME_LEVEL_M):
                return k
        return None

    def _open_flight(self):
        return self._flight_log_likelihood if self._flight_strides else None

    @property
    def estimate_m(self) -> float:
        """Return the riser height of the open (else the last) flight's stairwell, m."""
        return self._current_estimator().estimate_with(self._open_flight())

    @property
    def climbed_m(self) -> float:
        """Return the height of the finished flights, sum_w K_w N_w(K_w), m."""
        total = 0.0
        for k, well in enumerate(self._wells):
            more = self._open_flight() if k == self._index else None
            k_m = well.estimator.estimate_with(more)
            if (k, k_m) not in self._risers_at:
                self._risers_at[k, k_m] = well.flights.risers(k_m)
            total += k_m * self._risers_at[k, k_m]
        return total

    def forget_climbs(self):
        """Forget the finished flights (their height is in the caller's base: a new K, a floor)."""
        for well in self._wells:
            well.flights = FlightStrides.empty()
        self._risers_at.clear()

    def resume(self, estimate_m: float, strides: int):
        """Carry on from a saved estimate (a restart): one stairwell that has it."""
        estimator = self._new_estimator()
        estimator.resume(estimate_m, strides)
        self._wells = [Stairwell(estimator)]
        self._risers_at.clear()
        self._index = 0

    def set_prior(self, prior_m: float, sigma_m: float):
        """Move every stairwell's prior (a live parameter change); strides are kept."""
        for estimator in [self._template] + [well.estimator for well in self._wells]:
            estimator.set_prior(prior_m, sigma_m)

    @property
    def strides(self) -> int:
        """Return the stair strides behind the current estimate."""
        return self._current_estimator().strides + self._flight_strides * (
            self._open_flight() is not None)

    def _current_estimator(self) -> RiserHeightEstimator:
        """Return the estimator of the open (else the last) flight's stairwell, or the prior's."""
        return self._template if self._index is None else self._wells[self._index].estimator

    @property
    def estimating(self) -> bool:
        """Return whether K is estimated (not the file's, not taken as known)."""
        return self._template.estimating

    @property
    def stairwells(self) -> int:
        """Return the number of stairwells told apart so far."""
        return len(self._wells)


def stairwell_evidence(log_posterior: np.ndarray, flight_log_likelihood: np.ndarray) -> float:
    """
    Log evidence of a flight's strides for a stairwell (or a new one, with the prior).

    log p(dh_flight | w) = log sum_K p(K | w) p(dh_flight | K)
    """
    return log_sum_exp(log_posterior + flight_log_likelihood)
