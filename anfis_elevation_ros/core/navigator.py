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
closes one, the gait cycle with its features.

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
from dataclasses import dataclass, field
import math

import numpy as np

from . import ekf
from .ekf import EkfParams
from .errors import InputError
from .frames import dcm_to_quat, dcm_to_rpy, GRAVITY_MPS2, level_attitude_from_gravity
from .frames import quat_to_dcm
from .frames import rpy_to_dcm
from .gait import GaitCycle, GaitParams, GaitSegmenter, MountingEstimator
from .strapdown import strapdown_step
from .units import check_acc_scale, check_gyro_rate, check_rest_gravity
from .zupt import adaptive_threshold, GaitIntensity, ShoeDetector, ZuptParams

RATE_ESTIMATE_SAMPLES = 16


@dataclass(frozen=True)
class NavigatorParams:
    """
    Everything the navigator needs; each part is validated where it is defined.

    Attributes
    ----------
    zupt, ekf, gait : parameters of the detector, the filter and the gait segmentation.
    gravity_mps2 : local gravity magnitude.
    rate_hz : nominal IMU rate; 0 estimates it from the first stamps.
    init_stance_s : stance needed before navigation starts.
    still_gyr_rps : the start-up stance gives the initial gyro bias when no rate in it
        exceeds this (the foot was still, not rolling through a step).
    max_gap_s : a larger interval between samples is a gap (the cycle it falls in is invalid).
    mounting_rpy_deg : roll, pitch, yaw (deg) of the mounting C_fb, v_f = C_fb v_b (foot frame
        x forward, y left, z up), or None for automatic mode (forward axis from the first
        strides).

    """

    zupt: ZuptParams = field(default_factory=ZuptParams)
    ekf: EkfParams = field(default_factory=EkfParams)
    gait: GaitParams = field(default_factory=GaitParams)
    gravity_mps2: float = GRAVITY_MPS2
    rate_hz: float = 0.0
    init_stance_s: float = 0.1
    still_gyr_rps: float = 0.05
    max_gap_s: float = 0.05
    mounting_rpy_deg: tuple = None

    def __post_init__(self):
        if not 9.7 <= self.gravity_mps2 <= 9.9:
            raise InputError(f'gravity_mps2 = {self.gravity_mps2} is outside [9.7, 9.9]')
        if self.rate_hz != 0.0 and not 20.0 <= self.rate_hz <= 2000.0:
            raise InputError(f'rate_hz = {self.rate_hz} must be 0 (auto) or in [20, 2000]')
        if not 0.02 <= self.init_stance_s <= 10.0:
            raise InputError(f'init_stance_s = {self.init_stance_s} is outside [0.02, 10]')
        if not 0.0 <= self.still_gyr_rps <= 1.0:
            raise InputError(f'still_gyr_rps = {self.still_gyr_rps} is outside [0, 1]')
        if not 0.005 <= self.max_gap_s <= 1.0:
            raise InputError(f'max_gap_s = {self.max_gap_s} is outside [0.005, 1]')
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
    stance_samples: int = 0
    gaps: int = 0
    missing_samples: int = 0
    cycles: int = 0
    invalid_cycles: int = 0
    last_nis: float = 0.0
    pos_sigma_m: float = 0.0


