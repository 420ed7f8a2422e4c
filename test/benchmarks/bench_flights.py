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
Benchmark of the navigator on simulated walks: gait cycles and raw height per stair flight.

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_flights.py`` (a
script, not a test; the default grid takes about 10 minutes on one core). For each walk
(``random_walk(600, default_rng(seed))`` simulated with ``default_rng(seed)``, and
``building_walk()``), IMU preset and sample rate it runs
``FootNavigator(NavigatorParams()).run`` and prints one row:

- strides: true strides of the instrumented foot; cycles: gait cycles the navigator closed;
- false: cycles closed on a sample where the foot truly moves (faster than 0.1 m/s: a stance
  declared mid-swing; closing while the sole rolls flat at the end of a swing is on time);
- missed: strides that closed no cycle (two swings merged into one);
- flights: stair flights, a flight being a run of consecutive strides of the same nonzero
  mode; their raw EKF height error |est - true| / |true|, with est the EKF height at the last
  sample of the stance after the flight minus that at the last sample of the stance before
  it (the end of a stance, where the zero-velocity updates have settled), and true the truth
  height change of the flight: mean signed error, max |error| and the number of flights above
  the requirement (3 %).

``--details`` also prints every flight. Exit status 1 if a flight misses the requirement.
"""

import argparse
import sys
import time

from anfis_elevation_ros import sim
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.core.stride_gate import StrideGateParams
import numpy as np

REQUIREMENT = 0.03  # max |est - true| / true height of a flight
SLOW_MPS = 0.1  # a cycle closed while the foot moves slower is on time


def flights(strides: sim.StrideTruth) -> list:
    """Return (first, last) stride indices of each run of strides with the same nonzero mode."""
    runs = []
    start = None
    for i, mode in enumerate(strides.mode):
        if start is not None and mode != strides.mode[start]:
            runs.append((start, i - 1))
            start = None
        if start is None and mode != 0:
            start = i
    if start is not None:
        runs.append((start, len(strides) - 1))
    return runs


def evaluate(walk: sim.SimulatedWalk, track: list, cycles: list) -> dict:
    """Cycle counts and per-flight height errors of one navigated walk (see module docstring)."""
    s = walk.strides
    track_stamp = np.array([p.stamp_ns for p in track], dtype=np.int64)
    track_z = np.array([p.pos_n[2] for p in track])
    # Last sample of the stance before stride i's swing; the walk's last sample after the last.
    stance_end = np.append(np.searchsorted(walk.stamp_ns, s.swing_start_ns) - 1, len(walk) - 1)
    cycle_stamp = np.array([c.stamp_ns for c in cycles], dtype=np.int64)
    cycle_index = np.searchsorted(walk.stamp_ns, cycle_stamp)
    # A cycle closes the stride whose stance it falls in, or whose swing it ends early in while
    # the foot is almost still (rolling flat: below SLOW_MPS); any other is false.
    speed = np.linalg.norm(walk.vel_n[cycle_index], axis=1)
    in_stance = walk.stance[cycle_index]
    stride = np.searchsorted(s.stamp_ns, cycle_stamp, side='right') - np.where(in_stance, 1, 0)
    on_time = in_stance | (speed < SLOW_MPS)
    false = int(np.count_nonzero(~on_time))
    missed = len(s) - len(set(stride[on_time & (stride >= 0)].tolist()))

    def ekf_height(sample):
        k = np.searchsorted(track_stamp, walk.stamp_ns[sample])
        if k >= len(track_stamp) or track_stamp[k] != walk.stamp_ns[sample]:
            return np.nan  # before the navigator started
        return track_z[k]

    rows = []
    for first, last in flights(s):
        true_m = float(s.height_change_m[first:last + 1].sum())
        est_m = ekf_height(stance_end[last + 1]) - ekf_height(stance_end[first])
        rows.append({'first': first, 'strides': last - first + 1, 'mode': int(s.mode[first]),
                     'steps': int(s.n_steps[first:last + 1].sum()),
                     'steps_per_stride': int(s.n_steps[first]), 'true_m': true_m,
                     'est_m': est_m, 'error': est_m / true_m - 1.0})
    return {'strides': len(s), 'cycles': len(cycles), 'false': false, 'missed': missed,
            'flights': rows}


def scenarios(seeds, building: bool):
    """Yield (name, segments, seed of simulate_walk)."""
    for seed in seeds:
        yield f'random{seed}', sim.random_walk(600.0, np.random.default_rng(seed)), seed
    if building:
        yield 'building', sim.building_walk(), 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--seeds', type=int, nargs='*', default=[1, 2, 3, 4, 5],
                        help='seeds of random_walk(600 s)')
    parser.add_argument('--no-building', action='store_true', help='skip building_walk()')
    parser.add_argument('--presets', nargs='+', default=['ideal', 'tactical', 'consumer'],
                        choices=sorted(sim.IMU_PRESETS))
    parser.add_argument('--rates', type=float, nargs='+', default=[100.0, 200.0, 400.0],
                        help='IMU rates, Hz')
    parser.add_argument('--details', action='store_true', help='print every flight')
    parser.add_argument('--no-stride-gate', action='store_true',
                        help='stride_gate.enabled false (core/stride_gate.py; on by default)')
    args = parser.parse_args(argv)

    print(f'{"walk":9s} {"imu":8s} {"Hz":>4s} {"strides":>7s} {"cycles":>6s} {"false":>5s} '
          f'{"missed":>6s} {"flights":>7s} {"mean%":>6s} {"max|%|":>6s} {">3%":>4s}')
    totals = {}
    failed = 0
    for name, segments, seed in scenarios(args.seeds, not args.no_building):
        for preset in args.presets:
            for rate_hz in args.rates:
                start = time.perf_counter()
                walk = sim.simulate_walk(segments, rng=np.random.default_rng(seed),
                                         rate_hz=rate_hz, imu=preset)
                params = NavigatorParams(
                    stride_gate=StrideGateParams(enabled=not args.no_stride_gate))
                track, cycles = FootNavigator(params).run(
                    walk.stamp_ns, walk.acc_b, walk.gyr_b)
                result = evaluate(walk, track, cycles)
                errors = np.array([f['error'] for f in result['flights']])
                over = int(np.count_nonzero(~(np.abs(errors) <= REQUIREMENT)))
                failed += over
                key = (preset, rate_hz)
                total = totals.setdefault(key, [0, 0, 0, 0, []])
                total[0] += result['strides']
                total[1] += result['cycles']
                total[2] += result['false']
                total[3] += result['missed']
                total[4].extend(errors.tolist())
                print(f'{name:9s} {preset:8s} {rate_hz:4.0f} {result["strides"]:7d} '
                      f'{result["cycles"]:6d} {result["false"]:5d} {result["missed"]:6d} '
                      f'{len(errors):7d} {100 * np.mean(errors):+6.1f} '
                      f'{100 * np.max(np.abs(errors)):6.1f} {over:4d}   '
                      f'({time.perf_counter() - start:.0f} s)', flush=True)
                if args.details:
                    for f in result['flights']:
                        print(f'    flight at stride {f["first"]:4d}: {f["strides"]:2d} strides '
                              f'{f["steps"]:2d} steps ({f["steps_per_stride"]}/stride) '
                              f'{"up" if f["mode"] > 0 else "down":4s} true {f["true_m"]:+6.3f} m '
                              f'est {f["est_m"]:+6.3f} m error {100 * f["error"]:+6.1f} %')
    print('\nAll walks:')
    for (preset, rate_hz), (strides, cycles, false, missed, errors) in totals.items():
        errors = np.array(errors)
        print(f'{"all":9s} {preset:8s} {rate_hz:4.0f} {strides:7d} {cycles:6d} {false:5d} '
              f'{missed:6d} {len(errors):7d} {100 * np.mean(errors):+6.1f} '
              f'{100 * np.max(np.abs(errors)):6.1f} '
              f'{np.count_nonzero(~(np.abs(errors) <= REQUIREMENT)):4d}')
    print(f'\n{failed} flight(s) above the {100 * REQUIREMENT:.0f} % requirement')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
