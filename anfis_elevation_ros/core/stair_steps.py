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
Stair mode and whole risers of gait cycles and flights: method steps S7-S8 (eq. 13-14).

:func:`stair_mode` turns the classifier output y into the cycle's mode C (eq. 13: up +1,
level 0, down -1); :func:`quantised_step_count` and :func:`quantised_height_step` turn a
cycle's raw height change into a whole number of stair steps of height K (eq. 14);
:func:`flight_riser_count` counts a whole flight with one K (eq. 14 summed, our addition:
bounded by the riser counts the strides' lengths allow), :class:`FlightStrides` the strides of
any number of flights at once; :func:`bridged_step_count` credits lost cycles inside a flight.
``core/height.py`` (``ElevationTracker``) runs them per cycle.

Rounding: :func:`round_half_away` (``core/floors.py``), halves away from zero.

Public API: :func:`stair_mode`, :func:`quantised_step_count`, :func:`quantised_height_step`,
:func:`flight_riser_count`, :class:`FlightStrides`, :func:`bridged_step_count`,
:data:`MODE_UP`, :data:`MODE_LEVEL`, :data:`MODE_DOWN`, :data:`SURE_HEIGHT_RISERS`.

References
----------
[1] Patent CN111649742A, steps S7-S8, eq. (13) mode decision and eq. (14) height quantisation.

"""

from dataclasses import dataclass
import math

import numpy as np

from .floors import _int_result, round_half_away

MODE_UP, MODE_LEVEL, MODE_DOWN = 1, 0, -1
"""Values of the stair mode C of eq. 13."""

SURE_HEIGHT_RISERS = 0.25
"""A stride's height this close to a whole riser count (in risers) is counted as it says."""


def stair_mode(y, threshold: float):
    """
    Stair mode of a gait cycle from the ANFIS output, eq. 13.

    C = +1 if y > sigma_th;  C = -1 if y < -sigma_th;  C = 0 otherwise (|y| <= sigma_th)

    Parameters
    ----------
    y : float or array
        ANFIS output(s), dimensionless.
    threshold : float >= 0
        The mode threshold sigma_th.

    Returns
    -------
    int (scalar y) or int64 array of y's shape, values in {-1, 0, +1}.

    Raises
    ------
    ValueError : y holds NaN, or threshold is negative or not finite.

    """
    if not math.isfinite(threshold) or threshold < 0:
        raise ValueError(f'threshold must be a finite number >= 0, got {threshold!r}')
    y_array = np.asarray(y, dtype=float)
    if np.isnan(y_array).any():
        raise ValueError('stair_mode got NaN in y; the ANFIS output must be a number')
    mode = np.where(y_array > threshold, MODE_UP, np.where(y_array < -threshold, MODE_DOWN,
                                                           MODE_LEVEL))
    return _int_result(mode, np.ndim(y) == 0)


def quantised_step_count(mode, dh_m, step_height_m: float):
    """
    Signed whole number of stair steps climbed in a cycle, the integer part of eq. 14.

    n = C * max(1, round(|dh| / K))      (n = 0 when C = 0; round halves away from zero)

    Parameters
    ----------
    mode : int or array of int in {-1, 0, +1}
        C from :func:`stair_mode`.
    dh_m : float or array (broadcasting with mode)
        The cycle's raw height change, m.
    step_height_m : float > 0
        Stair step height K, m.

    Returns
    -------
    int (scalar inputs) or int64 array.

    """
    steps = np.maximum(1.0, round_half_away(np.abs(np.asarray(dh_m, dtype=float)) / step_height_m))
    return _int_result(np.asarray(mode) * steps, np.ndim(mode) == 0 and np.ndim(dh_m) == 0)


def bridged_step_count(mode_before: int, steps_before: int, mode_after: int,
                       lost_cycles: int) -> int:
    """
    Signed stair steps credited to a run of invalid cycles between two valid ones.

    n = lost_cycles * steps_before   if mode_before = mode_after != 0, else 0

    Parameters
    ----------
    mode_before, mode_after : int in {-1, 0, +1}
        Stair modes of the valid cycles before and after the run.
    steps_before : int
        Signed steps of the valid cycle before the run (from :func:`quantised_step_count`).
    lost_cycles : int
        Invalid cycles in the run.

    """
    if mode_before != mode_after or mode_before == MODE_LEVEL:
        return 0
    return int(lost_cycles * steps_before)


def quantised_height_step(mode, dh_m, step_height_m: float):
    """
    Height change of a cycle quantised to whole stair steps, eq. 14.

    h_i - h_i-1 = K * C_i * max(1, round(|dh_i| / K))      (0 when C_i = 0)

    A cycle classified as stairs climbs at least one step even when its raw dh is small; the sign
    comes from the mode, the number of steps from the raw height change.

    Parameters
    ----------
    mode : int or array of int in {-1, 0, +1}
        Stair mode C_i from :func:`stair_mode`.
    dh_m : float or array (broadcasting with mode)
        Raw height change of the cycle, m.
    step_height_m : float > 0
        Stair step height K, m.

    Returns
    -------
    float (scalar inputs) or float array, m.

    """
    steps = quantised_step_count(mode, dh_m, step_height_m)
    return step_height_m * steps if np.ndim(steps) else float(step_height_m * steps)


def flight_riser_count(mode: int, abs_dh_m, cycles, step_height_m: float, low=None,
                       high=None) -> int:
    """
    Signed risers of a whole flight with one riser height, eq. 14 summed over its strides.

    N = C * sum_i w_i n_i,   h_end - h_start = K N,   with m_i = max(1, round(|dh_i| / K)) and
    n_i = m_i                            if | |dh_i| / K - m_i | <= rho  (the height is sure)
    n_i = clip(m_i, n_low_i, n_high_i)   otherwise

    The bounds are the riser counts the stride's horizontal length allows
    (``riser_height.riser_count_bounds``, our addition): a stride whose height is off by half a
    riser (an INS glitch after a landing turn) is still counted as its length says. A height
    within rho = :data:`SURE_HEIGHT_RISERS` of a whole count is kept whatever the length says:
    one stride's INS length can read 0.2-0.35 m long in the middle of a flight whose heights
    are right to 3 mm (tactical IMU, random walks 11, 13 and 16), which the bound alone turned
    into one riser too many.

    Parameters
    ----------
    mode : int in {-1, +1}
        The flight's stair mode C.
    abs_dh_m : (S,) array
        |dh_i| of its strides, m.
    cycles : (S,) array of int
        w_i: 1, plus the lost cycles bridged after stride i (they climbed as stride i).
    step_height_m : float > 0
        K, m.
    low, high : (S,) arrays of int, or None
        n_low_i, n_high_i; None: no bound.

    Returns
    -------
    int.

    """
    abs_dh_m = np.asarray(abs_dh_m, dtype=float)
    steps = quantised_step_count(1, abs_dh_m, step_height_m)
    if low is not None:
        sure = np.abs(abs_dh_m / step_height_m - steps) <= SURE_HEIGHT_RISERS
        steps = np.where(sure, steps, np.clip(steps, np.asarray(low), np.asarray(high)))
    return int(mode * np.dot(steps, np.asarray(cycles, dtype=np.int64)))


@dataclass(frozen=True)
class FlightStrides:
    """
    The strides of finished flights, kept to count their risers again at any K.

    risers(K) = sum_f C_f sum_i w_i n_i(K) = :func:`flight_riser_count` with mode 1 on all the
    strides at once, each stride's cycles w_i signed by its flight's mode C_f. One call over
    arrays, however many flights: a stairwell walked all shift long is counted again quickly
    whenever its K moves (counted flight by flight, it cost about 1 ms a cycle by the sixth
    hour of the 8-hour soak, growing with every flight).

    Attributes
    ----------
    signed_cycles : (S,) int array, C_f w_i.
    abs_dh_m : (S,) array, |dh_i|, m.
    low, high : (S,) int arrays, n_low_i and n_high_i (``riser_height.riser_count_bounds``).

    """

    signed_cycles: np.ndarray
    abs_dh_m: np.ndarray
    low: np.ndarray
    high: np.ndarray

    @classmethod
    def of_flight(cls, mode: int, abs_dh_m, cycles, bounds) -> 'FlightStrides':
        """Return the strides of one flight of mode C, with their (n_low, n_high) bounds."""
        low, high = zip(*bounds) if len(bounds) else ((), ())
        return cls(int(mode) * np.asarray(cycles, dtype=np.int64),
                   np.asarray(abs_dh_m, dtype=float), np.asarray(low, dtype=np.int64),
                   np.asarray(high, dtype=np.int64))

    @classmethod
    def empty(cls) -> 'FlightStrides':
        """Return no strides (no flight counted)."""
        return cls.of_flight(MODE_UP, [], [], [])

    def __add__(self, other: 'FlightStrides') -> 'FlightStrides':
        """Return the strides of both."""
        return FlightStrides(*(np.concatenate([a, b]) for a, b in (
            (self.signed_cycles, other.signed_cycles), (self.abs_dh_m, other.abs_dh_m),
            (self.low, other.low), (self.high, other.high))))

    def risers(self, step_height_m: float) -> int:
        """Return the signed risers of all the flights at riser height K, m."""
        return flight_riser_count(MODE_UP, self.abs_dh_m, self.signed_cycles, step_height_m,
                                  self.low, self.high)
