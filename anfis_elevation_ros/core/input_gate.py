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
The input gate: every IMU sample is checked here before it reaches the navigator.

``InputGate.check(stamp_ns, acc_b, gyr_b, frame_id)`` returns ``None`` for a sample the
navigator may take, else the reason it is refused. The checks run in this order, and the first
that fails names the reason:

==================  ==========================================================================
``non_finite``      a NaN or Inf in the six values.
``wrong_frame``     ``frame_id`` differs from ``GateParams.frame_id`` (only when that is set).
``out_of_order``    the stamp is earlier than the last accepted stamp.
``duplicate``       the stamp equals the last accepted stamp.
``wrong_units``     a gyro component beyond 40 rad/s (no MEMS gyro measures that: the data are
                    deg/s, see ``core/units.py``) or an accelerometer component beyond
                    1000 m/s^2 (about 100 g: mg or cm/s^2 data).
``saturated``       only with ``reject_saturated``: see below.
==================  ==========================================================================

Wrong units latch. One spike past 40 rad/s is refused alone, but a deg/s stream is wrong
throughout: at rest and in slow movements its values pass as plausible rad/s and would make
the navigator publish garbage. So ``UNITS_LATCH_COUNT`` wrong-units samples within
``UNITS_LATCH_WINDOW_S`` latch the gate: from then on every sample is refused as
``wrong_units`` (``units_latched`` is True, the node reports an error) until ``reset_units``
or a parameter change; fix the sensor's units and restart.

Saturation (a component at or above ``SATURATION_FRACTION`` of the configured full scale,
``acc_range_mps2`` or ``gyr_range_rps``) is by default ACCEPTED AND FLAGGED: counted in
``flagged['saturated']`` and passed on. A clipped heel strike still has the right sign and
most of its size, and it falls at the start of a stance, where the next zero-velocity update
removes the velocity error it leaves; dropping the sample would instead integrate the interval
as if the impact had not happened. ``reject_saturated=True`` refuses such samples instead.

An interval longer than ``max_gap_s`` since the last accepted sample is not refused either:
the navigator marks the gait cycle it falls in invalid. The gate counts it in
``flagged['gap']`` (from the first sample on, also before the navigator has started).

Only accepted samples move the last stamp on, so one wild stamp far in the future would make
every later sample ``out_of_order``. ``GateParams.max_future_jump_s`` prevents that: a stamp
more than this ahead of the last accepted one is refused as ``out_of_order`` too, unless
``RESYNC_SAMPLES`` consecutive samples agree with it (at most ``max_gap_s`` apart): that is a
real dropout or clock jump, accepted from its third sample on (and counted as a gap).

