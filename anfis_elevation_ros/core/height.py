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
Stair mode, quantised height and floor per gait cycle: method steps S7-S8 (eq. 13-14).

For every gait cycle the navigator delivers its features (eq. 8-12 and the motion features,
order :data:`FEATURE_NAMES`, heights relative to the stance height at the cycle start). The stair
classifier (ANFIS or forest, ``core/classifier.py``) maps them to one number y;
:func:`stair_mode` turns y into the cycle's mode C (eq. 13: up +1, level 0, down -1),
:func:`quantised_height_step` turns the cycle's raw height change into a whole number of stair
steps of height K (eq. 14), and :func:`floor_index` turns the accumulated height into a floor.
:class:`ElevationTracker` holds the height between cycles and runs the three for each cycle.

Lost cycles (our policy; the method does not cover them). A gait cycle with missing IMU samples
(a gap) or an overlong swing is invalid: its features are not trusted, so it is not classified
and at first adds no step. Stair flights are continuous, so when the valid cycles on both sides
of a run of invalid ones have the same stair mode, the foot was on that flight all along: the
run is bridged with :func:`bridged_step_count` (each lost cycle climbed as many steps as the
cycle before it). Otherwise (the run is at the start or end of a flight, or on level ground)
nothing is added; at most one cycle's steps per flight end can be lost this way.

Rounding. "round" in eq. 14 and in the floor index rounds halves away from zero
(:func:`round_half_away`): 1.5 -> 2, -1.5 -> -2, 0.5 -> 1, -0.5 -> -1. Exact halves are rare with
real data; this choice treats going up and going down alike around the start floor, which numpy's
and Python's round-half-to-even would not (0.5 -> 0 but 1.5 -> 2).

Public API: :class:`ElevationParams`, :class:`CycleEstimate`, :class:`ElevationTracker`,
:func:`stair_mode`, :func:`quantised_step_count`, :func:`quantised_height_step`,
:func:`bridged_step_count`,
:func:`floor_index`, :func:`round_half_away`, :data:`FEATURE_NAMES`, :data:`HEIGHT_CHANGE`.

References
----------
[1] Patent CN111649742A, steps S7-S8, eq. (13) mode decision and eq. (14) height quantisation.

"""

from dataclasses import dataclass
import math
import numbers
from typing import Optional

import numpy as np

from .classifier import as_classifier
from .errors import InputError
from .gait import FEATURE_NAMES

HEIGHT_CHANGE = FEATURE_NAMES.index('height_change_m')
"""Index (2) of the cycle's raw height change dh (end minus start, m) in the feature vector."""

MAX_CYCLE_HEIGHT_CHANGE_M = 10.0
"""A gait cycle climbing more than this (m) comes from a diverged INS: treated as invalid."""

MODE_UP, MODE_LEVEL, MODE_DOWN = 1, 0, -1
"""Values of the stair mode C of eq. 13."""

DEFAULT_MODE_THRESHOLD = 0.5
"""sigma_th for a model that stores none: the midpoint of the training targets -1 / 0 / +1."""


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


def _check_real(name: str, value, low: Optional[float] = None, high: Optional[float] = None):
    ok = (isinstance(value, numbers.Real) and not isinstance(value, bool)
          and math.isfinite(value) and (low is None or value >= low)
          and (high is None or value <= high))
    if not ok:
        bounds = f'[{low}, {high}]' if high is not None else (
            f'>= {low}' if low is not None else 'finite')
        raise ValueError(f'ElevationParams.{name} must be a number in {bounds}, got {value!r}')


@dataclass(frozen=True)
class ElevationParams:
    """
    Parameters of the elevation half of the method (eq. 13-14, step S8).

    Attributes
    ----------
    step_height_m : stair step height K, m, in [0.10, 0.25]; 0.17 m is a typical building stair
        (most codes allow 0.15-0.19 m risers).
    mode_threshold : sigma_th of eq. 13, in [0, 1], or negative (the default) for the model's
        own: the threshold the training tool chose by cross-validation, stored in the model's
        metadata as ``mode_threshold`` (0.5, the midpoint of the targets -1 / 0 / +1, for a
        model without one). So a retrained model brings its threshold along.
    floor_height_m : storey height H, m, >= 2.0; 3.0 m is a common storey.
    start_floor : floor of the start point (int).
    start_height_m : height of the start point above the start floor's reference, m.

    """

    step_height_m: float = 0.17
    mode_threshold: float = -1.0
    floor_height_m: float = 3.0
    start_floor: int = 0
    start_height_m: float = 0.0

    def __post_init__(self):
        _check_real('step_height_m', self.step_height_m, 0.10, 0.25)
        _check_real('mode_threshold', self.mode_threshold, -1.0, 1.0)
        _check_real('floor_height_m', self.floor_height_m, 2.0)
        _check_real('start_height_m', self.start_height_m)
        start_floor = self.start_floor
        if isinstance(start_floor, bool) or not isinstance(start_floor, numbers.Integral):
            raise ValueError(f'ElevationParams.start_floor must be an int, got {start_floor!r}')


