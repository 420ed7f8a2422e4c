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
IMU error model and presets (ideal, tactical grade, consumer grade).

Misalignment and scale factor, turn-on bias, bias random walk, white noise, saturation and
quantisation, applied in that order by ``apply_imu_errors``.

Public API: ``ImuErrorModel``, ``IMU_PRESETS``, ``imu_error_model``, ``apply_imu_errors``.

References
----------
[1] InvenSense, MPU-9250 Product Specification PS-MPU-9250A-01 rev. 1.0, 2014, tables 1-2.
[2] IEEE Std 952-1997, gyro noise terms (angle random walk, rate random walk).
[3] P. D. Groves, Principles of GNSS, Inertial, and Multisensor Integrated Navigation Systems,
    2nd ed., Artech House, 2013, ch. 4 (IMU error models).

"""

from dataclasses import dataclass, fields
import math

import numpy as np

from .plan import DEG
from ..core.errors import InputError
from ..core.validation import check_range

_G0 = 9.80665  # for units given in g (mg, ug), independent of the simulated gravity


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
            if field.name not in ('name', 'interval_mean'):
                check_range(f'ImuErrorModel.{field.name}', getattr(self, field.name), 0.0,
                            math.inf)
        check_range('ImuErrorModel.gyr_range_rps', self.gyr_range_rps, 1e-3, math.inf)
        check_range('ImuErrorModel.acc_range_mps2', self.acc_range_mps2, 1e-3, math.inf)
        if self.adc_bits:
            check_range('ImuErrorModel.adc_bits', self.adc_bits, 8, 32, note='or 0: none')
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
    # Consumer MEMS, MPU-9250 / BMI160 class. Noise densities from the MPU-9250 datasheet [1]:
    # gyro 0.01 deg/s/sqrt(Hz), acc 300 ug/sqrt(Hz).
    # Ranges +-2000 deg/s and +-16 g, 16-bit words (16.4 LSB/(deg/s), 2048 LSB/g) [1].
    # Turn-on bias, scale factor and misalignment are those left after a simple user
    # calibration: 0.5 deg/s and 30 mg, 0.5 %, 0.5 deg (untrimmed datasheet tolerances are
    # +-5 deg/s, +-60..80 mg, +-3 %, +-2 % cross-axis [1]). Bias walks: 0.002 deg/s/sqrt(s) and
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
