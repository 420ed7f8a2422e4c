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

"""Writing a node's state file in a thread of its own, and what both nodes do with it."""

import threading
import time

from ..core.errors import InputError
from ..core.state import save_state


class StateWriter:
    """
    Writes a node's state file in a thread of its own, newest state first.

    ``save_state`` flushes the file to disk (fsync), which takes a millisecond on a quiet disk
    and up to half a second on a busy one; done in the executor's thread it delayed every
    output behind it (test/benchmarks/bench_live.py, 400 Hz: cycle-to-PointStamped latency
    p99 15 ms with the write in the callback, 4 ms without it; one 558 ms outlier in 10
    minutes). ``submit`` hands a state over and returns at once; a state still waiting when a
    newer one arrives is dropped (only the latest matters after a crash). ``close`` writes what
    is pending and stops the thread.

    The write starts ``DELAY_S`` after the submit: a state comes with a gait cycle, just when
    the cycle is being classified and published, and the writer's Python work (building and
    checking the JSON) would take the interpreter lock from those callbacks. Strides are about
    a second apart, so every cycle's state is still written.

    Parameters
    ----------
    path : Path
        State file.
    on_error : callable
        Called with the OSError or InputError of a failed write (from the writer's thread);
        ``errors`` counts them.

    """

    DELAY_S = 0.1     # s, between a submit and the write

    def __init__(self, path, on_error):
        self.path = path
        self.errors = 0
        self._on_error = on_error
        self._pending = None
        self._closed = False
        self._wake = threading.Condition()
        self._thread = threading.Thread(target=self._run, name='state_writer', daemon=True)
        self._thread.start()

    def submit(self, state):
        """Write this state soon (replacing one not yet written)."""
        with self._wake:
            self._pending = state
            self._wake.notify()

    def close(self, timeout_s: float = 2.0):
        """Write the pending state, then stop (waiting at most ``timeout_s``)."""
        with self._wake:
            self._closed = True
            self._wake.notify()
        self._thread.join(timeout_s)

    def _run(self):
        while True:
            with self._wake:
                while self._pending is None and not self._closed:
                    self._wake.wait()
                write_at = time.monotonic() + self.DELAY_S
                while not self._closed and time.monotonic() < write_at:
                    self._wake.wait(write_at - time.monotonic())
                state, self._pending = self._pending, None
            if state is None:
                return
            try:
                save_state(self.path, state)
            except (OSError, InputError) as err:
                self.errors += 1
                self._on_error(err)


class PersistsState:
    """
    What both nodes do with their ``StateWriter``: log its errors, count them, flush at the end.

    Mixed in before ``Node``; the node calls ``_start_state_writer`` in its constructor.
    """

    STATE_ERROR_LOG_PERIOD_S = 5.0

    def _start_state_writer(self, path, persist: bool):
        """Write state files to ``path`` from now on if ``persist``, else never."""
        self._state_writer = StateWriter(path, self._log_state_error) if persist else None

    def _log_state_error(self, err):
        self.get_logger().error(f'cannot write the state file: {err}',
                                throttle_duration_sec=self.STATE_ERROR_LOG_PERIOD_S)

    def _state_write_errors(self) -> int:
        return self._state_writer.errors if self._state_writer is not None else 0

    def destroy_node(self):
        """Write the pending state, then destroy the node."""
        if self._state_writer is not None:
            self._state_writer.close()
        super().destroy_node()
