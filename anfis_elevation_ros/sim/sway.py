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
Sway of a foot on the ground: the small rotation of a loaded or standing foot about the IMU.

A real foot is never still on the ground: a standing foot sways at 1-2 deg/s (the pyshoe VICON
stands, measured for the gyro bias; doc/hallway_notebook.md,
"Why the VICON trials learned z-gyro biases") and a walking stance rolls from heel to toe.
Without it the simulated gyro reads its bias alone through every stance, and a zero angular rate
update (ZARU) learns the bias at every stride, as it never can on a real walk. Each stance (the
stand before the first stride, then the stance after each swing) gets, per Euler angle, a sway
of a whole number m of half periods over its duration T (tau from the stance start):

    delta(tau) = (R / omega) sin(omega tau),   omega = m pi / T,   m = max(1, round(2 f T)),
    delta'(tau) = R cos(omega tau),

so the attitude is continuous with the swings on both sides (delta(0) = delta(T) = 0) and the
rate peaks at |R|; it steps by up to |R| at the stance's ends, at the impact and at heel-off. The
IMU stays where it is (the stance's position and velocity are unchanged: ZUPTs stay exact). R
and f are drawn per stance and axis: |R| from ``GaitParams.stance_sway_rps``, or
``stand_sway_rps`` for a stance of ``STAND_S`` or longer, its sign at random, f from
``sway_hz``.

Public API: ``stance_intervals``, ``draw_sway``, ``stance_sway``, ``add_sway``.
"""

import numpy as np

from .plan import GaitParams, STAND_S


def stance_intervals(plans, t_end_s: float) -> list:
    """Start and end (s) of every stance: the first stand, then the stance after each swing."""
    if not plans:
        return [(0.0, t_end_s)]
    starts = [0.0] + [p.t_start_s + p.swing_s for p in plans]
    ends = [p.t_start_s for p in plans] + [t_end_s]
    return list(zip(starts, ends))


def draw_sway(intervals, gait: GaitParams, rng: np.random.Generator) -> np.ndarray:
    """
    Per stance and Euler angle (roll, pitch, yaw): R (rad/s) and f (Hz); (S, 3, 2).

    R's sign is random: the rate steps at the stance's ends would otherwise all go one way and
    a point-sampling gyro's integration error at them would turn the heading steadily (the
    seed-003 walk's plain filter drifted 19.2 m instead of 5.4 m on average).
    """
    sway = np.empty((len(intervals), 3, 2))
    for k, (start, end) in enumerate(intervals):
        low, high = gait.stand_sway_rps if end - start >= STAND_S else gait.stance_sway_rps
        sway[k, :, 0] = rng.uniform(low, high, 3) * rng.choice((-1.0, 1.0), 3)
        sway[k, :, 1] = rng.uniform(*gait.sway_hz, 3)
    return sway


def stance_sway(tau: np.ndarray, duration_s: float, rate_rps: float, freq_hz: float) -> tuple:
    """
    One Euler angle's sway and its rate at times tau into a stance of duration T.

    delta = (R / omega) sin(omega tau), delta' = R cos(omega tau), omega = m pi / T,
    m = max(1, round(2 f T)).
    """
    omega = max(1, round(2.0 * freq_hz * duration_s)) * np.pi / duration_s
    return rate_rps / omega * np.sin(omega * tau), rate_rps * np.cos(omega * tau)


def add_sway(t: np.ndarray, intervals, sway: np.ndarray, euler: np.ndarray,
             euler_rate: np.ndarray) -> None:
    """Add each stance's sway (:func:`stance_sway`) to the Euler angles and rates at times t."""
    for (start, end), axes in zip(intervals, sway):
        a, b = np.searchsorted(t, [start, end], side='left')
        if b <= a or end <= start:
            continue
        tau = t[a:b] - start
        for axis, (rate_rps, freq_hz) in enumerate(axes):
            angle, rate = stance_sway(tau, end - start, rate_rps, freq_hz)
            euler[a:b, axis] += angle
            euler_rate[a:b, axis] += rate
