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
Benchmark of the command centre: synthetic responders, its model, web server and page.

N responders feed one Incident; its web server serves the page to headless chromium (a
script, not a test).

Run from the repository root: ``python test/benchmarks/bench_command_centre.py [--minutes 2]
[--responders 50]``. Each responder sends a pose at 10 Hz (``foot_odom``) and, once a second, a
gait cycle (``elevation``), its floor, floor certainty, stair mode and a diagnostics status;
two of them stand still (they raise the man-down alarm) and the model's timers tick at 4 Hz,
as the ROS node does. Prints, after a warm-up:

- CPU of this process (model + web server + the synthetic feed; no DDS), % of one core;
- latency from each update (its stamp, taken at the call) to the end of the page render that
  showed it, measured in the browser with ``Date.now()`` (p50, p99, max);
- the resident memory of this process over the run (flat = no growth after the tracks fill),
  and the page's JavaScript heap (``performance.memory``).

Needs chromium + chromium-driver (apt) and selenium (the ``test`` extra).
"""

import argparse
import json
import math
import os
from pathlib import Path
import signal
import sys
import threading
import time

from anfis_elevation_ros.command_centre.incident import Incident
from anfis_elevation_ros.command_centre.web import make_server
from bench_measures import LatencyHistogram, proc_rss_mb

POSE_HZ = 10.0
TICK_EVERY = 3              # timers at POSE_HZ / 3 (about 3 Hz)
STILL = 2                   # responders that stand still (man-down alarm)
WARM_UP_S = 20.0
SAMPLE_S = 10.0
TOKEN = 'benchmark-token-0123456789'


def feed(incident, responders: int, stop: threading.Event) -> None:
    """Send every responder's messages at their real rates until ``stop``."""
    step = 0
    period = 1.0 / POSE_HZ
    next_time = time.monotonic()
    while not stop.is_set():
        t = step * period
        for k in range(responders):
            rid = f'/ff{k + 1}'
            floor = k % 5
            still = k < STILL
            angle = 0.0 if still else 0.24 * t + k          # 1.2 m/s on a 5 m circle
            x_m, y_m = 10.0 * (k % 10) + 5.0 * math.cos(angle), 5.0 * math.sin(angle)
            stamp_ns = time.time_ns()
            incident.update_pose(rid, stamp_ns, x_m, y_m, 3.0 * floor,
                                 math.degrees(angle) + 90.0, 0.5 + 0.01 * t)
            if step % int(POSE_HZ) == k % int(POSE_HZ):     # once a second, spread out
                if not still:
                    incident.update_elevation(rid, stamp_ns, x_m, y_m, 3.0 * floor)
                incident.update_floor(rid, floor)
                incident.update_floor_certain(rid, True)
                incident.update_mode(rid, 0)
                incident.update_diagnostics(rid, 0, f'{rid}/imu_node: IMU input', 'ok')
        if step % TICK_EVERY == 0:
            incident.tick()
        step += 1
        next_time += period
        stop.wait(max(0.0, next_time - time.monotonic()))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--minutes', type=float, default=2.0, help='length of the run')
    parser.add_argument('--responders', type=int, default=50)
    parser.add_argument('--json', type=Path, help='also write the figures to this file')
    args = parser.parse_args()

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from browser_support import start_chromium, stop_chromium, why_no_browser
    if why_no_browser():
        sys.exit(f'cannot run: {why_no_browser()}')

    incident = Incident()
    server = make_server(incident, '127.0.0.1', 0, TOKEN)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    stop = threading.Event()
    feeder = threading.Thread(target=feed, args=(incident, args.responders, stop), daemon=True)
    feeder.start()
    driver, profile = start_chromium()
    latencies, samples = LatencyHistogram(), []
    signal.signal(signal.SIGTERM, signal.default_int_handler)   # stop early, still report
    try:
        driver.get(server.url)
        start = time.monotonic()
        end = start + 60.0 * args.minutes
        cpu0 = wall0 = None
        while time.monotonic() < end:
            try:
                time.sleep(SAMPLE_S)
            except KeyboardInterrupt:
                print('stopped early', flush=True)
                break
            now = time.monotonic()
            batch, heap = driver.execute_script(
                'return [window.commandCentre.latencies.splice(0), '
                'performance.memory ? performance.memory.usedJSHeapSize : null];')
            if now - start < WARM_UP_S:
                continue
            if cpu0 is None:
                cpu0, wall0 = time.process_time(), now
                continue
            latencies.add(batch)
            cpu = 100.0 * (time.process_time() - cpu0) / (now - wall0)
            page_mb = None if heap is None else round(heap / 2 ** 20, 1)
            rss = round(proc_rss_mb(os.getpid()), 1)
            samples.append({'t_s': round(now - start), 'rss_mb': rss,
                            'page_js_heap_mb': page_mb, 'cpu_percent_so_far': round(cpu, 1)})
            print(f't {now - start:6.0f} s  RSS {samples[-1]["rss_mb"]:7.1f} MB  page JS heap '
                  f'{page_mb} MB  CPU {cpu:5.1f} % of one core  updates seen {latencies.size}',
                  flush=True)
        renders, batches, render_s = driver.execute_script(
            'const p = window.commandCentre; return [p.renders, p.batches, p.renderSeconds];')
        roster_rows = driver.execute_script(
            "return document.querySelectorAll('#roster tbody tr').length;")
    finally:
        stop_chromium(driver, profile)
        stop.set()
        feeder.join(5)
        server.shutdown()
        server.server_close()
    if not latencies.size or not samples:
        sys.exit('no measurement: run longer than the warm-up (--minutes)')
    lat = latencies
    rss = [s['rss_mb'] for s in samples]
    figures = {
        'responders': args.responders, 'minutes': args.minutes,
        'cpu_percent_of_one_core': samples[-1]['cpu_percent_so_far'],
        'latency_s': {'p50': lat.percentile(50), 'p99': lat.percentile(99), 'max': lat.max_s,
                      'updates': lat.size},
        'rss_mb': {'first': rss[0], 'last': rss[-1], 'max': max(rss)},
        'page_js_heap_mb': {'first': samples[0]['page_js_heap_mb'],
                            'last': samples[-1]['page_js_heap_mb']},
        'page': {'renders': renders, 'batches': batches,
                 'mean_render_ms': round(1000.0 * render_s / max(renders, 1), 1)},
        'roster_rows': roster_rows,
        'rejected': incident.snapshot()['rejected'], 'samples': samples,
    }
    print(f'{args.responders} responders, {args.minutes:g} min: CPU '
          f'{figures["cpu_percent_of_one_core"]:.1f} % of one core; update -> page latency p50 '
          f'{figures["latency_s"]["p50"]:.3f} s, p99 {figures["latency_s"]["p99"]:.3f} s, max '
          f'{figures["latency_s"]["max"]:.3f} s ({lat.size} updates); RSS {rss[0]:.1f} -> '
          f'{rss[-1]:.1f} MB (max {max(rss):.1f}); page JS heap '
          f'{samples[0]["page_js_heap_mb"]} -> {samples[-1]["page_js_heap_mb"]} MB; page: '
          f'{renders} renders of {batches} pushes, '
          f'{figures["page"]["mean_render_ms"]} ms each; roster rows {roster_rows}')
    if args.json:
        args.json.write_text(json.dumps(figures, indent=2) + '\n')


if __name__ == '__main__':
    main()
