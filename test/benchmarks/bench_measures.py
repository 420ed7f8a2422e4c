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


"""What the command-centre benchmarks measure of a process: CPU, memory and latencies."""

import math
import os
from pathlib import Path

import numpy as np

TICKS_PER_S = os.sysconf('SC_CLK_TCK')
BIN_S = 0.001               # latency histogram: fixed memory however long the run
MAX_LATENCY_S = 30.0


def proc_cpu_s(pid: int) -> float:
    """Return user + system CPU time of a process, s (Linux /proc)."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS_PER_S


def proc_rss_mb(pid: int) -> float:
    """Return the resident memory of a process, MB (Linux /proc)."""
    for line in Path(f'/proc/{pid}/status').read_text().splitlines():
        if line.startswith('VmRSS:'):
            return int(line.split()[1]) / 1024.0
    return math.nan


class LatencyHistogram:
    """Counts of latencies in BIN_S bins (the last one: MAX_LATENCY_S and over)."""

    def __init__(self):
        self.counts = np.zeros(int(MAX_LATENCY_S / BIN_S) + 1, dtype=np.int64)
        self.max_s = 0.0

    def add(self, latencies_s) -> None:
        """Count a batch of latencies, s."""
        values = np.asarray(latencies_s, dtype=float)
        if values.size:
            bins = np.clip((values / BIN_S).astype(int), 0, self.counts.size - 1)
            np.add.at(self.counts, bins, 1)
            self.max_s = max(self.max_s, float(values.max()))

    @property
    def size(self) -> int:
        """Return the number of latencies counted."""
        return int(self.counts.sum())

    def percentile(self, q: float) -> float:
        """Return the upper edge of the bin holding the q-th percentile, s."""
        rank = np.searchsorted(np.cumsum(self.counts), q / 100.0 * self.size)
        return (rank + 1) * BIN_S

    def summary(self) -> dict:
        """Return p50, p99, max (s) and the count."""
        return {'p50': self.percentile(50), 'p99': self.percentile(99), 'max': self.max_s,
                'count': self.size}
