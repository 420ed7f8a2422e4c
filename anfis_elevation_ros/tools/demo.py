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
``demo`` subcommand: the nodes live over DDS on the bundled sample walk, in about a minute.

Starts ``run --record OUT/outputs`` (both nodes and a recorder) as a subprocess, plays the
bundled sample bag ``anfis_elevation_ros/data/sample_walk/imu`` (a simulated 67 s walk at
200 Hz: level, one flight of 14 steps up, turn, the flight down, level) from this process,
prints one line per gait cycle as the classifier publishes it, stops the nodes, and writes
``OUT/height.png`` (quantised height, raw INS height and the true height; floor below).

``--building FILE`` gives both nodes a building file (``run --building``): floors from its
elevations, its riser height if it has one (else estimated online).

DDS discovery is kept on this machine (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST) unless the
environment says otherwise; set ROS_DOMAIN_ID to keep apart from other ROS 2 systems.

``--responders 3`` runs the command-centre demo instead (``tools/incident_demo.py``): three
simulated responders in one tower, each its own namespaced pair of nodes, and the incident map.

Example: ``python -m anfis_elevation_ros demo --out /tmp/anfis_demo``
"""

import argparse
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import threading
import time

from ..core.errors import InputError

SAMPLE_DIR = Path(__file__).resolve().parents[1] / 'data' / 'sample_walk'
MODE_NAMES = {1: 'up', 0: 'level', -1: 'down'}
QUIET_S = 1.5            # after the last message, wait this long for the last cycles
START_TIMEOUT_S = 30.0   # the nodes must subscribe within this
READY_TIMEOUT_S = 180.0  # and be ready within this (numba compiles for 30-60 s on a new machine)


def log(message: str):
    print(f'[demo] {message}', file=sys.stderr, flush=True)


def stop_process(proc: subprocess.Popen):
    """Stop the nodes' process with SIGINT (then SIGKILL if it hangs); return its exit code."""
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=15.0)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    return proc.returncode


class _Printer:
    """Prints each elevation with the latest mode and floor, a moment after it arrives."""

    def __init__(self, listener, t0_ns: int, delay_s: float = 0.1):
        self.listener = listener
        self.t0_ns = t0_ns
        self.delay_ns = int(delay_s * 1e9)
        self.printed = 0

    def __call__(self):
        listener = self.listener
        while self.printed < len(listener.elevations):
            stamp_ns, _, _, height_m, received_ns = listener.elevations[self.printed]
            if time.time_ns() - received_ns < self.delay_ns:
                return
            mode = listener.modes[-1][0] if listener.modes else 0
            floor = listener.floors[-1][0] if listener.floors else 0
            name = MODE_NAMES.get(mode, mode)
            print(f't {(stamp_ns - self.t0_ns) * 1e-9:7.2f} s   mode {name:>5}   floor '
                  f'{floor:3d}   height {height_m:6.2f} m', flush=True)
            self.printed += 1


