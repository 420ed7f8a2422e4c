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
last ``MAX_REMEMBERED``, with the stamp of the sample each was applied at) and saved with the
IMU node's state, written with the position of a gait cycle: only the requests applied before
that cycle's closing sample are in the saved position (:meth:`PositionFixQueue.applied_before`),
so after a restart a request applied before the saved position is not applied again and one
applied after it (or at the closing sample itself) is, late. Repeats (the transient-local history
of the request topic, sent again to a restarted node) are counted as ``duplicate``. A node that
starts a fresh track refuses the requests of cycles before its first sample (``stale``: they
belong to a walk it does not continue, :meth:`PositionFixQueue.refuse_before`).

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

    """

    def __init__(self, delay_s: float, sigma_m: float):
        self._delay_ns = int(round(delay_s * 1e9))
        self._sigma_m = sigma_m
        self._pending = []
        self._applied = deque(maxlen=MAX_REMEMBERED)     # (identity, stamp applied at), ns
        self._last_stamp_ns = None
        self._not_before_ns = None
        self.received = 0
        self.applied_count = 0
        self.duplicates = 0
        self.late = 0
        self.stale = 0
        self.dropped = 0
        self.last_nis = math.nan

    def restore(self, applied_ids):
        """
        Take the identities (cycle stamps, ns) a resumed state had applied; never apply them.

        Requests already queued with one of these identities are dropped as duplicates.
        """
        for identity in applied_ids:
            if not self._is_applied(int(identity)):
                self._applied.append((int(identity), -1))
        kept = [(r, d) for r, d in self._pending if not self._is_applied(r.stamp_ns)]
        self.duplicates += len(self._pending) - len(kept)
        self._pending = kept

    def refuse_before(self, stamp_ns: int):
        """Refuse (as ``stale``) the requests of cycles before this stamp, queued or to come."""
        self._not_before_ns = int(stamp_ns)
        kept = [(r, d) for r, d in self._pending if r.stamp_ns >= stamp_ns]
        self.stale += len(self._pending) - len(kept)
        self._pending = kept

    def _is_applied(self, identity: int) -> bool:
        return any(applied == identity for applied, _ in self._applied)

    def submit(self, request: CorrectionRequest) -> str:
        """
        Queue a request; return 'queued', 'late', 'duplicate' or 'stale'.

        'late': the sample it was due at has already been processed; it will be applied at
        the next stance sample. 'duplicate' and 'stale' requests are not queued.
        """
        self.received += 1
        if self._is_applied(request.stamp_ns) \
                or any(r.stamp_ns == request.stamp_ns for r, _ in self._pending):
            self.duplicates += 1
            return 'duplicate'
        if self._not_before_ns is not None and request.stamp_ns < self._not_before_ns:
            self.stale += 1
            return 'stale'
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
            self._applied.append((request.stamp_ns, point.stamp_ns))
            self.applied_count += 1
            applied.append(request)
        return applied

    @property
    def applied_ids(self) -> list:
        """Return the identities applied (cycle stamps, ns), oldest first."""
        return [identity for identity, _ in self._applied]

    def applied_before(self, stamp_ns: int) -> list:
        """
        Return the identities applied at samples before ``stamp_ns``, oldest first.

        For a state saved with the position of the gait cycle closing at ``stamp_ns``: a
        request applied at that very sample is not in the cycle's position.
        """
        return [identity for identity, at_ns in self._applied if at_ns < stamp_ns]

    @property
    def pending(self) -> int:
        """Return the number of requests waiting for their sample."""
        return len(self._pending)

    @property
    def counters(self) -> dict:
        """Return the counters, for diagnostics."""
        return {'stair_fix_requests': self.received, 'stair_fix_applied': self.applied_count,
                'stair_fix_pending': self.pending, 'stair_fix_late': self.late,
                'stair_fix_duplicates': self.duplicates, 'stair_fix_stale': self.stale,
                'stair_fix_dropped': self.dropped,
                'stair_fix_last_nis': self.last_nis}


__all__ = ['MAX_REMEMBERED', 'PositionFixQueue']
