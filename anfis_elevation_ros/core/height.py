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
steps of height K (eq. 14), and ``core/floors.py`` turns the accumulated height into a floor
(the building's floors, or uniform storeys; changed only when the height settles on one).
:class:`ElevationTracker` holds the height between cycles and runs the three for each cycle.
The per-cycle equations are in ``core/stair_steps.py`` (re-exported here).

Riser height K (our addition; the method takes K as known). Nobody at an incident knows it, so
K is estimated from the stair strides themselves (``core/riser_height.py``, one estimate per
stairwell), with ``step_height_m`` as the prior, unless the building file gives it (then it is
used exactly) or ``step_height_sigma_m`` is 0 (then ``step_height_m`` is). A flight is a run of
valid cycles of one stair mode; its riser count is recomputed from all its strides with the
current estimate at every stride (:func:`flight_riser_count`), so when the estimate sharpens
mid-flight the flight's heights are corrected forward; at its end the count is fixed. The
height is a whole number of risers per stairwell, h = h_0 + sum_w K_w N_w (N_w: net risers
climbed in stairwell w), so a later flight that sharpens K_w corrects the stairwell's earlier
flights too, and coming back down the stairs one went up ends exactly where one started.
K only changes during a flight, so a level stretch keeps its height (no floor flicker).
With a building file, a height that settles on a floor (``core/floors.py``) becomes that
floor's elevation: the file knows where its floors are, a riser count off by one does not.

Lost cycles (our policy; the method does not cover them). A gait cycle with missing IMU samples
(a gap) or an overlong swing is invalid: its features are not trusted, so it is not classified
and at first adds no step. Stair flights are continuous, so when the valid cycles on both sides
of a run of invalid ones have the same stair mode, the foot was on that flight all along: the
run is bridged with :func:`bridged_step_count` (each lost cycle climbed as many steps as the
cycle before it). Otherwise (the run is at the start or end of a flight, or on level ground)
nothing is added; at most one cycle's steps per flight end can be lost this way.

Public API: :class:`ElevationParams`, :class:`CycleEstimate`, :class:`ElevationTracker`,
:func:`stair_mode`, :func:`quantised_step_count`, :func:`quantised_height_step`,
:func:`flight_riser_count`, :func:`bridged_step_count`, :func:`floor_index`,
:func:`round_half_away`, :data:`FEATURE_NAMES`, :data:`HEIGHT_CHANGE`.

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
from .floors import floor_index, floor_map_for, FloorSettler, round_half_away
from .gait import FEATURE_NAMES
from .level_strides import LevelSlope
from .riser_height import height_checked_mode, known_riser_height_m, MAX_RISERS
from .riser_height import PRIOR_SIGMA_M, riser_count_bounds
from .stair_steps import bridged_step_count, flight_riser_count, FlightStrides, MODE_DOWN
from .stair_steps import MODE_LEVEL, MODE_UP
from .stair_steps import quantised_height_step, quantised_step_count, stair_mode
from .stairwells import StairwellRiserHeights
from .validation import check_finite, check_range

__all__ = ['bridged_step_count', 'CycleEstimate', 'ElevationParams', 'ElevationTracker',
           'FEATURE_NAMES', 'flight_riser_count', 'floor_index', 'HEIGHT_CHANGE',
           'model_mode_threshold', 'quantised_height_step', 'quantised_step_count',
           'round_half_away', 'stair_mode']

HEIGHT_CHANGE = FEATURE_NAMES.index('height_change_m')
"""Index (2) of the cycle's raw height change dh (end minus start, m) in the feature vector."""

MAX_CYCLE_HEIGHT_CHANGE_M = 10.0
"""A gait cycle climbing more than this (m) comes from a diverged INS: treated as invalid."""

MISSED_STRIDE_RISERS = 0.5
"""A level cycle just before a flight that climbed this many risers (its way) was its first."""

MISSED_STRIDE_MAX_TURN_DEG = 45.0
"""... if it went the flight's way: a flight is straight, a landing turn is not its stride."""

MISSED_STRIDE_LIKE = (0.75, 1.25)
"""... and climbed like the flight's next stride (ratio): not a glitch after a landing turn."""

DEFAULT_MODE_THRESHOLD = 0.5
"""sigma_th for a model that stores none: the midpoint of the training targets -1 / 0 / +1."""


@dataclass(frozen=True)
class ElevationParams:
    """
    Parameters of the elevation half of the method (eq. 13-14, step S8).

    Attributes
    ----------
    step_height_m : stair step height K, m, in [0.10, 0.25]; 0.17 m is a typical building stair
        (most codes allow 0.15-0.19 m risers). The prior of the online estimate of K.
    step_height_sigma_m : width of that prior, m, in [0, 0.1]; 0 takes ``step_height_m`` as
        known (no estimation).
    mode_threshold : sigma_th of eq. 13, in [0, 1], or negative (the default) for the model's
        own: the threshold the training tool chose by cross-validation, stored in the model's
        metadata as ``mode_threshold`` (0.5, the midpoint of the targets -1 / 0 / +1, for a
        model without one). So a retrained model brings its threshold along.
    floor_height_m : storey height H, m, >= 2.0; 3.0 m is a common storey. Without a building
        file only a guess: the floor is certain only where every storey height within
        [floor_height_min_m, floor_height_max_m] (and a ground storey, the lobby, up to
        ``lobby_height_max_m``), counted from the start and the floors walked, gives the same
        floor (``core/floors.py``).
    floor_height_min_m, floor_height_max_m : the storeys' plausible heights without a building
        file, m (the issue's 2.8-4.5 m); both equal to ``floor_height_m`` and
        ``lobby_height_max_m`` 0: storeys known to be H.
    lobby_height_max_m : how tall the ground storey (floor 0 to floor 1) can be, m (6.0); at
        most ``floor_height_max_m``: no taller than the others.
    start_floor : floor of the start point (int).
    start_height_m : height of the start point above the start floor's reference, m.
    floor_tolerance_m : a level height this close to a floor's elevation settles on that floor,
        m, in [0.05, 1.5] (``core/floors.py``).

    """

    step_height_m: float = 0.17
    mode_threshold: float = -1.0
    floor_height_m: float = 3.0
    start_floor: int = 0
    start_height_m: float = 0.0
    step_height_sigma_m: float = PRIOR_SIGMA_M
    floor_tolerance_m: float = 0.5
    floor_height_min_m: float = 2.8
    floor_height_max_m: float = 4.5
    lobby_height_max_m: float = 6.0

    def __post_init__(self):
        check_range('ElevationParams.step_height_m', self.step_height_m, 0.10, 0.25)
        check_range('ElevationParams.step_height_sigma_m', self.step_height_sigma_m, 0.0, 0.1)
        check_range('ElevationParams.floor_tolerance_m', self.floor_tolerance_m, 0.05, 1.5)
        check_range('ElevationParams.mode_threshold', self.mode_threshold, -1.0, 1.0)
        check_finite('ElevationParams.floor_height_m', self.floor_height_m)
        check_range('ElevationParams.floor_height_m', self.floor_height_m, 2.0, math.inf)
        check_range('ElevationParams.floor_height_min_m', self.floor_height_min_m, 2.0, 20.0)
        check_range('ElevationParams.floor_height_max_m', self.floor_height_max_m,
                    self.floor_height_min_m, 20.0)
        check_range('ElevationParams.lobby_height_max_m', self.lobby_height_max_m, 0.0, 20.0)
        check_finite('ElevationParams.start_height_m', self.start_height_m)
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
    floor : int, the floor: the last one the height settled on (``core/floors.py``).
    x_m, y_m : float, horizontal position of the foot in the navigation frame n (ENU), m.
    anfis_output : float, the ANFIS output y that gave the mode (NaN for an invalid cycle).
    bridged_steps : int, steps credited to the invalid cycles just before this one.
    floor_certain : bool, whether the height is settled on the floor (False on stairs, on a
        landing between floors, off every floor).
    step_height_m : float, riser height K in use (the estimate, the file's, or the parameter), m.
    floor_range : (lowest, highest) floor the height can be on, or None when not known
        (``FloorSettler.floor_range``).

    """

    stamp_ns: int
    mode: int
    height_m: float
    floor: int
    x_m: float
    y_m: float
    anfis_output: float
    bridged_steps: int = 0
    floor_certain: bool = True
    step_height_m: float = float('nan')
    floor_range: Optional[tuple] = None


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

    The height is the start height plus whole numbers of risers per stairwell (module
    docstring), so it carries no rounding drift.

    Parameters
    ----------
    model : StairClassifier, Anfis or object with predict
        A stair classifier (``core/classifier.py``; a bare ANFIS of eq. (8)-(12) is wrapped) or
        any object whose ``predict`` maps a (1, N_FEATURES) feature array to a (1,) array.
    params : ElevationParams
        Step height (prior), mode threshold, storey height, start floor and height.
    height_m : float or None
        Height to resume from after a restart; default ``params.start_height_m``.
    building : Building or None
        The incident's building (``core/building.py``): its floors replace the uniform storeys,
        its riser height (building-wide, or the one all its stairwells give) replaces the
        estimate.

    Raises
    ------
    ValueError : a model of the wrong shape, params of the wrong type, or a start floor that is
        not one of the building's floors.

    """

    def __init__(self, model, params: ElevationParams, height_m: Optional[float] = None,
                 building=None):
        model = as_classifier(model)
        n_inputs = getattr(model, 'n_inputs', len(FEATURE_NAMES))
        if n_inputs != len(FEATURE_NAMES) or not callable(getattr(model, 'predict', None)):
            raise ValueError(f'model must have predict() and {len(FEATURE_NAMES)} inputs '
                             f'({", ".join(FEATURE_NAMES)}), got {model!r}')
        if not isinstance(params, ElevationParams):
            raise ValueError(f'params must be ElevationParams, got {type(params).__name__}')
        self.model = model
        self.params = params
        self.building = building
        self.mode_threshold = model_mode_threshold(model, params)
        self.reset(height_m)

    def reset(self, height_m: Optional[float] = None):
        """Restart from a height (m; default ``params.start_height_m``), e.g. after a restart."""
        if height_m is None:
            height_m = self.params.start_height_m
        if isinstance(height_m, bool) or not isinstance(height_m, numbers.Real) \
                or not math.isfinite(height_m):
            raise ValueError(f'height_m must be a finite number, got {height_m!r}')
        params = self.params
        self._base_height_m = float(height_m)
        self._flight_mode = MODE_LEVEL
        self._flight_abs_dh_m, self._flight_cycles, self._flight_bounds = [], [], []
        self._last_mode = MODE_LEVEL
        self._last_abs_dh_m = 0.0
        self._last_xy = None
        self._last_level = None     # (dh_m, length_m, start_xy, end_xy) of a level cycle before
        self._lost = 0
        self.risers = StairwellRiserHeights(params.step_height_m, known_riser_height_m(
            self.building), params.step_height_sigma_m)
        self.slope = LevelSlope()
        self.floors = FloorSettler(self._floor_map(params), params.floor_tolerance_m,
                                   self._base_height_m)
        self.bridged_cycles = 0
        self.unbridged_cycles = 0
        self.recovered_strides = 0
        self.level_calls_overruled = 0
        self.stair_calls_overruled = 0
        self.implausible_cycles = 0

    def resume_flight(self, last_mode: int, last_abs_dh_m: float):
        """
        Carry the last valid cycle across a restart: its stair mode and raw |dh| (m).

        The cycles lost in the outage are then bridged as if the node had never stopped
        (``core/outage.py``): a flight in progress goes on with the stride before.
        """
        if last_mode not in (MODE_DOWN, MODE_LEVEL, MODE_UP) or not (
                math.isfinite(last_abs_dh_m) and 0.0 <= last_abs_dh_m
                <= MAX_CYCLE_HEIGHT_CHANGE_M):
            raise ValueError(f'last_mode {last_mode!r} and last_abs_dh_m {last_abs_dh_m!r} do '
                             'not describe a gait cycle')
        self._last_mode = self._flight_mode = int(last_mode)
        self._last_abs_dh_m = float(last_abs_dh_m)

    @property
    def last_mode(self) -> int:
        """Return the stair mode of the last valid cycle."""
        return self._last_mode

    @property
    def last_abs_dh_m(self) -> float:
        """Return the raw |dh| of the last stair cycle, m."""
        return self._last_abs_dh_m

    def correct_height(self, height_m: float):
        """
        Set the height (a floor of the building confirmed after a doubt), m.

        h_base <- h_base + (h_new - h): the risers counted and the riser estimate are kept; the
        floor is the one nearest the new height.
        """
        if not math.isfinite(height_m):
            raise ValueError(f'height_m must be finite, got {height_m!r}')
        self._base_height_m += float(height_m) - self.height_m
        self.floors.rebase(self.floors.floor_map, self.height_m)

    def _floor_map(self, params: ElevationParams):
        return floor_map_for(self.building, params.start_floor, params.floor_height_m,
                             (params.floor_height_min_m, params.floor_height_max_m),
                             params.lobby_height_max_m)

    def set_params(self, params: ElevationParams):
        """
        Take new parameters mid-run (a live parameter change).

        The height is kept (the current flight starts again here, the new prior of K counts),
        and so are the counters, the strides of the riser estimate and the invalid cycles
        waiting to be bridged; the floor is the nearest one of the new storey height and start
        floor, certain if the height is within the tolerance of it and was settled.
        """
        if not isinstance(params, ElevationParams):
            raise ValueError(f'params must be ElevationParams, got {type(params).__name__}')
        mode_threshold = model_mode_threshold(self.model, params)
        floor_map = self._floor_map(params)
        self._base_height_m = self.height_m
        self.risers.forget_climbs()
        self._flight_abs_dh_m, self._flight_cycles, self._flight_bounds = [], [], []
        self.params = params
        self.mode_threshold = mode_threshold
        self.risers.set_prior(params.step_height_m, params.step_height_sigma_m)
        self.floors.tolerance_m = params.floor_tolerance_m
        self.floors.rebase(floor_map, self.height_m, self.floors.certain)

    @property
    def height_m(self) -> float:
        """Return the current quantised height, m (z up)."""
        return self._base_height_m + self.risers.climbed_m + self.step_height_m * \
            self._flight_risers()

    def _flight_risers(self) -> int:
        return self._flight_strides().risers(self.step_height_m) if self._flight_abs_dh_m else 0

    def _flight_strides(self) -> FlightStrides:
        """Return the open flight's strides, to count its risers at any K."""
        return FlightStrides.of_flight(self._flight_mode, self._flight_abs_dh_m,
                                       self._flight_cycles, self._flight_bounds)

    @property
    def step_height_m(self) -> float:
        """Return the riser height K in use (current stairwell's estimate, or the file's), m."""
        return self.risers.estimate_m

    @property
    def floor(self) -> int:
        """Return the current floor index (the last one the height settled on)."""
        return self.floors.floor

    @property
    def floor_certain(self) -> bool:
        """Return whether the height is settled on the floor."""
        return self.floors.certain

    @property
    def floor_range(self) -> Optional[tuple]:
        """Return the floors the height can be on, (lowest, highest), or None (FloorSettler)."""
        return self.floors.floor_range

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
            self._last_level = None
            known = math.isfinite(x_m) and math.isfinite(y_m)
            self.floors.update(self.height_m, None, (x_m, y_m) if known else None)
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
        dh_m = float(features[HEIGHT_CHANGE])
        length_m = None if self._last_xy is None or self._lost else math.hypot(
            x_m - self._last_xy[0], y_m - self._last_xy[1])
        checked = height_checked_mode(mode, dh_m, length_m, self.step_height_m,
                                      self._last_mode)
        self.stair_calls_overruled += mode != MODE_LEVEL and checked == MODE_LEVEL
        self.level_calls_overruled += mode == MODE_LEVEL and checked != MODE_LEVEL
        mode = checked
        start_xy, self._last_xy = self._last_xy, (x_m, y_m)
        bridged = self._bridge(mode)
        missed = self._missed_first_stride(mode, (x_m, y_m), self.slope.corrected(dh_m, length_m))
        if mode != self._flight_mode:
            self._end_flight(mode)
            if mode != MODE_LEVEL:
                self.risers.start_flight(missed[2] if missed else start_xy, mode, self.height_m)
                if missed:
                    self._add_stair_stride(*missed[:2], missed[3])
                    self.recovered_strides += 1
        if mode == MODE_LEVEL:
            self.slope.add_level(dh_m, length_m)
            self._last_level = (dh_m, length_m, start_xy, (x_m, y_m))
        else:
            self._add_stair_stride(dh_m, length_m, (x_m, y_m))
            self._last_level = None
        self._last_mode = mode
        self.floors.update(self.height_m, mode, (x_m, y_m))
        if self.floors.certain and self.building is not None:
            self._snap_to_floor()
        return self._estimate(stamp_ns, mode, x_m, y_m, output, bridged)

    def _missed_first_stride(self, mode: int, xy: tuple, next_dh_m: float) -> Optional[tuple]:
        """
        Return the level cycle just before a new flight if it was the flight's first stride.

        The classifier can call a flight's first stride level (a new wearer, a stride half on
        the level); the stride itself says otherwise when it climbed C dh' >= 0.5 K (dh' with
        the slope removed, :data:`MISSED_STRIDE_RISERS`) in the direction the flight goes on,
        angle(p_1 - p_0, p_2 - p_1) <= :data:`MISSED_STRIDE_MAX_TURN_DEG`, and about as much as
        the flight's next stride, 0.75 <= dh'_0 / dh'_1 <= 1.25 (:data:`MISSED_STRIDE_LIKE`). A
        level stride reads millimetres, but one turning on a landing can read decimetres
        (consumer IMU).
        """
        if mode == MODE_LEVEL or self._flight_mode != MODE_LEVEL or self._last_level is None:
            return None
        dh_m, length_m, start_xy, end_xy = self._last_level
        if start_xy is None or length_m is None:
            return None
        risen_m = mode * self.slope.corrected(dh_m, length_m)
        before = np.subtract(end_xy, start_xy)
        after = np.subtract(xy, end_xy)
        norms = float(np.linalg.norm(before) * np.linalg.norm(after))
        straight = norms > 0.0 and float(np.dot(before, after)) >= norms * math.cos(
            math.radians(MISSED_STRIDE_MAX_TURN_DEG))
        climbed = risen_m >= MISSED_STRIDE_RISERS * self.step_height_m
        alike = MISSED_STRIDE_LIKE[0] * abs(next_dh_m) <= risen_m <= \
            MISSED_STRIDE_LIKE[1] * abs(next_dh_m)
        return self._last_level if straight and climbed and alike else None

    def _add_stair_stride(self, dh_m: float, length_m: Optional[float], end_xy: tuple):
        """Add a stair stride to the open flight and its stairwell's riser estimate."""
        # The open flight's first stride starts on the floor before the stairs; after a restart
        # or a parameter change mid-flight the next stride is taken as one too (a looser bound).
        from_level = not self._flight_abs_dh_m
        if not self.risers.estimating:
            bounds = riser_count_bounds(None)       # K known: eq. 14 as the patent has it
        else:
            if riser_count_bounds(length_m)[1] <= MAX_RISERS:   # fits stairs: correct the slope
                dh_m = self.slope.corrected(dh_m, length_m)
            bounds = riser_count_bounds(length_m, from_level)
        self.risers.add(dh_m, length_m, end_xy, self.slope.stride_sigma_m, from_level)
        self._flight_abs_dh_m.append(abs(dh_m))
        self._flight_cycles.append(1)
        self._flight_bounds.append(bounds)
        self._last_abs_dh_m = abs(dh_m)

    def _snap_to_floor(self):
        """Settled on a floor of the building file: the height is that floor's elevation."""
        _, offset_m = self.floors.floor_map.nearest(self.height_m)
        if offset_m:
            self._base_height_m = self.height_m - offset_m
            self.risers.forget_climbs()     # their height is in the base now

    def _bridge(self, mode: int) -> int:
        """Credit the invalid cycles before this one (:func:`bridged_step_count`)."""
        if not self._lost:
            return 0
        lost, self._lost = self._lost, 0
        steps_before = self._last_mode * quantised_step_count(
            1, self._last_abs_dh_m, self.step_height_m)
        bridged = bridged_step_count(self._last_mode, steps_before, mode, lost)
        if bridged:             # the lost cycles climbed as the stride before
            if self._flight_abs_dh_m:
                self._flight_cycles[-1] += lost
            else:               # the flight started again at a parameter change
                self._flight_abs_dh_m.append(self._last_abs_dh_m)
                self._flight_cycles.append(lost)
                self._flight_bounds.append(riser_count_bounds(None))
            self.bridged_cycles += lost
        else:
            self.unbridged_cycles += lost
        if self._last_mode != MODE_LEVEL or mode != MODE_LEVEL:
            self.floors.forget_anchors()    # the lost cycles may have climbed, bridged or not
        return bridged

    def _end_flight(self, mode: int):
        """Hand the current flight's strides to its stairwell; start a flight of ``mode``."""
        self.risers.end_flight(self._flight_strides(), self.height_m)
        self._flight_abs_dh_m, self._flight_cycles, self._flight_bounds = [], [], []
        self._flight_mode = mode

    def _estimate(self, stamp_ns, mode, x_m, y_m, output, bridged=0) -> CycleEstimate:
        return CycleEstimate(stamp_ns=int(stamp_ns), mode=mode, height_m=self.height_m,
                             floor=self.floor, x_m=x_m, y_m=y_m, anfis_output=output,
                             bridged_steps=bridged, floor_certain=self.floor_certain,
                             step_height_m=self.step_height_m, floor_range=self.floor_range)