Public API: ``GateParams``, ``InputGate``, the reason constants ``NON_FINITE``,
``WRONG_FRAME``, ``OUT_OF_ORDER``, ``DUPLICATE``, ``WRONG_UNITS``, ``SATURATED``, ``GAP``,
``REJECT_REASONS`` and ``FLAG_REASONS``.
"""

from collections import Counter, deque
from dataclasses import dataclass
import math

from .errors import InputError
from .units import MAX_PHYSICAL_GYR_RPS
from .validation import check_range

NON_FINITE = 'non_finite'
WRONG_FRAME = 'wrong_frame'
OUT_OF_ORDER = 'out_of_order'
DUPLICATE = 'duplicate'
WRONG_UNITS = 'wrong_units'
SATURATED = 'saturated'
GAP = 'gap'

REJECT_REASONS = (NON_FINITE, WRONG_FRAME, OUT_OF_ORDER, DUPLICATE, WRONG_UNITS, SATURATED)
"""Every reason ``check`` can return (``saturated`` only with ``reject_saturated``)."""
FLAG_REASONS = (SATURATED, GAP)
"""Conditions counted on accepted samples."""

MAX_PLAUSIBLE_ACC_MPS2 = 1000.0
"""About 100 g: no accelerometer for body motion reads more; larger values are mg or cm/s^2."""
SATURATION_FRACTION = 0.999
"""A component at or above this fraction of the full scale counts as saturated (a sensor's
clip value is rarely exactly its nominal range)."""
RESYNC_SAMPLES = 3
"""Consecutive samples that confirm a forward stamp jump beyond ``max_future_jump_s``."""
UNITS_LATCH_COUNT = 10
"""Wrong-units samples within ``UNITS_LATCH_WINDOW_S`` that latch the gate (a deg/s stream
exceeds 40 'rad/s' in every stride; a spike is one or two samples)."""
UNITS_LATCH_WINDOW_S = 5.0

STANDARD_GRAVITY_MPS2 = 9.80665


@dataclass(frozen=True)
class GateParams:
    """
    Parameters of the input gate.

    Attributes
    ----------
    acc_range_mps2 : float
        Accelerometer full scale, m/s^2 (default 16 g).
    gyr_range_rps : float
        Gyroscope full scale, rad/s (default 2000 deg/s).
    reject_saturated : bool
        Refuse saturated samples instead of accepting and flagging them.
    frame_id : str
        Expected header frame_id of the IMU messages; '' accepts any.
    max_gap_s : float
        An interval longer than this is counted as a gap (the navigator's ``max_gap_s``).
    max_future_jump_s : float
        A stamp further ahead than this of the last accepted one is refused until
        ``RESYNC_SAMPLES`` samples confirm it.

    """

    acc_range_mps2: float = 16.0 * STANDARD_GRAVITY_MPS2
    gyr_range_rps: float = math.radians(2000.0)
    reject_saturated: bool = False
    frame_id: str = ''
    max_gap_s: float = 0.05
    max_future_jump_s: float = 1.0

    def __post_init__(self):
        check_range('GateParams.acc_range_mps2', self.acc_range_mps2,
                    2.0 * STANDARD_GRAVITY_MPS2, MAX_PLAUSIBLE_ACC_MPS2)
        check_range('GateParams.gyr_range_rps', self.gyr_range_rps, 1.0, MAX_PHYSICAL_GYR_RPS)
        check_range('GateParams.max_gap_s', self.max_gap_s, 0.005, 1.0)
        check_range('GateParams.max_future_jump_s', self.max_future_jump_s, self.max_gap_s,
                    3600.0)
        if not isinstance(self.reject_saturated, bool):
            raise InputError(f'GateParams.reject_saturated = {self.reject_saturated!r} must be '
                             'true or false')
        if not isinstance(self.frame_id, str):
            raise InputError(f'GateParams.frame_id = {self.frame_id!r} must be a string '
                             "('' accepts any frame)")


class InputGate:
    """
    Checks IMU samples one by one and counts what it refuses and flags.

    Parameters
    ----------
    params : GateParams
        Ranges, expected frame and gap length.

    Attributes
    ----------
    rejected : Counter
        Refused samples by reason (every key of ``REJECT_REASONS`` present, 0 at start).
    flagged : Counter
        Accepted samples that were saturated, and gaps (keys of ``FLAG_REASONS``).
    accepted : int
        Samples passed on.
    last_stamp_ns : int or None
        Stamp of the last accepted sample.
    units_latched : bool
        True once the data were found to be in the wrong units (every sample is refused).

    """

    def __init__(self, params: GateParams = None):
        self.params = params or GateParams()
        self.rejected = Counter(dict.fromkeys(REJECT_REASONS, 0))
        self.flagged = Counter(dict.fromkeys(FLAG_REASONS, 0))
        self.accepted = 0
        self.last_stamp_ns = None
        self._jump_stamp_ns = None
        self._jump_count = 0
        self._units_stamps_ns = deque(maxlen=UNITS_LATCH_COUNT)
        self.units_latched = False
        self._set_limits()

    def set_params(self, params: GateParams):
        """Use new parameters from the next sample on; counters and last stamp are kept."""
        self.params = params
        self._set_limits()
        self.reset_units()

    def reset_units(self):
        """Release the wrong-units latch (after the sensor's units were fixed)."""
        self.units_latched = False
        self._units_stamps_ns.clear()

    def _set_limits(self):
        p = self.params
        self._acc_sat = SATURATION_FRACTION * p.acc_range_mps2
        self._gyr_sat = SATURATION_FRACTION * p.gyr_range_rps
        self._max_gap_ns = int(round(p.max_gap_s * 1e9))
        self._max_jump_ns = int(round(p.max_future_jump_s * 1e9))

    @property
    def rejected_total(self) -> int:
        """Return the number of refused samples, all reasons."""
        return sum(self.rejected.values())

    def check(self, stamp_ns: int, acc_b, gyr_b, frame_id: str = None):
        """
        Check one sample; return None to pass it on, else the reason it is refused.

        Parameters
        ----------
        stamp_ns : int
            Sample stamp, ns.
        acc_b : sequence of 3 float
            Specific force, m/s^2.
        gyr_b : sequence of 3 float
            Angular rate, rad/s.
        frame_id : str or None
            Header frame_id of the message; None skips the frame check.

        Returns
        -------
        None, or one of ``REJECT_REASONS`` (also counted in ``rejected``).

        """
        reason = self._reason(stamp_ns, acc_b, gyr_b, frame_id)
        if reason is not None:
            self.rejected[reason] += 1
        return reason

    def refuse_accepted(self, reason: str):
        """Count the sample just accepted as refused instead (the navigator refused it)."""
        self.accepted -= 1
        self.rejected[reason] += 1

    def _reason(self, stamp_ns, acc_b, gyr_b, frame_id):
        ax, ay, az = acc_b
        gx, gy, gz = gyr_b
        # A sum is finite when every term is (fast path); else look at each value.
        if not math.isfinite(ax + ay + az + gx + gy + gz) and \
                not all(math.isfinite(v) for v in (ax, ay, az, gx, gy, gz)):
            return NON_FINITE
        acc_peak = max(abs(ax), abs(ay), abs(az))
        gyr_peak = max(abs(gx), abs(gy), abs(gz))
        p = self.params
        if p.frame_id and frame_id is not None and frame_id != p.frame_id:
            return WRONG_FRAME
        last = self.last_stamp_ns
        if last is not None:
            if stamp_ns < last:
                return OUT_OF_ORDER
            if stamp_ns == last:
                return DUPLICATE
            if stamp_ns - last > self._max_jump_ns and not self._confirm_jump(stamp_ns):
                return OUT_OF_ORDER
        if self.units_latched:
            return WRONG_UNITS
        if gyr_peak > MAX_PHYSICAL_GYR_RPS or acc_peak > MAX_PLAUSIBLE_ACC_MPS2:
            self._note_wrong_units(stamp_ns)
            return WRONG_UNITS
        if acc_peak >= self._acc_sat or gyr_peak >= self._gyr_sat:
            if p.reject_saturated:
                return SATURATED
            self.flagged[SATURATED] += 1
        if last is not None and stamp_ns - last > self._max_gap_ns:
            self.flagged[GAP] += 1
        self.last_stamp_ns = stamp_ns
        self._jump_count = 0
        self.accepted += 1
        return None

    def _note_wrong_units(self, stamp_ns):
        stamps = self._units_stamps_ns
        stamps.append(stamp_ns)
        if len(stamps) == stamps.maxlen and \
                stamps[-1] - stamps[0] <= UNITS_LATCH_WINDOW_S * 1e9:
            self.units_latched = True

    def _confirm_jump(self, stamp_ns):
        """Count samples that agree on a far-ahead stamp; True once they confirm the jump."""
        if self._jump_count and 0 < stamp_ns - self._jump_stamp_ns <= self._max_gap_ns:
            self._jump_count += 1
        else:
            self._jump_count = 1
        self._jump_stamp_ns = stamp_ns
        return self._jump_count >= RESYNC_SAMPLES


__all__ = ['DUPLICATE', 'FLAG_REASONS', 'GAP', 'GateParams', 'InputGate', 'NON_FINITE',
           'OUT_OF_ORDER', 'REJECT_REASONS', 'SATURATED', 'WRONG_FRAME', 'WRONG_UNITS']
