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

"""Helpers of the live command-centre tests: processes with their own environment, the page."""

from pathlib import Path
import signal
import subprocess
import time

from anfis_elevation_ros.tools.incident_demo import fetch_state
from live_support import cli, cli_env, PACKAGE_ROOT, wait_for

START_TIMEOUT_S = 90.0     # a Python process with rclpy and numba starting on a loaded machine


class Processes:
    """
    Subprocesses of one test, each logging to its own file; all stopped with SIGINT at exit.

    Parameters
    ----------
    log_dir : Path
        Where ``<name>.log`` files go.

    """

    def __init__(self, log_dir):
        self.log_dir = Path(log_dir)
        self.procs = {}

    def start(self, name: str, *args, env_changes=None, drop=()) -> subprocess.Popen:
        """Start ``python -m anfis_elevation_ros ARGS`` as ``name``."""
        env = cli_env()
        env.update(env_changes or {})
        for key in drop:
            env.pop(key, None)
        log = open(self.log_dir / f'{name}.log', 'w')
        proc = subprocess.Popen(cli(*args), stdout=log, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, env=env, cwd=PACKAGE_ROOT)
        log.close()
        self.procs[name] = proc
        return proc

    def log(self, name: str) -> str:
        """Return what process ``name`` printed so far."""
        return (self.log_dir / f'{name}.log').read_text()

    def stop(self, name: str, timeout_s: float = 20.0) -> int:
        """Stop one process (SIGINT, then SIGKILL if it hangs); return its exit code."""
        proc = self.procs[name]
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=timeout_s)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        return proc.returncode

    def wait(self, name: str, timeout_s: float) -> int:
        """Wait for process ``name`` to end; return its exit code."""
        return self.procs[name].wait(timeout=timeout_s)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        for name in reversed(list(self.procs)):
            self.stop(name)

    def url_and_token(self, name: str = 'command_centre') -> tuple:
        """Wait for the command centre's URL and token lines; return them."""
        def lines():
            return [line for line in self.log(name).splitlines()
                    if line.startswith('command-centre:')]
        assert wait_for(lambda: len(lines()) >= 2 or self.procs[name].poll() is not None,
                        START_TIMEOUT_S), self.log(name)
        assert len(lines()) >= 2, self.log(name)
        return lines()[0].split()[1], lines()[1].split()[-1]


def responders(url: str) -> dict:
    """Return {id: responder} of the command centre's /api/state."""
    return {r['id']: r for r in fetch_state(url)['responders']}


def wait_state(url: str, condition, timeout_s: float, what: str) -> dict:
    """Poll /api/state until ``condition(state)``; fail saying ``what`` otherwise."""
    deadline = time.monotonic() + timeout_s
    while True:
        state = fetch_state(url)
        if condition(state):
            return state
        if time.monotonic() > deadline:
            seen = [(r['id'], r['floor'], r['x_m']) for r in state['responders']]
            raise AssertionError(f'/api/state did not show {what} within {timeout_s:g} s: '
                                 f'{seen}')
        time.sleep(0.25)


__all__ = ['Processes', 'responders', 'START_TIMEOUT_S', 'wait_state']
