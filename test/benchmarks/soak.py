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
Soak benchmark: an 8-hour simulated shift through offline replay, then a live run (a script).

Run from the repository root, one part at a time on a shared machine:

- ``PYTHONPATH=. python test/benchmarks/soak.py --live-minutes 0``: the 8-hour shift offline
  (about 20 minutes at 6000 samples/s);
- ``PYTHONPATH=. python test/benchmarks/soak.py --hours 0``: 30 minutes live through the nodes
  (about 32 minutes);
- ``PYTHONPATH=. python test/benchmarks/soak.py --hours 0.05 --row-minutes 1 --live-minutes 1``:
  a two-minute check of the script itself.

The shift. A building of 3.06 m storeys (18 risers of 0.17 m, the default step height K, so
that a height error is a miscounted step and not a riser mismatch; two flights of 9 with a
180 deg landing turn), floors -2 to +6. The firefighter's shift is cut into walks of about
five minutes (``--chunk-minutes``), each simulated at 200 Hz with the tactical IMU preset and
its own seed: level search on a floor (walks with turns, turns on the spot, stops) and, in
the first walk and 80 % of the others, a stair trip of one to three storeys up or down (1, 2
or 3 steps per stride).
Every walk starts and ends standing on a floor, its stamps continue those of the walk before,
and its truth height is offset by the truth height at the end of the walk before. The readings
of a foot at rest do not depend on its heading, so a walk that starts at heading 0 is the same
data as one that continues the last heading: no rotation is needed; what does jump between
walks is the IMU's turn-on error draw (tactical grade: 1 deg/h, 0.5 mg). ``random_walk`` is
not used: its risers and flight lengths do not add up to storeys, so its heights name no floor.
The walks are simulated in a worker process one walk ahead, so the simulator's memory and time
stay out of the figures. All samples go through ONE input gate, ``FootNavigator`` and
``ElevationTracker`` (default parameters, packaged model) in replay's loop
(``navigated_samples``, ``cycle_row``). Per row of ``--row-minutes`` (default 60) simulated
minutes it reports:

- RSS of this process at the end of the row (after ``gc.collect``, with the next walk
  received). glibc's mmap threshold is fixed at 128 KiB (``mallopt``) for this process: the
  walks arrive as arrays of about 1.5 MB, and with glibc's default sliding threshold their
  freed blocks stay in the heap for reuse, so that the RSS moved by up to 15 MB from row to
  row while the memory in use did not (mallinfo2 over an hour in 5-minute rows: 15.1-15.4 MB
  in use, 6-15 MB free);
- throughput: samples per wall second and per CPU second of the pipeline alone;
- cycles (and true strides), level cycles, floor errors and max |quantised - true height| at
  level cycles. A level cycle closes while the foot stands on a floor: its true height at the
  cycle's stamp is within 3 cm of a whole storey. The true floor is
  ``floor_index(true height, floor_height_m)``, with the tracker's 3.0 m storey height;
- the floor the tracker publishes at those level cycles (no building file: the storeys are
  2.8-4.5 m to it, the floors walked its anchors, ``core/floors.py``): how many it says are
  certain, and how many of those are not the true floor (``floor_index(true height, 3.06 m)``).

Targets: RSS growth from the end of the first row (warm-up) to the end < 5 %; zero
floor errors at level cycles, and no published floor certain and wrong; throughput steady,
i.e. no slowdown: the least-squares line of the rows' samples per CPU second loses less than
10 % of the median from the first row to the last. CPU, not wall, time because the machine is
shared and the wall clock also measures the neighbours; a trend and not a band because even
the CPU rate of the same hour of data varies by 15 % between runs on a loaded machine (two
8-hour runs: hour 2 at 6989 and 5918 samples per CPU s), and the rows differ in content
(stance samples carry the ZUPT update).

