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
Benchmark of the command centre over DDS: N fake responders into the ``command-centre`` process.

Run from the repository root: ``python test/benchmarks/bench_command_centre_dds.py [--minutes
2] [--responders 50] [--track-hz 10] [--centre-track-hz 2]`` (a script, not a test). This
process publishes, for each responder ``/bK`` as ``run --namespace /bK`` does, ``foot_odom`` at
``--track-hz`` (the IMU node's ``track_rate_hz``, 10 Hz by default), ``foot_odom_throttle`` at
``--centre-track-hz`` (``centre_track_rate_hz``, 2 Hz; what the centre subscribes) and, once a
second,
``elevation``, ``floor``, ``floor_certain``, ``stair_mode`` and a ``/diagnostics`` array; the
``command-centre`` subprocess discovers them, subscribes and feeds its Incident, and this
process reads its push stream (``/api/events``). After a warm-up it prints:

- CPU of the command-centre process (node, DDS, model, web server), % of one core, from
  /proc/<pid>/stat;
- latency from a pose's publication (its stamp, wall clock) to its first appearance in the
  push stream (p50, p99, max); the page's render adds its own (bench_command_centre.py);
- the command centre's resident memory at the start and the end of the measurement.

DDS discovery stays on this machine (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST unless set).
"""

import argparse
import json
import math
import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time
import urllib.request

import numpy as np

TICK_HZ = 10                     # the publisher's timer: poses at up to this rate
WARM_UP_S = 30.0
TICKS_PER_S = os.sysconf('SC_CLK_TCK')


def proc_cpu_s(pid: int) -> float:
    """Return user + system CPU time of a process, s (Linux /proc)."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS_PER_S


def proc_rss_mb(pid: int) -> float:
    """Return the resident memory of a process, MB."""
    for line in Path(f'/proc/{pid}/status').read_text().splitlines():
        if line.startswith('VmRSS:'):
            return int(line.split()[1]) / 1024.0
    return math.nan


class FakeResponders:
    """One node publishing the topics of N responders at their real rates."""

    def __init__(self, node, responders: int, track_hz: float, centre_track_hz: float):
        from diagnostic_msgs.msg import DiagnosticArray
        from geometry_msgs.msg import PointStamped
        from nav_msgs.msg import Odometry
        from std_msgs.msg import Bool, Int32, Int8

        from anfis_elevation_ros.nodes.qos import DIAGNOSTICS_QOS, LATEST_QOS

        self.types = {'elevation': PointStamped, 'floor': Int32, 'floor_certain': Bool,
                      'stair_mode': Int8, 'foot_odom': Odometry, 'foot_odom_throttle': Odometry}
        self.namespaces = [f'/b{k + 1}' for k in range(responders)]
        self.pubs = {ns: {name: node.create_publisher(t, f'{ns}/{name}', LATEST_QOS)
                          for name, t in self.types.items()} for ns in self.namespaces}
        self.diagnostics = node.create_publisher(DiagnosticArray, '/diagnostics',
                                                 DIAGNOSTICS_QOS)
        self.step = 0
        self.pose_every = round(TICK_HZ / track_hz)
        self.throttled_every = round(TICK_HZ / centre_track_hz)
        node.create_timer(1.0 / TICK_HZ, self.publish)

    def publish(self):
        from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

        t = self.step / TICK_HZ
        for k, ns in enumerate(self.namespaces):
            angle = 0.24 * t + k                         # 1.2 m/s on a 5 m circle
            pubs = self.pubs[ns]
            odom = self.types['foot_odom']()
            stamp_ns = time.time_ns()
            odom.header.stamp.sec, odom.header.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
            odom.pose.pose.position.x = 10.0 * (k % 10) + 5.0 * math.cos(angle)
            odom.pose.pose.position.y = 5.0 * math.sin(angle)
            odom.pose.pose.orientation.w = 1.0
            odom.pose.covariance[0] = odom.pose.covariance[7] = 0.1
            if (self.step + k) % self.pose_every == 0:
                pubs['foot_odom'].publish(odom)
            if (self.step + k) % self.throttled_every == 0:
                pubs['foot_odom_throttle'].publish(odom)
            if self.step % TICK_HZ == k % TICK_HZ:         # once a second, spread out
                point = self.types['elevation']()
                point.header.stamp = odom.header.stamp
                point.point.x = odom.pose.pose.position.x
                point.point.y = odom.pose.pose.position.y
                pubs['elevation'].publish(point)
                pubs['floor'].publish(self.types['floor'](data=k % 5))
                pubs['floor_certain'].publish(self.types['floor_certain'](data=True))
                pubs['stair_mode'].publish(self.types['stair_mode'](data=0))
                self.diagnostics.publish(DiagnosticArray(status=[DiagnosticStatus(
                    level=b'\x00', name=f'{ns}/imu_node: IMU input', message='ok')]))
        self.step += 1


class PushLatency:
    """Reads /api/events; records each new pose stamp's delay to the stream, s."""

    def __init__(self, url: str):
        self.latencies = []
        self.recording = False
        self._last = {}
        self._response = urllib.request.urlopen(url.rstrip('/') + '/api/events?since=0',
                                                timeout=30)
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for raw in self._response:
            line = raw.decode()
            if not line.startswith('data: '):
                continue
            now = time.time()
            for event in json.loads(line[6:])['events']:
                if event['type'] != 'responder':
                    continue
                r = event['responder']
                stamp = r.get('stamp_unix_s')
                if stamp is None or self._last.get(r['id']) == stamp:
                    continue
                self._last[r['id']] = stamp
                if self.recording:
                    self.latencies.append(now - stamp)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--minutes', type=float, default=2.0, help='length of the measurement')
    parser.add_argument('--responders', type=int, default=50)
    parser.add_argument('--track-hz', type=float, default=10.0, choices=(10.0, 5.0, 2.0, 1.0),
                        help="rate of each responder's foot_odom (track_rate_hz)")
    parser.add_argument('--centre-track-hz', type=float, default=2.0,
                        choices=(10.0, 5.0, 2.0, 1.0),
                        help="rate of each responder's foot_odom_throttle (centre_track_rate_hz)")
    args = parser.parse_args()
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')

    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    centre = subprocess.Popen([sys.executable, '-m', 'anfis_elevation_ros', 'command-centre',
                               '--port', '0'], stdout=subprocess.PIPE, text=True,
                              stdin=subprocess.DEVNULL)
    first = centre.stdout.readline().split()
    url, pid = first[1], int(first[3].rstrip(';'))
    centre.stdout.readline()
    rclpy.init()
    node = rclpy.create_node('fake_responders')
    FakeResponders(node, args.responders, args.track_hz, args.centre_track_hz)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinning = threading.Thread(target=executor.spin, daemon=True)
    spinning.start()
    try:
        push = PushLatency(url)
        time.sleep(WARM_UP_S)
        push.recording = True
        cpu0, wall0, rss0 = proc_cpu_s(pid), time.monotonic(), proc_rss_mb(pid)
        time.sleep(args.minutes * 60.0)
        cpu1, wall1, rss1 = proc_cpu_s(pid), time.monotonic(), proc_rss_mb(pid)
        push.recording = False
        latencies = np.array(push.latencies)
        state = json.load(urllib.request.urlopen(url + 'api/state', timeout=30))
        print(f'{args.responders} responders over DDS, foot_odom at {args.track_hz:g} Hz, '
              f'foot_odom_throttle at {args.centre_track_hz:g} Hz, {args.minutes:g} min after a '
              f'{WARM_UP_S:g} s warm-up; {len(state["responders"])} on the map')
        print(f'command-centre CPU {100 * (cpu1 - cpu0) / (wall1 - wall0):.1f} % of one core; '
              f'RSS {rss0:.1f} -> {rss1:.1f} MB')
        if len(latencies):
            p50, p99 = np.percentile(latencies, [50, 99])
            print(f'pose publication -> push stream: p50 {p50:.3f} s, p99 {p99:.3f} s, max '
                  f'{latencies.max():.3f} s over {len(latencies)} poses '
                  f'(load average {os.getloadavg()[0]:.1f})')
    finally:
        executor.shutdown()
        spinning.join(timeout=10.0)     # destroying the node under a spinning executor raises
        node.destroy_node()
        rclpy.try_shutdown()
        centre.send_signal(signal.SIGINT)
        centre.wait(timeout=30)


if __name__ == '__main__':
    main()
