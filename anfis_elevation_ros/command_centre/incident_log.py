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
The incident log: every join, alarm, acknowledgement, clearing, evacuation and roll call.

Entries carry the incident's change counter (``seq``), so that the push stream can send the
entries after a given one. The log keeps ``MAX_LOG_ENTRIES`` (far more than an incident
makes: 50 responders each raising and clearing an alarm a minute for 8 hours is 48,000) and
counts what it had to drop, which the CSV export states in its first line.
"""

import bisect
import collections
import csv
import datetime
import io

MAX_LOG_ENTRIES = 100_000
CSV_COLUMNS = ('seq', 'time_utc', 'time_unix_s', 'responder', 'event', 'alarm_id', 'kind',
               'severity', 'by', 'text')


class IncidentLog:
    """Bounded, ordered list of log entries (dicts, the /api/state ``log[]`` form)."""

    def __init__(self, max_entries: int = MAX_LOG_ENTRIES):
        self._entries = collections.deque(maxlen=max_entries)
        self._seqs = collections.deque(maxlen=max_entries)
        self.dropped = 0

    def append(self, seq: int, unix_s: float, responder: str, event: str, alarm,
               text: str, by: str = None) -> None:
        """Add an entry; ``alarm`` is the Alarm it is about, or None; ``by`` who did it."""
        if len(self._entries) == self._entries.maxlen:
            self.dropped += 1
        self._entries.append({
            'seq': seq,
            'time_unix_s': round(unix_s, 3),
            'time_utc': datetime.datetime.fromtimestamp(unix_s, datetime.timezone.utc)
            .strftime('%Y-%m-%dT%H:%M:%SZ'),
            'responder': responder,
            'event': event,
            'alarm_id': None if alarm is None else alarm.alarm_id,
            'kind': None if alarm is None else alarm.kind,
            'severity': None if alarm is None else alarm.severity,
            'by': by,
            'text': text,
        })
        self._seqs.append(seq)

    def latest(self, count: int) -> list:
        """Return the last ``count`` entries, oldest first."""
        start = max(0, len(self._entries) - count)
        return [self._entries[k] for k in range(start, len(self._entries))]

    def since(self, seq: int):
        """Return the entries after ``seq``; None if some of them were dropped already."""
        if self.dropped and self._seqs and seq < self._seqs[0] - 1:
            return None
        start = bisect.bisect_right(self._seqs, seq)
        return [self._entries[k] for k in range(start, len(self._entries))]

    def csv(self) -> str:
        """Return the log as CSV text, a header line first."""
        out = io.StringIO()
        writer = csv.writer(out, lineterminator='\n')
        if self.dropped:
            writer.writerow([f'# {self.dropped} older entries were dropped (log full)'])
        writer.writerow(CSV_COLUMNS)
        for entry in self._entries:
            writer.writerow(['' if entry[c] is None else entry[c] for c in CSV_COLUMNS])
        return out.getvalue()