Live (``--live-minutes N``, default 30, 0 skips it): an N-minute walk of the same building
(one simulation) is written as a bag, ``python -m anfis_elevation_ros run`` (packaged model,
default parameters) is started in a subprocess, the bag is played at its pace by
``python -m anfis_elevation_ros play``, and this script samples the RSS and CPU time of the
``run`` process every 10 s and subscribes to /elevation and /diagnostics. Targets: RSS growth
from 5 minutes into the playing (half the run if shorter) to its end < 5 %; zero floor errors
at level cycles (floor of the elevation's height against the truth at its stamp); zero lost
IMU messages (published minus those the IMU node counted as received); the nodes exit with 0.

Prints the tables, writes the figures as JSON with ``--json``, and exits 1 if a target is
missed.
"""

import argparse
from concurrent.futures import ProcessPoolExecutor
import ctypes
import gc
import json
import os
from pathlib import Path
import sys
import tempfile
import threading
import time
from types import SimpleNamespace

from anfis_elevation_ros import sim
from anfis_elevation_ros.core.height import ElevationTracker, floor_index
from anfis_elevation_ros.core.input_gate import InputGate
from anfis_elevation_ros.core.navigator import FootNavigator
from anfis_elevation_ros.core.params import load_model, load_pipeline_params
from anfis_elevation_ros.tools.replay import CYCLE_COLUMNS, cycle_row, navigated_samples
import numpy as np

TEST_DIR = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TEST_DIR))
sys.path.insert(0, str(TEST_DIR / 'benchmarks'))

from bench_live import cpu_seconds, IMU_INPUT  # noqa: E402, I100
from live_support import listening, NodesProcess, play_at_recorded_pace  # noqa: E402
from live_support import wait_for, write_params  # noqa: E402

RATE_HZ = 200.0
IMU_PRESET = 'tactical'
RISER_M = 0.17
STEPS_PER_FLIGHT = 9
STOREY_M = 2 * STEPS_PER_FLIGHT * RISER_M
LOWEST_FLOOR, HIGHEST_FLOOR = -2, 6
STAIR_WALK_FRACTION = 0.8
STEPS_PER_STRIDE_WEIGHTS = {1: 0.3, 2: 0.6, 3: 0.1}
LEVEL_TOLERANCE_M = 0.03
MEMORY_GROWTH_TARGET_PCT = 5.0
SLOWDOWN_TOLERANCE = 0.10
LIVE_SAMPLE_PERIOD_S = 10.0
LIVE_WARM_UP_S = 300.0
MAX_LISTED_ERRORS = 20
M_MMAP_THRESHOLD = -3   # glibc mallopt parameter
HEIGHT_COLUMN, FLOOR_COLUMN, CERTAIN_COLUMN = (CYCLE_COLUMNS.index(name) for name in (
    'height_m', 'floor', 'floor_certain'))


# -- the shift ---------------------------------------------------------------------------------

def stair_trip(storeys: int, rng: np.random.Generator) -> list:
    """Segments of a trip of ``storeys`` storeys (negative: down), landing turns included."""
    direction = 1 if storeys > 0 else -1
    per_stride = int(rng.choice(list(STEPS_PER_STRIDE_WEIGHTS),
                                p=list(STEPS_PER_STRIDE_WEIGHTS.values())))
    side = float(rng.choice((-1.0, 1.0)))
    landing = sim.Segment.level(2, turn_deg=180.0 * side, stride_length_m=0.7)
    flight = sim.Segment.stairs(STEPS_PER_FLIGHT, direction, steps_per_stride=per_stride,
                                step_height_m=RISER_M)
    segments = []
    for storey in range(abs(storeys)):
        if storey:
            segments.append(landing)   # the floor's own landing, on to the next flight
        segments += [flight, landing, flight]
    return segments


def search_activity(rng: np.random.Generator) -> list:
    """One piece of level search: a walk (maybe turning), a turn on the spot or a stop."""
    activity = rng.choice(3, p=(0.6, 0.2, 0.2))
    if activity == 0:
        strides = int(rng.integers(3, 16))
        turn = float(rng.choice((0.0, 0.0, 45.0, 90.0, 180.0))) * float(rng.choice((-1, 1)))
        return [sim.Segment.level(strides, turn_deg=turn if abs(turn) <= 60.0 * strides else 0)]
    if activity == 1:
        return [sim.Segment.turn(float(rng.uniform(45.0, 180.0)) * float(rng.choice((-1, 1))))]
    return [sim.Segment.stand(float(rng.uniform(2.0, 30.0)))]


def plan_walk(floor: int, duration_s: float, rng: np.random.Generator, first: bool) -> tuple:
    """
    Plan one walk of about ``duration_s`` starting on ``floor``.

    The first walk of a shift always takes the stairs (up to the fire floor, and so that a
    short run checks stairs too); later ones in ``STAIR_WALK_FRACTION`` of the walks.

    Returns
    -------
    (tuple of Segment, floor at the end)

    """
    segments = [sim.Segment.level(int(rng.integers(5, 16)))]
    if first or rng.uniform() < STAIR_WALK_FRACTION:
        direction = 1 if first else int(rng.choice((-1, 1)))
        room = (HIGHEST_FLOOR - floor) if direction > 0 else (floor - LOWEST_FLOOR)
        if room == 0:
            direction = -direction
            room = HIGHEST_FLOOR - LOWEST_FLOOR
        storeys = direction * min(room, int(rng.integers(1, 4)))
        segments += stair_trip(storeys, rng)
        floor += storeys
    budget_s = duration_s - sim.DEFAULT_INITIAL_STAND_S - sim.DEFAULT_FINAL_STAND_S
    while sim.nominal_duration_s(segments, step_height_m=RISER_M) < budget_s:
        segments += search_activity(rng)
    return tuple(segments), floor


def shift_plans(chunk_s: float, seed: int):
    """Yield (segments, seed) of consecutive walks, without end."""
    rng = np.random.default_rng(seed)
    floor = 0
    for index in range(sys.maxsize):
        segments, floor = plan_walk(floor, chunk_s, rng, index == 0)
        yield segments, seed * 100_000 + index


def simulate(segments, seed: int) -> sim.SimulatedWalk:
    """Simulate a walk of the shift at 200 Hz with the tactical preset."""
    return sim.simulate_walk(segments, rng=np.random.default_rng(seed), rate_hz=RATE_HZ,
                             imu=IMU_PRESET, step_height_m=RISER_M)


def simulate_chunk(segments, seed: int) -> dict:
    """Simulate one walk (in the worker process); return what the pipeline and the check need."""
    start = time.perf_counter()
    walk = simulate(segments, seed)
    return {'offset_ns': walk.stamp_ns - walk.stamp_ns[0], 'acc_b': walk.acc_b,
            'gyr_b': walk.gyr_b, 'z_m': walk.pos_n[:, 2].copy(),
            'stride_offset_ns': walk.strides.stamp_ns - walk.stamp_ns[0],
            'sim_s': time.perf_counter() - start}


# -- checks shared by both parts ---------------------------------------------------------------

def on_floor(true_height_m: float) -> bool:
    """Return True if a true height is that of a floor (the foot stands on one)."""
    return abs(true_height_m - STOREY_M * round(true_height_m / STOREY_M)) <= LEVEL_TOLERANCE_M


class FloorCheck:
    """Level cycles, floor errors and the largest height error at level cycles."""

    def __init__(self, floor_height_m: float):
        self.floor_height_m = floor_height_m
        self.level_cycles = 0
        self.floor_errors = 0
        self.certain_floors = 0
        self.wrong_certain_floors = 0
        self.max_height_error_m = 0.0
        self.errors = []   # the first few: (time from the start s, true height, estimate)

    def add(self, time_s: float, true_height_m: float, height_m: float, floor=None,
            certain=False):
        """Check one cycle's quantised height (and published floor) against the truth."""
        if not on_floor(true_height_m):
            return
        self.level_cycles += 1
        if certain:
            self.certain_floors += 1
            self.wrong_certain_floors += floor != floor_index(true_height_m, STOREY_M)
        self.max_height_error_m = max(self.max_height_error_m, abs(height_m - true_height_m))
        true_floor = floor_index(true_height_m, self.floor_height_m)
        if floor_index(height_m, self.floor_height_m) != true_floor:
            self.floor_errors += 1
            if len(self.errors) < MAX_LISTED_ERRORS:
                self.errors.append((round(time_s, 2), round(true_height_m, 3),
                                    round(height_m, 3)))


def rss_mb(pid='self') -> float:
    """Resident set size of a process (VmRSS), MB."""
    for line in Path(f'/proc/{pid}/status').read_text().splitlines():
        if line.startswith('VmRSS:'):
            return int(line.split()[1]) / 1024.0
    raise RuntimeError(f'no VmRSS in /proc/{pid}/status')


# -- offline -----------------------------------------------------------------------------------

class Row:
    """Figures of one row of simulated time."""

    def __init__(self, floor_height_m: float):
        self.samples = self.cycles = self.strides = 0
        self.wall_s = self.cpu_s = 0.0
        self.check = FloorCheck(floor_height_m)

    def figures(self, end_h: float) -> dict:
        """Close the row: its figures and the RSS."""
        gc.collect()
        return {'end_h': round(end_h, 4), 'samples': self.samples, 'cycles': self.cycles,
                'strides': self.strides, 'level_cycles': self.check.level_cycles,
                'floor_errors': self.check.floor_errors,
                'certain_floors': self.check.certain_floors,
                'wrong_certain_floors': self.check.wrong_certain_floors,
                'max_level_height_error_m': round(self.check.max_height_error_m, 3),
                'floor_error_cycles': self.check.errors, 'rss_mb': round(rss_mb(), 2),
                'samples_per_s': round(self.samples / max(self.wall_s, 1e-9)),
                'samples_per_cpu_s': round(self.samples / max(self.cpu_s, 1e-9))}


def feed(chunk, k0: int, k1: int, t0_ns: int, pipeline, row: Row):
    """Run samples k0..k1 of a chunk through the pipeline; account them in the row."""
    gate, navigator, tracker = pipeline
    piece = SimpleNamespace(stamp_ns=chunk.stamp_ns[k0:k1], acc_b=chunk.acc_b[k0:k1],
                            gyr_b=chunk.gyr_b[k0:k1])
    wall, cpu = time.perf_counter(), time.process_time()
    cycles = []
    for _, _, cycle in navigated_samples(piece, gate, navigator):
        if cycle is not None:
            cycles.append(cycle_row(cycle, tracker))
    row.wall_s += time.perf_counter() - wall
    row.cpu_s += time.process_time() - cpu
    row.samples += k1 - k0
    row.cycles += len(cycles)
    row.strides += int(np.count_nonzero((chunk.stride_ns >= chunk.stamp_ns[k0])
                                        & (chunk.stride_ns < chunk.stamp_ns[k1 - 1] + 1)))
    for values in cycles:
        stamp_ns, height_m = values[0], values[HEIGHT_COLUMN]
        true_m = chunk.z_m[np.searchsorted(chunk.stamp_ns, stamp_ns)]
        row.check.add((stamp_ns - t0_ns) * 1e-9, true_m, height_m, values[FLOOR_COLUMN],
                      bool(values[CERTAIN_COLUMN]))


def run_offline(hours: float, row_minutes: float, chunk_minutes: float, seed: int) -> dict:
    """Run the shift through one pipeline; return the figures."""
    ctypes.CDLL(None).mallopt(M_MMAP_THRESHOLD, 128 * 1024)   # see the module docstring
    params = load_pipeline_params()
    model = load_model(params.model_path)
    pipeline = (InputGate(params.gate), FootNavigator(params.navigator),
                ElevationTracker(model, params.elevation))
    floor_height_m = params.elevation.floor_height_m
    t0_ns = start_ns = sim.EPOCH_NS
    end_ns = t0_ns + round(hours * 3600e9)
    row_ns = round(row_minutes * 60e9)
    period_ns = round(1e9 / RATE_HZ)
    boundary_ns = t0_ns + row_ns
    true_offset_m = 0.0
    rows, row = [], Row(floor_height_m)
    sim_s = wait_s = 0.0
    chunks = 0
    plans = shift_plans(chunk_minutes * 60.0, seed)
    started = time.perf_counter()
    with ProcessPoolExecutor(max_workers=1) as worker:
        pending = worker.submit(simulate_chunk, *next(plans))
        while start_ns < end_ns:
            waited = time.perf_counter()
            data = pending.result()
            wait_s += time.perf_counter() - waited
            pending = worker.submit(simulate_chunk, *next(plans))  # one walk ahead
            sim_s += data['sim_s']
            chunks += 1
            chunk = SimpleNamespace(stamp_ns=data['offset_ns'] + start_ns, acc_b=data['acc_b'],
                                    gyr_b=data['gyr_b'], z_m=data['z_m'] + true_offset_m,
                                    stride_ns=data['stride_offset_ns'] + start_ns)
            start_ns = int(chunk.stamp_ns[-1]) + period_ns
            true_offset_m = float(chunk.z_m[-1])
            end = int(np.searchsorted(chunk.stamp_ns, end_ns))
            final_true_m = float(chunk.z_m[end - 1])
            k0 = 0
            while k0 < end:
                k1 = min(end, int(np.searchsorted(chunk.stamp_ns, boundary_ns)))
                if k1 > k0:
                    feed(chunk, k0, k1, t0_ns, pipeline, row)
                k0 = k1
                if k0 < end:
                    pending.result()   # every row ends with the next walk in memory
                    rows.append(row.figures((boundary_ns - t0_ns) / 3600e9))
                    log_row(rows[-1])
                    row, boundary_ns = Row(floor_height_m), boundary_ns + row_ns
        if row.samples:
            pending.result()
            rows.append(row.figures(hours))
            log_row(rows[-1])
    navigator = pipeline[1]
    return {'hours': hours, 'row_minutes': row_minutes, 'chunk_minutes': chunk_minutes,
            'seed': seed, 'walks': chunks, 'samples': sum(r['samples'] for r in rows),
            'wall_s': round(time.perf_counter() - started, 1),
            'simulation_s': round(sim_s, 1), 'waited_for_simulation_s': round(wait_s, 1),
            'navigator_cycles': navigator.status.cycles,
            'invalid_cycles': navigator.status.invalid_cycles, 'gaps': navigator.status.gaps,
            'rejected': {k: v for k, v in pipeline[0].rejected.items() if v},
            'final_height_m': pipeline[2].height_m, 'final_true_height_m': final_true_m,
            'rows': rows}


def log_row(row: dict):
    """Progress to stderr."""
    print(f'[soak] {row["end_h"]:.2f} h: RSS {row["rss_mb"]:.1f} MB, {row["samples_per_s"]} '
          f'samples/s, {row["cycles"]} cycles, {row["floor_errors"]} floor errors, load '
          f'{os.getloadavg()[0]:.2f}', file=sys.stderr, flush=True)


def offline_verdicts(figures: dict) -> list:
    """Add the targets' figures; return (target, met, figure) for each target."""
    rows = figures['rows']
    first, last = rows[0]['rss_mb'], rows[-1]['rss_mb']
    growth = 100.0 * (last - first) / first
    floor_errors = sum(r['floor_errors'] for r in rows)
    level_cycles = sum(r['level_cycles'] for r in rows)
    certain = sum(r['certain_floors'] for r in rows)
    wrong_certain = sum(r['wrong_certain_floors'] for r in rows)
    rates = np.array([r['samples_per_cpu_s'] for r in rows], dtype=float)
    hours = np.array([r['end_h'] for r in rows])
    spread = float(np.max(np.abs(rates / np.median(rates) - 1.0)))
    trend = float(np.polyfit(hours, rates, 1)[0] * (hours[-1] - hours[0]) / np.median(rates)
                  if len(rows) > 1 else 0.0)
    figures.update({'rss_growth_pct': round(growth, 2), 'floor_errors': floor_errors,
                    'level_cycles': level_cycles, 'certain_floors': certain,
                    'wrong_certain_floors': wrong_certain,
                    'throughput_max_deviation_from_median_pct': round(100.0 * spread, 1),
                    'throughput_trend_pct': round(100.0 * trend, 1)})
    return [
        (f'offline RSS growth after row 1 < {MEMORY_GROWTH_TARGET_PCT:g} %',
         growth < MEMORY_GROWTH_TARGET_PCT, f'{growth:+.2f} % ({first:.1f} -> {last:.1f} MB)'),
        ('offline floor errors at level cycles = 0', floor_errors == 0 and level_cycles > 0,
         f'{floor_errors} in {level_cycles} level cycles'),
        ('offline published floors certain and wrong = 0', wrong_certain == 0,
         f'{wrong_certain} of {certain} certain ({level_cycles} level cycles)'),
        (f'offline throughput trend over the run > -{100 * SLOWDOWN_TOLERANCE:.0f} %',
         trend > -SLOWDOWN_TOLERANCE, f'{100.0 * trend:+.1f} % (rows within '
         f'{100.0 * spread:.1f} % of the median)'),
    ]


def print_offline(figures: dict):
    """Print the table of rows and the totals."""
    print(f'\nOffline: {figures["hours"]:g} h at {RATE_HZ:g} Hz, {figures["walks"]} walks, '
          f'{figures["samples"]} samples in {figures["wall_s"]:.0f} s wall (simulation '
          f'{figures["simulation_s"]:.0f} s in the worker process, waited for it '
          f'{figures["waited_for_simulation_s"]:.0f} s)')
    print('| end h | samples | cycles | strides | level cycles | floor errors | floors certain '
          '(wrong) | max dh level m | RSS MB | samples/s | samples/CPU s |')
    print('| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |')
    for r in figures['rows']:
        print(f'| {r["end_h"]:g} | {r["samples"]} | {r["cycles"]} | {r["strides"]} | '
              f'{r["level_cycles"]} | {r["floor_errors"]} | {r["certain_floors"]} '
              f'({r["wrong_certain_floors"]}) | {r["max_level_height_error_m"]:.2f} '
              f'| {r["rss_mb"]:.1f} | {r["samples_per_s"]} | {r["samples_per_cpu_s"]} |')
    print(f'RSS growth after the first row {figures["rss_growth_pct"]:+.2f} %; floor errors '
          f'{figures["floor_errors"]} in {figures["level_cycles"]} level cycles; throughput '
          f'trend {figures["throughput_trend_pct"]:+.1f} %, rows within '
          f'{figures["throughput_max_deviation_from_median_pct"]:.1f} % of the median; '
          f'final height {figures["final_height_m"]:.2f} m (true '
          f'{figures["final_true_height_m"]:.2f} m); invalid cycles '
          f'{figures["invalid_cycles"]}, gaps {figures["gaps"]}, rejected '
          f'{figures["rejected"] or "none"}')
    for r in figures['rows']:
        for time_s, true_m, height_m in r['floor_error_cycles']:
            print(f'floor error at {time_s:.2f} s: true height {true_m:.2f} m, quantised '
                  f'{height_m:.2f} m')


# -- live --------------------------------------------------------------------------------------

class ProcessSampler(threading.Thread):
    """Samples (wall time ns, RSS MB, CPU s) of a process every period, and once at stop."""

    def __init__(self, pid: int, period_s: float):
        super().__init__(daemon=True)
        self.pid, self.period_s = pid, period_s
        self.samples = []
        self._halt = threading.Event()

    def sample(self) -> bool:
        """Take one sample; False once the process is gone."""
        try:
            self.samples.append((time.time_ns(), rss_mb(self.pid), cpu_seconds(self.pid)))
        except (OSError, IndexError, RuntimeError):
            return False
        return True

    def run(self):
        while not self._halt.is_set() and self.sample():
            self._halt.wait(self.period_s)

    def stop(self):
        """Stop sampling after one last sample."""
        self._halt.set()
        self.join()
        self.sample()


def plan_live_walk(minutes: float, seed: int) -> tuple:
    """Segments of one walk of about ``minutes`` through the shift's building."""
    rng = np.random.default_rng(seed)
    floor = 0
    segments = ()
    duration_s = minutes * 60.0
    while sim.nominal_duration_s(segments, step_height_m=RISER_M) < duration_s - 5.0:
        walk, floor = plan_walk(floor, min(300.0, duration_s), rng, not segments)
        segments += walk
    return segments


def run_live(minutes: float, seed: int) -> dict:
    """Play an N-minute walk to the nodes; return the figures."""
    from anfis_elevation_ros.tools.bags import write_imu_bag

    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))
    work = Path(tempfile.mkdtemp(prefix='soak_live_'))
    walk = simulate(plan_live_walk(minutes, seed), seed)
    bag = write_imu_bag(work / 'walk', walk.to_recording(), storage='mcap')
    truth_ns, truth_z = walk.stamp_ns, walk.pos_n[:, 2].copy()
    samples, strides, duration_s = len(walk), len(walk.strides), walk.duration_s
    del walk
    params = write_params(work / 'params.yaml', '')   # '': the packaged default model
    publish_log = work / 'published.csv'
    print(f'[soak] live: {duration_s / 60:.1f} min walk at {RATE_HZ:g} Hz in {bag}; load '
          f'average {os.getloadavg()[0]:.2f}', file=sys.stderr, flush=True)

    with listening() as listener, NodesProcess(params, work / 'run.log') as nodes:
        if not wait_for(lambda: listener.count_publishers('/elevation') >= 1, 30.0):
            sys.exit(f'the nodes did not start:\n{nodes.log()}')
        sampler = ProcessSampler(nodes.proc.pid, LIVE_SAMPLE_PERIOD_S)
        sampler.start()
        published = play_at_recorded_pace(bag, publish_log)
        time.sleep(1.5)                               # one more diagnostics message
        sampler.stop()
        code = nodes.stop()

    first_ns, last_ns = int(published[0, 1]), int(published[-1, 1])
    received = int(listener.diagnostic_value(IMU_INPUT, 'received', -1))
    check = FloorCheck(load_pipeline_params().elevation.floor_height_m)
    unmatched = 0
    for stamp_ns, _, _, height_m, _ in listener.elevations:
        j = int(np.searchsorted(truth_ns, stamp_ns))
        if j == len(truth_ns) or truth_ns[j] != stamp_ns:
            unmatched += 1
            continue
        check.add((stamp_ns - int(truth_ns[0])) * 1e-9, float(truth_z[j]), height_m)
    series = [((t - first_ns) * 1e-9, rss, cpu) for t, rss, cpu in sampler.samples]
    warm_up_s = min(LIVE_WARM_UP_S, 0.5 * (last_ns - first_ns) * 1e-9)
    warm = next(s for s in series if s[0] >= warm_up_s)
    end = series[-1]
    playing = [s for s in series if 0.0 <= s[0] <= (last_ns - first_ns) * 1e-9 + 2.0]
    cpu_pct = (100.0 * (playing[-1][2] - playing[0][2]) / (playing[-1][0] - playing[0][0])
               if len(playing) >= 2 else float('nan'))
    return {
        'minutes': round(duration_s / 60.0, 2), 'seed': seed, 'samples': samples,
        'imu_messages_published': len(published), 'imu_messages_received': received,
        'lost_imu_messages': len(published) - received, 'strides': strides,
        'elevations': len(listener.elevations), 'elevations_without_truth_stamp': unmatched,
        'level_cycles': check.level_cycles, 'floor_errors': check.floor_errors,
        'max_level_height_error_m': round(check.max_height_error_m, 3),
        'floor_error_cycles': check.errors,
        'rss_mb_before_playing': round(series[0][1], 2),
        'rss_warm_up_s': round(warm[0], 1), 'rss_mb_at_warm_up': round(warm[1], 2),
        'rss_mb_at_end': round(end[1], 2),
        'rss_growth_pct': round(100.0 * (end[1] - warm[1]) / warm[1], 2),
        'nodes_cpu_pct_of_one_core': round(cpu_pct, 1), 'nodes_exit_code': code,
        'load_average_1min': os.getloadavg()[0],
        'rss_series': [(round(t, 1), round(rss, 2)) for t, rss, _ in series],
    }


