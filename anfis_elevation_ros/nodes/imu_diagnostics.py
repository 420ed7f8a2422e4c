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
The IMU node's two diagnostic statuses, "IMU input" and "foot navigator", from its counters.

Rates, refusals, gaps and losses are over one diagnostics period: ``InputPeriod`` keeps the
counts at its start. The levels: "IMU input" is ERROR when the gate latched wrong units, STALE
without messages, WARN on refusals, gaps, saturation or more than ``LOSS_WARN_FRACTION`` of the
samples lost in transit; "foot navigator" is ERROR on internal errors, WARN on failed state
writes, late or malformed stair-entry corrections, or before the first stance.

Public API: ``InputPeriod``, ``input_status``, ``navigator_status``.
"""

from dataclasses import dataclass

from diagnostic_msgs.msg import DiagnosticStatus

from .diagnostics import diagnostic_status
from ..core.input_gate import FLAG_REASONS, GAP, REJECT_REASONS, SATURATED

LOSS_WARN_FRACTION = 0.01   # more lost samples than this (per diagnostics period) is a warning


@dataclass(frozen=True)
class InputCounts:
    """Running totals of the input at one instant (messages, navigator samples, gate counts)."""

    received: int
    samples: int
    stance_samples: int
    missing_samples: int
    rejected: dict
    flagged: dict


@dataclass(frozen=True)
class PeriodFigures:
    """The input over one diagnostics period."""

    period_s: float
    received: int
    samples: int
    stance_samples: int
    rejected: dict
    flagged: dict
    loss_fraction: float


class InputPeriod:
    """
    The counts at the start of the current diagnostics period.

    Parameters
    ----------
    gate : InputGate
        Its counters at start-up (every reason present).
    now_ns : int
        Start of the first period, ns.

    """

    def __init__(self, gate, now_ns: int):
        self._start = InputCounts(0, 0, 0, 0, dict(gate.rejected), dict(gate.flagged))
        self._start_ns = now_ns

    def close(self, now_ns: int, received: int, gate, status) -> PeriodFigures:
        """Return the figures of the period that ends now and start the next one."""
        start = self._start
        now = InputCounts(received, status.samples, status.stance_samples,
                          status.missing_samples, dict(gate.rejected), dict(gate.flagged))
        samples = now.samples - start.samples
        missing = now.missing_samples - start.missing_samples
        figures = PeriodFigures(
            period_s=max(1e-9, (now_ns - self._start_ns) * 1e-9),
            received=now.received - start.received, samples=samples,
            stance_samples=now.stance_samples - start.stance_samples,
            rejected={r: now.rejected[r] - start.rejected.get(r, 0) for r in REJECT_REASONS},
            flagged={r: now.flagged[r] - start.flagged.get(r, 0) for r in FLAG_REASONS},
            loss_fraction=missing / (samples + missing) if samples + missing else 0.0)
        self._start, self._start_ns = now, now_ns
        return figures


def input_status(name: str, hardware_id: str, topic: str, period: PeriodFigures, gate, status,
                 received: int, malformed: int, internal_errors: int) -> DiagnosticStatus:
    """Build the "IMU input" status: the gate's counts, the rate and the losses."""
    rejected, flagged, loss = period.rejected, period.flagged, period.loss_fraction
    if gate.units_latched:
        level, message = DiagnosticStatus.ERROR, ('IMU data in the wrong units (deg/s or '
                                                  'mg?): all refused; fix and restart')
    elif period.received == 0:
        level, message = DiagnosticStatus.STALE, 'no IMU messages'
    elif sum(rejected.values()):
        refused = ', '.join(f'{n} {r}' for r, n in rejected.items() if n)
        level, message = DiagnosticStatus.WARN, f'refused: {refused}'
    elif flagged[GAP] or flagged[SATURATED] or loss > LOSS_WARN_FRACTION:
        level, message = DiagnosticStatus.WARN, (f'{100 * loss:.1f} % of samples lost, '
                                                 f'{flagged[GAP]} gaps, '
                                                 f'{flagged[SATURATED]} saturated')
    else:
        level, message = DiagnosticStatus.OK, 'ok'
    # The input topic tells a player which node this is: its first diagnostics say it is ready.
    values = {'imu_topic': topic,
              'input_rate_hz': period.received / period.period_s, 'received': received,
              'accepted': gate.accepted, 'rejected': gate.rejected_total}
    values.update({f'rejected_{r}': gate.rejected[r] for r in REJECT_REASONS})
    values.update({f'{r}_count': gate.flagged[r] for r in FLAG_REASONS})
    values['missing_samples'] = status.missing_samples
    values['loss_fraction'] = loss
    values['malformed'] = malformed
    values['units_latched'] = gate.units_latched
    values['internal_errors'] = internal_errors
    return diagnostic_status(f'{name}: IMU input', level, message, hardware_id, values)


def navigator_status(name: str, hardware_id: str, period: PeriodFigures, status,
                     internal_errors: int, state_write_errors: int, late_fixes: int,
                     malformed_fixes: int, node_values: dict) -> DiagnosticStatus:
    """Build the "foot navigator" status: the navigator's figures, then ``node_values``."""
    if internal_errors:
        level, message = DiagnosticStatus.ERROR, f'{internal_errors} internal errors'
    elif state_write_errors:
        level, message = DiagnosticStatus.WARN, f'{state_write_errors} failed state writes'
    elif late_fixes or malformed_fixes:
        level, message = DiagnosticStatus.WARN, (
            f'stair-entry corrections: {late_fixes} late, {malformed_fixes} malformed')
    elif not status.initialised:
        level, message = DiagnosticStatus.WARN, 'waiting for the first stance'
    else:
        level, message = DiagnosticStatus.OK, 'navigating'
    values = {
        'initialised': status.initialised, 'rate_hz': status.rate_hz,
        'stance_fraction': period.stance_samples / period.samples if period.samples else 0.0,
        'samples': status.samples, 'cycles': status.cycles,
        'invalid_cycles': status.invalid_cycles, 'gaps': status.gaps,
        'zaru_samples': status.zaru_samples, 'waiting_zupts': status.waiting_zupts,
        'relaxed_stances': status.relaxed_stances, 'late_stances': status.late_stances,
        'late_cycles': status.late_cycles,
        'rail_filled_samples': status.rail_filled_samples,
        'last_nis': status.last_nis, 'pos_sigma_m': status.pos_sigma_m, **node_values}
    return diagnostic_status(f'{name}: foot navigator', level, message, hardware_id, values)
