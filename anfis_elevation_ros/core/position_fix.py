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
When a stair-entry correction reaches the filter: once, at a sample fixed in sensor time.

Stair entries are recognised after the classifier (``stair_database.StairEntryMonitor``) but the
filter runs on the IMU side. The hand-over must give the same track live (two nodes, DDS in
between), in ``replay`` (one loop) and after a restart, so the moment of the update is not
"when the request arrives" but a rule on the sensor's own clock:

    a request made by the gait cycle stamped t is applied at the first stance sample whose
    stamp is at least t + D (D = ``stair_fix_delay_s``, 0.5 s, far above the classifier's
    latency of a few ms),

after that sample went through the navigator and the gait segmentation (the cycle closing at it
keeps the uncorrected position). Replay hands the request over at once and live within
milliseconds, so both apply it at the same sample. A request that arrives after its sample was
processed (the classifier stalled for D) is applied at the next stance sample and counted as
``late``: the track then differs from a replay, and diagnostics say so.

Exactly once: a request's identity is its cycle's stamp. Applied identities are remembered (the
last ``MAX_REMEMBERED``) and saved with the IMU node's state, written with the position they
belong to: after a restart, a request applied before the saved position is not applied again,
one applied after it is (the saved position does not contain it). Repeats (the classifier's
transient-local history after a restart of either node) are counted as ``duplicate``.

Public API: :class:`PositionFixQueue`.
"""

from collections import deque
import math

from .stair_database import CorrectionRequest

MAX_REMEMBERED = 256        # far more stair entries than a request history holds
MAX_PENDING = 64


class PositionFixQueue:
    """
    Pending stair-entry corrections of one navigator, applied by the rule above.

    Parameters
    ----------
    delay_s : float
        D, s.
    sigma_m : float
        Measurement standard deviation, m.
    applied : iterable of int
        Identities (cycle stamps, ns) applied before a restart.

    """

    def __init__(self, delay_s: float, sigma_m: float, applied=()):
        self._delay_ns = int(round(delay_s * 1e9))
        self._sigma_m = sigma_m
        self._pending = []
        self._applied = deque((int(a) for a in applied), maxlen=MAX_REMEMBERED)
        self._last_stamp_ns = None
        self.received = 0
        self.applied_count = 0
        self.duplicates = 0
        self.late = 0
        self.dropped = 0
        self.last_nis = math.nan

    def submit(self, request: CorrectionRequest) -> str:
        """
        Queue a request; return 'queued', 'late' or 'duplicate'.

        'late': the sample it was due at has already been processed; it will be applied at
        the next stance sample.
        """
        self.received += 1
        if request.stamp_ns in self._applied \
                or any(r.stamp_ns == request.stamp_ns for r, _ in self._pending):
            self.duplicates += 1
            return 'duplicate'
        due_ns = request.stamp_ns + self._delay_ns
        verdict = 'queued'
        if self._last_stamp_ns is not None and self._last_stamp_ns >= due_ns:
            self.late += 1
            verdict = 'late'
        if len(self._pending) >= MAX_PENDING:
            self._pending.pop(0)
            self.dropped += 1
        self._pending.append((request, due_ns))
        return verdict

    def after_step(self, navigator, point) -> list:
        """
        Apply the requests due at this navigated sample; return those applied.

        Parameters
        ----------
        navigator : FootNavigator
            Its filter gets the position updates (``correct_position``).
        point : TrackPoint
            The sample the navigator just returned.

        """
        self._last_stamp_ns = point.stamp_ns
        if not point.stance or not self._pending:
            return []
        due = [(r, d) for r, d in self._pending if d <= point.stamp_ns]
        if not due:
            return []
        self._pending = [(r, d) for r, d in self._pending if d > point.stamp_ns]
        applied = []
        for request, _ in due:
            self.last_nis = navigator.correct_position(request.innovation_xy, self._sigma_m)
            self._applied.append(request.stamp_ns)
            self.applied_count += 1
            applied.append(request)
        return applied

    @property
    def applied_ids(self) -> list:
        """Return the identities applied (cycle stamps, ns), oldest first, for the state file."""
        return list(self._applied)

    @property
    def pending(self) -> int:
        """Return the number of requests waiting for their sample."""
        return len(self._pending)

    @property
    def counters(self) -> dict:
        """Return the counters, for diagnostics."""
        return {'stair_fix_requests': self.received, 'stair_fix_applied': self.applied_count,
                'stair_fix_pending': self.pending, 'stair_fix_late': self.late,
                'stair_fix_duplicates': self.duplicates, 'stair_fix_dropped': self.dropped,
                'stair_fix_last_nis': self.last_nis}


__all__ = ['MAX_REMEMBERED', 'PositionFixQueue']