def live_verdicts(figures: dict) -> list:
    """Return (target, met, figure) for each live target."""
    return [
        (f'live RSS growth after {figures["rss_warm_up_s"]:.0f} s < '
         f'{MEMORY_GROWTH_TARGET_PCT:g} %', figures['rss_growth_pct'] < MEMORY_GROWTH_TARGET_PCT,
         f'{figures["rss_growth_pct"]:+.2f} % ({figures["rss_mb_at_warm_up"]:.1f} -> '
         f'{figures["rss_mb_at_end"]:.1f} MB)'),
        ('live floor errors at level cycles = 0',
         figures['floor_errors'] == 0 and figures['level_cycles'] > 0,
         f'{figures["floor_errors"]} in {figures["level_cycles"]} level cycles'),
        ('live lost IMU messages = 0', figures['lost_imu_messages'] == 0,
         f'{figures["lost_imu_messages"]} of {figures["imu_messages_published"]}'),
        ('live nodes exit code = 0', figures['nodes_exit_code'] == 0,
         str(figures['nodes_exit_code'])),
    ]


def print_live(figures: dict):
    """Print the live figures."""
    print(f'\nLive: {figures["minutes"]:g} min at {RATE_HZ:g} Hz through `run`')
    print('| t s | RSS MB |')
    print('| --- | --- |')
    for t, rss in figures['rss_series']:
        print(f'| {t:.0f} | {rss:.1f} |')
    print(f'RSS {figures["rss_mb_before_playing"]:.1f} MB before playing, '
          f'{figures["rss_mb_at_warm_up"]:.1f} MB at {figures["rss_warm_up_s"]:.0f} s, '
          f'{figures["rss_mb_at_end"]:.1f} MB at the end ({figures["rss_growth_pct"]:+.2f} %); '
          f'CPU {figures["nodes_cpu_pct_of_one_core"]:.1f} % of one core; '
          f'{figures["elevations"]} elevations for {figures["strides"]} strides, '
          f'{figures["level_cycles"]} level cycles, {figures["floor_errors"]} floor errors, '
          f'max |dh| at level cycles {figures["max_level_height_error_m"]:.2f} m; lost IMU '
          f'messages {figures["lost_imu_messages"]} of {figures["imu_messages_published"]}')


