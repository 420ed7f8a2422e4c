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
Each stride of the instrumented foot is a swing followed by a stance (foot flat, the IMU in
place, the foot swaying about it: ``sway``). During the swing every coordinate -- horizontal
progress, height, roll, pitch, yaw -- follows a C2 chain of quintic pieces between knots that
fix the value and its first two derivatives
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

from dataclasses import dataclass
import math

import numpy as np

from .plan import DEG, GaitParams, Segment


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


def quat_multiply_batch(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """(N, 4) Hamilton products p * q of [w, x, y, z] quaternions (q may be (4,))."""
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(np.broadcast_to(q, p.shape), -1, 0)
    return np.stack([pw * qw - px * qx - py * qy - pz * qz,
                     pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy - px * qz + py * qw + pz * qx,
                     pw * qz + px * qy - py * qx + pz * qw], axis=-1)


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


def draw_uniform(rng: np.random.Generator, bounds: tuple) -> float:
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
        return draw_uniform(rng, gait.level_stride_s)
    if seg.kind == 'turn':
        return draw_uniform(rng, gait.turn_stride_s)
    return draw_uniform(rng, gait.stair_stride_base_s) + n_steps * draw_uniform(
        rng, gait.stair_stride_per_step_s)


def plan_strides(segments, gait: GaitParams, step_height_m: float, rng, t0_s: float):
    """Expand segments into stride plans; returns (plans, end time of the last stance)."""
    t = t0_s
    pos = np.zeros(3)
    yaw = 0.0
    plans = []
    for index, seg in enumerate(segments):
        if seg.kind == 'stand':
            t += seg.duration_s
            continue
        for stride in segment_strides(seg, step_height_m):
            n_steps, turn, dz, length, mode, riser_m = stride
            duration = _stride_duration_s(seg, n_steps, gait, rng)
            stance = duration * draw_uniform(rng, gait.stance_fraction)
            roll_rate = draw_uniform(rng, gait.swing_roll_rps) * float(rng.choice((-1.0, 1.0)))
            if seg.kind == 'level':
                if length is None:
                    length = draw_uniform(rng, gait.level_stride_length_m)
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


def segment_strides(seg: Segment, step_height_m: float):
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
    impact_s = draw_uniform(rng, gait.impact_s)
    flat_s = draw_uniform(rng, gait.foot_flat_s)
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
        clearance = draw_uniform(rng, gait.turn_clearance_m)
        toe_off = draw_uniform(rng, gait.turn_toe_off_deg) * DEG
        sink = draw_uniform(rng, gait.turn_sink_mps)
        progress = ((0, 0), (u_stop, 1))
        z = ((0, 0), (at(0.45), clearance)) + touchdown(0.0, -sink, 1.0)
        elev = ((0, 0), (at(0.4), toe_off), (u_stop, 0.3 * abs(toe_off)),
                (u_roll, 0.1 * abs(toe_off)), (1, 0))
        yaw = ((0, 0), (at(0.15), 0), (at(0.95), 1), (1, 1))
        turns = (at(0.4),)
    elif mode == 0:
        clearance = draw_uniform(rng, gait.level_clearance_m)
        toe_off = draw_uniform(rng, gait.level_toe_off_deg) * DEG
        landing = draw_uniform(rng, gait.level_landing_deg) * DEG
        forward = draw_uniform(rng, gait.level_touchdown_mps)
        sink = draw_uniform(rng, gait.level_sink_mps)
        # Half-way at 0.55 u_c keeps the peak foot speed at 4-5 m/s (2.5-3 x walking speed).
        progress = ((0, 0), (at(0.06), 0), (at(0.55), 0.52)) + touchdown(1.0, forward, length_m)
        z = ((0, 0), (at(0.45), clearance)) + touchdown(0.0, -sink, 1.0)
        elev = ((0, 0), (at(0.42), toe_off), (u_stop, landing), (u_roll, 0.35 * landing), (1, 0))
        yaw = ((0, 0), (at(0.1), 0), (at(0.95), 1), (1, 1))
        turns = (at(0.42),)
    elif mode > 0:
        # Up: lift above the target tread first, then move over it; forefoot first.
        clearance = draw_uniform(rng, gait.stair_clearance_m)
        toe_off = draw_uniform(rng, gait.up_toe_off_deg) * DEG * stair_scale
        mid = draw_uniform(rng, gait.up_mid_swing_deg) * DEG * stair_scale
        landing = draw_uniform(rng, gait.up_landing_deg) * DEG
        forward = draw_uniform(rng, gait.stair_touchdown_mps)
        sink = draw_uniform(rng, gait.up_sink_mps)
        progress = ((0, 0), (at(0.25), 0)) + touchdown(1.0, forward, length_m)
        z = ((0, 0), (at(0.6), dz + clearance)) + touchdown(dz, -sink, 1.0)
        elev = ((0, 0), (at(0.32), toe_off), (at(0.72), mid), (u_stop, landing),
                (u_roll, 0.35 * landing), (1, 0))
        yaw = ((0, 0), (at(0.1), 0), (at(0.95), 1), (1, 1))
        turns = (at(0.32), at(0.72))
    else:
        # Down: clear the nose of the current tread, move over the lower one, toe first.
        clearance = draw_uniform(rng, gait.stair_clearance_m)
        toe_off = draw_uniform(rng, gait.down_toe_off_deg) * DEG * stair_scale
        mid = draw_uniform(rng, gait.down_mid_swing_deg) * DEG * stair_scale
        landing = draw_uniform(rng, gait.down_landing_deg) * DEG * stair_scale
        forward = draw_uniform(rng, gait.stair_touchdown_mps)
        sink = draw_uniform(rng, gait.down_sink_mps)
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
