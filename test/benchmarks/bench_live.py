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
Benchmark of the live nodes at 400 Hz: latency, CPU, lost messages (a script, not a test).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_live.py`` (about
80 s: the 67 s sample walk simulated at 400 Hz) or ``--scenario building`` for the 10-minute
walk (about 11 minutes; run it once per change that matters, not in CI).

Three processes, as deployed: ``run`` (both nodes, one executor), ``play`` (the bag at the
recorded pace, logging the wall-clock time ``time.time_ns()`` right after each message is
handed to the middleware), and this script, which subscribes to /elevation and /diagnostics.

- Latency of a gait cycle: the time from ``play`` publishing the IMU sample that closes the
  cycle (the PointStamped's header stamp names that sample) to this script receiving the
  PointStamped, both on the machine's wall clock. Target: p99 <= 20 ms.
- CPU of the nodes: user + system time of the ``run`` process (all its threads, from
  /proc/PID/stat) over the playing interval, in % of one core. Target: <= 10 %.
- Lost IMU messages: messages ``play`` published minus those the imu node counted as received
  (its /diagnostics). Target: 0.

With ``--baseline`` the same bag is then played to a subscriber that does nothing with the
messages (same QoS, raw messages taken as the IMU node takes them, the nodes' ``Spinner``), and
its CPU is printed beside the nodes' with their ratio: the share of rclpy and DDS in the figure,
and a comparison that holds when the host's speed changes between runs.

The model is a fixed linear one (``test/live_support.py``), so the figures do not depend on the
trained default. Prints the figures, writes them as JSON with ``--json``, and exits 1 if a
target is missed. The machine's load (``os.getloadavg``) is printed: other work on the same
cores inflates both the latency and the CPU time.
"""

import argparse
import json
import os
from pathlib import Path
import subprocess
import sys
import tempfile
import threading
import time

from anfis_elevation_ros.core.params import IMU_NODE, node_specs
import numpy as np

TEST_DIR = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TEST_DIR))

from live_support import BackgroundProcess, cli, cli_env, NodesProcess  # noqa: E402, I100
from live_support import listening, PACKAGE_ROOT, play_at_recorded_pace  # noqa: E402
from live_support import wait_for  # noqa: E402
from live_support import write_linear_model, write_params  # noqa: E402

LATENCY_P99_TARGET_MS = 20.0
CPU_TARGET_PCT = 10.0
IMU_INPUT = '/imu_node: IMU input'


def cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process (all threads), s."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


class CpuSampler(threading.Thread):
    """Samples (wall time ns, CPU s) of a process every period."""

    def __init__(self, pid: int, period_s: float = 0.5):
        super().__init__(daemon=True)
        self.pid, self.period_s = pid, period_s
        self.samples = []
        self._halt = threading.Event()

    def run(self):
        while not self._halt.is_set():
            try:
                self.samples.append((time.time_ns(), cpu_seconds(self.pid)))
            except (OSError, IndexError):
                return
            self._halt.wait(self.period_s)

    def stop(self):
        self._halt.set()
        self.join()

    def percent_between(self, start_ns: int, end_ns: int) -> float:
        """CPU in % of one core between the first and last samples inside [start, end]."""
        inside = [s for s in self.samples if start_ns <= s[0] <= end_ns]
        if len(inside) < 2:
            return float('nan')
        (t0, c0), (t1, c1) = inside[0], inside[-1]
        return 100.0 * (c1 - c0) / ((t1 - t0) * 1e-9)


# A subscriber that receives the Imu stream as the IMU node does and does nothing with it.
BASELINE_SUBSCRIBER = """
import sys
import threading
import rclpy
from sensor_msgs.msg import Imu
from anfis_elevation_ros.nodes.polled_subscription import PolledSubscription
from anfis_elevation_ros.nodes.qos import imu_qos
from anfis_elevation_ros.nodes.spin import Spinner
rclpy.init()
node = rclpy.create_node('baseline_imu_subscriber')
batch_period_s = float(sys.argv[1])
if batch_period_s > 0.0:
    polled = PolledSubscription(node, Imu, '/imu/data', imu_qos(2000), lambda data: None,
                                batch_period_s, threading.Lock())
else:
    node.create_subscription(Imu, '/imu/data', lambda data: None, imu_qos(2000), raw=True)
spinner = Spinner('events')
spinner.add_node(node)
try:
    spinner.spin()
except KeyboardInterrupt:      # the SIGINT that BackgroundProcess stops it with
    pass
"""


def baseline_cpu_pct(bag: Path, work: Path, batch_period_s: float) -> float:
    """CPU (% of one core) of BASELINE_SUBSCRIBER while the bag plays at its recorded pace."""
    with BackgroundProcess([sys.executable, '-c', BASELINE_SUBSCRIBER, str(batch_period_s)],
                           work / 'baseline.log') as baseline:
        sampler = CpuSampler(baseline.proc.pid)
        sampler.start()
        published = play_at_recorded_pace(bag, work / 'published_baseline.csv', ready_s=0)
        sampler.stop()
    return sampler.percent_between(int(published[0, 1]), int(published[-1, 1]))


def simulate(out_dir: Path, scenario: str, rate_hz: float, seed: int) -> Path:
    """Simulate the walk at the IMU rate; return the bag directory."""
    result = subprocess.run(cli('simulate', '--scenario', scenario, '--rate-hz', rate_hz,
                                '--seed', seed, '--storage', 'mcap', '--out', out_dir),
                            env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f'simulate failed:\n{result.stderr}')
    return out_dir / 'imu'


def main(argv=None) -> int:
    """Run the benchmark; return 0 if every target is met."""
    parser = argparse.ArgumentParser(description=__doc__.strip().split('\n\n')[0])
    parser.add_argument('--scenario', choices=('sample', 'building'), default='sample',
                        help='sample: 67 s; building: about 640 s (the 10-minute run)')
    parser.add_argument('--rate-hz', type=float, default=400.0, help='IMU rate')
    parser.add_argument('--seed', type=int, default=7, help='simulation seed')
    parser.add_argument('--executor', choices=('events', 'single'), default='events',
                        help='executor of the nodes')
    parser.add_argument('--batch-period-s', type=float, default=None,
                        help="the imu node's imu_batch_period_s (default: the node's default)")
    parser.add_argument('--baseline', action='store_true',
                        help='then play the bag to a do-nothing subscriber and compare CPU')
    parser.add_argument('--json', type=Path, default=None, help='write the figures here')
    args = parser.parse_args(argv)

    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))
    work = Path(tempfile.mkdtemp(prefix='bench_live_'))
    bag = simulate(work / 'walk', args.scenario, args.rate_hz, args.seed)
    batch_period_s = args.batch_period_s
    if batch_period_s is None:
        batch_period_s = node_specs(IMU_NODE)['imu_batch_period_s'].default
    params = write_params(work / 'params.yaml', write_linear_model(work / 'model.json'),
                          imu={'imu_batch_period_s': batch_period_s})
    publish_log = work / 'published.csv'
    print(f'[bench] {args.scenario} walk at {args.rate_hz:g} Hz in {bag}; load average '
          f'{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores', file=sys.stderr)

    with listening() as listener, \
            NodesProcess(params, work / 'run.log', ('--executor', args.executor)) as nodes:
        if not wait_for(lambda: listener.count_publishers('/elevation') >= 1, 30.0):
            sys.exit(f'the nodes did not start:\n{nodes.log()}')
        sampler = CpuSampler(nodes.proc.pid)
        sampler.start()
        published = play_at_recorded_pace(bag, publish_log)
        time.sleep(1.5)                               # one more diagnostics message
        sampler.stop()
        code = nodes.stop()

    publish_ns = dict(zip(published[:, 0].tolist(), published[:, 1].tolist()))
    latencies_ms = np.array([(received - publish_ns[stamp]) * 1e-6
                             for stamp, _, _, _, received in listener.elevations
                             if stamp in publish_ns])
    cpu_pct = sampler.percent_between(int(published[0, 1]), int(published[-1, 1]))
    received = int(listener.diagnostic_value(IMU_INPUT, 'received', -1))
    lost = len(published) - received
    figures = {
        'scenario': args.scenario, 'rate_hz': args.rate_hz, 'executor': args.executor,
        'imu_batch_period_s': batch_period_s,
        'imu_messages_published': len(published), 'imu_messages_received': received,
        'lost_imu_messages': lost, 'cycles': len(latencies_ms),
        'latency_ms_p50': float(np.percentile(latencies_ms, 50)) if len(latencies_ms) else None,
        'latency_ms_p99': float(np.percentile(latencies_ms, 99)) if len(latencies_ms) else None,
        'latency_ms_max': float(latencies_ms.max()) if len(latencies_ms) else None,
        'nodes_cpu_pct_of_one_core': cpu_pct, 'load_average_1min': os.getloadavg()[0],
        'nodes_exit_code': code,
    }
    if args.baseline:
        baseline_pct = baseline_cpu_pct(bag, work, batch_period_s)
        figures['baseline_subscriber_cpu_pct_of_one_core'] = baseline_pct
        figures['nodes_over_baseline_cpu'] = cpu_pct / baseline_pct
    print(json.dumps(figures, indent=2))
    if args.json is not None:
        args.json.write_text(json.dumps(figures, indent=2) + '\n')
    failed = []
    if not len(latencies_ms) or figures['latency_ms_p99'] > LATENCY_P99_TARGET_MS:
        failed.append(f'latency p99 > {LATENCY_P99_TARGET_MS} ms')
    if not cpu_pct <= CPU_TARGET_PCT:
        failed.append(f'CPU > {CPU_TARGET_PCT} % of one core')
    if lost != 0:
        failed.append(f'{lost} IMU messages lost')
    if code != 0:
        failed.append(f'the nodes exited with code {code}')
    for message in failed:
        print(f'[bench] MISSED: {message}', file=sys.stderr)
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
