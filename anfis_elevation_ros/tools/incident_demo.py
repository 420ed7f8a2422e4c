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
``demo --responders N``: N simulated responders in one tower and the command centre, live.

Simulates the walks of ``sim/responders.py`` (``/ff1`` to floor 1, ``/ff2`` to floor 2,
``/ff3`` stays on the ground floor and stands still: man down) and writes their bags and the
tower's building file to the demo's folder; starts the command centre and, per responder, the
nodes (``run --namespace /ffN --building``) and a player (``play --topic /ffN/imu/data``), each
its own process over DDS; prints the page's URL; when the walks end, compares each
responder's floor on the page with the truth, writes a screenshot of the page
(``command_centre.png``, when chromium and chromedriver are installed) and stops everything
(``--keep-open`` leaves the command centre and the nodes running until Ctrl-C).

The bags play at ``--rate`` (2: twice real time), so the alarm timers are divided by it
(man-down pre-alarm after 10 s instead of 20 s): the page shows what the same walk would show
in real time.
"""

import json
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import time
import urllib.request

from .demo import log, READY_TIMEOUT_S, stop_process
from ..core.errors import InputError

START_TIMEOUT_S = 60.0     # the command centre prints its URL within this
PLAY_MARGIN_S = 60.0       # a player may take this much longer than its walk


def write_incident(out, plans=None, rate_hz: float = 100.0) -> tuple:
    """
    Simulate the responders and write their bags and the building file to ``out``.

    Returns
    -------
    (building file, {namespace: bag directory}); each bag's topic is ``<namespace>/imu/data``.

    """
    from .bags import write_imu_bag
    from ..core.building import save_building
    from ..sim.responders import RESPONDERS, simulate_responder, tower_building

    plans = RESPONDERS if plans is None else plans
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    walks, bags = [], {}
    for plan in plans:
        walk = simulate_responder(plan, rate_hz=rate_hz)
        bag = out / f'{plan.namespace.strip("/")}_imu'
        shutil.rmtree(bag, ignore_errors=True)
        write_imu_bag(bag, walk.to_recording('imu_link'), topic=f'{plan.namespace}/imu/data')
        walks.append(walk)
        bags[plan.namespace] = bag
    building = out / 'tower.yaml'
    save_building(building, tower_building(walks))
    return building, bags


def read_url_and_token(proc, timeout_s: float = START_TIMEOUT_S) -> tuple:
    """Read ``command-centre``'s first two lines (URL, token) from its stdout pipe."""
    url = token = None
    deadline = time.monotonic() + timeout_s
    while (url is None or token is None) and time.monotonic() < deadline:
        line = proc.stdout.readline()
        if not line:
            break
        if 'session token' in line:
            token = line.split()[-1]
        elif '://' in line:
            url = line.split()[1]
    if url is None or token is None:
        raise InputError(f'the command centre did not start (exit code {proc.poll()})')
    return url, token


def fetch_state(url: str) -> dict:
    """GET ``/api/state`` of the command centre at ``url``."""
    with urllib.request.urlopen(url.rstrip('/') + '/api/state', timeout=10) as response:
        return json.load(response)


def _cli(*args) -> list:
    return [sys.executable, '-m', 'anfis_elevation_ros', *(str(a) for a in args)]


def run_incident_demo(args) -> int:
    """Run the demo with ``args.responders`` responders; return the exit code."""
    from .screenshot import screenshot, why_no_browser
    from ..core.navigator import compile_navigator
    from ..sim.responders import RESPONDERS

    plans = RESPONDERS[:args.responders]
    out = Path(args.out)
    started = time.monotonic()
    log(f'simulating {len(plans)} responders in a three-storey tower')
    building, bags = write_incident(out, plans)
    compile_navigator()        # once, into numba's cache, not in every responder's process
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    state_dir = out / 'state'
    shutil.rmtree(state_dir, ignore_errors=True)
    logs = out / 'logs'
    logs.mkdir(exist_ok=True)
    alarms = [f'alarm.{name}:={seconds / args.rate}' for name, seconds in (
        ('no_motion_prealarm_s', 20.0), ('no_motion_alarm_s', 30.0), ('lost_contact_s', 10.0))]
    procs = []

    def start(name, command, **kwargs):
        log = open(logs / f'{name}.log', 'w')
        proc = subprocess.Popen(command, stdin=subprocess.DEVNULL, stderr=log,
                                stdout=kwargs.pop('stdout', log), **kwargs)
        procs.append(proc)
        return proc

    try:
        centre = start('command_centre', _cli('command-centre', '--building', building,
                                              '--port', args.port, '--ros-args',
                                              *(a for p in alarms for a in ('-p', p))),
                       stdout=subprocess.PIPE, text=True)
        url, token = read_url_and_token(centre)
        print(f'Command centre: {url}   (session token {token})', flush=True)
        for plan in plans:
            name = plan.namespace.strip('/')
            start(name, _cli('run', '--namespace', plan.namespace, '--building', building,
                             '--ros-args', '-p', f'state_dir:={state_dir}'))
        players = [start(f'play_{ns.strip("/")}',
                         _cli('play', bag, '--topic', f'{ns}/imu/data', '--rate', args.rate,
                              '--wait-s', START_TIMEOUT_S, '--ready-s', READY_TIMEOUT_S))
                   for ns, bag in bags.items()]
        log(f'playing {len(players)} walks at {args.rate:g}x; open {url} to watch')
        for player in players:
            player.wait(timeout=START_TIMEOUT_S + READY_TIMEOUT_S + PLAY_MARGIN_S
                        + 70.0 / args.rate)
            if player.returncode != 0:
                raise InputError(f'a player failed (see {logs})')
        time.sleep(2.0)
        state = fetch_state(url)
        floors = {r['id']: r['floor'] for r in state['responders']}
        for plan in plans:
            log(f'{plan.namespace}: floor {floors.get(plan.namespace, "-")} on the page, '
                f'{plan.final_floor} in truth')
        reason = why_no_browser()
        if reason is None:
            png = out / 'command_centre.png'
            screenshot(url, png, "return document.querySelectorAll('#roster tbody tr').length "
                       f'>= {len(plans)}')
            log(f'wrote {png}')
        else:
            log(f'no screenshot: {reason}')
        log(f'done in {time.monotonic() - started:.0f} s; logs in {logs}')
        if args.keep_open:
            print(f'Command centre still at {url}; Ctrl-C to stop', flush=True)
            stop_signals = {signal.SIGINT, signal.SIGTERM}
            signal.pthread_sigmask(signal.SIG_BLOCK, stop_signals)
            signal.sigwait(stop_signals)
    finally:
        for proc in reversed(procs):
            stop_process(proc)
    return 0
