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
Stance detection from the gait's structure: one stance between two swings.

The SHOE threshold alone (``core/zupt.py``) misses the stances of a brisk walk, where the foot
is never still enough (statistic minima up to 1.9e8 against gamma 6-8e7 on gdin_hallway), and
a threshold raised to catch them takes the mid-swing reversal of the foot's rotation (the gyro
through zero for a few samples) for a stance. The gate uses what every stride has:

- a swing: the statistic above ``swing_level`` for ``swing_arm_s`` arms the gate;
- one stance after it: the first stance (SHOE, or relaxed below) of an armed gate opens a new
  gait cycle; a stance within ``max_break_s`` of the last continues it (a stance broken by a
  few moving samples is one stance); any other stance gets its ZUPT but is no gait stance
  (no swing since the last: shuffling, turning on the spot);
- relaxed stance: once ``refractory_fraction`` of the running stride period has passed since
  the last stance sample (the mid-swing dip comes earlier; counted from the start of the last
  cycle's stance, as until 2026-12-06, a stair stride's long stance put that moment in
  mid-swing, where the foot hovers over the next step: x-io's spiral stairs were cut into 51
  cycles for 33 strides), the lowest statistic of the armed
  gate counts as a stance when it has stayed the lowest for ``confirm_s``, if it is below
  the bound max(``relaxed_factor`` x gamma, ``relaxed_floor``) and the statistic of that
  confirming sample below ``current_factor`` x the bound. The ZUPT is applied at the
  confirming sample, ``confirm_s`` after the minimum: a sample that is itself almost still (a
  brief dip just before the heel strikes is followed by the impact, not by a stance); nothing
  waits, so live and replay stay identical. A relaxed stance is a young stance: with an
  implausible ZUPT (NIS above ``zupt.young_stance_max_nis``) it is none (a foot dropping
  down a stair without turning, 0.3 s before it lands).
- late stance: a stance too shaky for either (a brisk or running stride never stills the foot,
  a gentle first step meets a bound still at its floor) leaves the gate armed into the next
  swing. When that swing has armed (``swing_arm_s`` above ``swing_level``) with no stance
  since the first, the lowest statistic between them (after the refractory period) is a
  candidate; if no stance follows within ``late_balance`` times the time from the last stance
  to it (a dip late in a swing is followed by its stance sooner: 0.24-0.32 s after dips 0.7-0.9
  s into the swing on gdin_hallway, 0.66-1.35 s after the missed stances), it was the stance.
  A candidate is kept only if its INS velocity is plausible as the filter's velocity error:
  the ZUPT's normalised innovation squared at most ``late_max_nis`` (0-138 at gdin_hallway's
  late stances, 424-952 at the dips of long simulated stair swings, where the foot moves at
  1.5-2.5 m/s). The gate reports it then, with its age (``LATE_AGE``); the navigator applies
  the velocity there as a ZUPT late (``navigation_step``) and carries its correction back to
  the cycle's samples since then (``GaitSegmenter.late_stance``). It closes the gait cycle
  only on level ground (a slope of at most ``late_max_slope`` from the cycle's stance, and
  in the cycle before): cut on stairs, HuGaDB's stair cycles were brisk stair strides the
  classifier calls level (doc/hallway_notebook.md, "Late stances").

