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
The walk plan: segments of a walk and the ranges of the gait values drawn for each stride.

Public API: ``Segment``, ``GaitParams``, ``EPOCH_NS``, ``DEFAULT_TREAD_M`` and the default stand
times.
"""

from dataclasses import dataclass, fields
import math

from ..core.errors import InputError
from ..core.validation import check_range

EPOCH_NS = 1_700_000_000_000_000_000  # stamp of the first sample, ns (2023-11-14T22:13:20Z)
DEFAULT_INITIAL_STAND_S = 3.0  # at rest before the first stride: the navigator levels itself
DEFAULT_FINAL_STAND_S = 2.0
MIN_INITIAL_STAND_S = 2.0
STAND_S = 1.0                  # a stance this long or longer is standing (GaitParams sway)
SEGMENT_KINDS = ('level', 'stairs', 'turn', 'stand')
DEFAULT_TREAD_M = 0.28        # tread depth of a flight, m: 2R + G = 0.56-0.66 m for R 0.14-0.19 m
DEG = math.pi / 180.0


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
    tread_m: float = DEFAULT_TREAD_M
    turn_deg: float = 0.0
    stride_length_m: float | None = None
    duration_s: float = 0.0

    def __post_init__(self):
        if self.kind not in SEGMENT_KINDS:
            raise InputError(f'Segment.kind={self.kind!r} is not one of {SEGMENT_KINDS}')
        if self.kind == 'level':
            check_range('Segment.n_strides', self.n_strides, 1, 100_000)
            if self.stride_length_m is not None:
                check_range('Segment.stride_length_m', self.stride_length_m, 0.2, 2.5)
            check_range('Segment abs(turn_deg)', abs(self.turn_deg), 0.0,
                        120.0 * self.n_strides, note='at most 120 deg per stride')
        elif self.kind == 'stairs':
            check_range('Segment.n_steps', self.n_steps, 1, 1000)
            if self.direction not in (-1, 1):
                raise InputError(
                    f'Segment.direction={self.direction} must be +1 (up) or -1 (down)')
            check_range('Segment.steps_per_stride', self.steps_per_stride, 1, 4)
            if self.step_height_m is not None:
                check_range('Segment.step_height_m', self.step_height_m, 0.05, 0.30)
            check_range('Segment.tread_m', self.tread_m, 0.15, 0.50)
        elif self.kind == 'turn':
            check_range('Segment abs(turn_deg)', abs(self.turn_deg), 1.0, 720.0)
        else:
            check_range('Segment.duration_s', self.duration_s, 0.01, 1e6)

    @classmethod
    def level(cls, n_strides: int, *, turn_deg: float = 0.0,
              stride_length_m: float | None = None) -> 'Segment':
        """Walk ``n_strides`` strides on the level, turning by ``turn_deg`` in total."""
        return cls('level', n_strides=int(n_strides), turn_deg=float(turn_deg),
                   stride_length_m=stride_length_m)

    @classmethod
    def stairs(cls, n_steps: int, direction: int, *, steps_per_stride: int = 2,
               step_height_m: float | None = None, tread_m: float = DEFAULT_TREAD_M) -> 'Segment':
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
    the pitch turns (a random sign per stride). A foot on the ground is not still: it sways
    about the IMU at ``sway_hz``, with a peak rate per axis of ``stance_sway_rps`` in a walking
    stance and ``stand_sway_rps`` in a stance of ``STAND_S`` or longer (standing); (0, 0) keeps
    it still.
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
    stance_sway_rps: tuple = (0.03, 0.08)
    stand_sway_rps: tuple = (0.01, 0.03)
    sway_hz: tuple = (1.0, 3.0)

    def __post_init__(self):
        for field in fields(self):
            value = getattr(self, field.name)
            if isinstance(value, tuple):
                if len(value) != 2 or not value[0] <= value[1]:
                    raise InputError(f'GaitParams.{field.name}={value} must be (low, high) '
                                     'with low <= high')
                if field.name.endswith(('_m', '_s', '_mps', 'fraction')) and value[0] <= 0:
                    raise InputError(f'GaitParams.{field.name}={value} must be positive')
        check_range('GaitParams.stance_fraction', self.stance_fraction[1], 0.0, 0.8)
        check_range('GaitParams.swing_roll_rps', self.swing_roll_rps[1], 0.0, 5.0)
        check_range('GaitParams.stance_sway_rps', self.stance_sway_rps[1], 0.0, 0.5)
        check_range('GaitParams.stand_sway_rps', self.stand_sway_rps[1], 0.0, 0.5)
        check_range('GaitParams.sway_hz', self.sway_hz[0], 0.1, 20.0)
        check_range('GaitParams.sway_hz', self.sway_hz[1], 0.1, 20.0)
        check_range('GaitParams.stride_length_jitter', self.stride_length_jitter, 0.0, 0.2)
        check_range('GaitParams.toe_from_imu_m', self.toe_from_imu_m, 0.0, 0.3)
        check_range('GaitParams.heel_from_imu_m', self.heel_from_imu_m, 0.0, 0.3)
        shortest_swing_s = (1.0 - self.stance_fraction[1]) * min(
            self.level_stride_s[0], self.turn_stride_s[0],
            self.stair_stride_base_s[0] + self.stair_stride_per_step_s[0])
        check_range('GaitParams 2 * impact_s[1] + foot_flat_s[1]',
                    2.0 * self.impact_s[1] + self.foot_flat_s[1], 0.0, 0.5 * shortest_swing_s,
                    note=f'at most half the shortest swing ({shortest_swing_s:.3f} s), so that '
                    'the touch-down fits in every swing')
