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
A supervisor restart in the middle of a stair flight, over DDS (a script, not a test).

Run from the repository root: ``python test/benchmarks/bench_restart.py [--root CHECKOUT]``.

A simulated walk (level, a flight of 36 risers of 0.15 m at two per stride, level; tactical
IMU, 100 Hz) is played at its recorded pace from this process, as a sensor driver would go on
publishing. Both nodes run in processes of their own (``python -m ...nodes.<node>``, from
``--root``: another checkout measures the code before a change). In the middle of the flight
both are killed with SIGKILL and started again 1 s later, as a supervisor would. Printed: the
outage in sensor time (from the IMU node's log: the saved cycle to its first sample after the
restart), the cycles it counts as lost, the height and floor certainty at the end against the
truth, and the log lines of the restart.
"""

import argparse
import os
from pathlib import Path
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / 'test')]

STEP_M = 0.15


def node(module, root, params, log_path):
    """Start a node from checkout ``root`` with the parameter file; return the process."""
    env = dict(os.environ)
    env['PYTHONPATH'] = os.pathsep.join([str(root)] + [
        p for p in env.get('PYTHONPATH', '').split(os.pathsep) if p])
    log = open(log_path, 'a')
    return subprocess.Popen([sys.executable, '-m', f'anfis_elevation_ros.nodes.{module}',
                             '--ros-args', '--params-file', str(params)],
                            stdout=log, stderr=subprocess.STDOUT, env=env, cwd=root)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--root', type=Path, default=ROOT, help='checkout the nodes run from')
    parser.add_argument('--delay-s', type=float, default=1.0, help='supervisor restart delay')
    args = parser.parse_args(argv)
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))

    from anfis_elevation_ros import sim
    from anfis_elevation_ros.tools.ros_io import ImuPlayer
    from live_support import listening, wait_for, write_linear_model, write_params

    segments = (sim.Segment.level(8),
                sim.Segment.stairs(36, +1, steps_per_stride=2, step_height_m=STEP_M),
                sim.Segment.level(8))
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(3), rate_hz=100.0,
                             imu='tactical', step_height_m=STEP_M)
    rec = walk.to_recording()
    up = np.flatnonzero(walk.strides.mode == 1)
    kill_stamp_ns = int(walk.strides.stamp_ns[up[len(up) // 2]]) + 300_000_000
    with tempfile.TemporaryDirectory() as tmp, listening() as listener:
        tmp = Path(tmp)
        model = write_linear_model(tmp / 'model.json', STEP_M)
        params = write_params(tmp / 'params.yaml', model,
                              classifier={'elevation.step_height_m': STEP_M})
        logs = {m: tmp / f'{m}.log' for m in ('imu_node', 'classifier_node')}
        procs = {m: node(m, args.root, params, logs[m]) for m in logs}
        player = ImuPlayer(rec)
        try:
            assert player.wait_for_subscribers(1, 60.0), 'no IMU node'
            assert wait_for(lambda: 'floor' in logs['classifier_node'].read_text(), 60.0)
            playing = threading.Thread(target=player.play, kwargs={'rate': 1.0})
            playing.start()
            start_ns, start_s = int(rec.stamp_ns[0]), time.monotonic()
            time.sleep((kill_stamp_ns - start_ns) * 1e-9 - (time.monotonic() - start_s))
            for proc in procs.values():
                proc.send_signal(signal.SIGKILL)
                proc.wait()
            time.sleep(args.delay_s)
            procs = {m: node(m, args.root, params, logs[m]) for m in logs}
            playing.join()
            time.sleep(2.0)
        finally:
            for proc in procs.values():
                proc.send_signal(signal.SIGINT)
                proc.wait(timeout=20)
            player.destroy_node()
        imu_log, cls_log = logs['imu_node'].read_text(), logs['classifier_node'].read_text()
    truth = float(walk.strides.height_m[-1])
    final = listener.elevations[-1][3] if listener.elevations else float('nan')
    gap = re.search(r'after (\d+\.\d+) s', imu_log)
    print(f'checkout {args.root}')
    print(f'outage in sensor time: {gap.group(1) if gap else "?"} s '
          f'(stride period {np.median(np.diff(walk.strides.stamp_ns)) * 1e-9:.2f} s)')
    print(f'final height {final:.2f} m, truth {truth:.2f} m, error {final - truth:+.2f} m; '
          f'floor_certain at the end: '
          f'{listener.floor_certain[-1][0] if listener.floor_certain else "?"}')
    for line in (imu_log + cls_log).splitlines():
        if re.search(r'resum|fresh|outage|lost|since the saved|credited|uncertain|certain '
                     r'again', line):
            print('  ' + line[line.find(']: ') + 3:] if ']: ' in line else line)
    return 0


if __name__ == '__main__':
    sys.exit(main())
