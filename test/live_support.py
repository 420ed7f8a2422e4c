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
Helpers of the live node tests and benchmarks: a known model, parameter files, subprocesses.

``write_linear_model`` writes an ANFIS whose every rule has the same consequent
y = height_change_m / K: the normalised firing strengths sum to one, so the network computes
exactly that line whatever the memberships, and eq. (13) calls a cycle "up" when it climbed
more than half a step. It is a model with a known answer, independent of training (the
packaged default is trained separately and may change).
"""

from contextlib import contextmanager
import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import yaml

PACKAGE_ROOT = Path(__file__).resolve().parents[1]
SAMPLE_DIR = PACKAGE_ROOT / 'anfis_elevation_ros' / 'data' / 'sample_walk'
SAMPLE_BAG = SAMPLE_DIR / 'imu'
SAMPLE_STRIDES = SAMPLE_DIR / 'strides.csv'
FLOOR_HEIGHT_M = 3.0


def write_linear_model(path, step_height_m: float = 0.17) -> Path:
    """Write the model y = height_change_m / step_height_m (see the module docstring)."""
    from anfis_elevation_ros.core.anfis import Anfis, grid_partition

    universe = np.array([[-1.0, 1.0], [0.0, 1.0], [-1.5, 1.5], [0.0, 2.0], [-1.0, 2.0]])
    consequents = np.zeros((2 ** 5, 6))
    consequents[:, 2] = 1.0 / step_height_m
    model = Anfis.from_params(grid_partition(universe, 2, 'triangle'), consequents, universe,
                              'triangle', {'note': 'test model: y = height_change_m / K'})
    model.save(path)
    return Path(path)


def write_params(path, model_path, imu=None, classifier=None) -> Path:
    """
    Write a ROS 2 parameter YAML for both nodes (model_path plus any extra values).

    The state files go to ``state/`` beside the YAML, so that no test resumes another's state
    or touches ~/.ros.
    """
    state = {'state_dir': str(Path(path).parent / 'state')}
    doc = {'imu_node': {'ros__parameters': {**state, **(imu or {})}},
           'classifier_node': {'ros__parameters': {'model_path': str(model_path), **state,
                                                   **(classifier or {})}}}
    Path(path).write_text(yaml.safe_dump(doc, sort_keys=False))
    return Path(path)


def cli(*args) -> list:
    """Return the command line of ``python -m anfis_elevation_ros ARGS``."""
    return [sys.executable, '-m', 'anfis_elevation_ros', *(str(a) for a in args)]


def cli_env() -> dict:
    """Environment for subprocesses: this checkout first on PYTHONPATH, the ROS isolation kept."""
    env = dict(os.environ)
    env['PYTHONPATH'] = os.pathsep.join(
        [str(PACKAGE_ROOT)] + [p for p in env.get('PYTHONPATH', '').split(os.pathsep) if p])
    return env


def truth_floors(strides_csv=SAMPLE_STRIDES):
    """
    Return (final floor, highest floor) of a strides.csv truth, by the nodes' settle rule.

    The floor changes only when the height settles on one (``core/floors.py``). The sample
    walk's 2.38 m climb is no 3 m storey: its highest floor depends on how many cycles of the
    turn at the top are classified level (floor 1, uncertain, after 3), so compare it with an
    offline replay rather than with this.
    """
    from anfis_elevation_ros.core.floors import floor_map_for, FloorSettler

    truth = np.genfromtxt(strides_csv, delimiter=',', names=True)
    settler = FloorSettler(floor_map_for(None, 0, FLOOR_HEIGHT_M), 0.5, 0.0)
    floors = [settler.update(h, int(m)) for h, m in zip(truth['height_m'], truth['mode'])]
    return int(floors[-1]), int(max(floors))


class BackgroundProcess:
    """
    A command in a subprocess of this checkout; stopped with SIGINT on exit.

    Parameters
    ----------
    command : sequence of str
        The command line.
    log_path : Path
        Where the process's output goes.

    """

    def __init__(self, command, log_path):
        self.command = list(command)
        self.log_path = Path(log_path)
        self.proc = None
        self.returncode = None

    def __enter__(self):
        self._log = open(self.log_path, 'w')
        self.proc = subprocess.Popen(self.command, stdout=self._log, stderr=subprocess.STDOUT,
                                     stdin=subprocess.DEVNULL, env=cli_env(),
                                     cwd=PACKAGE_ROOT)
        return self

    def stop(self, timeout_s: float = 20.0) -> int:
        """SIGINT, wait; SIGKILL if it hangs (then the return code is negative)."""
        if self.proc is not None and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(timeout=timeout_s)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.returncode = self.proc.returncode if self.proc is not None else None
        return self.returncode

    def log(self) -> str:
        """Return what the process printed so far."""
        return self.log_path.read_text() if self.log_path.exists() else ''

    def __exit__(self, *exc):
        self.stop()
        self._log.close()


class NodesProcess(BackgroundProcess):
    """
    ``python -m anfis_elevation_ros run`` in a subprocess; stopped with SIGINT on exit.

    Parameters
    ----------
    params : Path
        Parameter YAML.
    log_path : Path
        Where the process's output goes.
    extra : sequence of str
        More arguments for ``run``.

    """

    def __init__(self, params, log_path, extra=()):
        super().__init__(cli('run', '--params', params, *extra), log_path)


def play_at_recorded_pace(bag, publish_log, ready_s=None) -> np.ndarray:
    """
    Play a bag with ``play`` at its recorded pace; return the (stamp_ns, publish_ns) log.

    ``ready_s`` is ``play``'s ``--ready-s`` (None: its default, wait for the IMU node's first
    diagnostics; 0: play once any subscriber appears, for a subscriber that is no IMU node).
    """
    options = () if ready_s is None else ('--ready-s', ready_s)
    play = subprocess.run(cli('play', bag, '--rate', 1, '--log-publish', publish_log,
                              '--linger-s', 1.0, '--wait-s', 30, *options),
                          env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True)
    if play.returncode != 0:
        raise RuntimeError(f'play failed:\n{play.stderr}')
    return np.loadtxt(publish_log, delimiter=',', skiprows=1, dtype=np.int64, ndmin=2)


@contextmanager
def listening(**node_kwargs):
    """
    Start rclpy and a CycleListener spun in a background thread; shut both down after.

    ``node_kwargs`` go to the listener (``namespace='/ff3'`` listens to that responder).
    """
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    from anfis_elevation_ros.tools.ros_io import CycleListener

    rclpy.init()
    executor = SingleThreadedExecutor()
    listener = CycleListener(**node_kwargs)
    executor.add_node(listener)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        yield listener
    finally:
        executor.shutdown()
        listener.destroy_node()
        rclpy.try_shutdown()
        thread.join(timeout=5.0)


def wait_for(condition, timeout_s: float, period_s: float = 0.05) -> bool:
    """Poll condition() until it is true or the time is up; return its last value."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline:
            return bool(condition())
        time.sleep(period_s)
    return True