``stride_gate_update`` is the per-sample step (compiled, called by the navigator's kernel);
``samples_to_relaxed_stance`` tells the live node when a relaxed stance may be due.
"""

from dataclasses import dataclass
import math

import numpy as np

from .ekf import zupt_nis
from .jit import jit
from .validation import check_range

# Layout of the gate's state array:
ARMED, SWING_SAMPLES, RUN_MIN, MIN_AGE, SINCE_ONSET, PERIOD_S, SINCE_STANCE, LAST_GAIT, \
    ONSETS, SWING_RUN, CANDIDATE_AGE, CANDIDATE_SPAN, LATE_AGE = range(13)
MIN_VEL, CANDIDATE_VEL, LATE_DPOS, LATE_DVEL = (slice(13, 16), slice(16, 19), slice(19, 22),
                                                slice(22, 25))
N_INTERVALS = 5
INTERVALS = slice(25, 25 + N_INTERVALS)
N_STATE = INTERVALS.stop
# and of its settings array:
RELAXED_FACTOR, REFRACTORY, SWING_LEVEL, ARM_SAMPLES, CONFIRM_SAMPLES, RATE_HZ, MIN_PERIOD_S, \
    MAX_PERIOD_S, ENABLED, RELAXED_SIGMA, RELAXED_FLOOR, MAX_BREAK_SAMPLES, CURRENT_FACTOR, \
    LATE_BALANCE, LATE_SIGMA, LATE_MAX_NIS = range(16)
N_CONFIG = 16


@dataclass(frozen=True)
class StrideGateParams:
    """
    Parameters of the stride gate.

    Attributes
    ----------
    enabled : use the gate (else every SHOE stance is a stance and opens a cycle after a swing);
        on by default since 2026-12-06, when the default models were trained with it.
    relaxed_factor, relaxed_floor : a relaxed stance needs a statistic below
        max(relaxed_factor x gamma, relaxed_floor).
    refractory_fraction : no relaxed stance before this fraction of the stride period has
        passed since the last stance sample.
    swing_level : statistic of a swing (3e8: a foot turning at 1.5 rad/s), dimensionless.
    swing_arm_s : time above ``swing_level`` that makes a swing, s.
    confirm_s : a minimum counts when no lower statistic follows for this long, s.
    min_period_s, max_period_s : bounds of the running stride period (median of the last 5
        intervals between cycle starts), s.
    current_factor : the sample that confirms a relaxed stance (and gets its ZUPT) needs a
        statistic below this multiple of the bound (not the impact that follows a brief dip).
    max_break_s : a stance this soon after the last stance sample continues it, s.
    relaxed_sigma_mps : standard deviation of the ZUPT at a relaxed stance, m/s (the foot
        there is not quite still; 0.1 until 2026-12-06, which left the velocity error of
        HuGaDB's clipped swings in the next stride: its new-wearer accuracy 0.930 with the
        gate, 0.949 at 0.02; doc/classifier_notebook.md, "Fixed the same day").
    late_stances : find the stances between two swings after the fact (their ZUPT late).
    late_balance : a late stance needs no stance to follow it within this fraction of the time
        from the last stance to it.
    late_sigma_mps : standard deviation of a late stance's ZUPT (the velocity error grows by
        about g x 0.01 rad x 0.45 s between the late stance and the sample that finds it).
    late_max_nis : largest normalised innovation squared of a late stance's ZUPT.
    late_max_slope : a late stance closes its gait cycle when the foot reached it along a slope
        |dh| / run of at most this, and the cycle before kept to it too
        (``GaitSegmenter.late_stance``; 0.2: a ramp is at most 1:12, a stair 0.5-0.8); 0
        closes none.

    """

    enabled: bool = True
    relaxed_factor: float = 3.0
    relaxed_floor: float = 1.0e7
    refractory_fraction: float = 0.7
    swing_level: float = 3.0e8
    swing_arm_s: float = 0.05
    confirm_s: float = 0.05
    min_period_s: float = 0.5
    max_period_s: float = 2.0
    max_break_s: float = 0.15
    current_factor: float = 5.0
    relaxed_sigma_mps: float = 0.02
    late_stances: bool = True
    late_balance: float = 0.5
    late_sigma_mps: float = 0.05
    late_max_nis: float = 200.0
    late_max_slope: float = 0.2

    def __post_init__(self):
        for name, low, high in (('relaxed_factor', 1.0, 100.0),
                                ('relaxed_floor', 0.0, 1e13), ('refractory_fraction', 0.0, 1.0),
                                ('swing_level', 1.0, 1e13), ('swing_arm_s', 0.0, 1.0),
                                ('confirm_s', 0.0, 0.5), ('min_period_s', 0.1, 10.0),
                                ('max_period_s', self.min_period_s, 10.0),
                                ('max_break_s', 0.0, 1.0), ('current_factor', 1.0, 1e6),
                                ('relaxed_sigma_mps', 1e-4, 10.0),
                                ('late_balance', 0.0, 2.0),
                                ('late_sigma_mps', 1e-4, 10.0),
                                ('late_max_nis', 0.0, 1e12),
                                ('late_max_slope', 0.0, 10.0)):
            check_range(f'stride gate {name}', getattr(self, name), low, high)

    def config(self, rate_hz: float) -> np.ndarray:
        """Return the settings array of ``stride_gate_update`` at a sample rate."""
        config = np.zeros(N_CONFIG)
        config[[RELAXED_FACTOR, REFRACTORY, SWING_LEVEL, RATE_HZ, MIN_PERIOD_S, MAX_PERIOD_S,
                ENABLED, RELAXED_SIGMA, RELAXED_FLOOR]] = (
            self.relaxed_factor, self.refractory_fraction, self.swing_level, rate_hz,
            self.min_period_s, self.max_period_s, float(self.enabled), self.relaxed_sigma_mps,
            self.relaxed_floor)
        config[ARM_SAMPLES] = max(1, int(round(self.swing_arm_s * rate_hz)))
        config[CONFIRM_SAMPLES] = int(round(self.confirm_s * rate_hz))
        config[MAX_BREAK_SAMPLES] = int(round(self.max_break_s * rate_hz))
        config[CURRENT_FACTOR] = self.current_factor
        config[LATE_BALANCE] = self.late_balance if self.late_stances else math.inf
        config[LATE_SIGMA] = self.late_sigma_mps
        config[LATE_MAX_NIS] = self.late_max_nis
        return config


def initial_state() -> np.ndarray:
    """Return the gate's state at start-up: standing (a stance in progress), not armed."""
    state = np.zeros(N_STATE)
    state[RUN_MIN] = math.inf
    state[PERIOD_S] = 1.0
    state[LAST_GAIT] = 1.0
    state[CANDIDATE_AGE] = -1.0
    return state