@dataclass(frozen=True)
class CycleEstimate:
    """
    Result of one gait cycle (step S8).

    Attributes
    ----------
    stamp_ns : int, stamp of the cycle (its end), ns.
    mode : int, stair mode C of eq. 13: +1 up, 0 level, -1 down.
    height_m : float, quantised height h after this cycle (eq. 14), m, z up.
    floor : int, floor index at height_m.
    x_m, y_m : float, horizontal position of the foot in the navigation frame n (ENU), m.
    anfis_output : float, the ANFIS output y that gave the mode (NaN for an invalid cycle).
    bridged_steps : int, steps credited to the invalid cycles just before this one.

    """

    stamp_ns: int
    mode: int
    height_m: float
    floor: int
    x_m: float
    y_m: float
    anfis_output: float
    bridged_steps: int = 0


def model_mode_threshold(model, params: ElevationParams) -> float:
    """
    Return sigma_th for a model: ``params.mode_threshold``, or the model's own if that is < 0.

    The model's own is its metadata ``mode_threshold`` (the training tool's cross-validated
    choice), else ``DEFAULT_MODE_THRESHOLD``.

    Raises
    ------
    ValueError : the model's stored threshold is not a number in [0, 1].

    """
    if params.mode_threshold >= 0.0:
        return float(params.mode_threshold)
    metadata = getattr(model, 'metadata_', None)
    threshold = metadata.get('mode_threshold', DEFAULT_MODE_THRESHOLD) \
        if isinstance(metadata, dict) else DEFAULT_MODE_THRESHOLD
    if isinstance(threshold, bool) or not isinstance(threshold, numbers.Real) \
            or not 0.0 <= threshold <= 1.0:
        raise ValueError(f'the model stores mode_threshold = {threshold!r}, not a number in '
                         '[0, 1]; set elevation.mode_threshold explicitly or retrain')
    return float(threshold)


