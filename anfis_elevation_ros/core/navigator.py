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
The foot navigator: mechanisation, SHOE detection, ZUPT-EKF and gait cycles, per sample.

``FootNavigator.step`` is the one pipeline behind the IMU node, offline replay and training:
each call takes one IMU sample and returns the navigated sample and, on the sample that
closes one, the gait cycle with its features. After start-up a sample goes through
``navigation_step`` (S1-S3, ``core/navigation_step.py``: the equation functions of strapdown,
zupt and ekf, compiled with numba, on plain arrays that this class owns), then through
``GaitSegmenter`` (S4, Python: it works once per cycle).

Start-up: the navigator estimates the sample rate from the first stamps (unless given), then
waits for the first stance of at least ``init_stance_s`` (a firefighter may start walking at
once), takes roll and pitch from gravity, the gyro bias from the mean rate when the foot was
truly still, and the accelerometer bias along gravity from the magnitude it reads (which
must be g at rest), and starts navigating at the origin with heading 0, or at a position and
heading resumed from a saved state (``start_pos_n``, ``start_heading_rad``).

Gaps: samples missing for longer than ``max_gap_s`` are bridged by integrating the mean of the
samples on either side, over at most ``gait.max_swing_s`` (a foot is not in the air longer; a
long dropout must not throw the track kilometres away). They leave the attitude unknown (the
foot may have turned tens of degrees in a swing), and a tilt error would corrupt the height of
the cycles after it. So at the first stance after a gap roll and pitch are taken from gravity
again (the detector's mean specific force), the velocity is set to zero and their covariance
reset as at start-up (``ekf.relevelled_covariance``); position, heading and biases carry on.
"""

from collections import deque
from dataclasses import dataclass, field, replace
import math
import time

import numpy as np

from . import ekf
from .ekf import EkfParams
from .errors import InputError
from .frames import dcm_to_rpy, GRAVITY_MPS2, quat_multiply, quat_to_dcm, rpy_to_dcm
from .gait import GaitCycle, GaitParams, GaitSegmenter, MountingEstimator
from .gyro_rail import GyroRailParams, GyroRailStage
from .heading_aids import HeadingAider, HeadingAidParams
from .map_frame import MapAlignment, rotate_error_covariance
from .navigation_step import ACC_BIAS_B, ADAPTIVE, attitude_at_rest, GAPS, GRAVITY, GYR_BIAS_B
from .navigation_step import GYR_RAIL, GYR_RAIL_NOISE, LAST_NIS, MAX_DT_S, MAX_GAP_S
from .navigation_step import MIN_STANCE_SAMPLES, MISSING_SAMPLES, N_NOMINAL, navigation_step
from .navigation_step import POS_N, PREV_STAMP_NS, Q_NB, RATE_HZ, RELAXED_STANCES
from .navigation_step import STANCE_SAMPLES, STILL_SAMPLES, THRESHOLD, THRESHOLD_LAW, VEL_N
from .navigation_step import WAITING_ZUPTS, YOUNG_MAX_NIS, YOUNG_STANCE_SAMPLES, ZARU_MAX_GYR
from .navigation_step import ZARU_SAMPLES, ZARU_SIGMA, ZUPT_SIGMA
from .stride_gate import initial_state, LATE_AGE, LATE_DPOS, LATE_DVEL
from .stride_gate import samples_to_relaxed_stance, StrideGateParams
from .units import check_acc_scale, check_gyro_rate, check_rest_gravity
from .validation import check_range
from .zupt import adaptive_threshold, GaitIntensity, ShoeDetector, ZuptParams

RATE_ESTIMATE_SAMPLES = 16

GYR_RAIL_FRACTION = 0.99
"""A rate within 1 % of ``gyro_range_rps`` is at the rail (sensors stop a little short)."""


@dataclass(frozen=True)
class NavigatorParams:
    """
    Everything the navigator needs; each part is validated where it is defined.

    Attributes
    ----------
    zupt, ekf, gait : parameters of the detector, the filter and the gait segmentation.
    heading : parameters of the heading aids (HDE, ZARU), off by default.
    stride_gate : parameters of the stance detection from the gait's structure
        (``core/stride_gate.py``).
    gravity_mps2 : local gravity magnitude.
    rate_hz : nominal IMU rate; 0 estimates it from the first stamps.
    init_stance_s : stance needed before navigation starts.
    still_gyr_rps : the start-up stance gives the initial gyro bias when no rate in it
        exceeds this (the foot was still, not rolling through a step).
    max_gap_s : a larger interval between samples is a gap (the cycle it falls in is invalid).
    gyro_range_rps : the gyroscope's measurement range, rad/s (a rate at it is clipped, see
        ``ekf.clipped_gyro_noise`` and ``rail``); 0 when unknown (no clipping handled).
    rail : the saturation recovery of the clipped samples (``core/gyro_rail.py``), used only
        when ``gyro_range_rps`` is declared.
    mounting_rpy_deg : roll, pitch, yaw (deg) of the mounting C_fb, v_f = C_fb v_b (foot frame
        x forward, y left, z up), or None for automatic mode (forward axis from the first
        strides).

    """

    zupt: ZuptParams = field(default_factory=ZuptParams)
    ekf: EkfParams = field(default_factory=EkfParams)
    gait: GaitParams = field(default_factory=GaitParams)
    heading: HeadingAidParams = field(default_factory=HeadingAidParams)
    stride_gate: StrideGateParams = field(default_factory=StrideGateParams)
    rail: GyroRailParams = field(default_factory=GyroRailParams)
    gravity_mps2: float = GRAVITY_MPS2
    rate_hz: float = 0.0
    init_stance_s: float = 0.1
    still_gyr_rps: float = 0.05
    max_gap_s: float = 0.05
    gyro_range_rps: float = 0.0
    mounting_rpy_deg: tuple = None

    def __post_init__(self):
        check_range('gravity_mps2', self.gravity_mps2, 9.7, 9.9)
        if self.rate_hz != 0.0:
            check_range('rate_hz', self.rate_hz, 20.0, 2000.0, note='or 0: automatic')
        check_range('init_stance_s', self.init_stance_s, 0.02, 10.0)
        check_range('still_gyr_rps', self.still_gyr_rps, 0.0, 1.0)
        check_range('max_gap_s', self.max_gap_s, 0.005, 1.0)
        if self.gyro_range_rps != 0.0:
            check_range('gyro_range_rps', self.gyro_range_rps, 1.0, 200.0,
                        note='rad/s, or 0: unknown')
        if self.mounting_rpy_deg is not None and len(self.mounting_rpy_deg) != 3:
            raise InputError(f'mounting_rpy_deg = {self.mounting_rpy_deg} must be 3 angles')


@dataclass(frozen=True, slots=True)
class TrackPoint:
    """One navigated sample: stamp, position (m, ENU), attitude q_nb, zero-velocity flag."""

    stamp_ns: int
    pos_n: np.ndarray
    quat_nb: np.ndarray
    stance: bool


@dataclass
class NavigatorStatus:
    """
    Health figures for diagnostics (counts since start).

    ``missing_samples`` estimates the samples lost between navigated ones: round(dt * rate) - 1
    summed over the intervals longer than one period.
    """

    initialised: bool = False
    rate_hz: float = 0.0
    samples: int = 0
    rail_filled_samples: int = 0   # clipped gyro samples rebuilt (core/gyro_rail.py)
    stance_samples: int = 0
    zaru_samples: int = 0
    waiting_zupts: int = 0         # young SHOE stance samples whose implausible ZUPT waited, and
    #                                relaxed stances refused for it
    relaxed_stances: int = 0       # stances the stride gate found where SHOE saw none
    late_stances: int = 0          # stances it found after the fact (their ZUPT late)
    late_cycles: int = 0           # cycles those closed (on level ground)
    gaps: int = 0
    missing_samples: int = 0
    cycles: int = 0
    invalid_cycles: int = 0
    last_nis: float = 0.0
    pos_sigma_m: float = 0.0       # sqrt(trace of the position covariance), at the last cycle
    yaw_sigma_rad: float = 0.0     # standard deviation of the heading, at the last cycle


class FootNavigator:
    """
    ZUPT-aided strapdown navigation of a foot IMU, one sample at a time.

    With the gyro's range declared, samples first pass ``GyroRailStage``, which holds them
    while the gyro clips and releases them rebuilt (``core/gyro_rail.py``). Start-up runs here
    in Python; every sample after it goes through the compiled ``navigation_step`` (S1-S3),
    then ``GaitSegmenter`` (S4).

    Parameters
    ----------
    params : NavigatorParams
        Detector, filter, gait and start-up parameters.
    start_pos_n : (3,) array or None
        Position to start at, m (resuming a saved state); default the origin.
    start_heading_rad : float
        IMU yaw to start with, rad (resuming a saved state).
    start_sigmas : (float, float) or None
        Resuming a saved state: (sqrt of the trace of the position covariance, m; heading
        standard deviation, rad) it had; the filter starts with that uncertainty (spread evenly
        over x, y, z) instead of a known position and heading, so that the next stair-entry
        correction weighs as it would have without the restart.
    map_alignment : MapAlignment or None
        Put the track in a building's map frame (``core/map_frame.py``): positions and
        attitudes returned are map-frame ones; after the alignment strides the filter itself
        is rotated into the map frame.
    dominant_directions_deg : sequence of float or None
        Corridor directions for HDE, deg counter-clockwise from +x, in the frame of the track
        (the map frame with ``map_alignment``); None learns them from the walk.

    Examples
    --------
    >>> nav = FootNavigator(NavigatorParams())
    >>> for stamp_ns, acc_b, gyr_b in samples:            # doctest: +SKIP
    ...     for point, cycle in nav.step(stamp_ns, acc_b, gyr_b):
    ...         if cycle is not None:
    ...             print(cycle.features)

    """

    def __init__(self, params: NavigatorParams = None, start_pos_n=None,
                 start_heading_rad: float = 0.0, map_alignment: MapAlignment = None,
                 dominant_directions_deg=None, start_sigmas=None):
        self.params = params or NavigatorParams()
        self._map = map_alignment
        self._aider = HeadingAider(self.params.heading, None if dominant_directions_deg is None
                                   else np.radians(dominant_directions_deg))
        self._status = NavigatorStatus()
        # Where navigation starts: the origin, or a resumed position and heading.
        self._start_pos_n = np.zeros(3) if start_pos_n is None else np.array(start_pos_n, float)
        self._start_heading_rad = float(start_heading_rad)
        self._start_sigmas = None if start_sigmas is None else tuple(float(s)
                                                                     for s in start_sigmas)
        if self._start_sigmas is not None and (
                len(self._start_sigmas) != 2
                or not all(math.isfinite(s) and s >= 0.0 for s in self._start_sigmas)):
            raise InputError(f'start sigmas must be two finite numbers >= 0, got {start_sigmas}')
        if self._start_pos_n.shape != (3,) or not np.all(np.isfinite(self._start_pos_n)) \
                or not math.isfinite(self._start_heading_rad):
            raise InputError('start position must be 3 finite numbers and heading finite')
        self._pending = deque(maxlen=RATE_ESTIMATE_SAMPLES)
        p = self.params
        self._rail = GyroRailStage(p.rail.range_fraction * p.gyro_range_rps, p.rail) \
            if p.gyro_range_rps > 0.0 and p.rail.enabled else None
        self._detector = None
        self._rest = None
        self._kernel_args = None
        self._zupt_dx = np.zeros(6)    # this sample's ZUPT correction: position, velocity

    # -- start-up ------------------------------------------------------------------------------

    def _start_detector(self, rate_hz):
        p = self.params
        self._status.rate_hz = rate_hz
        self._detector = ShoeDetector(p.zupt, rate_hz, p.gravity_mps2)
        self._intensity = GaitIntensity(p.zupt, rate_hz)
        self._scalars = np.zeros(THRESHOLD_LAW.stop)
        self._scalars[THRESHOLD_LAW] = p.zupt.threshold_law()
        self._scalars[[GRAVITY, RATE_HZ, MAX_GAP_S, MAX_DT_S, ZUPT_SIGMA, ADAPTIVE, GYR_RAIL,
                       GYR_RAIL_NOISE, ZARU_MAX_GYR, ZARU_SIGMA, YOUNG_MAX_NIS]] = (
            p.gravity_mps2, rate_hz, p.max_gap_s, p.gait.max_swing_s, p.ekf.zupt_sigma_mps,
            float(p.zupt.adaptive), GYR_RAIL_FRACTION * p.gyro_range_rps,
            p.ekf.gyr_rail_noise_rps,
            p.heading.zaru_max_gyr_rps if p.heading.zaru_enabled else 0.0,
            p.heading.zaru_sigma_rps, p.zupt.young_stance_max_nis)
        self._scalars[THRESHOLD] = self._current_threshold()
        self._counts = np.zeros(RELAXED_STANCES + 1, dtype=np.int64)
        self._counts[MIN_STANCE_SAMPLES] = p.zupt.min_stance_samples(rate_hz)
        self._counts[YOUNG_STANCE_SAMPLES] = p.zupt.young_stance_samples(rate_hz)
        init_samples = int(round(p.init_stance_s * rate_hz))
        self._rest = deque(maxlen=max(self._detector.window, RATE_ESTIMATE_SAMPLES, init_samples))

    def _initialise(self):
        p = self.params
        rest = np.array([(a, g) for _, a, g in self._rest])
        check_rest_gravity(rest[:, 0])
        acc_mean = rest[:, 0].mean(axis=0)
        rest_g = float(np.linalg.norm(acc_mean))
        still = np.max(np.abs(rest[:, 1])) <= p.still_gyr_rps
        self._nominal = np.zeros(N_NOMINAL)
        self._nominal[Q_NB] = attitude_at_rest(acc_mean, self._start_heading_rad)
        self._nominal[POS_N] = self._start_pos_n
        self._nominal[ACC_BIAS_B] = (rest_g - p.gravity_mps2) * acc_mean / rest_g
        self._nominal[GYR_BIAS_B] = rest[:, 1].mean(axis=0) if still else 0.0
        self._detector.gravity_mps2 = rest_g
        self._P = ekf.initial_covariance(p.ekf)
        if self._start_sigmas is not None:
            pos_sigma_m, yaw_sigma_rad = self._start_sigmas
            yaw = ekf.ATT.start + 2
            self._P[ekf.POS, ekf.POS] += np.eye(3) * pos_sigma_m ** 2 / 3.0
            self._P[yaw, yaw] = max(self._P[yaw, yaw], yaw_sigma_rad ** 2)
        self._C_nb = quat_to_dcm(self._nominal[Q_NB])
        stamp_ns, acc_b, gyr_b = self._rest[-1]
        self._counts[PREV_STAMP_NS] = stamp_ns
        self._prev_sample = np.concatenate((acc_b, gyr_b))
        d, i = self._detector, self._intensity
        self._gate_state = initial_state()
        self._gate_config = p.stride_gate.config(self._status.rate_hz)
        self._kernel_args = (
            self._nominal, self._P, np.eye(ekf.N_STATES), ekf.process_noise(p.ekf, 1.0),
            ekf.initial_covariance(p.ekf), self._prev_sample, self._C_nb, self._zupt_dx,
            self._counts, self._scalars, d.samples, d.sums, d.count, d.config, i.peaks, i.state,
            i.counts, self._gate_state, self._gate_config)
        C_fb = None if p.mounting_rpy_deg is None else rpy_to_dcm(*np.radians(p.mounting_rpy_deg))
        self._gait = GaitSegmenter(p.gait, self._status.rate_hz, MountingEstimator(p.gait, C_fb))
        self._gait.update(stamp_ns, True, self._nominal[POS_N].copy(), self._C_nb.copy(),
                          acc_b, gyr_b, self._nominal[VEL_N])
        if self._map is not None:
            self._map.start(self._nominal[POS_N])
        self._status.initialised = True

    def _step_uninitialised(self, stamp_ns, acc_b, gyr_b):
        if self._detector is None:
            self._pending.append((stamp_ns, acc_b, gyr_b))
            if self.params.rate_hz > 0.0:
                rate_hz = self.params.rate_hz
            elif len(self._pending) == RATE_ESTIMATE_SAMPLES:
                stamps = np.array([s for s, _, _ in self._pending], dtype=np.int64)
                rate_hz = 1e9 / float(np.median(np.diff(stamps)))
            else:
                return
            if not 20.0 <= rate_hz <= 2000.0:
                self._pending.clear()
                raise InputError(f'IMU rate {rate_hz:.1f} Hz is outside [20, 2000] Hz')
            try:
                check_acc_scale(np.array([a for _, a, _ in self._pending]))
            except InputError:
                self._pending.clear()
                raise
            self._start_detector(rate_hz)
            pending = list(self._pending)
            self._pending.clear()
        else:
            pending = [(stamp_ns, acc_b, gyr_b)]
        for sample in pending:
            statistic = self._detector.update(sample[1], sample[2])
            self._update_threshold(sample[2])
            if statistic is None or statistic >= self._scalars[THRESHOLD]:
                self._rest.clear()
                continue
            self._rest.append(sample)
            if len(self._rest) == self._rest.maxlen:
                try:
                    self._initialise()
                except InputError:
                    self._rest.clear()
                    raise
                return

    def _update_threshold(self, gyr_b):
        if self.params.zupt.adaptive and self._intensity.update(math.sqrt(gyr_b.dot(gyr_b))):
            self._scalars[THRESHOLD] = self._current_threshold()

    def _current_threshold(self):
        zupt = self.params.zupt
        return adaptive_threshold(self._intensity.value, *zupt.threshold_law()) \
            if zupt.adaptive else zupt.threshold

    # -- navigation ----------------------------------------------------------------------------

    def step(self, stamp_ns: int, acc_b: np.ndarray, gyr_b: np.ndarray) -> list:
        """
        Process one IMU sample.

        Parameters
        ----------
        stamp_ns : int
            Sample stamp, ns, later than the previous sample's.
        acc_b : (3,) array
            Specific force, m/s^2.
        gyr_b : (3,) array
            Angular rate, rad/s.

        Returns
        -------
        list of (TrackPoint, GaitCycle or None)
            One per sample navigated now, in order: this sample's alone, none while starting
            up or while clipped gyro samples are held, and the held ones with this one when
            they are released (``core/gyro_rail.py``).

        Raises
        ------
        InputError : data in the wrong units (found at start-up) or a rate out of range.

        """
        # One memory layout and type, so the compiled step never needs another compilation.
        stamp_ns = int(stamp_ns)
        acc_b = np.ascontiguousarray(acc_b, dtype=np.float64)
        gyr_b = np.ascontiguousarray(gyr_b, dtype=np.float64)
        if self._rail is None:
            out = self._step_sample(stamp_ns, acc_b, gyr_b, gyr_b)
            return [] if out is None else [out]
        return self._navigate(self._rail.push(stamp_ns, acc_b, gyr_b))

    def flush(self) -> list:
        """Navigate the samples held now as they came (at the end of a record); as ``step``."""
        return [] if self._rail is None else self._navigate(self._rail.flush())

    def _navigate(self, samples) -> list:
        outputs = []
        for sample in samples:
            out = self._step_sample(*sample)
            if out is not None:
                outputs.append(out)
        return outputs

    def _step_sample(self, stamp_ns, acc_b, gyr_b, sensor_gyr_b):
        """
        Navigate one sample: None while starting up, else (TrackPoint, GaitCycle or None).

        ``gyr_b`` is integrated; the stance detector sees ``sensor_gyr_b``, the rate as the
        sensor gave it (they differ where clipped samples were rebuilt).
        """
        status = self._status
        status.samples += 1
        if not status.initialised:
            self._step_uninitialised(stamp_ns, acc_b, sensor_gyr_b)
            if not status.initialised:
                return None
            return self._map_point(TrackPoint(stamp_ns, self._nominal[POS_N].copy(),
                                              self._nominal[Q_NB].copy(), True)), None
        flags = navigation_step(stamp_ns, acc_b, gyr_b, sensor_gyr_b, *self._kernel_args)
        stance = flags & 1 == 1
        pos_n = self._nominal[POS_N].copy()
        # S4, eq. (8)-(12): gait cycles from the corrected track, cut at the gait stances.
        cycle = self._gait.update(stamp_ns, flags & 4 == 4, pos_n, self._C_nb.copy(), acc_b, gyr_b,
                                  self._nominal[VEL_N], flags & 2 == 2, self._zupt_dx)
        late_cycle = None
        if flags & 8 == 8:
            # A stance the gate found after the fact: its late ZUPT reaches the cycle's samples,
            # and on level ground it closes the cycle there.
            gate = self._gate_state
            late_cycle = self._gait.late_stance(int(gate[LATE_AGE]), gate[LATE_DPOS],
                                                gate[LATE_DVEL],
                                                self.params.stride_gate.late_max_slope)
            status.late_stances += 1
            status.late_cycles += late_cycle is not None
            cycle = cycle if late_cycle is None else late_cycle
        if cycle is not None:
            status.cycles += 1
            status.invalid_cycles += not cycle.valid
            status.pos_sigma_m = math.sqrt(max(0.0, np.trace(self._P[ekf.POS, ekf.POS])))
            status.yaw_sigma_rad = math.sqrt(max(0.0, self._P[ekf.ATT.start + 2,
                                                              ekf.ATT.start + 2]))
            if self._map is not None and not self._map.fixed:
                cycle = self._align_map(cycle)
            elif late_cycle is None:
                # The aids measure at a stance, which a late one no longer is.
                self._aid_heading()
        # The nominal state, not pos_n: the filter may have been rotated into the map frame.
        return self._map_point(TrackPoint(stamp_ns, self._nominal[POS_N].copy(),
                                          self._nominal[Q_NB].copy(), stance)), cycle

    # -- building aids -------------------------------------------------------------------------

    def _map_point(self, point: TrackPoint) -> TrackPoint:
        """Return the sample in the map frame while the filter is not in it yet."""
        if self._map is None or self._map.fixed:
            return point
        return TrackPoint(point.stamp_ns, self._map.to_map(point.pos_n),
                          quat_multiply(self._map_quat(), point.quat_nb), point.stance)

    def _map_quat(self) -> np.ndarray:
        half = 0.5 * self._map.psi_rad
        return np.array([math.cos(half), 0.0, 0.0, math.sin(half)])

    def _align_map(self, cycle: GaitCycle) -> GaitCycle:
        """Add a stride to the map alignment; rotate the filter into the map frame once fixed."""
        if cycle.valid and self._map.add_stride(cycle.pos_n):
            # In place: the compiled step holds these arrays.
            nominal, R = self._nominal, self._map.rotation()
            nominal[POS_N] = self._map.to_map(nominal[POS_N])
            nominal[VEL_N] = R @ nominal[VEL_N]
            nominal[Q_NB] = quat_multiply(self._map_quat(), nominal[Q_NB])
            self._P[:, :] = rotate_error_covariance(self._P, self._map.psi_rad)
            self._C_nb[:, :] = quat_to_dcm(nominal[Q_NB])
        # The cycle's own position: a late stance's cycle closed samples before this one.
        return replace(cycle, pos_n=self._map.to_map(cycle.pos_n))

    def _aid_heading(self):
        """Apply the heading aids that hold at this stance (``core/heading_aids.py``)."""
        nominal = self._nominal
        for dx, P in self._aider.at_stance(nominal[POS_N], self._P):
            self._apply_correction(dx, P)

    def _apply_correction(self, dx, P):
        """Take an EKF update's covariance and feed its error state into the nominal state."""
        nominal = self._nominal
        self._P[:, :] = P
        (nominal[Q_NB], nominal[VEL_N], nominal[POS_N], nominal[ACC_BIAS_B],
         nominal[GYR_BIAS_B]) = ekf.apply_correction(
            nominal[Q_NB].copy(), nominal[VEL_N].copy(), nominal[POS_N].copy(),
            nominal[ACC_BIAS_B].copy(), nominal[GYR_BIAS_B].copy(), dx)
        self._C_nb[:, :] = quat_to_dcm(nominal[Q_NB])

    def correct_position(self, innovation_xy, sigma_m: float) -> float:
        """
        Apply a horizontal position measurement now (a stair entry, ``ekf.position_correction``).

        Parameters
        ----------
        innovation_xy : (2,) array
            P_database - P_xy, map frame, m.
        sigma_m : float
            Its standard deviation, m.

        Returns
        -------
        The normalised innovation squared.

        """
        innovation = np.asarray(innovation_xy, dtype=float)
        if self._map is not None and not self._map.fixed:
            innovation = self._map.rotation()[:2, :2].T @ innovation
        dx, P, nis = ekf.position_correction(self._P, innovation, sigma_m)
        self._apply_correction(dx, P)
        return nis

    @property
    def initialised(self) -> bool:
        """Return True once start-up is done (the first stance was found)."""
        return self._status.initialised

    @property
    def status(self) -> NavigatorStatus:
        """Return a snapshot of the health figures."""
        status = replace(self._status)
        if status.initialised:
            counts = self._counts
            status.gaps = int(counts[GAPS])
            status.missing_samples = int(counts[MISSING_SAMPLES])
            status.stance_samples = int(counts[STANCE_SAMPLES])
            status.zaru_samples = int(counts[ZARU_SAMPLES])
            status.waiting_zupts = int(counts[WAITING_ZUPTS])
            status.relaxed_stances = int(counts[RELAXED_STANCES])
            status.last_nis = float(self._scalars[LAST_NIS])
        if self._rail is not None:
            status.rail_filled_samples = self._rail.filled_samples
        return status

    @property
    def samples_to_stance(self):
        """
        Return the samples still needed for a stance to count (None unless the foot is still).

        After c still samples, c < ``min_stance_samples``, the (min_stance_samples - c)-th
        sample from now is the first stance sample if the foot stays still, and it closes the
        gait cycle after a swing; a relaxed stance of the stride gate is due when its minimum
        is confirmed (``samples_to_relaxed_stance``). The IMU node wakes its input thread when
        that sample is due instead of a whole batch period later.
        """
        if not self._status.initialised:
            return None
        still, needed = self._counts[STILL_SAMPLES], self._counts[MIN_STANCE_SAMPLES]
        relaxed = samples_to_relaxed_stance(self._gate_state, self._gate_config,
                                            self._scalars[THRESHOLD])
        due = [n for n in (needed - still if 0 < still < needed else -1, relaxed) if n > 0]
        return int(min(due)) if due else None

    @property
    def gyro_bias_b(self) -> np.ndarray:
        """Return the estimated gyro bias, rad/s, body frame; zeros before start-up."""
        if not self._status.initialised:
            return np.zeros(3)
        return self._nominal[GYR_BIAS_B].copy()

    @property
    def heading_rad(self) -> float:
        """Return the yaw of the IMU (ZYX Euler), rad; 0 before start-up."""
        if not self._status.initialised:
            return 0.0
        yaw = float(dcm_to_rpy(self._C_nb)[2])
        if self._map is not None and not self._map.fixed:
            yaw = math.remainder(yaw + self._map.psi_rad, 2.0 * math.pi)
        return yaw

    def run(self, stamp_ns: np.ndarray, acc_b: np.ndarray, gyr_b: np.ndarray):
        """
        Batch form: a loop of ``step`` over arrays, then ``flush``.

        Returns (list of TrackPoint, list of GaitCycle).
        """
        check_gyro_rate(gyr_b)
        acc_b = np.ascontiguousarray(acc_b, dtype=np.float64)
        gyr_b = np.ascontiguousarray(gyr_b, dtype=np.float64)
        outputs = []
        for k in range(len(stamp_ns)):
            outputs += self.step(int(stamp_ns[k]), acc_b[k], gyr_b[k])
        outputs += self.flush()
        return [point for point, _ in outputs], [c for _, c in outputs if c is not None]


def compile_navigator() -> float:
    """
    Compile the navigator's numba code now, or load it from the cache; return the seconds taken.

    The first run on a machine compiles (about 20 s), later ones load the cache (well under a
    second). A live node calls this before it subscribes, so no IMU message waits for it.
    """
    start = time.monotonic()
    rate_hz = 200.0
    n = int(rate_hz)                       # 1 s at rest: start-up, then the compiled step
    acc_b = np.zeros((n, 3))
    acc_b[:, 2] = GRAVITY_MPS2
    FootNavigator(NavigatorParams(rate_hz=rate_hz)).run(
        np.arange(n, dtype=np.int64) * int(1e9 / rate_hz), acc_b, np.zeros((n, 3)))
    return time.monotonic() - start


__all__ = ['attitude_at_rest', 'compile_navigator', 'FootNavigator', 'GaitCycle',
           'navigation_step', 'NavigatorParams', 'NavigatorStatus', 'TrackPoint']