@jit
def stride_gate_update(state: np.ndarray, config: np.ndarray, statistic: float, gamma: float,
                       shoe_stance: bool, vel_n: np.ndarray, P: np.ndarray,
                       young_max_nis: float) -> int:
    """
    One sample through the gate: 1 for a stance sample, plus 2 for a gait stance, plus 4 relaxed.

    Or 8 alone for a late stance, ``state[LATE_AGE]`` samples before this one (no ZUPT there;
    the navigator applies ``state[CANDIDATE_VEL]``, the velocity there, as its ZUPT now). A
    candidate whose ZUPT is implausible, NIS = v^T (H P H^T + R)^-1 v above ``late_max_nis``
    (``ekf.zupt_nis``), was no stance. Or 16 alone for a relaxed stance refused: a stance of
    one sample is a young stance, and as a young SHOE stance (``zupt.young_stance_waits``) it
    is no stance when its ZUPT's NIS, at ``relaxed_sigma_mps``, is above ``young_max_nis``
    (0: no test): a foot dropping down a stair at constant velocity without turning looks
    still to an IMU (random walk 524: 2.0-2.4 m/s, 0.3 s before it landed). The refused
    minimum stays the gate's: only a lower statistic, a SHOE stance or a late stance ends the
    swing (searching on from the next sample found a stance later in the same fall).

    A gait stance is a stance that opens a gait cycle (armed gate) or continues the last stance
    (within ``max_break_s``); any other stance still gets its ZUPT but does not cut the
    cycle. A relaxed stance (not a SHOE one)
    gets its ZUPT with ``relaxed_sigma_mps``.

    Parameters
    ----------
    state : (N_STATE,) array
        The gate's state (``initial_state``), updated in place.
    config : (N_CONFIG,) array
        ``StrideGateParams.config``.
    statistic : float
        SHOE statistic T_k of the sample (NaN while its window fills).
    gamma : float
        The SHOE threshold in force.
    shoe_stance : bool
        The SHOE decision: T below gamma for ``min_stance_s``.
    vel_n : (3,) array
        The INS velocity at the sample (kept at the lowest statistic: a late stance's ZUPT).
    P : (15, 15) array
        The error covariance at the sample (a late or relaxed stance's plausibility).
    young_max_nis : float
        ``ZuptParams.young_stance_max_nis``; 0 when the young-stance rule is off or the INS
        velocity is no evidence (after a gap).

    """
    if config[ENABLED] == 0.0:
        return 3 if shoe_stance else 0
    rate_hz = config[RATE_HZ]
    state[SINCE_ONSET] += 1.0
    state[SINCE_STANCE] += 1.0
    if state[CANDIDATE_AGE] >= 0.0:
        state[CANDIDATE_AGE] += 1.0
    if statistic > config[SWING_LEVEL]:
        state[SWING_SAMPLES] += 1.0
        state[SWING_RUN] += 1.0
        if state[SWING_SAMPLES] >= config[ARM_SAMPLES]:
            state[ARMED] = 1.0
    else:
        state[SWING_RUN] = 0.0
    stance = shoe_stance
    relaxed = 0
    if not stance and state[ARMED] != 0.0 \
            and state[SINCE_STANCE] >= config[REFRACTORY] * state[PERIOD_S] * rate_hz:
        if statistic < state[RUN_MIN]:
            state[RUN_MIN] = statistic
            state[MIN_AGE] = 0.0
            state[MIN_VEL] = vel_n
        else:
            state[MIN_AGE] += 1.0
        bound = max(config[RELAXED_FACTOR] * gamma, config[RELAXED_FLOOR])
        stance = state[MIN_AGE] == config[CONFIRM_SAMPLES] and state[RUN_MIN] < bound \
            and statistic < config[CURRENT_FACTOR] * bound
        if stance and young_max_nis > 0.0 \
                and zupt_nis(P, vel_n, config[RELAXED_SIGMA]) > young_max_nis:
            return 16
        relaxed = 4 if stance else 0
        if not stance and state[CANDIDATE_AGE] < 0.0 and state[SWING_RUN] >= config[ARM_SAMPLES] \
                and state[MIN_AGE] >= state[SWING_RUN] and state[RUN_MIN] < config[SWING_LEVEL]:
            # A second swing with no stance since the first: its lowest point may be one.
            state[CANDIDATE_AGE] = state[MIN_AGE]
            state[CANDIDATE_SPAN] = state[SINCE_STANCE] - state[MIN_AGE]
            state[CANDIDATE_VEL] = state[MIN_VEL]
    if not stance:
        if state[CANDIDATE_AGE] >= max(1.0, config[LATE_BALANCE] * state[CANDIDATE_SPAN]):
            if zupt_nis(P, state[CANDIDATE_VEL], config[LATE_SIGMA]) <= config[LATE_MAX_NIS]:
                return _late_stance(state, config)
            state[CANDIDATE_AGE] = -1.0
        return 0
    state[CANDIDATE_AGE] = -1.0
    state[SWING_SAMPLES] = 0.0
    continues = state[SINCE_STANCE] <= config[MAX_BREAK_SAMPLES] and state[LAST_GAIT] != 0.0
    state[SINCE_STANCE] = 0.0
    if state[ARMED] != 0.0:
        _open_cycle(state, config)
    elif not continues:
        state[LAST_GAIT] = 0.0
        return 1 + relaxed
    state[LAST_GAIT] = 1.0
    return 3 + relaxed


