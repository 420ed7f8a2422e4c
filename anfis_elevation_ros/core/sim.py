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
Foot-mounted IMU simulator: a walk plan, its true foot trajectory and the IMU readings.

A walk is a sequence of ``Segment`` s (level walking, stair flights, turns on the spot, standing).
Each stride of the instrumented foot is a swing followed by a stance (foot flat and still). During
the swing every coordinate -- horizontal progress, height, roll, pitch, yaw -- follows a C2
chain of quintic pieces between knots that fix the value and its first two derivatives
(``knot_profile``), so position, velocity, acceleration, attitude and Euler rates are analytic
and the ideal IMU readings are exact samples of

    f_b = C_bn (a_n - g_n),  g_n = [0, 0, -g]          (specific force, REP 145 sign)
    w_b = C_bf E(roll, pitch) [roll', pitch', yaw']     (rate of b w.r.t. n, in b)

with ``C_nb = C_nf C_fb``: ``C_nf`` is the foot attitude and ``C_fb`` the fixed IMU mounting
(``v_f = C_fb v_b``). Frames: navigation ENU with z up and its origin at the IMU's first sample;
foot x forward (toe), y left, z up. The IMU sits at the foot reference point (no lever arm).

Sign of foot pitch: REP 103 pitch is a right-handed rotation about the foot's y (left) axis, so
a positive pitch puts the toe *down*. The gait parameters are given as the foot's *elevation*
(toe up positive, the clinical and aviation sign): ``pitch = -elevation``.

A real foot is never still while it moves: it rotates through the whole swing and lands with
an impact (on the MaD stair recordings [5], 72 swings of both feet, the least |w| between 15 and
85 % of a swing has a median of 1 rad/s, the pitch rate peaks at 5-8 rad/s and the impacts
reach the 16 g range of the sensor). A swing in which the foot travels fast without
rotating and with |f| = g cannot be told from a stance by any inertial zero-velocity detector,
so the swing is built never to have one:

- no knot makes the foot dwell: where the elevation turns (toe-off, mid-swing, landing) its
  rate passes through zero with a nonzero angular acceleration, and everywhere else a knot
  keeps the slope of its neighbours (``_knots``);
- the foot rolls (inversion / eversion, ``swing_roll_rps``) in quadrature with the pitch: the
  roll crosses zero at its fastest, ``swing_roll_rps`` (0.8-1.6 rad/s), just where the pitch
  turns, so |w| stays near 0.8 rad/s or above through the swing;
- touch-down: the sole meets the ground moving forward and down (``*_touchdown_mps``,
  ``*_sink_mps``) and stops under a triangular deceleration pulse lasting 2 ``impact_s``
  (a 2-6 g spike), then rolls flat over the heel or toe in ``foot_flat_s`` and stops abruptly.

Gait shape (one stride, u_c the contact time as a fraction of the swing, about 0.8):
- level: heel off and toe off to elevation -30..-50 deg at 0.42 u_c, dorsiflexion through the
  swing (peak pitch rate 5-8 rad/s) to +10..+20 deg at heel strike, foot flat.
- stairs up: rise above the target tread first, then move over it; toe-off -12..-25 deg, toe up
  +6..+16 deg in mid-swing, forefoot first (-3..-8 deg); peak pitch rate 2-5 rad/s.
- stairs down: move over the nose first, then drop; toe-off -8..-20 deg, toe up +4..+12 deg,
  toe first (-6..-16 deg). On stairs a step-to stride (one step) rolls the foot 30 % less.
The foot is rigid: while it is pitched the IMU is also raised by ``toe * sin(-elevation)`` (toe
down) or ``heel * sin(elevation)`` (toe up), the rise of rolling over the toe at heel-off and
over the heel at heel strike, so the sole does not pass through the floor or the stair noses.
Per-stride values are drawn uniformly from the ``GaitParams`` ranges through an explicit
``np.random.Generator``.

IMU errors (``ImuErrorModel``): misalignment and scale factor, turn-on bias, bias random walk,
white noise, saturation and quantisation, applied in that order by ``apply_imu_errors``.

Public API: ``Segment``, ``GaitParams``, ``ImuErrorModel``, ``IMU_PRESETS``, ``imu_error_model``,
``StrideTruth``, ``SimulatedWalk``, ``simulate_walk``, ``apply_imu_errors``, ``building_walk``,
``random_walk``, ``sample_walk``, ``nominal_duration_s``, ``EPOCH_NS``.

References
----------
[1] T. Flash and N. Hogan, "The coordination of arm movements: an experimentally confirmed
    mathematical model", J. Neuroscience 5(7), 1985 (minimum-jerk profile).
[2] InvenSense, MPU-9250 Product Specification PS-MPU-9250A-01 rev. 1.0, 2014, tables 1-2.
[3] IEEE Std 952-1997, gyro noise terms (angle random walk, rate random walk).
[4] P. D. Groves, Principles of GNSS, Inertial, and Multisensor Integrated Navigation Systems,
    2nd ed., Artech House, 2013, ch. 4 (IMU error models).
[5] N. Roth et al., MaD stair ambulation dataset, Sensors 21(19):6559, 2021 (foot IMUs on
    stairs; subject 11 is in the project's shared data, mad_stairs/).
[6] F. N. Fritsch and R. E. Carlson, "Monotone piecewise cubic interpolation", SIAM J. Numer.
    Anal. 17(2), 1980 (the harmonic-mean knot slopes).

"""

from dataclasses import dataclass, fields
import math

import numpy as np

from .errors import InputError
from .frames import GRAVITY_MPS2, rpy_to_dcm
from .imu_data import ImuRecording

EPOCH_NS = 1_700_000_000_000_000_000  # stamp of the first sample, ns (2023-11-14T22:13:20Z)
DEFAULT_INITIAL_STAND_S = 3.0  # at rest before the first stride: the navigator levels itself
DEFAULT_FINAL_STAND_S = 2.0
MIN_INITIAL_STAND_S = 2.0
SEGMENT_KINDS = ('level', 'stairs', 'turn', 'stand')
DEG = math.pi / 180.0
_G0 = 9.80665  # for units given in g (mg, ug), independent of the simulated gravity


def _check_range(name: str, value, low, high, allowed: str | None = None):
    """Raise InputError naming the parameter unless low <= value <= high."""
    if not (low <= value <= high):
        raise InputError(f'{name}={value} is out of range; allowed: '
                         f'{allowed or f"{low} <= {name} <= {high}"}')


# ----------------------------------------------------------------------------------------------
# Walk description
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Segment:
    """
    One part of a walk; build it with ``Segment.level/stairs/turn/stand``.

    Attributes
    ----------
    kind : 'level' (walking strides), 'stairs' (one flight), 'turn' (on the spot) or 'stand'.
    n_strides : level: number of strides of the instrumented foot.
    n_steps : stairs: number of steps in the flight.
    direction : stairs: +1 up, -1 down.
    steps_per_stride : stairs: steps the instrumented foot climbs per stride, 1..4 (2 is the
        usual alternating gait; 1 is step-to; 3-4 skip steps); the last stride takes the rest.
    step_height_m : stairs: riser height K, m; None uses ``simulate_walk``'s ``step_height_m``.
    tread_m : stairs: tread depth, m.
    turn_deg : level: heading change spread over the strides (turn while walking);
        turn: angle turned on the spot. Positive is a left turn (ENU, about z up).
    stride_length_m : level: nominal stride length, m; None draws one per stride from GaitParams.
    duration_s : stand: time at rest, s.

    """

    kind: str
    n_strides: int = 0
    n_steps: int = 0
    direction: int = 0
    steps_per_stride: int = 2
    step_height_m: float | None = None
    tread_m: float = 0.28
    turn_deg: float = 0.0
    stride_length_m: float | None = None
    duration_s: float = 0.0

    def __post_init__(self):
        if self.kind not in SEGMENT_KINDS:
            raise InputError(f'Segment.kind={self.kind!r} is not one of {SEGMENT_KINDS}')
        if self.kind == 'level':
            _check_range('Segment.n_strides', self.n_strides, 1, 100_000)
            if self.stride_length_m is not None:
                _check_range('Segment.stride_length_m', self.stride_length_m, 0.2, 2.5)
            _check_range('Segment.turn_deg', abs(self.turn_deg), 0.0, 120.0 * self.n_strides,
                         'abs(turn_deg) <= 120 deg per stride')
        elif self.kind == 'stairs':
            _check_range('Segment.n_steps', self.n_steps, 1, 1000)
            if self.direction not in (-1, 1):
                raise InputError(
                    f'Segment.direction={self.direction} must be +1 (up) or -1 (down)')
            _check_range('Segment.steps_per_stride', self.steps_per_stride, 1, 4)
            if self.step_height_m is not None:
                _check_range('Segment.step_height_m', self.step_height_m, 0.05, 0.30)
            _check_range('Segment.tread_m', self.tread_m, 0.15, 0.50)
        elif self.kind == 'turn':
            _check_range('Segment.turn_deg', abs(self.turn_deg), 1.0, 720.0)
        else:
            _check_range('Segment.duration_s', self.duration_s, 0.01, 1e6)

    @classmethod
    def level(cls, n_strides: int, *, turn_deg: float = 0.0,
              stride_length_m: float | None = None) -> 'Segment':
        """Walk ``n_strides`` strides on the level, turning by ``turn_deg`` in total."""
        return cls('level', n_strides=int(n_strides), turn_deg=float(turn_deg),
                   stride_length_m=stride_length_m)

    @classmethod
    def stairs(cls, n_steps: int, direction: int, *, steps_per_stride: int = 2,
               step_height_m: float | None = None, tread_m: float = 0.28) -> 'Segment':
        """Walk one straight flight of ``n_steps`` steps up (+1) or down (-1)."""
        return cls('stairs', n_steps=int(n_steps), direction=int(direction),
                   steps_per_stride=int(steps_per_stride), step_height_m=step_height_m,
                   tread_m=float(tread_m))

    @classmethod
    def turn(cls, angle_deg: float) -> 'Segment':
        """Turn on the spot by ``angle_deg`` (positive left) in pivot strides of at most 90 deg."""
        return cls('turn', turn_deg=float(angle_deg))

    @classmethod
    def stand(cls, duration_s: float) -> 'Segment':
        """Stand still for ``duration_s`` seconds."""
        return cls('stand', duration_s=float(duration_s))


@dataclass(frozen=True)
class GaitParams:
    """
    Ranges (low, high) from which each stride's gait values are drawn uniformly.

    Defaults are typical adult values: level strides of 1.2-1.5 m at about one stride per
    second with a foot-flat stance of 35-50 % of the cycle; foot elevation angles as in the
    module docstring (negative = toe down). Stair stride duration is
    ``base + per_step * n_steps``. Touch-down (module docstring): ``*_touchdown_mps`` is the
    forward and ``*_sink_mps`` the downward speed of the IMU when the sole meets the ground,
    ``impact_s`` the rise (and the fall) time of the deceleration pulse that stops it,
    ``foot_flat_s`` the time to roll flat after it; ``swing_roll_rps`` is the roll rate where
    the pitch turns (a random sign per stride).
    """

    level_stride_length_m: tuple = (1.2, 1.5)
    level_stride_s: tuple = (0.95, 1.15)
    stance_fraction: tuple = (0.35, 0.5)
    level_clearance_m: tuple = (0.04, 0.08)
    level_toe_off_deg: tuple = (-50.0, -30.0)
    level_landing_deg: tuple = (10.0, 20.0)
    level_touchdown_mps: tuple = (0.4, 0.8)
    level_sink_mps: tuple = (0.2, 0.5)
    stair_stride_base_s: tuple = (0.55, 0.70)
    stair_stride_per_step_s: tuple = (0.26, 0.32)
    stair_clearance_m: tuple = (0.04, 0.07)
    stair_touchdown_mps: tuple = (0.1, 0.3)
    up_toe_off_deg: tuple = (-25.0, -12.0)
    up_mid_swing_deg: tuple = (6.0, 16.0)
    up_landing_deg: tuple = (-8.0, -3.0)
    up_sink_mps: tuple = (0.3, 0.6)
    down_toe_off_deg: tuple = (-20.0, -8.0)
    down_mid_swing_deg: tuple = (4.0, 12.0)
    down_landing_deg: tuple = (-16.0, -6.0)
    down_sink_mps: tuple = (0.3, 0.6)
    turn_stride_s: tuple = (0.8, 1.0)
    turn_clearance_m: tuple = (0.02, 0.04)
    turn_toe_off_deg: tuple = (-15.0, -5.0)
    turn_sink_mps: tuple = (0.1, 0.2)
    impact_s: tuple = (0.02, 0.04)
    foot_flat_s: tuple = (0.06, 0.10)
    toe_from_imu_m: float = 0.12         # along the foot, IMU to the toe pivot
    heel_from_imu_m: float = 0.10        # along the foot, IMU to the heel pivot
    swing_roll_rps: tuple = (0.8, 1.6)
    stride_length_jitter: float = 0.03   # relative std of a Segment's given stride length

    def __post_init__(self):
        for field in fields(self):
            value = getattr(self, field.name)
            if isinstance(value, tuple):
                if len(value) != 2 or not value[0] <= value[1]:
                    raise InputError(f'GaitParams.{field.name}={value} must be (low, high) '
                                     'with low <= high')
                if field.name.endswith(('_m', '_s', '_mps', 'fraction')) and value[0] <= 0:
                    raise InputError(f'GaitParams.{field.name}={value} must be positive')
        _check_range('GaitParams.stance_fraction', self.stance_fraction[1], 0.0, 0.8)
        _check_range('GaitParams.swing_roll_rps', self.swing_roll_rps[1], 0.0, 5.0)
        _check_range('GaitParams.stride_length_jitter', self.stride_length_jitter, 0.0, 0.2)
        _check_range('GaitParams.toe_from_imu_m', self.toe_from_imu_m, 0.0, 0.3)
        _check_range('GaitParams.heel_from_imu_m', self.heel_from_imu_m, 0.0, 0.3)
        shortest_swing_s = (1.0 - self.stance_fraction[1]) * min(
            self.level_stride_s[0], self.turn_stride_s[0],
            self.stair_stride_base_s[0] + self.stair_stride_per_step_s[0])
        _check_range('GaitParams 2 * impact_s[1] + foot_flat_s[1]',
                     2.0 * self.impact_s[1] + self.foot_flat_s[1], 0.0, 0.5 * shortest_swing_s,
                     f'at most half the shortest swing ({shortest_swing_s:.3f} s), so that '
                     'the touch-down fits in every swing')


# ----------------------------------------------------------------------------------------------
# IMU error model
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ImuErrorModel:
    """
    Errors of a triad of gyros and accelerometers (all 1-sigma, per axis).

    measured = Q(sat((I + M) true + b0 + b_rw(t) + n)),  true = x(t_k) or its interval mean

    Attributes
    ----------
    name : preset name, for logs.
    gyr_noise_density_rps_rthz, acc_noise_density_mps2_rthz : white noise density (angle /
        velocity random walk); per-sample std = density * sqrt(rate_hz).
    gyr_bias_sigma_rps, acc_bias_sigma_mps2 : turn-on bias, constant per run.
    gyr_bias_walk_rps_rts, acc_bias_walk_mps2_rts : bias random walk (rate random walk),
        std of the bias change after t seconds = walk * sqrt(t).
    gyr_scale_sigma, acc_scale_sigma : scale-factor error, fraction.
    gyr_misalign_sigma_rad, acc_misalign_sigma_rad : each off-diagonal term of M (axis
        misalignment / cross-axis sensitivity), rad.
    gyr_range_rps, acc_range_mps2 : full scale; readings saturate at +-range (inf: none).
    adc_bits : signed output word length; the step is range / 2^(bits-1) (0: no quantisation).
    interval_mean : False: each reading samples the motion at its stamp; True: it is the mean
        over the sample interval centred on the stamp (``interval_means``), as an IMU that
        outputs velocity and angle increments gives, and close to what the decimation filter of
        a MEMS part does. A foot's touch-down lasts a few samples at 100 Hz: instantaneous
        samples of it alias, and a strapdown integration of them misses up to 0.15 m/s of its
        velocity change; the means keep the increments.

    """

    name: str = 'custom'
    gyr_noise_density_rps_rthz: float = 0.0
    acc_noise_density_mps2_rthz: float = 0.0
    gyr_bias_sigma_rps: float = 0.0
    acc_bias_sigma_mps2: float = 0.0
    gyr_bias_walk_rps_rts: float = 0.0
    acc_bias_walk_mps2_rts: float = 0.0
    gyr_scale_sigma: float = 0.0
    acc_scale_sigma: float = 0.0
    gyr_misalign_sigma_rad: float = 0.0
    acc_misalign_sigma_rad: float = 0.0
    gyr_range_rps: float = math.inf
    acc_range_mps2: float = math.inf
    adc_bits: int = 0
    interval_mean: bool = False

    def __post_init__(self):
        if not isinstance(self.interval_mean, bool):
            raise InputError(f'ImuErrorModel.interval_mean={self.interval_mean!r} must be a bool')
        for field in fields(self):
            value = getattr(self, field.name)
            if field.name not in ('name', 'interval_mean') and not value >= 0:
                raise InputError(f'ImuErrorModel.{field.name}={value} must be >= 0')
        _check_range('ImuErrorModel.gyr_range_rps', self.gyr_range_rps, 1e-3, math.inf)
        _check_range('ImuErrorModel.acc_range_mps2', self.acc_range_mps2, 1e-3, math.inf)
        if self.adc_bits and not 8 <= self.adc_bits <= 32:
            raise InputError(f'ImuErrorModel.adc_bits={self.adc_bits} must be 0 (none) or 8..32')
        if self.adc_bits and not (math.isfinite(self.gyr_range_rps)
                                  and math.isfinite(self.acc_range_mps2)):
            raise InputError('ImuErrorModel.adc_bits needs finite gyr_range_rps and '
                             'acc_range_mps2 (quantisation step = range / 2^(bits-1))')

    @property
    def is_ideal(self) -> bool:
        """Tell whether the model leaves the readings unchanged."""
        return self == ImuErrorModel(name=self.name)

    def noise_std(self, rate_hz: float) -> tuple:
        """Return the per-sample white-noise std (gyro rad/s, acc m/s^2), density*sqrt(rate)."""
        root = math.sqrt(rate_hz)
        return self.gyr_noise_density_rps_rthz * root, self.acc_noise_density_mps2_rthz * root


IMU_PRESETS = {
    # No errors: the readings are exact samples of the analytic motion.
    'ideal': ImuErrorModel(name='ideal'),
    # Tactical-grade MEMS (Groves 2013 ch. 4 class; e.g. ADIS16495 / HG1700 order): ARW
    # 0.1 deg/sqrt(h), bias 1 deg/h, VRW 0.03 m/s/sqrt(h), bias 0.5 mg. Bias walks are chosen so
    # the bias changes by about its turn-on value over 10 min. Ranges are not limiting. Such
    # units output velocity and angle increments: interval means.
    'tactical': ImuErrorModel(
        name='tactical',
        gyr_noise_density_rps_rthz=0.1 / 60.0 * DEG,            # 0.1 deg/sqrt(h)
        acc_noise_density_mps2_rthz=0.03 / 60.0,                # 0.03 m/s/sqrt(h)
        gyr_bias_sigma_rps=1.0 / 3600.0 * DEG,                  # 1 deg/h
        acc_bias_sigma_mps2=0.5e-3 * _G0,                       # 0.5 mg
        gyr_bias_walk_rps_rts=1.0 / 3600.0 * DEG / math.sqrt(600.0),
        acc_bias_walk_mps2_rts=0.5e-3 * _G0 / math.sqrt(600.0),
        gyr_scale_sigma=1e-4, acc_scale_sigma=3e-4,             # 100 / 300 ppm
        gyr_misalign_sigma_rad=1e-4, acc_misalign_sigma_rad=1e-4, interval_mean=True),
    # Consumer MEMS, MPU-9250 / BMI160 class. Noise densities from the MPU-9250 datasheet [2]:
    # gyro 0.01 deg/s/sqrt(Hz), acc 300 ug/sqrt(Hz).
    # Ranges +-2000 deg/s and +-16 g, 16-bit words (16.4 LSB/(deg/s), 2048 LSB/g) [2].
    # Turn-on bias, scale factor and misalignment are those left after a simple user
    # calibration: 0.5 deg/s and 30 mg, 0.5 %, 0.5 deg (untrimmed datasheet tolerances are
    # +-5 deg/s, +-60..80 mg, +-3 %, +-2 % cross-axis [2]). Bias walks: 0.002 deg/s/sqrt(s) and
    # 0.1 mg/sqrt(s), i.e. 0.05 deg/s and 2.4 mg after 10 min (assumed; datasheets give none).
    # Their digital low-pass and decimation filters are modelled by interval means.
    'consumer': ImuErrorModel(
        name='consumer',
        gyr_noise_density_rps_rthz=0.01 * DEG,
        acc_noise_density_mps2_rthz=300e-6 * _G0,
        gyr_bias_sigma_rps=0.5 * DEG,
        acc_bias_sigma_mps2=30e-3 * _G0,
        gyr_bias_walk_rps_rts=0.002 * DEG,
        acc_bias_walk_mps2_rts=0.1e-3 * _G0,
        gyr_scale_sigma=0.005, acc_scale_sigma=0.005,
        gyr_misalign_sigma_rad=0.5 * DEG, acc_misalign_sigma_rad=0.5 * DEG,
        gyr_range_rps=2000.0 * DEG, acc_range_mps2=16.0 * _G0, adc_bits=16,
        interval_mean=True),
}


def imu_error_model(imu) -> ImuErrorModel:
    """Return ``imu`` if it is an ImuErrorModel, else the preset of that name."""
    if isinstance(imu, ImuErrorModel):
        return imu
    try:
        return IMU_PRESETS[imu]
    except (KeyError, TypeError):
        raise InputError(f'unknown IMU error preset {imu!r}; use one of '
                         f'{sorted(IMU_PRESETS)} or an ImuErrorModel') from None


def apply_imu_errors(acc_b: np.ndarray, gyr_b: np.ndarray, rate_hz: float,
                     model: ImuErrorModel, rng: np.random.Generator) -> tuple:
    """
    Corrupt exact IMU readings with the errors of ``model``.

    y = Q(sat((I + M) x + b0 + b_rw(t_k) + n_k)),  M = diag(scale) + off-diagonal misalignment,
    b_rw(t_k) = sum_{j<=k} w_j sqrt(dt) (random walk from 0), n_k ~ N(0, density^2 rate_hz),
    sat clips to +-range, Q rounds to the step range / 2^(bits-1) (two's complement word).

    Parameters
    ----------
    acc_b : (N, 3) array
        Exact specific force, m/s^2.
    gyr_b : (N, 3) array
        Exact angular rate, rad/s.
    rate_hz : float
        Sample rate, Hz (sets the per-sample noise and the random-walk step).
    model : ImuErrorModel
        The error model.
    rng : np.random.Generator
        Draws in a fixed order (gyro then acc: misalignment and scale, turn-on bias, bias walk,
        white noise).

    Returns
    -------
    (acc_b, gyr_b) measured, new (N, 3) arrays.

    """
    if model.is_ideal:
        return acc_b.copy(), gyr_b.copy()
    dt_s = 1.0 / rate_hz
    gyr_std, acc_std = model.noise_std(rate_hz)
    gyr = _sensor_errors(gyr_b, rng, model.gyr_scale_sigma, model.gyr_misalign_sigma_rad,
                         model.gyr_bias_sigma_rps, model.gyr_bias_walk_rps_rts * math.sqrt(dt_s),
                         gyr_std, model.gyr_range_rps, model.adc_bits)
    acc = _sensor_errors(acc_b, rng, model.acc_scale_sigma, model.acc_misalign_sigma_rad,
                         model.acc_bias_sigma_mps2,
                         model.acc_bias_walk_mps2_rts * math.sqrt(dt_s),
                         acc_std, model.acc_range_mps2, model.adc_bits)
    return acc, gyr


def _sensor_errors(x, rng, scale_sigma, misalign_sigma, bias_sigma, walk_step, noise_std,
                   full_scale, bits):
    """One triad: y = Q(sat((I + M) x + b0 + b_rw + n)); see apply_imu_errors."""
    n = len(x)
    m = rng.normal(0.0, 1.0, (3, 3)) * misalign_sigma
    m[np.diag_indices(3)] = rng.normal(0.0, 1.0, 3) * scale_sigma
    bias0 = rng.normal(0.0, 1.0, 3) * bias_sigma
    walk = np.cumsum(rng.normal(0.0, 1.0, (n, 3)), axis=0) * walk_step if walk_step else 0.0
    noise = rng.normal(0.0, 1.0, (n, 3)) * noise_std if noise_std else 0.0
    y = x + x @ m.T + bias0 + walk + noise
    if math.isfinite(full_scale):
        lsb = full_scale / 2 ** (bits - 1) if bits else 0.0
        y = np.clip(y, -full_scale, full_scale - lsb)
        if bits:
            y = np.round(y / lsb) * lsb
    return y


# ----------------------------------------------------------------------------------------------
# Results
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class StrideTruth:
    """
    Per-stride truth of the instrumented foot, M strides in time order.

    Attributes
    ----------
    stamp_ns : (M,) int64, stamp of the first stance sample after the swing.
    swing_start_ns : (M,) int64, stamp of the first moving sample of the swing.
    mode : (M,) int8, +1 stairs up, 0 level (walking or turning), -1 stairs down.
    height_change_m : (M,) float, end minus start height of the foot, m.
    n_steps : (M,) int, stair steps climbed or descended in the stride (0 on the level).
    step_height_m : (M,) float, riser height K of the stride's flight, m (0 on the level).
    start_pos_n, end_pos_n : (M, 3) float, IMU position at the stances before and after, m.
    heading_change_rad : (M,) float, change of foot yaw over the stride, rad.
    segment_index : (M,) int, index of the Segment the stride belongs to.

    """

    stamp_ns: np.ndarray
    swing_start_ns: np.ndarray
    mode: np.ndarray
    height_change_m: np.ndarray
    n_steps: np.ndarray
    step_height_m: np.ndarray
    start_pos_n: np.ndarray
    end_pos_n: np.ndarray
    heading_change_rad: np.ndarray
    segment_index: np.ndarray

    def __len__(self):
        return len(self.stamp_ns)

    @property
    def height_m(self) -> np.ndarray:
        """(M,) foot height after each stride relative to the first sample, m."""
        return self.end_pos_n[:, 2]


@dataclass(frozen=True)
class SimulatedWalk:
    """
    A simulated walk: truth at every sample, per-stride truth and the IMU readings.

    Attributes
    ----------
    stamp_ns : (N,) int64 sample stamps, EPOCH_NS + round(k * 1e9 / rate_hz).
    acc_b, gyr_b : (N, 3) measured specific force (m/s^2) and angular rate (rad/s), IMU frame.
    pos_n, vel_n : (N, 3) true IMU position (m) and velocity (m/s), ENU, origin at sample 0.
    quat_nb : (N, 4) true attitude [w, x, y, z], IMU to ENU (continuous, not sign-fixed).
    stance : (N,) bool, True where the foot is flat and still (truth velocity exactly zero).
    strides : per-stride truth.
    rate_hz : nominal sample rate, Hz.
    imu : the error model applied to the readings.
    mounting_rpy_deg : IMU mounting as roll, pitch, yaw of C_fb (v_f = C_fb v_b), deg.
    gravity_mps2 : gravity magnitude used, m/s^2.
    segments : the walk plan.

    """

    stamp_ns: np.ndarray
    acc_b: np.ndarray
    gyr_b: np.ndarray
    pos_n: np.ndarray
    vel_n: np.ndarray
    quat_nb: np.ndarray
    stance: np.ndarray
    strides: StrideTruth
    rate_hz: float
    imu: ImuErrorModel
    mounting_rpy_deg: tuple
    gravity_mps2: float
    segments: tuple

    def __len__(self):
        return len(self.stamp_ns)

    @property
    def duration_s(self) -> float:
        """Time from the first to the last sample, s."""
        return (int(self.stamp_ns[-1]) - int(self.stamp_ns[0])) * 1e-9

    def to_recording(self, frame_id: str = 'imu_link') -> ImuRecording:
        """Return the measured readings as an ImuRecording (what a bag or a live IMU gives)."""
        return ImuRecording(self.stamp_ns, self.acc_b, self.gyr_b, frame_id)


# ----------------------------------------------------------------------------------------------
# Equations
# ----------------------------------------------------------------------------------------------

def quintic_hermite(w: np.ndarray, y0, v0, a0, y1, v1, a1) -> tuple:
    """
    Quintic through (y, y', y'') at w = 0 and w = 1, and its derivatives d/dw, d2/dw2.

    p(w) = sum_k c_k w^k, k = 0..5, with c0 = y0, c1 = v0, c2 = a0 / 2 and, from
    Y = y1 - c0 - c1 - c2, V = v1 - c1 - 2 c2, A = a1 - 2 c2:
    c3 = 10 Y - 4 V + A / 2,  c4 = -15 Y + 7 V - A,  c5 = 6 Y - 3 V + A / 2.
    With zero end derivatives it is the minimum-jerk profile y0 + (y1 - y0) s(w).

    Parameters
    ----------
    w : (K,) array
        Normalised time in [0, 1].
    y0, v0, a0, y1, v1, a1 : (K,) arrays or floats
        Value, first and second derivative (per unit w) at w = 0 and at w = 1.

    Returns
    -------
    p, dp/dw, d2p/dw2 as (K,) arrays.

    """
    c2 = 0.5 * a0
    big_y = y1 - y0 - v0 - c2
    big_v = v1 - v0 - 2.0 * c2
    big_a = a1 - 2.0 * c2
    c3 = 10.0 * big_y - 4.0 * big_v + 0.5 * big_a
    c4 = -15.0 * big_y + 7.0 * big_v - big_a
    c5 = 6.0 * big_y - 3.0 * big_v + 0.5 * big_a
    p = y0 + w * (v0 + w * (c2 + w * (c3 + w * (c4 + w * c5))))
    dp = v0 + w * (2.0 * c2 + w * (3.0 * c3 + w * (4.0 * c4 + w * 5.0 * c5)))
    ddp = 2.0 * c2 + w * (6.0 * c3 + w * (12.0 * c4 + w * 20.0 * c5))
    return p, dp, ddp


def knot_profile(u: np.ndarray, knots_u, knots_y, duration_s: float, knots_v=None,
                 knots_a=None) -> tuple:
    """
    Chain of quintic pieces through knots, and its first two time derivatives.

    On [u_i, u_(i+1)], with h = u_(i+1) - u_i and w = (u - u_i) / h, y(u) is the quintic_hermite
    through (y_i, h v_i, h^2 a_i) and (y_(i+1), h v_(i+1), h^2 a_(i+1)), where v and a are dy/du
    and d2y/du2 at the knots (zero when not given: a chain of minimum-jerk pieces). The chain is
    C2; u = (t - t0) / duration_s, so dy/dt = dy/du / duration_s.

    Parameters
    ----------
    u : (K,) array
        Normalised time in [0, 1].
    knots_u : (J,) array
        Knot times, strictly increasing from 0 to 1.
    knots_y : (J,) array
        Values at the knots.
    duration_s : float
        Length of the u interval, s.
    knots_v, knots_a : (J,) arrays or None
        dy/du and d2y/du2 at the knots (None: zero).

    Returns
    -------
    y, dy/dt, d2y/dt2 as (K,) arrays.

    """
    knots_u = np.asarray(knots_u, dtype=float)
    knots_y = np.asarray(knots_y, dtype=float)
    knots_v = np.zeros_like(knots_y) if knots_v is None else np.asarray(knots_v, dtype=float)
    knots_a = np.zeros_like(knots_y) if knots_a is None else np.asarray(knots_a, dtype=float)
    i = np.clip(np.searchsorted(knots_u, u, side='right') - 1, 0, len(knots_u) - 2)
    width = knots_u[i + 1] - knots_u[i]
    w = np.clip((u - knots_u[i]) / width, 0.0, 1.0)
    p, dp, ddp = quintic_hermite(w, knots_y[i], knots_v[i] * width, knots_a[i] * width ** 2,
                                 knots_y[i + 1], knots_v[i + 1] * width,
                                 knots_a[i + 1] * width ** 2)
    scale = 1.0 / (width * duration_s)
    return p, dp * scale, ddp * scale * scale


def euler_zyx_to_dcm(roll, pitch, yaw) -> np.ndarray:
    """(N, 3, 3) C = Rz(yaw) Ry(pitch) Rx(roll) for arrays of angles (rad), REP 103."""
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cy, sy = np.cos(yaw), np.sin(yaw)
    return np.stack([
        np.stack([cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr], axis=-1),
        np.stack([sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr], axis=-1),
        np.stack([-sp, cp * sr, cp * cr], axis=-1),
    ], axis=-2)


def euler_zyx_to_quat(roll, pitch, yaw) -> np.ndarray:
    """(N, 4) quaternion [w, x, y, z] of C = Rz(yaw) Ry(pitch) Rx(roll): q = qz * qy * qx."""
    cr, sr = np.cos(0.5 * roll), np.sin(0.5 * roll)
    cp, sp = np.cos(0.5 * pitch), np.sin(0.5 * pitch)
    cy, sy = np.cos(0.5 * yaw), np.sin(0.5 * yaw)
    return np.stack([cr * cp * cy + sr * sp * sy,
                     sr * cp * cy - cr * sp * sy,
                     cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy], axis=-1)


def body_rate_from_euler_zyx(roll, pitch, roll_rate, pitch_rate, yaw_rate) -> np.ndarray:
    """
    (N, 3) angular rate in the rotated frame from ZYX Euler angles and their rates (rad/s).

    w = [roll' - yaw' sin(pitch),
         pitch' cos(roll) + yaw' cos(pitch) sin(roll),
         -pitch' sin(roll) + yaw' cos(pitch) cos(roll)]
    """
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    return np.stack([roll_rate - yaw_rate * sp,
                     pitch_rate * cr + yaw_rate * cp * sr,
                     -pitch_rate * sr + yaw_rate * cp * cr], axis=-1)


def specific_force_b(acc_n: np.ndarray, C_nb: np.ndarray, gravity_mps2: float) -> np.ndarray:
    """
    (N, 3) specific force f_b = C_nb^T (a_n - g_n), g_n = [0, 0, -g].

    Parameters
    ----------
    acc_n : (N, 3) array
        Kinematic acceleration, m/s^2, ENU.
    C_nb : (N, 3, 3) array
        Attitude, body to navigation.
    gravity_mps2 : float
        Gravity magnitude g, m/s^2.

    """
    f_n = acc_n + np.array([0.0, 0.0, gravity_mps2])
    return np.einsum('nji,nj->ni', C_nb, f_n)


def _quat_multiply_batch(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """(N, 4) Hamilton products p * q of [w, x, y, z] quaternions (q may be (4,))."""
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(np.broadcast_to(q, p.shape), -1, 0)
    return np.stack([pw * qw - px * qx - py * qy - pz * qz,
                     pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy - px * qz + py * qw + pz * qx,
                     pw * qz + px * qy - py * qx + pz * qw], axis=-1)


# ----------------------------------------------------------------------------------------------
# Planning: segments -> strides
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _StridePlan:
    """
    One stride: swing from t_start_s for swing_s, then stance_s at rest.

    Each ``*_knots`` is a knot chain (u, y, dy/du, d2y/du2) for knot_profile.
    """

    t_start_s: float
    swing_s: float
    stance_s: float
    pos0_n: np.ndarray
    pos1_n: np.ndarray
    yaw0: float
    yaw1: float
    progress_knots: tuple   # fraction of the horizontal displacement
    z_knots: tuple          # height relative to the start, m
    lift_knots: tuple       # extra height from rolling over the toe or heel, m
    elev_knots: tuple       # elevation, rad, toe up positive
    roll_knots: tuple       # roll, rad
    yaw_knots: tuple        # fraction of the heading change
    mode: int
    n_steps: int
    step_height_m: float
    segment_index: int


def _uniform(rng: np.random.Generator, bounds: tuple) -> float:
    return float(rng.uniform(bounds[0], bounds[1]))


def _knots(*specs) -> tuple:
    """
    Knot chain (u, y, v, a), v = dy/du and a = d2y/du2, from specs (u, y[, v[, a]]).

    Specs at an equal u keep the first. Derivatives not given (or None) are filled so that the
    chain moves smoothly through its knots without lingering: v = a = 0 at the ends and next
    to a plateau (an adjacent secant is 0); at an extremum v = 0 and a is the second difference
    2 (s_r - s_l) / (h_l + h_r), so the rate passes through zero instead of dwelling near it as
    a minimum-jerk piece does; elsewhere v is the weighted harmonic mean of the secants s_l, s_r
    (monotone, as in PCHIP, Fritsch and Carlson 1980) and a the second difference.
    """
    chain = []
    for spec in specs:
        if not chain or spec[0] > chain[-1][0]:
            chain.append(tuple(float(x) if x is not None else None for x in spec)
                         + (None,) * (4 - len(spec)))
    u = [c[0] for c in chain]
    y = [c[1] for c in chain]
    v, a = [], []
    for i, (_, _, vi, ai) in enumerate(chain):
        auto_v = auto_a = 0.0
        if 0 < i < len(chain) - 1:
            h_l, h_r = u[i] - u[i - 1], u[i + 1] - u[i]
            s_l, s_r = (y[i] - y[i - 1]) / h_l, (y[i + 1] - y[i]) / h_r
            if s_l != 0.0 and s_r != 0.0:
                auto_a = 2.0 * (s_r - s_l) / (h_l + h_r)
                if s_l * s_r > 0.0:
                    w_l, w_r = 2.0 * h_r + h_l, h_r + 2.0 * h_l
                    auto_v = (w_l + w_r) / (w_l / s_l + w_r / s_r)
        v.append(auto_v if vi is None else vi)
        a.append(auto_a if ai is None else ai)
    return tuple(u), tuple(y), tuple(v), tuple(a)


def _stride_duration_s(seg: Segment, n_steps: int, gait: GaitParams, rng) -> float:
    if seg.kind == 'level':
        return _uniform(rng, gait.level_stride_s)
    if seg.kind == 'turn':
        return _uniform(rng, gait.turn_stride_s)
    return _uniform(rng, gait.stair_stride_base_s) + n_steps * _uniform(
        rng, gait.stair_stride_per_step_s)


def _plan_strides(segments, gait: GaitParams, step_height_m: float, rng, t0_s: float):
    """Expand segments into stride plans; returns (plans, end time of the last stance)."""
    t = t0_s
    pos = np.zeros(3)
    yaw = 0.0
    plans = []
    for index, seg in enumerate(segments):
        if seg.kind == 'stand':
            t += seg.duration_s
            continue
        for stride in _segment_strides(seg, step_height_m):
            n_steps, turn, dz, length, mode, riser_m = stride
            duration = _stride_duration_s(seg, n_steps, gait, rng)
            stance = duration * _uniform(rng, gait.stance_fraction)
            roll_rate = _uniform(rng, gait.swing_roll_rps) * float(rng.choice((-1.0, 1.0)))
            if seg.kind == 'level':
                if length is None:
                    length = _uniform(rng, gait.level_stride_length_m)
                else:
                    length *= 1.0 + gait.stride_length_jitter * float(
                        np.clip(rng.normal(), -3.0, 3.0))
            heading = yaw + 0.5 * turn
            step = np.array([length * math.cos(heading), length * math.sin(heading), dz])
            shape = _swing_shape(seg.kind, mode, n_steps, dz, length, duration - stance,
                                 roll_rate, gait, rng)
            shape['lift_knots'] = _pivot_lift_knots(shape['elev_knots'], gait)
            plans.append(_StridePlan(
                t_start_s=t, swing_s=duration - stance, stance_s=stance, pos0_n=pos.copy(),
                pos1_n=pos + step, yaw0=yaw, yaw1=yaw + turn, mode=mode,
                n_steps=n_steps, step_height_m=riser_m,
                segment_index=index, **shape))
            t += duration
            pos = pos + step
            yaw += turn
    return plans, t


def _segment_strides(seg: Segment, step_height_m: float):
    """Yield (n_steps, turn_rad, height_change_m, length_m or None, mode, riser_m) per stride."""
    if seg.kind == 'level':
        turn = seg.turn_deg * DEG / seg.n_strides
        for _ in range(seg.n_strides):
            yield 0, turn, 0.0, seg.stride_length_m, 0, 0.0
    elif seg.kind == 'turn':
        n = math.ceil(abs(seg.turn_deg) / 90.0 - 1e-9)
        for _ in range(n):
            yield 0, seg.turn_deg * DEG / n, 0.0, 0.0, 0, 0.0
    else:
        k = seg.step_height_m if seg.step_height_m is not None else step_height_m
        full, rest = divmod(seg.n_steps, seg.steps_per_stride)
        for m in [seg.steps_per_stride] * full + ([rest] if rest else []):
            yield m, 0.0, seg.direction * m * k, m * seg.tread_m, seg.direction, k


def _pivot_lift_knots(elev_knots: tuple, gait: GaitParams) -> tuple:
    """
    Knots of the IMU's rise as the foot rolls over its toe or heel (rigid-foot pivot).

    lift = toe sin(-e) for toe down (e < 0), heel sin(e) for toe up, with its exact first and
    second derivatives at the elevation knots (lift' = r cos(e) e',
    lift'' = r (cos(e) e'' - sin(e) e'^2), r = heel, or -toe for toe down): the toe or heel
    stays on the ground at heel-off and while the sole rolls flat after touch-down.
    """
    lift, dlift, ddlift = [], [], []
    for e, de, dde in zip(*elev_knots[1:]):
        r = gait.heel_from_imu_m if e > 0.0 or (e == 0.0 and de > 0.0) else -gait.toe_from_imu_m
        lift.append(r * math.sin(e))
        dlift.append(r * math.cos(e) * de)
        ddlift.append(r * (math.cos(e) * dde - math.sin(e) * de * de))
    return tuple(elev_knots[0]), tuple(lift), tuple(dlift), tuple(ddlift)


def _swing_shape(kind: str, mode: int, n_steps: int, dz: float, length_m: float,
                 swing_s: float, roll_rate: float, gait: GaitParams, rng) -> dict:
    """
    Knot chains of one swing; the draws happen in a fixed order.

    The swing ends with the touch-down (module docstring): the sole meets the ground at u_c
    moving forward at v and down at w and is stopped by a triangular deceleration pulse of
    peak (v, w) / tau at u_td, tau after contact, and zero at u_stop, tau later (tau =
    ``impact_s``); then it rolls flat (elevation to 0, the IMU pivoting about the heel or toe)
    in ``foot_flat_s``. The knots of the flight before u_c sit at fixed fractions of u_c, so
    the flight keeps its shape for any swing time.
    """
    impact_s = _uniform(rng, gait.impact_s)
    flat_s = _uniform(rng, gait.foot_flat_s)
    u_stop = 1.0 - flat_s / swing_s                 # the sole has stopped; it rolls flat
    u_td = u_stop - impact_s / swing_s              # peak of the touch-down deceleration
    u_c = u_td - impact_s / swing_s                 # contact
    u_roll = 1.0 - 0.45 * flat_s / swing_s          # the roll slows to a stop from here

    stair_scale = min(1.0, 0.4 + 0.3 * n_steps)     # a step-to stride rolls the foot less

    def at(fraction):
        return fraction * u_c

    def touchdown(y_end, speed_mps, scale_m):
        """Knots at u_c, u_td, u_stop of a coordinate that meets the ground at speed_mps."""
        if scale_m == 0.0:
            return ((u_stop, y_end),)
        v = speed_mps * swing_s / scale_m           # dy/du at contact
        peak = -v / impact_s * swing_s              # d2y/du2 at u_td
        return ((u_c, y_end - speed_mps * impact_s / scale_m, v, 0.0),
                (u_td, y_end - speed_mps * impact_s / 6.0 / scale_m, 0.5 * v, peak),
                (u_stop, y_end, 0.0, 0.0))

    if kind == 'turn':
        clearance = _uniform(rng, gait.turn_clearance_m)
        toe_off = _uniform(rng, gait.turn_toe_off_deg) * DEG
        sink = _uniform(rng, gait.turn_sink_mps)
        progress = ((0, 0), (u_stop, 1))
        z = ((0, 0), (at(0.45), clearance)) + touchdown(0.0, -sink, 1.0)
        elev = ((0, 0), (at(0.4), toe_off), (u_stop, 0.3 * abs(toe_off)),
                (u_roll, 0.1 * abs(toe_off)), (1, 0))
        yaw = ((0, 0), (at(0.15), 0), (at(0.95), 1), (1, 1))
        turns = (at(0.4),)
    elif mode == 0:
        clearance = _uniform(rng, gait.level_clearance_m)
        toe_off = _uniform(rng, gait.level_toe_off_deg) * DEG
        landing = _uniform(rng, gait.level_landing_deg) * DEG
        forward = _uniform(rng, gait.level_touchdown_mps)
        sink = _uniform(rng, gait.level_sink_mps)
        # Half-way at 0.55 u_c keeps the peak foot speed at 4-5 m/s (2.5-3 x walking speed).
        progress = ((0, 0), (at(0.06), 0), (at(0.55), 0.52)) + touchdown(1.0, forward, length_m)
        z = ((0, 0), (at(0.45), clearance)) + touchdown(0.0, -sink, 1.0)
        elev = ((0, 0), (at(0.42), toe_off), (u_stop, landing), (u_roll, 0.35 * landing), (1, 0))
        yaw = ((0, 0), (at(0.1), 0), (at(0.95), 1), (1, 1))
        turns = (at(0.42),)
    elif mode > 0:
        # Up: lift above the target tread first, then move over it; forefoot first.
        clearance = _uniform(rng, gait.stair_clearance_m)
        toe_off = _uniform(rng, gait.up_toe_off_deg) * DEG * stair_scale
        mid = _uniform(rng, gait.up_mid_swing_deg) * DEG * stair_scale
        landing = _uniform(rng, gait.up_landing_deg) * DEG
        forward = _uniform(rng, gait.stair_touchdown_mps)
        sink = _uniform(rng, gait.up_sink_mps)
        progress = ((0, 0), (at(0.25), 0)) + touchdown(1.0, forward, length_m)
        z = ((0, 0), (at(0.6), dz + clearance)) + touchdown(dz, -sink, 1.0)
        elev = ((0, 0), (at(0.32), toe_off), (at(0.72), mid), (u_stop, landing),
                (u_roll, 0.35 * landing), (1, 0))
        yaw = ((0, 0), (at(0.1), 0), (at(0.95), 1), (1, 1))
        turns = (at(0.32), at(0.72))
    else:
        # Down: clear the nose of the current tread, move over the lower one, toe first.
        clearance = _uniform(rng, gait.stair_clearance_m)
        toe_off = _uniform(rng, gait.down_toe_off_deg) * DEG * stair_scale
        mid = _uniform(rng, gait.down_mid_swing_deg) * DEG * stair_scale
        landing = _uniform(rng, gait.down_landing_deg) * DEG * stair_scale
        forward = _uniform(rng, gait.stair_touchdown_mps)
        sink = _uniform(rng, gait.down_sink_mps)
        progress = ((0, 0), (at(0.06), 0), (at(0.72), 0.99))
        progress += touchdown(1.0, forward, length_m)
        z = ((0, 0), (at(0.35), clearance)) + touchdown(dz, -sink, 1.0)
        elev = ((0, 0), (at(0.35), toe_off), (at(0.65), mid), (u_stop, landing),
                (u_roll, 0.35 * landing), (1, 0))
        yaw = ((0, 0), (at(0.1), 0), (at(0.95), 1), (1, 1))
        turns = (at(0.35), at(0.65))
    return {'progress_knots': _knots(*progress, (1, 1)), 'z_knots': _knots(*z, (1, dz)),
            'elev_knots': _knots(*elev), 'yaw_knots': _knots(*yaw),
            'roll_knots': _knots(*_roll_knots(turns + (u_stop,), roll_rate, swing_s), (1, 0))}


def _roll_knots(turns: tuple, rate_rps: float, swing_s: float) -> tuple:
    """
    Roll knots that pass through zero where the pitch turns (its rate is zero there).

    The roll (inversion / eversion) alternates in sign between the pitch's turning points,
    peaking half-way with amplitude rate_rps * h (h: the time from the peak to the turning
    points), so it crosses zero at each turning point at about rate_rps: the foot never stops
    rotating in mid-swing. rate_rps < 0 starts with eversion.
    """
    knots = [(0.0, 0.0)]
    previous = 0.0
    for k, u in enumerate(turns):
        half_s = 0.5 * (u - previous) * swing_s
        knots += [(0.5 * (previous + u), rate_rps * half_s * (-1.0) ** k), (u, 0.0)]
        previous = u
    return tuple(knots)


# ----------------------------------------------------------------------------------------------
# Simulation
# ----------------------------------------------------------------------------------------------

def simulate_walk(segments, *, rng: np.random.Generator, rate_hz: float = 200.0,
                  imu='consumer', mounting_rpy_deg=(0.0, 0.0, 0.0), step_height_m: float = 0.17,
                  gait: GaitParams = GaitParams(), gravity_mps2: float = GRAVITY_MPS2,
                  initial_stand_s: float = DEFAULT_INITIAL_STAND_S,
                  final_stand_s: float = DEFAULT_FINAL_STAND_S) -> SimulatedWalk:
    """
    Simulate a walk: true foot motion and the readings of an IMU mounted on the foot.

    The walk starts with ``initial_stand_s`` at rest (>= 2 s, for the navigator's levelling)
    and ends with ``final_stand_s`` at rest. ``rng`` is split into two independent streams, one
    for the gait and one for the IMU errors, so the same seed gives the same trajectory for any
    IMU preset.

    Parameters
    ----------
    segments : sequence of Segment
        The walk plan (e.g. from building_walk()).
    rng : np.random.Generator
        Seeded generator, the only source of randomness.
    rate_hz : float
        IMU sample rate, Hz, 50..2000.
    imu : str or ImuErrorModel
        Error preset name ('ideal', 'tactical', 'consumer') or a model.
    mounting_rpy_deg : (3,) floats
        Roll, pitch, yaw of the mounting C_fb (v_f = C_fb v_b), deg; (180, 0, 0) mounts the
        IMU z axis down.
    step_height_m : float
        Riser height K for stair segments that give none, m.
    gait : GaitParams
        Ranges of the per-stride gait values.
    gravity_mps2 : float
        Gravity magnitude, m/s^2.
    initial_stand_s : float
        Time at rest before the first stride, s (>= 2).
    final_stand_s : float
        Time at rest after the last stride, s.

    Returns
    -------
    SimulatedWalk

    """
    segments = tuple(segments)
    if not segments or not all(isinstance(s, Segment) for s in segments):
        raise InputError('simulate_walk needs a non-empty sequence of Segment')
    if not isinstance(rng, np.random.Generator):
        raise InputError(f'rng must be a numpy.random.Generator, got {type(rng).__name__}')
    _check_range('rate_hz', rate_hz, 50.0, 2000.0)
    _check_range('step_height_m', step_height_m, 0.05, 0.30)
    _check_range('gravity_mps2', gravity_mps2, 9.7, 9.9)
    _check_range('initial_stand_s', initial_stand_s, MIN_INITIAL_STAND_S, 1e6)
    _check_range('final_stand_s', final_stand_s, 0.0, 1e6)
    mounting_rpy_deg = tuple(float(a) for a in mounting_rpy_deg)
    if len(mounting_rpy_deg) != 3:
        raise InputError(f'mounting_rpy_deg={mounting_rpy_deg} must be 3 angles (roll, pitch, '
                         'yaw) in degrees')
    model = imu_error_model(imu)
    gait_rng, imu_rng = rng.spawn(2)

    plans, t_end = _plan_strides(segments, gait, step_height_m, gait_rng, initial_stand_s)
    t_end += final_stand_s
    n = int(math.floor(t_end * rate_hz + 1e-9)) + 1
    offset_ns = np.round(np.arange(n) * (1e9 / rate_hz)).astype(np.int64)
    stamp_ns = EPOCH_NS + offset_ns
    t = offset_ns * 1e-9

    C_fb = rpy_to_dcm(*(a * DEG for a in mounting_rpy_deg))
    pos, vel, euler, stance, acc_true_b, gyr_true_b = _true_motion(plans, t, C_fb, gravity_mps2)
    if model.interval_mean:
        moving = np.zeros(n, dtype=bool)
        half_s = 0.5 / rate_hz
        for plan in plans:
            moving[np.searchsorted(t, plan.t_start_s - half_s, side='right'):np.searchsorted(
                t, plan.t_start_s + plan.swing_s + half_s, side='left')] = True
        acc_true_b[moving], gyr_true_b[moving] = interval_means(
            lambda times: _true_motion(plans, times, C_fb, gravity_mps2)[4:], t[moving],
            1.0 / rate_hz)
    q_nf = euler_zyx_to_quat(euler[:, 0], euler[:, 1], euler[:, 2])
    q_fb = euler_zyx_to_quat(*(np.array([a * DEG]) for a in mounting_rpy_deg))[0]
    quat_nb = _quat_multiply_batch(q_nf, q_fb)
    acc_b, gyr_b = apply_imu_errors(acc_true_b, gyr_true_b, rate_hz, model, imu_rng)

    return SimulatedWalk(
        stamp_ns=stamp_ns, acc_b=acc_b, gyr_b=gyr_b, pos_n=pos, vel_n=vel, quat_nb=quat_nb,
        stance=stance, strides=_stride_truth(plans, t, stamp_ns), rate_hz=float(rate_hz),
        imu=model, mounting_rpy_deg=mounting_rpy_deg, gravity_mps2=float(gravity_mps2),
        segments=segments)


def interval_means(signals, t: np.ndarray, dt_s: float, sub_samples: int = 8,
                   chunk: int = 32768) -> tuple:
    """
    Means of signals over the intervals [t_k - dt/2, t_k + dt/2] (midpoint rule).

    y_k = 1/dt integral x(t) dt over the interval ~ 1/S sum_j x(t_k + (j + 1/2 - S/2) dt / S),
    j = 0..S-1; the error is (dt / S)^2 / 24 x'' (second order), and S = 8 sub-samples resolve
    a 20 ms touch-down pulse at 100 Hz to within 1 %.

    Parameters
    ----------
    signals : callable
        signals(times) -> tuple of (M, 3) arrays at the (M,) sorted times, s.
    t : (K,) array
        Sorted sample times, s.
    dt_s : float
        Sample interval, s.
    sub_samples, chunk : int
        S, and samples evaluated at once (memory).

    Returns
    -------
    tuple of (K, 3) arrays, the interval means of each signal.

    """
    offsets = ((np.arange(sub_samples) + 0.5) / sub_samples - 0.5) * dt_s
    parts = []
    for start in range(0, len(t), chunk):
        times = (t[start:start + chunk, None] + offsets).ravel()
        parts.append([x.reshape(-1, sub_samples, 3).mean(axis=1) for x in signals(times)])
    if not parts:
        return tuple(np.zeros((0, 3)) for _ in signals(np.zeros(0)))
    return tuple(np.concatenate(p) for p in zip(*parts))


def _true_motion(plans, t: np.ndarray, C_fb: np.ndarray, gravity_mps2: float) -> tuple:
    """
    Truth and exact IMU signals at times t (s).

    Returns pos, vel (N, 3) in n, the foot's Euler angles (N, 3), the stance flags (N,), and the
    specific force and angular rate in b (N, 3): f_b = C_bf C_fn (a_n - g_n), w_b = C_bf w_f.
    """
    pos, vel, acc, euler, euler_rate, stance = _trajectory(plans, t)
    C_nf = euler_zyx_to_dcm(euler[:, 0], euler[:, 1], euler[:, 2])
    gyr_f = body_rate_from_euler_zyx(euler[:, 0], euler[:, 1], *euler_rate.T)
    gyr_b = gyr_f @ C_fb                             # rows: C_fb^T w_f
    acc_b = specific_force_b(acc, C_nf, gravity_mps2) @ C_fb
    return pos, vel, euler, stance, acc_b, gyr_b


def _trajectory(plans, t: np.ndarray):
    """
    Evaluate the stride plans at times t (s).

    Returns pos, vel, acc (N, 3) in n, the foot's Euler angles (roll, pitch, yaw) and their
    rates (N, 3), and the stance flags (N,).
    """
    n = len(t)
    pos = np.zeros((n, 3))
    vel = np.zeros((n, 3))
    acc = np.zeros((n, 3))
    euler = np.zeros((n, 3))
    euler_rate = np.zeros((n, 3))
    stance = np.ones(n, dtype=bool)
    for i, plan in enumerate(plans):
        t1 = plan.t_start_s + plan.swing_s
        a = int(np.searchsorted(t, plan.t_start_s, side='left'))
        b = int(np.searchsorted(t, t1, side='left'))
        c = int(np.searchsorted(t, plans[i + 1].t_start_s, side='left')) if i + 1 < len(
            plans) else n
        if b > a:   # the swing has samples (not so in most chunks of interval_means)
            u = (t[a:b] - plan.t_start_s) / plan.swing_s
            stance[a:b] = u <= 0.0
            duration = plan.swing_s
            s, ds, dds = _chain(u, plan.progress_knots, duration)
            d_xy = plan.pos1_n[:2] - plan.pos0_n[:2]
            pos[a:b, :2] = plan.pos0_n[:2] + s[:, None] * d_xy
            vel[a:b, :2] = ds[:, None] * d_xy
            acc[a:b, :2] = dds[:, None] * d_xy
            z, dz, ddz = (a + b for a, b in zip(_chain(u, plan.z_knots, duration),
                                                _chain(u, plan.lift_knots, duration)))
            pos[a:b, 2] = plan.pos0_n[2] + z
            vel[a:b, 2] = dz
            acc[a:b, 2] = ddz
            roll, droll, _ = _chain(u, plan.roll_knots, duration)
            elev, delev, _ = _chain(u, plan.elev_knots, duration)
            f, df, _ = _chain(u, plan.yaw_knots, duration)
            turn = plan.yaw1 - plan.yaw0
            euler[a:b] = np.stack([roll, -elev, plan.yaw0 + f * turn], axis=-1)
            euler_rate[a:b] = np.stack([droll, -delev, df * turn], axis=-1)
        # Stance after the swing: the end pose, at rest, until the next swing.
        pos[b:c] = plan.pos1_n
        euler[b:c, 2] = plan.yaw1
    return pos, vel, acc, euler, euler_rate, stance


def _chain(u: np.ndarray, knots: tuple, duration_s: float) -> tuple:
    """Evaluate a knot chain (u, y, v, a) with knot_profile."""
    knots_u, knots_y, knots_v, knots_a = knots
    return knot_profile(u, knots_u, knots_y, duration_s, knots_v, knots_a)


def _stride_truth(plans, t: np.ndarray, stamp_ns: np.ndarray) -> StrideTruth:
    t_end = np.array([p.t_start_s + p.swing_s for p in plans])
    t_start = np.array([p.t_start_s for p in plans])
    end_index = np.searchsorted(t, t_end, side='left')
    start_index = np.searchsorted(t, t_start, side='right')
    pos0 = np.array([p.pos0_n for p in plans]).reshape(-1, 3)
    pos1 = np.array([p.pos1_n for p in plans]).reshape(-1, 3)
    return StrideTruth(
        stamp_ns=stamp_ns[end_index],
        swing_start_ns=stamp_ns[start_index],
        mode=np.array([p.mode for p in plans], dtype=np.int8),
        height_change_m=pos1[:, 2] - pos0[:, 2],
        n_steps=np.array([p.n_steps for p in plans], dtype=np.int64),
        step_height_m=np.array([p.step_height_m for p in plans], dtype=float),
        start_pos_n=pos0,
        end_pos_n=pos1,
        heading_change_rad=np.array([p.yaw1 - p.yaw0 for p in plans], dtype=float),
        segment_index=np.array([p.segment_index for p in plans], dtype=np.int64))


# ----------------------------------------------------------------------------------------------
# Scenarios
# ----------------------------------------------------------------------------------------------

def nominal_duration_s(segments, gait: GaitParams = GaitParams(),
                       step_height_m: float = 0.17) -> float:
    """
    Return the expected duration of the segments alone (mid-range stride times), s.

    Excludes simulate_walk's initial and final stands.
    """
    total = 0.0
    for seg in segments:
        if seg.kind == 'stand':
            total += seg.duration_s
            continue
        for n_steps, *_ in _segment_strides(seg, step_height_m):
            if seg.kind == 'level':
                total += sum(gait.level_stride_s) / 2
            elif seg.kind == 'turn':
                total += sum(gait.turn_stride_s) / 2
            else:
                total += (sum(gait.stair_stride_base_s)
                          + n_steps * sum(gait.stair_stride_per_step_s)) / 2
    return total


def building_walk(*, step_height_m: float = 0.15, steps_per_flight: int = 18,
                  steps_per_stride: int = 2, total_duration_s: float = 640.0,
                  gait: GaitParams = GaitParams()) -> tuple:
    """
    Plan the issue's seed replica: down two flights, a long level walk, back up the stairs.

    Plan: start upstairs (walk 20 strides to the stairwell, stand 10 s), down 2 flights of
    ``steps_per_flight`` steps of ``step_height_m`` with a 180 deg landing turn, about 500 s of
    level walking in out-and-back corridor legs with turns while walking, turns on the spot and
    stops, then turn round and back up both flights, walk 20 strides and stand. The level part
    is sized so that the walk, with simulate_walk's default stands, lasts about
    ``total_duration_s`` (640 s: 36 steps x 0.15 m = 5.4 m down and up).

    Returns
    -------
    tuple of Segment, for simulate_walk.

    """
    _check_range('total_duration_s', total_duration_s, 200.0, 1e5)
    flight = {'steps_per_stride': steps_per_stride, 'step_height_m': step_height_m}
    down = (Segment.stairs(steps_per_flight, -1, **flight),
            Segment.level(2, turn_deg=180.0, stride_length_m=0.7),
            Segment.stairs(steps_per_flight, -1, **flight))
    up = (Segment.turn(180.0),
          Segment.stairs(steps_per_flight, +1, **flight),
          Segment.level(2, turn_deg=-180.0, stride_length_m=0.7),
          Segment.stairs(steps_per_flight, +1, **flight))
    head = (Segment.level(20), Segment.stand(10.0)) + down
    tail = up + (Segment.level(20), Segment.stand(5.0))
    block = (Segment.level(20), Segment.level(3, turn_deg=90.0), Segment.level(12),
             Segment.stand(8.0), Segment.turn(180.0), Segment.level(12),
             Segment.level(3, turn_deg=-90.0), Segment.level(20), Segment.stand(12.0),
             Segment.turn(-180.0))
    budget = (total_duration_s - DEFAULT_INITIAL_STAND_S - DEFAULT_FINAL_STAND_S
              - nominal_duration_s(head + tail, gait))
    middle = ()
    while nominal_duration_s(middle + block, gait) <= budget:
        middle += block
    stride_s = sum(gait.level_stride_s) / 2
    rest = budget - nominal_duration_s(middle, gait)
    if rest >= 2 * stride_s:
        # Out and back along the same corridor for the remaining time.
        half = int((rest - 2 * sum(gait.turn_stride_s)) / (2 * stride_s))
        if half >= 1:
            middle += (Segment.level(half), Segment.turn(180.0), Segment.level(half),
                       Segment.turn(180.0))
    return head + middle + tail


def random_walk(duration_s: float, rng: np.random.Generator, *,
                step_height_range_m: tuple = (0.14, 0.19),
                steps_per_stride_weights: tuple = (0.35, 0.5, 0.1, 0.05),
                max_floors: int = 3, gait: GaitParams = GaitParams()) -> tuple:
    """
    Plan a random mixture of level walking, stair flights, turns and stops (training data).

    Activities are drawn until the nominal duration reaches ``duration_s`` (minus simulate_walk's
    default stands): level walks of 3-15 strides (straight or turning up to 180 deg), stair
    flights of 6-20 steps (often two flights with a landing turn) with a riser height drawn per
    staircase from ``step_height_range_m`` and steps per stride 1..4 drawn with
    ``steps_per_stride_weights``, turns on the spot of 45-180 deg and stops of 2-10 s. The floor
    stays within +-``max_floors`` flights of the start.

    Returns
    -------
    tuple of Segment, for simulate_walk (its duration is within a few strides of duration_s).

    """
    _check_range('duration_s', duration_s, 5.0, 1e6)
    if not isinstance(rng, np.random.Generator):
        raise InputError(f'rng must be a numpy.random.Generator, got {type(rng).__name__}')
    low, high = step_height_range_m
    _check_range('step_height_range_m[0]', low, 0.05, 0.30)
    _check_range('step_height_range_m[1]', high, low, 0.30)
    weights = np.asarray(steps_per_stride_weights, dtype=float)
    if weights.shape != (4,) or np.any(weights < 0) or weights.sum() <= 0:
        raise InputError(f'steps_per_stride_weights={steps_per_stride_weights} must be 4 '
                         'non-negative weights for 1, 2, 3, 4 steps per stride')
    weights = weights / weights.sum()
    budget = duration_s - DEFAULT_INITIAL_STAND_S - DEFAULT_FINAL_STAND_S
    segments = []
    elapsed = 0.0
    floor = 0
    while elapsed < budget:
        activity = rng.choice(4, p=(0.4, 0.3, 0.15, 0.15))
        if activity == 0:
            turn = float(rng.choice((0.0, 0.0, 0.0, 45.0, 90.0, 180.0))) * rng.choice((-1, 1))
            n = int(rng.integers(3, 16))
            new = [Segment.level(n, turn_deg=turn if abs(turn) <= 60.0 * n else 0.0)]
        elif activity == 1:
            direction = int(rng.choice((-1, 1)))
            if abs(floor + direction) > max_floors:
                direction = -direction
            flights = 2 if rng.uniform() < 0.6 else 1
            k = _uniform(rng, (low, high))
            steps = int(rng.integers(6, 21))
            per_stride = int(rng.choice(4, p=weights)) + 1
            side = float(rng.choice((-1.0, 1.0)))
            new = [Segment.level(1)]
            for j in range(flights):
                if j:
                    new.append(Segment.level(2, turn_deg=180.0 * side, stride_length_m=0.7))
                new.append(Segment.stairs(steps, direction, steps_per_stride=per_stride,
                                          step_height_m=k))
            floor += direction
        elif activity == 2:
            new = [Segment.turn(_uniform(rng, (45.0, 180.0)) * rng.choice((-1, 1)))]
        else:
            new = [Segment.stand(_uniform(rng, (2.0, 10.0)))]
        segments.extend(new)
        elapsed += nominal_duration_s(new, gait)
    return tuple(segments)


def sample_walk() -> tuple:
    """
    Plan a short demo walk (about 65 s): level, a flight up, turn, the flight down, level.

    Stair segments leave the riser height to simulate_walk's ``step_height_m``.
    """
    return (Segment.level(15),
            Segment.stairs(14, +1),
            Segment.level(1, stride_length_m=0.5),
            Segment.stand(5.0),
            Segment.turn(180.0),
            Segment.stairs(14, -1),
            Segment.level(15),
            Segment.stand(5.0))
