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
2] [--responders 50] [--track-hz 10] [--centre-track-hz 2] [--browser] [--json FILE]`` (a
script, not a test). This process publishes, for each responder ``/bK`` as ``run --namespace
/bK`` does, ``foot_odom`` at ``--track-hz`` (the IMU node's ``track_rate_hz``, 10 Hz by
default), ``foot_odom_throttle`` at ``--centre-track-hz`` (``centre_track_rate_hz``, 2 Hz; what
the centre subscribes) and, once a second, ``elevation``, ``floor``, ``floor_certain``,
``stair_mode`` and a ``/diagnostics`` array, each stamped with the wall clock when published;
the ``command-centre`` subprocess discovers them, subscribes and feeds its Incident; this
process reads its push stream (``/api/events``) and, with ``--browser``, keeps the page open
in headless chromium (chromium + chromium-driver from apt, selenium from the ``test`` extra).
After a warm-up it prints, sampling every 10 s:

- CPU of the command-centre process (node, DDS, model, web server), % of one core, from
  /proc/<pid>/stat;
- its resident memory at every sample (first, last, max: flat = no growth);
- latency from a message's publication (its stamp) to its first appearance in the push
  stream, and with ``--browser`` to the end of the page's render that showed it, for every
  new stamp (poses and elevations) and for ``elevation`` messages alone (p50, p99, max).

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

from bench_measures import LatencyHistogram, proc_cpu_s, proc_rss_mb

TICK_HZ = 10                     # the publisher's timer: poses at up to this rate
WARM_UP_S = 30.0
SAMPLE_S = 10.0


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


def open_page(url: str):
    """Open the command centre's page in headless chromium; return (driver, profile)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from browser_support import start_chromium, why_no_browser
    if why_no_browser():
        sys.exit(f'cannot run --browser: {why_no_browser()}')
    driver, profile = start_chromium()
    driver.get(url)
    return driver, profile


def take_page_latencies(driver) -> tuple:
    """Return and empty the page's probes: (every new stamp, elevation stamps), s."""
    return driver.execute_script(
        'const p = window.commandCentre; '
        'return [p.latencies.splice(0), p.elevationLatencies.splice(0)];')


def print_latency(what: str, summary: dict) -> None:
    """Print one latency line."""
    print(f'{what}: p50 {summary["p50"]:.3f} s, p99 {summary["p99"]:.3f} s, max '
          f'{summary["max"]:.3f} s over {summary["count"]} messages')


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--minutes', type=float, default=2.0, help='length of the measurement')
    parser.add_argument('--responders', type=int, default=50)
    parser.add_argument('--track-hz', type=float, default=10.0, choices=(10.0, 5.0, 2.0, 1.0),
                        help="rate of each responder's foot_odom (track_rate_hz)")
    parser.add_argument('--centre-track-hz', type=float, default=2.0,
                        choices=(10.0, 5.0, 2.0, 1.0),
                        help="rate of each responder's foot_odom_throttle (centre_track_rate_hz)")
    parser.add_argument('--browser', action='store_true',
                        help='also keep the page open in headless chromium and time its updates')
    parser.add_argument('--json', type=Path, help='also write the figures to this file')
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
    driver = profile = None
    page, page_elevation, samples = LatencyHistogram(), LatencyHistogram(), []
    signal.signal(signal.SIGTERM, signal.default_int_handler)   # stop early, still report
    try:
        push = PushLatency(url)
        if args.browser:
            driver, profile = open_page(url)
        time.sleep(WARM_UP_S)
        if driver:
            take_page_latencies(driver)
        push.recording = True
        cpu0, wall0 = proc_cpu_s(pid), time.monotonic()
        end = wall0 + 60.0 * args.minutes
        while time.monotonic() < end:
            try:
                time.sleep(min(SAMPLE_S, max(0.0, end - time.monotonic())))
            except KeyboardInterrupt:
                print('stopped early', flush=True)
                break
            if driver:
                every, elevation = take_page_latencies(driver)
                page.add(every)
                page_elevation.add(elevation)
            now = time.monotonic()
            samples.append({'t_s': round(now - wall0), 'rss_mb': round(proc_rss_mb(pid), 1),
                            'cpu_percent_so_far': round(
                                100.0 * (proc_cpu_s(pid) - cpu0) / (now - wall0), 1),
                            'load_average': os.getloadavg()[0]})
            print(f't {samples[-1]["t_s"]:6d} s  command-centre RSS {samples[-1]["rss_mb"]:6.1f} '
                  f'MB  CPU {samples[-1]["cpu_percent_so_far"]:5.1f} % of one core  page '
                  f'updates {page.size}, elevation {page_elevation.size}  load average '
                  f'{samples[-1]["load_average"]:.1f}', flush=True)
        push.recording = False
        renders = driver.execute_script('return window.commandCentre.renders;') if driver \
            else None
        state = json.load(urllib.request.urlopen(url + 'api/state', timeout=30))
    finally:
        if driver:
            from browser_support import stop_chromium
            stop_chromium(driver, profile)
        executor.shutdown()
        spinning.join(timeout=10.0)     # destroying the node under a spinning executor raises
        node.destroy_node()
        rclpy.try_shutdown()
        centre.send_signal(signal.SIGINT)
        centre.wait(timeout=30)
    if not samples:
        sys.exit('no measurement: run longer (--minutes)')
    pushed = LatencyHistogram()
    pushed.add(push.latencies)
    rss = [s['rss_mb'] for s in samples]
    figures = {
        'responders': args.responders, 'minutes': samples[-1]['t_s'] / 60.0,
        'track_hz': args.track_hz, 'centre_track_hz': args.centre_track_hz,
        'on_the_map': len(state['responders']),
        'cpu_percent_of_one_core': samples[-1]['cpu_percent_so_far'],
        'rss_mb': {'first': rss[0], 'last': rss[-1], 'max': max(rss)},
        'publication_to_push_s': pushed.summary(),
        'samples': samples,
    }
    print(f'{args.responders} responders over DDS, foot_odom at {args.track_hz:g} Hz, '
          f'foot_odom_throttle at {args.centre_track_hz:g} Hz, {figures["minutes"]:.1f} min '
          f'after a {WARM_UP_S:g} s warm-up; {figures["on_the_map"]} on the map')
    print(f'command-centre CPU {figures["cpu_percent_of_one_core"]:.1f} % of one core; RSS '
          f'{rss[0]:.1f} -> {rss[-1]:.1f} MB (max {max(rss):.1f})')
    print_latency('publication -> push stream', figures['publication_to_push_s'])
    if driver:
        figures['publication_to_page_s'] = page.summary()
        figures['elevation_publication_to_page_s'] = page_elevation.summary()
        figures['page_renders'] = renders
        print_latency('publication -> page rendered (every new stamp)',
                      figures['publication_to_page_s'])
        print_latency('elevation publication -> page rendered',
                      figures['elevation_publication_to_page_s'])
    if args.json:
        args.json.write_text(json.dumps(figures, indent=2) + '\n')


if __name__ == '__main__':
    main()