@jit
def samples_to_relaxed_stance(state: np.ndarray, config: np.ndarray, gamma: float) -> int:
    """Return the samples until the current minimum is confirmed as a stance, or -1 if none."""
    if config[ENABLED] == 0.0 or state[ARMED] == 0.0 or not state[RUN_MIN] < max(
            config[RELAXED_FACTOR] * gamma, config[RELAXED_FLOOR]) \
            or state[MIN_AGE] >= config[CONFIRM_SAMPLES]:
        return -1
    return int(config[CONFIRM_SAMPLES] - state[MIN_AGE])


@jit
def _late_stance(state: np.ndarray, config: np.ndarray) -> int:
    """Confirm the candidate as a stance found after the fact, a stride onset in the past."""
    age = state[CANDIDATE_AGE]
    state[LATE_AGE] = age
    state[CANDIDATE_AGE] = -1.0
    _open_cycle(state, config, age)
    state[ARMED] = 1.0
    state[SWING_SAMPLES] = config[ARM_SAMPLES]
    state[SINCE_STANCE] = age
    state[LAST_GAIT] = 1.0
    return 8


@jit
def _open_cycle(state: np.ndarray, config: np.ndarray, age: float = 0.0):
    """Open a gait cycle at a stance after a swing, ``age`` samples ago; add the interval."""
    if state[ONSETS] > 0.0:
        n = int(min(state[ONSETS], N_INTERVALS))
        slot = INTERVALS.start + int(state[ONSETS] - 1.0) % N_INTERVALS
        state[slot] = (state[SINCE_ONSET] - age) / config[RATE_HZ]
        period = np.median(state[INTERVALS.start:INTERVALS.start + n])
        state[PERIOD_S] = min(max(period, config[MIN_PERIOD_S]), config[MAX_PERIOD_S])
    state[ONSETS] += 1.0
    state[SINCE_ONSET] = age
    state[ARMED] = 0.0
    state[RUN_MIN] = math.inf
    state[MIN_AGE] = 0.0