def run_demo(args) -> int:
    """Run the demo; return the exit code."""
    if args.responders > 1:
        from .incident_demo import run_incident_demo
        return run_incident_demo(args)
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    from ..core.building import load_building
    from .bags import read_imu_bag
    from .plot import plot_height, read_outputs_bag, read_truth_csv
    from .ros_io import CycleListener, ImuPlayer

    bag = args.bag or SAMPLE_DIR / 'imu'
    truth_csv = args.truth if args.truth is not None else (
        SAMPLE_DIR / 'strides.csv' if args.bag is None else None)
    recording = read_imu_bag(bag)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    outputs = out / 'outputs'
    if outputs.exists():
        if not (outputs / 'metadata.yaml').is_file():
            raise InputError(f'{outputs} exists and is not a bag; choose another --out')
        shutil.rmtree(outputs)
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    state_dir = out / 'state'   # a demo starts fresh and leaves ~/.ros alone
    shutil.rmtree(state_dir, ignore_errors=True)
    command = [sys.executable, '-m', 'anfis_elevation_ros', 'run', '--record', str(outputs)]
    if args.params is not None:
        command += ['--params', str(args.params)]
    if args.building is not None:
        load_building(args.building)            # a bad file stops here, with its key named
        command += ['--building', str(Path(args.building).resolve())]
    command += ['--ros-args', '-p', f'state_dir:={state_dir}']
    log(f'starting the nodes: {" ".join(command[1:])}')
    started = time.monotonic()
    proc = subprocess.Popen(command, stdin=subprocess.DEVNULL)
    rclpy.init(args=['demo'])
    executor = SingleThreadedExecutor()
    spinner = threading.Thread(target=executor.spin, daemon=True)
    listener = player = None
    try:
        listener = CycleListener()
        listener.create_timer(0.05, _Printer(listener, int(recording.stamp_ns[0])))
        player = ImuPlayer(recording)
        executor.add_node(listener)
        spinner.start()
        deadline = time.monotonic() + START_TIMEOUT_S
        while not player.wait_for_subscribers(timeout_s=0.5):
            if proc.poll() is not None or time.monotonic() > deadline:
                raise InputError('the nodes did not start (see the messages above); '
                                 f'exit code {proc.poll()}')
        if not player.wait_until_ready(READY_TIMEOUT_S, stop=lambda: proc.poll() is not None):
            raise InputError('the IMU node did not become ready (see the messages above); '
                             f'exit code {proc.poll()}')
        log(f'playing {bag} ({len(recording)} IMU messages, {recording.rate_hz:.0f} Hz) at '
            f'{args.rate:g}x')
        result = player.play(rate=args.rate, stop=lambda: proc.poll() is not None)
        log(f'published {result.published} messages in {result.wall_s:.1f} s')
        time.sleep(1.0)                      # the last messages are still being processed
        _wait_quiet(listener)
    finally:
        code = stop_process(proc)
        executor.shutdown()
        for node in (player, listener):
            if node is not None:
                node.destroy_node()
        rclpy.try_shutdown()
    if code != 0:
        raise InputError(f'the nodes exited with code {code}')
    series = read_outputs_bag(outputs)
    truth = read_truth_csv(truth_csv) if truth_csv is not None else None
    png = plot_height(series, out / 'height.png', truth,
                      title=f'{bag.name if args.bag else "sample walk"}: height and floor')
    floors = listener.floors
    summary = (f'{len(listener.elevations)} gait cycles classified, final floor '
               f'{floors[-1][0] if floors else "-"}')
    if truth is not None and len(truth[1]):
        summary += f' (true final height {truth[1][-1]:.2f} m)'
    log(f'{summary}; recorded {outputs}; wrote {png} in {time.monotonic() - started:.0f} s')
    return 0


def _wait_quiet(listener):
    """Wait until no output arrived for QUIET_S (the last cycles are on their way)."""
    def last_ns():
        times = [items[-1][-1] for items in (listener.elevations, listener.cycles) if items]
        return max(times) if times else 0

    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline and time.time_ns() - last_ns() < QUIET_S * 1e9:
        time.sleep(0.1)


def add_parser(subparsers):
    """Register the ``demo`` subcommand."""
    parser = subparsers.add_parser(
        'demo', help='live demo over DDS on the bundled sample walk (about a minute)',
        description=__doc__.strip().split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--out', type=Path, default=Path('anfis_demo'),
                        help='output folder (outputs bag and height.png)')
    parser.add_argument('--rate', type=float, default=2.0,
                        help='playback speed factor (1 = real time)')
    parser.add_argument('--params', type=Path, default=None,
                        help='ROS 2 parameter YAML for the nodes')
    parser.add_argument('--bag', type=Path, default=None,
                        help='another Imu bag to play instead of the sample walk')
    parser.add_argument('--building', type=Path, default=None, metavar='FILE',
                        help='building file for both nodes (floors, riser height; format in the '
                        'README)')
    parser.add_argument('--truth', type=Path, default=None,
                        help="truth CSV for the plot (default: the sample walk's strides.csv)")
    parser.add_argument('--responders', type=int, choices=(1, 2, 3), default=1,
                        help='2 or 3: simulated responders in one tower and the command centre')
    parser.add_argument('--port', type=int, default=8088,
                        help='--responders: port of the command-centre page (0 = any free)')
    parser.add_argument('--keep-open', action='store_true',
                        help='--responders: keep the command centre running until Ctrl-C')
    parser.set_defaults(handler=run_demo)
    return parser