class ElevationTracker:
    """
    Height and floor from the features of successive gait cycles (eq. 13-14, step S8).

    The height is kept as a whole number of stair steps above a base height, so it carries no
    rounding drift: height_m = base_height_m + K * steps.

    Parameters
    ----------
    model : StairClassifier, Anfis or object with predict
        A stair classifier (``core/classifier.py``; a bare ANFIS of eq. (8)-(12) is wrapped) or
        any object whose ``predict`` maps a (1, N_FEATURES) feature array to a (1,) array.
    params : ElevationParams
        Step height, mode threshold, storey height, start floor and height.
    height_m : float or None
        Height to resume from after a restart; default ``params.start_height_m``.

    """

    def __init__(self, model, params: ElevationParams, height_m: Optional[float] = None):
        model = as_classifier(model)
        n_inputs = getattr(model, 'n_inputs', len(FEATURE_NAMES))
        if n_inputs != len(FEATURE_NAMES) or not callable(getattr(model, 'predict', None)):
            raise ValueError(f'model must have predict() and {len(FEATURE_NAMES)} inputs '
                             f'({", ".join(FEATURE_NAMES)}), got {model!r}')
        if not isinstance(params, ElevationParams):
            raise ValueError(f'params must be ElevationParams, got {type(params).__name__}')
        self.model = model
        self.params = params
        self.mode_threshold = model_mode_threshold(model, params)
        self.reset(height_m)

    def reset(self, height_m: Optional[float] = None):
        """Restart from a height (m; default ``params.start_height_m``), e.g. after a restart."""
        if height_m is None:
            height_m = self.params.start_height_m
        if isinstance(height_m, bool) or not isinstance(height_m, numbers.Real) \
                or not math.isfinite(height_m):
            raise ValueError(f'height_m must be a finite number, got {height_m!r}')
        self._base_height_m = float(height_m)
        self._steps = 0
        self._last_mode = MODE_LEVEL
        self._last_steps = 0
        self._lost = 0
        self.bridged_cycles = 0
        self.unbridged_cycles = 0
        self.implausible_cycles = 0

    def set_params(self, params: ElevationParams):
        """
        Take new parameters mid-run (a live parameter change).

        The height is kept (the new step height counts from here), and so are the counters and
        the invalid cycles waiting to be bridged; the floor follows the new storey height and
        start floor.
        """
        if not isinstance(params, ElevationParams):
            raise ValueError(f'params must be ElevationParams, got {type(params).__name__}')
        mode_threshold = model_mode_threshold(self.model, params)
        self._base_height_m = self.height_m
        self._steps = 0
        self.params = params
        self.mode_threshold = mode_threshold

    @property
    def height_m(self) -> float:
        """Return the current quantised height, m (z up)."""
        return self._base_height_m + self.params.step_height_m * self._steps

    @property
    def floor(self) -> int:
        """Return the current floor index."""
        return floor_index(self.height_m, self.params.floor_height_m, self.params.start_floor)

    def update(self, stamp_ns: int, features, x_m: float, y_m: float,
               valid: bool = True) -> CycleEstimate:
        """
        Process one gait cycle: ANFIS -> mode (eq. 13) -> height (eq. 14) -> floor.

        Parameters
        ----------
        stamp_ns : int
            Stamp of the cycle, ns.
        features : (N_FEATURES,) array
            In the order of :data:`FEATURE_NAMES`; ignored when not valid.
        x_m, y_m : float
            Horizontal position in the navigation frame n, m.
        valid : bool
            False for a cycle with a gap or an overlong swing: not classified (mode 0, height
            unchanged) and bridged later if the valid cycles around it agree (module docstring).
            A cycle climbing more than ``MAX_CYCLE_HEIGHT_CHANGE_M`` is handled as invalid too
            (counted in ``implausible_cycles``).

        Returns
        -------
        CycleEstimate.

        Raises
        ------
        InputError : features of a valid cycle not of shape (N_FEATURES,) or not finite, or
            x_m / y_m not finite; the tracker state is left unchanged.

        """
        try:
            x_m, y_m = float(x_m), float(y_m)
        except (TypeError, ValueError):
            raise InputError(f'cycle position must be numbers, got x_m={x_m!r}, y_m={y_m!r}') \
                from None
        if not valid:
            self._lost += 1
            return self._estimate(stamp_ns, MODE_LEVEL, x_m, y_m, float('nan'))
        if not (math.isfinite(x_m) and math.isfinite(y_m)):
            raise InputError(f'cycle position is not finite: x_m={x_m}, y_m={y_m}; cycle skipped')
        try:
            features = np.asarray(features, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f'cycle features must be {len(FEATURE_NAMES)} numbers '
                             f'({", ".join(FEATURE_NAMES)}), got {features!r}') from None
        if features.shape != (len(FEATURE_NAMES),):
            raise InputError(f'cycle features must have shape ({len(FEATURE_NAMES)},) '
                             f'({", ".join(FEATURE_NAMES)}), got {features.shape}')
        if not np.isfinite(features).all():
            raise InputError(f'cycle features are not finite: {features.tolist()}; cycle skipped')
        if abs(features[HEIGHT_CHANGE]) > MAX_CYCLE_HEIGHT_CHANGE_M:
            self.implausible_cycles += 1
            return self.update(stamp_ns, features, x_m, y_m, valid=False)
        output = float(self.model.predict(features[None, :])[0])
        mode = stair_mode(output, self.mode_threshold)                                   # eq. 13
        steps = quantised_step_count(mode, features[HEIGHT_CHANGE],
                                     self.params.step_height_m)                         # eq. 14
        bridged = 0
        if self._lost:
            bridged = bridged_step_count(self._last_mode, self._last_steps, mode, self._lost)
            if bridged:
                self.bridged_cycles += self._lost
            else:
                self.unbridged_cycles += self._lost
            self._lost = 0
        self._steps += steps + bridged
        self._last_mode, self._last_steps = mode, steps
        return self._estimate(stamp_ns, mode, x_m, y_m, output, bridged)

    def _estimate(self, stamp_ns, mode, x_m, y_m, output, bridged=0) -> CycleEstimate:
        height_m = self.height_m
        return CycleEstimate(stamp_ns=int(stamp_ns), mode=mode, height_m=height_m,
                             floor=floor_index(height_m, self.params.floor_height_m,
                                               self.params.start_floor),
                             x_m=x_m, y_m=y_m, anfis_output=output, bridged_steps=bridged)
