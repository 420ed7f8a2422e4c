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
Where a node's start-up time goes, as a supervisor restarts it (a script, not a test).

Run from the repository root: ``python test/benchmarks/bench_startup.py [--runs N]``.

A restart loses the IMU samples from the kill until the new node takes its first one, so that
time is what a supervisor restart costs. The script publishes a still IMU at 100 Hz from its
own process (a sensor driver that keeps running), starts each node as ``ros2 run`` would
(``python -m anfis_elevation_ros.nodes.<node>``, a process of its own) and reads the stamps of
the node's own log lines: ready (``listening on`` / ``start floor``) and, for the IMU node, its
first IMU sample (the resume decision, logged at the first accepted message). It also times
the parts in fresh processes: the interpreter alone, ``import numba``, ``import rclpy`` with
``rclpy.init()``, the node module's imports, and ``compile_navigator()`` (numba's cache load)
after them. Medians over ``--runs``.
"""

import argparse
import os
from pathlib import Path
import re
import statistics
import subprocess
import sys
import tempfile
import threading
import time

ROOT = Path(__file__).resolve().parents[2]
LOG_TIME = re.compile(r'\[(\d+\.\d+)\] \[[^\]]+\]: (.*)')

PARTS = {
    'python': 'pass',
    'import numba': 'import numba',
    'import rclpy + init': 'import rclpy; rclpy.init(); rclpy.shutdown()',
    'import imu_node': 'import anfis_elevation_ros.nodes.imu_node',
    'import classifier_node': 'import anfis_elevation_ros.nodes.classifier_node',
}
COMPILE = ('import time; from anfis_elevation_ros.core.navigator import compile_navigator; '
           't = time.monotonic(); compile_navigator(); print(time.monotonic() - t)')


def env() -> dict:
    """Return the environment with this checkout first on PYTHONPATH."""
    result = dict(os.environ)
    result['PYTHONPATH'] = os.pathsep.join([str(ROOT)] + [
        p for p in result.get('PYTHONPATH', '').split(os.pathsep) if p])
    return result


def time_command(code: str) -> float:
    """Wall time of ``python -c code``, s."""
    start = time.monotonic()
    subprocess.run([sys.executable, '-c', code], check=True, env=env(), cwd=ROOT,
                   capture_output=True)
    return time.monotonic() - start


def compile_time() -> float:
    """Seconds ``compile_navigator()`` takes in a fresh process (the cache is warm)."""
    out = subprocess.run([sys.executable, '-c', COMPILE], check=True, env=env(), cwd=ROOT,
                         capture_output=True, text=True)
    return float(out.stdout.strip().splitlines()[-1])


def log_times(log: str, marks) -> dict:
    """Wall time (s) of the first log line containing each mark."""
    found = {}
    for line in log.splitlines():
        match = LOG_TIME.search(line)
        if not match:
            continue
        for mark in marks:
            if mark not in found and mark in match.group(2):
                found[mark] = float(match.group(1))
    return found


def node_start(module: str, marks, state_dir: Path, timeout_s: float = 60.0) -> dict:
    """Start a node, wait for its marks in the log, stop it; seconds from spawn to each mark."""
    log_path = state_dir / f'{module}.log'
    with open(log_path, 'w') as log:
        spawn = time.time()
        proc = subprocess.Popen(
            [sys.executable, '-m', f'anfis_elevation_ros.nodes.{module}', '--ros-args',
             '-p', f'state_dir:={state_dir}'], stdout=log, stderr=subprocess.STDOUT,
            env=env(), cwd=ROOT)
        deadline = time.monotonic() + timeout_s
        try:
            while time.monotonic() < deadline:
                found = log_times(log_path.read_text(), marks)
                if len(found) == len(marks):
                    return {mark: t - spawn for mark, t in found.items()}
                time.sleep(0.02)
            raise RuntimeError(f'{module}: {marks} not all logged:\n{log_path.read_text()}')
        finally:
            proc.terminate()
            proc.wait(timeout=20)


def still_imu_publisher(stop: threading.Event):
    """Publish a still IMU (REP 145) at 100 Hz on /imu/data until stop is set."""
    import rclpy
    from sensor_msgs.msg import Imu

    from anfis_elevation_ros.tools.ros_io import PLAYER_QOS

    rclpy.init()
    node = rclpy.create_node('bench_startup_sensor')
    publisher = node.create_publisher(Imu, '/imu/data', PLAYER_QOS)
    msg = Imu()
    msg.header.frame_id = 'imu_link'
    msg.linear_acceleration.z = 9.81
    period_s = 0.01
    next_s = time.monotonic()
    while not stop.is_set():
        stamp_ns = time.time_ns()
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
        publisher.publish(msg)
        next_s += period_s
        time.sleep(max(0.0, next_s - time.monotonic()))
    node.destroy_node()
    rclpy.try_shutdown()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--runs', type=int, default=3, help='runs per measurement (median)')
    args = parser.parse_args(argv)
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))

    for name, code in PARTS.items():
        times = [time_command(code) for _ in range(args.runs)]
        print(f'{name:28s} {statistics.median(times):6.2f} s')
    times = [compile_time() for _ in range(args.runs)]
    print(f'{"compile_navigator (cache)":28s} {statistics.median(times):6.2f} s')

    stop = threading.Event()
    sensor = threading.Thread(target=still_imu_publisher, args=(stop,), daemon=True)
    sensor.start()
    try:
        with tempfile.TemporaryDirectory() as tmp:
            for module, marks in (('imu_node', ('listening on', 'starting fresh')),
                                  ('classifier_node', ('start floor',))):
                runs = [node_start(module, marks, Path(tmp)) for _ in range(args.runs)]
                for mark in marks:
                    median = statistics.median(run[mark] for run in runs)
                    print(f'{module} spawn -> {mark!r}: {median:.2f} s '
                          f'({", ".join(f"{run[mark]:.2f}" for run in runs)})')
    finally:
        stop.set()
        sensor.join(timeout=10)
    return 0


if __name__ == '__main__':
    sys.exit(main())