class FootNavigator:
    """
    ZUPT-aided strapdown navigation of a foot IMU, one sample at a time.

    Parameters
    ----------
    params : NavigatorParams
        Detector, filter, gait and start-up parameters.
    start_pos_n : (3,) array or None
        Position to start at, m (resuming a saved state); default the origin.
    start_heading_rad : float
        IMU yaw to start with, rad (resuming a saved state).

    Examples
    --------
    >>> nav = FootNavigator(NavigatorParams())
    >>> for stamp_ns, acc_b, gyr_b in samples:            # doctest: +SKIP
    ...     out = nav.step(stamp_ns, acc_b, gyr_b)
    ...     if out is not None and out[1] is not None:
    ...         print(out[1].features)

    """

    def __init__(self, params: NavigatorParams = None, start_pos_n=None,
                 start_heading_rad: float = 0.0):
        self.params = params or NavigatorParams()
        self.status = NavigatorStatus()
        # Where navigation starts: the origin, or a resumed position and heading.
        self._start_pos_n = np.zeros(3) if start_pos_n is None else np.array(start_pos_n, float)
        self._start_heading_rad = float(start_heading_rad)
        if self._start_pos_n.shape != (3,) or not np.all(np.isfinite(self._start_pos_n)) \
                or not math.isfinite(self._start_heading_rad):
            raise InputError('start position must be 3 finite numbers and heading finite')
        self._pending = deque(maxlen=RATE_ESTIMATE_SAMPLES)
        self._detector = None
        self._rest = None
        self._prev = None

    # -- start-up ------------------------------------------------------------------------------

    def _start_detector(self, rate_hz):
        p = self.params
        self.status.rate_hz = rate_hz
        self._detector = ShoeDetector(p.zupt, rate_hz, p.gravity_mps2)
        self._intensity = GaitIntensity(p.zupt, rate_hz)
        self._threshold = self._current_threshold()
        self._min_stance = p.zupt.min_stance_samples(rate_hz)
        self._still_samples = 0
        init_samples = int(round(p.init_stance_s * rate_hz))
        self._rest = deque(maxlen=max(self._detector.window, RATE_ESTIMATE_SAMPLES, init_samples))

    def _initialise(self):
        p = self.params
        rest = np.array([(a, g) for _, a, g in self._rest])
        check_rest_gravity(rest[:, 0])
        acc_mean = rest[:, 0].mean(axis=0)
        rest_g = float(np.linalg.norm(acc_mean))
        C_nb = level_attitude_from_gravity(acc_mean)
        C_nb = rpy_to_dcm(0.0, 0.0, self._start_heading_rad - dcm_to_rpy(C_nb)[2]) @ C_nb
        still = np.max(np.abs(rest[:, 1])) <= p.still_gyr_rps
        self._q = dcm_to_quat(C_nb)
        self._vel = np.zeros(3)
        self._pos = self._start_pos_n.copy()
        self._acc_bias = (rest_g - p.gravity_mps2) * acc_mean / rest_g
        self._detector.gravity_mps2 = rest_g
        self._gyr_bias = rest[:, 1].mean(axis=0) if still else np.zeros(3)
        self._P = ekf.initial_covariance(p.ekf)
        self._relevel = False
        self._phi = np.eye(ekf.N_STATES)
        self._Q_per_s = ekf.process_noise(p.ekf, 1.0)
        C_fb = None if p.mounting_rpy_deg is None else rpy_to_dcm(*np.radians(p.mounting_rpy_deg))
        self._gait = GaitSegmenter(p.gait, self.status.rate_hz, MountingEstimator(p.gait, C_fb))
        self._gait.update(self._rest[-1][0], True, self._pos, C_nb)
        self.status.initialised = True

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
            if statistic is None or statistic >= self._threshold:
                self._rest.clear()
                continue
            self._rest.append(sample)
            if len(self._rest) == self._rest.maxlen:
                try:
                    self._initialise()
                except InputError:
                    self._rest.clear()
                    raise
                self._prev = sample
                return

    # -- navigation ----------------------------------------------------------------------------

    def step(self, stamp_ns: int, acc_b: np.ndarray, gyr_b: np.ndarray):
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
        None while starting up, else (TrackPoint, GaitCycle or None).

        Raises
        ------
        InputError : data in the wrong units (found at start-up) or a rate out of range.

        """
        self.status.samples += 1
        if not self.status.initialised:
            self._step_uninitialised(stamp_ns, acc_b, gyr_b)
            if not self.status.initialised:
                return None
            return self._track_point(stamp_ns, True), None
        p = self.params
        prev_stamp_ns, prev_acc_b, prev_gyr_b = self._prev
        self._prev = (stamp_ns, acc_b, gyr_b)
        dt_s = (stamp_ns - prev_stamp_ns) * 1e-9
        gap = dt_s > p.max_gap_s
        if gap:
            self.status.gaps += 1
            self._relevel = True
        self.status.missing_samples += max(0, round(dt_s * self.status.rate_hz) - 1)
        dt_s = min(dt_s, p.gait.max_swing_s)

        # S1, eq. (1)-(3): bias-corrected interval means, trapezoidal integration.
        acc_mid = 0.5 * (acc_b + prev_acc_b) - self._acc_bias
        gyr_mid = 0.5 * (gyr_b + prev_gyr_b) - self._gyr_bias
        self._q, vel_new, self._pos, C_mid = strapdown_step(
            self._q, self._vel, self._pos, acc_mid, gyr_mid, dt_s, p.gravity_mps2)
        self._vel = vel_new

        # S3, eq. (5)-(6): covariance prediction.
        phi = ekf.error_transition_matrix(C_mid, C_mid.dot(acc_mid), dt_s, self._phi)
        self._P = ekf.predict_covariance(self._P, phi, self._Q_per_s * dt_s)

        # S2, eq. (4): zero-velocity decision; S3, eq. (7): ZUPT in every stance sample.
        still = self._detector.update(acc_b, gyr_b) < self._threshold
        self._still_samples = self._still_samples + 1 if still else 0
        stance = self._still_samples >= self._min_stance
        self._update_threshold(gyr_b)
        if stance:
            self.status.stance_samples += 1
            if self._relevel:
                self._relevel_at_rest()
            dx, self._P, self.status.last_nis = ekf.zupt_correction(
                self._P, self._vel, p.ekf.zupt_sigma_mps)
            self._q, self._vel, self._pos, self._acc_bias, self._gyr_bias = ekf.apply_correction(
                self._q, self._vel, self._pos, self._acc_bias, self._gyr_bias, dx)

        # S4, eq. (8)-(12): gait cycles from the corrected track.
        cycle = self._gait.update(stamp_ns, stance, self._pos, quat_to_dcm(self._q), gap)
        if cycle is not None:
            self.status.cycles += 1
            self.status.invalid_cycles += not cycle.valid
            self.status.pos_sigma_m = math.sqrt(max(0.0, np.trace(self._P[ekf.POS, ekf.POS])))
        return self._track_point(stamp_ns, stance), cycle

    def _relevel_at_rest(self):
        """Roll and pitch from gravity, zero velocity, at the first stance after a gap."""
        yaw = dcm_to_rpy(quat_to_dcm(self._q))[2]
        C_nb = level_attitude_from_gravity(self._detector.mean_acc() - self._acc_bias)
        C_nb = rpy_to_dcm(0.0, 0.0, yaw - dcm_to_rpy(C_nb)[2]) @ C_nb
        self._q = dcm_to_quat(C_nb)
        self._vel = np.zeros(3)
        self._P = ekf.relevelled_covariance(self._P, self.params.ekf)
        self._relevel = False

    def _update_threshold(self, gyr_b):
        if self.params.zupt.adaptive and self._intensity.update(math.sqrt(gyr_b.dot(gyr_b))):
            self._threshold = self._current_threshold()

    @property
    def heading_rad(self) -> float:
        """Return the yaw of the IMU (ZYX Euler), rad; 0 before start-up."""
        return float(dcm_to_rpy(quat_to_dcm(self._q))[2]) if self.status.initialised else 0.0

    def _current_threshold(self):
        zupt = self.params.zupt
        return adaptive_threshold(self._intensity.value, zupt) if zupt.adaptive \
            else zupt.threshold

    def _track_point(self, stamp_ns, stance):
        return TrackPoint(stamp_ns, self._pos.copy(), self._q.copy(), stance)

    def run(self, stamp_ns: np.ndarray, acc_b: np.ndarray, gyr_b: np.ndarray):
        """Batch form: a loop of ``step`` over arrays; returns (list of TrackPoint, cycles)."""
        check_gyro_rate(gyr_b)
        track, cycles = [], []
        for k in range(len(stamp_ns)):
            out = self.step(int(stamp_ns[k]), acc_b[k], gyr_b[k])
            if out is None:
                continue
            track.append(out[0])
            if out[1] is not None:
                cycles.append(out[1])
        return track, cycles


__all__ = ['FootNavigator', 'GaitCycle', 'NavigatorParams', 'NavigatorStatus', 'TrackPoint']