def main(argv=None) -> int:
    """Run the soak; return 0 if every target is met."""
    parser = argparse.ArgumentParser(description=__doc__.strip().split('\n\n')[0])
    parser.add_argument('--hours', type=float, default=8.0,
                        help='simulated hours offline (0 skips the offline part)')
    parser.add_argument('--row-minutes', type=float, default=60.0,
                        help='simulated minutes per row of the offline table')
    parser.add_argument('--chunk-minutes', type=float, default=5.0,
                        help='length of each simulated walk of the shift')
    parser.add_argument('--live-minutes', type=float, default=30.0,
                        help='minutes played live through the nodes (0 skips the live part)')
    parser.add_argument('--seed', type=int, default=1, help='seed of the shift and live walk')
    parser.add_argument('--json', type=Path, default=None, help='write the figures here')
    args = parser.parse_args(argv)
    if args.hours < 0 or args.live_minutes < 0 or not args.row_minutes > 0 \
            or not 1.0 <= args.chunk_minutes <= 60.0:
        parser.error('--hours and --live-minutes must be >= 0, --row-minutes > 0 and '
                     '--chunk-minutes within 1..60')

    figures, verdicts = {'load_average_1min': os.getloadavg()[0]}, []
    if args.hours > 0:
        figures['offline'] = run_offline(args.hours, args.row_minutes, args.chunk_minutes,
                                         args.seed)
        verdicts += offline_verdicts(figures['offline'])
        print_offline(figures['offline'])
    if args.live_minutes > 0:
        figures['live'] = run_live(args.live_minutes, args.seed)
        verdicts += live_verdicts(figures['live'])
        print_live(figures['live'])
    if args.json is not None:
        args.json.write_text(json.dumps(figures, indent=2) + '\n')
    print()
    for target, met, figure in verdicts:
        print(f'{"PASS" if met else "FAIL"} {target}: {figure}')
    return 0 if all(met for _, met, _ in verdicts) else 1


if __name__ == '__main__':
    sys.exit(main())
