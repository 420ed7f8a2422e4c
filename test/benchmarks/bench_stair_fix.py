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
Benchmark of the stair-position correction on the seed-003-like walk (``sim/seed003.py``).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_stair_fix.py
[--seeds 3 4 5] [--rate-hz 100] [--hde] [--no-zaru]`` (a script, not a test; about a minute
per seed). For each seed it simulates the walk (``SEED003_IMU``), writes its building file and
replays the pipeline (``replay_recording``, the default model; ``--no-zaru``: zero angular
rate updates off) three times on the same readings:

- plain: the building's map frame only (no ``stairs``): the ZUPT filter alone;
- database: the whole building file: corrections at the stair entries;
- unknown: the file without stairwell D, the walk still goes through D;
- with ``--hde``, also plain+hde and database+hde: heuristic drift elimination
  (``heading.hde_enabled``) along the corridors, the building's ``dominant_directions_deg``
  = 0 (the map frame's axes).

Error: horizontal distance between each valid gait cycle's x/y (map frame) and the true
position of the foot at the end of the stride it closes (stamps matched), mean and max over the
walk, and at the end. Also the stair entries seen, the associations accepted and refused, the
corrections applied, and for the unknown variant any correction made at stairwell D (there
must be none).
"""

import argparse
from dataclasses import replace
import sys
import time

from anfis_elevation_ros.core.building import Building
from anfis_elevation_ros.core.params import load_model, load_pipeline_params
from anfis_elevation_ros.sim import simulate_walk
from anfis_elevation_ros.sim.seed003 import map_from_sim, seed003_building, SEED003_IMU
from anfis_elevation_ros.sim.seed003 import seed003_walk, STEP_HEIGHT_M
from anfis_elevation_ros.tools.replay import replay_recording
import numpy as np

MAX_MATCH_S = 0.3    # a cycle closes within this of the true stride's first stance sample


def horizontal_errors(result, walk) -> np.ndarray:
    """(M,) |cycle x/y - true x/y| of the valid cycles matched to a true stride, m."""
    true_stamp = walk.strides.stamp_ns
    true_xy = map_from_sim(walk.strides.end_pos_n)
    errors = []
    for row in result.cycles:
        stamp_ns, x_m, y_m, valid = row[0], row[3], row[4], row[7]
        k = int(np.argmin(np.abs(true_stamp - stamp_ns)))
        if valid and abs(int(true_stamp[k]) - stamp_ns) * 1e-9 <= MAX_MATCH_S:
            errors.append(np.hypot(x_m - true_xy[k, 0], y_m - true_xy[k, 1]))
    return np.array(errors)


def run_seed(seed: int, rate_hz: float, model, pipeline, hde: bool = False) -> dict:
    """Simulate one walk and replay it plain, with the database and with an unknown stairwell."""
    segments, transitions = seed003_walk()
    walk = simulate_walk(segments, rng=np.random.default_rng(seed), rate_hz=rate_hz,
                         imu=SEED003_IMU, step_height_m=STEP_HEIGHT_M)
    full = seed003_building(walk, transitions)
    variants = {'plain': Building(name=full.name, floors=full.floors, start=full.start),
                'database': full,
                'unknown': seed003_building(walk, transitions, unknown='D')}
    if hde:
        for name in ('plain', 'database'):
            variants[f'{name}+hde'] = replace(variants[name], dominant_directions_deg=(0.0,))
    distance_m = float(np.sum(np.hypot(*np.diff(walk.pos_n[:, :2], axis=0).T)))
    rows = {}
    d_segments = {index for index, stairwell, _, _ in transitions if stairwell == 'D'}
    d_stamps = walk.strides.stamp_ns[np.isin(walk.strides.segment_index, list(d_segments))]
    for name, building in variants.items():
        navigator = pipeline.navigator
        settings = replace(pipeline, navigator=replace(navigator, heading=replace(
            navigator.heading, hde_enabled=name.endswith('+hde'))))
        result = replay_recording(walk.to_recording(), settings, model, building=building)
        errors = horizontal_errors(result, walk)
        monitor = result.stair_monitor
        at_d = 0
        if monitor is not None and name == 'unknown':
            # A correction whose cycle is a stride on stairwell D's flights.
            applied = result.fixes.applied_ids
            at_d = sum(1 for stamp in applied
                       if np.min(np.abs(d_stamps - stamp)) * 1e-9 <= MAX_MATCH_S)
        rows[name] = {
            'mean': float(errors.mean()), 'max': float(errors.max()), 'end': float(errors[-1]),
            'cycles': len(errors),
            'entries': monitor.entries if monitor else 0,
            'accepted': monitor.accepted if monitor else 0,
            'far': monitor.refused_far if monitor else 0,
            'none': monitor.refused_no_entry if monitor else 0,
            'applied': result.fixes.applied_count, 'at_d': at_d}
    return {'distance_m': distance_m, 'strides': len(walk.strides), 'rows': rows}


def main(argv=None) -> int:
    """Run the benchmark and print one block per seed; exit 1 if a target is missed."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--seeds', type=int, nargs='+', default=[3])
    parser.add_argument('--rate-hz', type=float, default=100.0)
    parser.add_argument('--hde', action='store_true',
                        help='also replay with heuristic drift elimination along the corridors')
    parser.add_argument('--no-zaru', action='store_true',
                        help='zero angular rate updates off (heading.zaru_enabled, on by default)')
    args = parser.parse_args(argv)
    pipeline = load_pipeline_params()
    if args.no_zaru:
        heading = replace(pipeline.navigator.heading, zaru_enabled=False)
        pipeline = replace(pipeline, navigator=replace(pipeline.navigator, heading=heading))
    model = load_model(pipeline.model_path)
    missed = False
    for seed in args.seeds:
        start = time.monotonic()
        out = run_seed(seed, args.rate_hz, model, pipeline, args.hde)
        print(f'seed {seed}: {out["distance_m"]:.0f} m walked, {out["strides"]} strides, '
              f'{args.rate_hz:.0f} Hz ({time.monotonic() - start:.0f} s)')
        for name, r in out['rows'].items():
            print(f'  {name:9s} mean {r["mean"]:6.2f} m  max {r["max"]:6.2f} m  end '
                  f'{r["end"]:6.2f} m  ({r["cycles"]} cycles; stair entries {r["entries"]}, '
                  f'accepted {r["accepted"]}, too far {r["far"]}, no entry {r["none"]}, '
                  f'applied {r["applied"]}, at unknown D {r["at_d"]})')
        rows = out['rows']
        missed |= rows['database']['mean'] > 1.0 or rows['unknown']['at_d'] > 0
    return 1 if missed else 0


if __name__ == '__main__':
    sys.exit(main())
