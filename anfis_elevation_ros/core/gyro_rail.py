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
Saturation recovery: the rotation a clipped gyro loses, rebuilt from the samples around it.

A foot gyro's swing-phase rate is a smooth peak. Where the peak exceeds the sensor's range
the sensor reports its rail (gdin_hallway walk 35: y at +-500 deg/s on 458 samples, runs of up
to 35 samples), and the rotation lost there is an attitude error that the ZUPTs book as gyro
bias. ``fill_rail_run`` replaces an axis's samples at the rail by a least-squares polynomial
through the samples just before and just after them, never below the rail in magnitude (the
sensor read at least that much).

``GyroRailStage`` does it per sample, ahead of the navigator, so that live and replay stay
identical: it passes samples through until one has an axis at the rail, then holds them until
``fit_samples`` samples in a row are clear of the rail on every axis and releases them
corrected. The latency it adds is only there while the gyro clips: at most ``max_run_s`` plus
``fit_samples`` sample periods (0.11 s at 200 Hz). A longer run is released as it came, and
so is every rail sample after it until the gyro leaves the rail (the EKF's rail noise,
``ekf.clipped_gyro_noise``, treats them as before): the output never stalls, and a long run's
peak is too far from the samples that would fit it. Each released sample carries the rate as
the sensor gave it too: the navigator integrates the rebuilt rate, while its stance detector
and the threshold's gait intensity keep the sensor's (fed the rebuilt peaks, the adaptive
threshold rose by up to 74 % and cut an extra cycle on walks 34 and 43).

Public API: ``GyroRailParams``, ``fill_rail_run``, ``GyroRailStage``.
"""

from collections import deque
from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .validation import check_range


@dataclass(frozen=True)
class GyroRailParams:
    """
    Saturation recovery of a clipped gyro (used only when ``gyro_range_rps`` is declared).

    Attributes
    ----------
    enabled : rebuild the clipped samples (on by default, acting only where
        ``gyro_range_rps`` is declared: see Notes).
    fit_samples : samples each side of a run that the polynomial is fitted to.
    fit_order : degree of the polynomial (less than 2 x ``fit_samples``).
    max_run_s : a run held longer than this is released as it came, s.
    range_fraction : a rate of this fraction of ``gyro_range_rps`` or more counts as clipped
        (it is rebuilt, not fitted to): the sensor reads the last per cent or two before its
        rail compressed (gdin_hallway: 8.42, 8.65, 8.70, 8.72 rad/s into a 8.73 rad/s rail).

    Notes
    -----
    Chosen on gdin_hallway walks 34 and 35 (fit_samples 2-4, degree 1-3, max_run_s
    0.05-0.2 s, range_fraction 0.97-0.99): walk 35 ends 1.9 % of the path off instead of
    12.7 % (plain filter), 1.6 % instead of 14.3 % with both heading aids; max_run_s holds
    from 0.07 to 0.11 s (longer: the running strides' 0.13-0.18 s plateaus are extrapolated
    too far). Held out: the pyshoe VICON trials gain (median 0.066 -> 0.063 m with both aids),
    gdin walk 43 ends worse (both aids 1.0 -> 1.5 %; with the stride gate its mean stride
    error 0.83 -> 0.96 m) and 38 a little (1.0 -> 1.1 %). On by default since 2026-12-05:
    without it a gyro that clips in the wearer's gait leaves the worst walk 15 % of its path
    off, worse with the heading aids than without (doc/hallway_notebook.md,
    "Rebuilding the clipped samples").

    """

    enabled: bool = True
    fit_samples: int = 2
    fit_order: int = 2
    max_run_s: float = 0.1
    range_fraction: float = 0.98

    def __post_init__(self):
        check_range('rail.fit_samples', self.fit_samples, 1, 20)
        check_range('rail.fit_order', self.fit_order, 1, 5)
        if self.fit_order >= 2 * self.fit_samples:
            raise InputError(f'rail.fit_order = {self.fit_order} needs more than '
                             f'{self.fit_order} fit points: rail.fit_samples >= '
                             f'{self.fit_order // 2 + 1}')
        check_range('rail.max_run_s', self.max_run_s, 0.0, 1.0)
        check_range('rail.range_fraction', self.range_fraction, 0.5, 1.0)


def fill_rail_run(t_s: np.ndarray, rate_rps: np.ndarray, rail_rps: float, fit_samples: int,
                  fit_order: int) -> np.ndarray:
    """
    Return one gyro axis with its samples at the rail rebuilt from the samples around them.

    With s and e the first and last sample at the rail (|w_k| >= rail) and K the
    ``fit_samples`` samples before s and after e, the polynomial p of degree ``fit_order``

        p = argmin_p sum_{k in K} (w_k - p(t_k))^2

    replaces the samples from s to e where it exceeds them in magnitude:

        w'_k = sgn(w_k) max(|w_k|, sgn(w_k) p(t_k)),   s <= k <= e

    The axis is returned unchanged when it never reaches the rail, or when fewer than
    ``fit_samples`` samples precede s or follow e (a run at either end of the record).

    Parameters
    ----------
    t_s : (N,) array
        Sample times, s.
    rate_rps : (N,) array
        The axis's angular rate, rad/s.
    rail_rps : float
        A rate of this magnitude or more is at the rail, rad/s.
    fit_samples, fit_order : int
        Samples each side of the run, and the polynomial's degree (< 2 x fit_samples).

    """
    at_rail = np.flatnonzero(np.abs(rate_rps) >= rail_rps)
    if at_rail.size == 0:
        return rate_rps
    s, e = at_rail[0], at_rail[-1]
    if s < fit_samples or e + fit_samples >= len(rate_rps):
        return rate_rps
    fit = np.r_[s - fit_samples:s, e + 1:e + 1 + fit_samples]
    t0 = 0.5 * (t_s[s] + t_s[e])          # centred: a well-conditioned fit
    coef = np.polyfit(t_s[fit] - t0, rate_rps[fit], fit_order)
    run = rate_rps[s:e + 1]
    sign = np.where(run < 0.0, -1.0, 1.0)
    filled = rate_rps.copy()
    filled[s:e + 1] = sign * np.maximum(np.abs(run), sign * np.polyval(coef, t_s[s:e + 1] - t0))
    return filled


class GyroRailStage:
    """
    Per-sample saturation recovery: holds samples while the gyro clips, releases them rebuilt.

    Parameters
    ----------
    rail_rps : float
        A rate of this magnitude or more is at the rail, rad/s.
    params : GyroRailParams
        Fit and hold settings.

    Examples
    --------
    >>> stage = GyroRailStage(8.64, GyroRailParams())
    >>> for stamp_ns, acc_b, gyr_b in samples:              # doctest: +SKIP
    ...     for stamp_ns, acc_b, gyr_b, sensor_gyr_b in stage.push(stamp_ns, acc_b, gyr_b):
    ...         navigate(stamp_ns, acc_b, gyr_b)

    """

    def __init__(self, rail_rps: float, params: GyroRailParams):
        self.rail_rps = float(rail_rps)
        self.params = params
        self._max_run_ns = int(round(params.max_run_s * 1e9))
        self._before = deque(maxlen=params.fit_samples)   # the last samples released
        self._held = []
        self._clear = 0          # held samples in a row clear of the rail
        self._passing = False    # releasing a run longer than max_run_s as it comes
        self.filled_samples = 0  # samples released rebuilt
        self.long_run_samples = 0  # rail samples released as they came (long runs)

    @property
    def holding(self) -> int:
        """Return the number of samples held now."""
        return len(self._held)

    def push(self, stamp_ns: int, acc_b: np.ndarray, gyr_b: np.ndarray) -> list:
        """
        Take one sample; return the samples released by it, in order (often just this one).

        Each is (stamp_ns, acc_b, gyr_b, sensor_gyr_b): gyr_b rebuilt where the sensor
        clipped, sensor_gyr_b as it was pushed.
        """
        sample = (stamp_ns, acc_b, gyr_b, gyr_b)
        at_rail = bool(np.any(np.abs(gyr_b) >= self.rail_rps))
        if self._passing:
            self._passing = at_rail
            self.long_run_samples += at_rail
            return self._release([sample])
        if not self._held and not at_rail:
            return self._release([sample])
        self._held.append(sample)
        if at_rail:
            self._clear = 0
            if stamp_ns - self._held[0][0] > self._max_run_ns:
                self._passing = True
                held = self._take_held()
                self.long_run_samples += sum(
                    bool(np.any(np.abs(g) >= self.rail_rps)) for _, _, g, _ in held)
                return self._release(held)
            return []
        self._clear += 1
        if self._clear < self.params.fit_samples:
            return []
        return self._release(self._rebuilt(self._take_held()))

    def flush(self) -> list:
        """Release the samples held now as they came (the record ended during a run)."""
        return self._release(self._take_held())

    def _take_held(self) -> list:
        held, self._held, self._clear = self._held, [], 0
        return held

    def _release(self, samples: list) -> list:
        self._before.extend(samples)
        return samples

    def _rebuilt(self, held: list) -> list:
        """Return the held samples with every axis's run rebuilt (``fill_rail_run``)."""
        p = self.params
        context = list(self._before) + held
        stamps = np.array([s for s, _, _, _ in context], dtype=np.int64)
        t_s = (stamps - stamps[0]) * 1e-9
        gyr = np.array([g for _, _, _, g in context])
        filled = np.column_stack([fill_rail_run(t_s, gyr[:, axis], self.rail_rps,
                                                p.fit_samples, p.fit_order)
                                  for axis in range(3)])
        first = len(context) - len(held)
        changed = np.any(filled[first:] != gyr[first:], axis=1)
        self.filled_samples += int(changed.sum())
        return [(stamp, acc, filled[first + k] if changed[k] else gyr_b, gyr_b)
                for k, (stamp, acc, gyr_b, _) in enumerate(held)]
