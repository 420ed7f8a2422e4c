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
Benchmark of the online riser height and the floors (issue 13): simulated walks, K not given.

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_riser_height.py
[--out DIR] [--cases seed,floors,nofile,storeys,landings,drawn,random,heldout]`` (a script,
not a test; about 5-10 minutes on one core, each random walk about 10 s). Every walk runs through
``replay_recording`` with the packaged model and the default parameters (prior K = 0.17 m),
at 100 Hz, tactical and consumer IMUs. The cases are the issue's done-when list:

- ``floors``: towers of 4-6 floors with one stairwell and a taller lobby
  (``sim.tower_walk``; storeys of about 3 m, the lobby about 4.2 m, risers 0.14-0.19 m),
  with a building file that gives only the floors: at every level cycle whose true height is
  a floor's (truth: a level stride at a floor elevation), the floor must be right and
  ``floor_certain`` true, and |height error| <= 0.15 m;
- ``nofile``: the same kind of tower, 10-minute walks up and down several floors, no
  building file (storeys of ``floor_height_m`` = 3 m): |height error| at every cycle
  <= 0.15 m (tactical) / 0.30 m (consumer);
- ``random`` and ``heldout``: the same requirement on 10-minute ``sim.random_walk`` s (one
  riser height, steps per flight, flights and place per storey, storeys 0.14-0.19 m apart; 1-4
  steps per stride; up to 3 storeys up or down), seeds ``--seeds`` (11-13: the estimator's
  rules were chosen on them) and ``--held-out-seeds`` (14-20: chosen on nothing), reported
  apart, each ending with every IMU's mean of the walks' max errors, the largest and the
  misses;
- ``file``: the tower walks again with the building file's ``step_height_m``: the height
  must be exact (|error| < 1 mm at every cycle the mode is right);
- ``storeys`` (not in the default list): towers of 6 floors whose storeys nobody gave,
  2.8-4.5 m with a ground storey (lobby) of the same height, 4.2 or 5.0 m, no building file,
  tactical and consumer IMUs, K 0.17 m (not given): at every level cycle on a floor, whether
  the floor is right and ``floor_certain``, where it is not certain whether the floors it
  says the height can be on (``floor_lowest``, ``floor_highest``) hold the true one, and at
  the level cycles off every floor (landings) whether one is said certain; a wrong floor said
  to be certain, a range without the true floor, or a landing said to be on a floor, misses;
- ``landings`` (not in the default list): the same on towers of 3.0-4.5 m storeys of three
  flights, every landing walked round (four strides on a small circle), up four floors and
  down again: a landing two thirds up a storey of 3.5 m or more is a storey's height above
  the floor below;
- ``drawn`` (not in the default list): the same on ``--towers`` towers per seed of
  ``--draw-seeds``, each drawn at random: a route that skips floors (``DRAWN_ROUTES``), storeys
  of 2.8-4.5 m, a lobby of the same height (probability 0.4) or up to 5.8 m, K 0.14-0.19 m,
  1-3 steps a stride;
- ``seed``: the seed's 640 s walk (``sim.building_walk``: down 36 steps of 0.15 m, 500 s of
  corridors, back up): max |height error| <= 0.15 m, final error 0.

Measured 2026-12-03 (doc/riser_height_notebook.md, "With the stairs in place"), after
``random_walk`` put each storey's stairs at one place and a sure stride height stopped being
clipped by its INS length: everything met but held-out random walk 19 on the consumer IMU
(0.647 m at the one cycle the classifier calls a 4-riser stride level).

The truth height of a cycle is that of the last true stride ending up to 0.2 s after it.
With ``--out DIR`` it writes ``riser_convergence.png``: the estimate of K over the first
flights of a tower walk (prior 0.17 m, truth 0.15 m) and the height error. Exit status 1
when a case misses its requirement.
"""

import argparse
from pathlib import Path
import sys

from anfis_elevation_ros import sim
from anfis_elevation_ros.core.building import building_from_dict
from anfis_elevation_ros.core.params import load_model, load_pipeline_params
from anfis_elevation_ros.tools.replay import CYCLE_COLUMNS, replay_recording
import numpy as np

RATE_HZ = 100.0
MOUNTING_RPY_DEG = (0.0, 0.0, 0.0)     # the IMU's axes along the foot's
TREAD_RANGE_M = (sim.DEFAULT_TREAD_M,) * 2   # one tread everywhere: 2R + G = 0.56-0.66 m
IMUS = ('tactical', 'consumer')
RISERS_M = (0.14, 0.155, 0.17, 0.19)
TOWERS = {4: (0, 3, 1, 2, 0), 5: (0, 4, 1, 3, 0), 6: (0, 5, 2, 4, 0)}   # floors: route
LONG_ROUTE = (0, 4, 1, 3, 0, 2, 4, 1, 0)                                  # ~10 minutes
STOREYS_ROUTE = (0, 1, 2, 3, 4, 5, 3, 0)                                  # every floor
CORRIDOR_STRIDES = 12                                                     # each way
DRAWN_ROUTES = ((0, 4, 1, 3, 0), (0, 5, 2, 4, 0), LONG_ROUTE, (0, 2, 5, 3, 1, 0),
                (0, 1, 3, 5, 4, 2, 0))                                  # floors skipped
COLUMN = {name: k for k, name in enumerate(CYCLE_COLUMNS)}


def storey_steps(k_m: float, floors: int, lobby_m: float = 4.2, storey_m: float = 3.0) -> tuple:
    """Return the steps per storey: a lobby of about ``lobby_m``, storeys of about ``storey_m``."""
    def even(height_m):
        return int(2 * round(height_m / k_m / 2))
    return (even(lobby_m),) + (even(storey_m),) * (floors - 2)


def building(elevations_m, k_m=None) -> object:
    """Return a building with these floors (and this riser height), no start, no stairs."""
    tree = {'format': 'anfis_elevation_ros/building', 'version': 1, 'name': 'bench tower',
            'floors': [{'index': i, 'elevation_m': float(e)} for i, e in enumerate(elevations_m)]}
    if k_m is not None:
        tree['step_height_m'] = float(k_m)
    return building_from_dict(tree)


def replay(walk, the_building=None):
    """
    Replay a walk with the default parameters; return per-cycle arrays and truth.

    Also the raw INS height, the cycles' stamps (ns) and the ``ReplayResult`` itself.
    """
    result = replay_recording(walk.to_recording(), PIPELINE, MODEL, building=the_building)
    rows = np.array([[float(v) for v in row] for row in result.cycles])
    stamp = np.array([row[0] for row in result.cycles], dtype=np.int64)
    strides = walk.strides
    k = np.searchsorted(strides.stamp_ns, stamp + 200_000_000, side='right') - 1
    return {'height': rows[:, COLUMN['height_m']], 'floor': rows[:, COLUMN['floor']].astype(int),
            'certain': rows[:, COLUMN['floor_certain']].astype(bool),
            'lowest': rows[:, COLUMN['floor_lowest']], 'highest': rows[:, COLUMN['floor_highest']],
            'k': rows[:, COLUMN['step_height_m']], 'mode': rows[:, COLUMN['mode']].astype(int),
            'true_height': strides.height_m[k], 'true_mode': strides.mode[k],
            'stamp_s': (stamp - stamp[0]) * 1e-9, 'stamp_ns': stamp,
            'raw_height': rows[:, COLUMN['raw_height_m']], 'result': result}


def tower(floors, k_m, imu, seed, route=None):
    """Simulate a tower walk; return (walk, floor elevations)."""
    steps = storey_steps(k_m, floors)
    segments = sim.tower_walk(route or TOWERS[floors], storey_steps=steps, step_height_m=k_m)
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(seed), rate_hz=RATE_HZ,
                             imu=imu, step_height_m=k_m)
    return walk, sim.tower_floor_elevations_m(steps, k_m)


def on_floor_level_cycles(out, elevations_m):
    """Return the cycles whose true stride is level at a floor elevation, and its index."""
    distance = np.abs(out['true_height'][:, None] - elevations_m[None, :])
    floor = np.argmin(distance, axis=1)
    return (out['true_mode'] == 0) & (distance.min(axis=1) < 0.01), floor


def case_floors_and_file(failures):
    """Run towers with a floors-only file, and with the file's riser height."""
    print('case floors (file with floors only) and file (file with step_height_m)')
    print(f'{"imu":9s} {"floors":>6s} {"K":>6s} {"dur s":>6s} | {"level@floor":>11s} '
          f'{"wrong fl":>8s} {"uncertain":>9s} {"max|err|":>8s} {"K end":>6s} | '
          f'{"file max|err|":>13s}')
    seed = 100
    for imu in IMUS:
        for floors, k_m in zip((4, 5, 6, 5), RISERS_M):
            seed += 1
            walk, elevations = tower(floors, k_m, imu, seed)
            out = replay(walk, building(elevations))
            mask, truth = on_floor_level_cycles(out, elevations)
            wrong = int(np.sum(out['floor'][mask] != truth[mask]))
            uncertain = int(np.sum(~out['certain'][mask]))
            err = np.abs(out['height'] - out['true_height'])[mask].max()
            exact = replay(walk, building(elevations, k_m))
            right_mode = exact['mode'] == exact['true_mode']
            file_err = np.abs(exact['height'] - exact['true_height'])[right_mode].max()
            print(f'{imu:9s} {floors:6d} {k_m:6.3f} {out["stamp_s"][-1]:6.0f} | '
                  f'{int(mask.sum()):11d} {wrong:8d} {uncertain:9d} {err:8.3f} '
                  f'{out["k"][-1]:6.3f} | {file_err:13.4f}')
            if wrong or uncertain or err > 0.15:
                failures.append(f'floors {imu} {floors} floors K {k_m}')
            if file_err > 0.001:
                failures.append(f'file {imu} {floors} floors K {k_m}')


def case_no_file(failures):
    """Run 10-minute walks without a building file: height error at every cycle."""
    print('case nofile (no building file, every cycle)')
    print(f'{"imu":9s} {"walk":22s} {"dur s":>6s} {"cycles":>6s} {"max|err|":>8s} '
          f'{"final":>7s} {"limit":>5s}')
    seed = 200
    for imu in IMUS:
        limit = 0.15 if imu == 'tactical' else 0.30
        for k_m in RISERS_M:
            seed += 1
            walk, _ = tower(5, k_m, imu, seed, LONG_ROUTE)
            out = replay(walk)
            err = out['height'] - out['true_height']
            print(f'{imu:9s} {f"tower K {k_m:.3f}":22s} {out["stamp_s"][-1]:6.0f} '
                  f'{len(err):6d} {np.abs(err).max():8.3f} {err[-1]:+7.3f} {limit:5.2f}')
            if np.abs(err).max() > limit:
                failures.append(f'nofile {imu} tower K {k_m}')


def case_unknown_storeys(failures):
    """Run towers of storeys nobody gave without a building file: a certain floor never wrong."""
    print('case storeys (no building file; level cycles on a floor: right & certain, '
          'wrong & certain, wrong & uncertain, right & uncertain, uncertain with a floor '
          'range, the true floor outside it; level cycles off every floor (landings): all, '
          'certain)')
    k_m = 0.17
    for imu, seed in zip(IMUS, (500, 600)):
        total = np.zeros(8, dtype=int)
        for lobby_m in (None, 4.2, 5.0):
            for storey_m in (2.8, 3.0, 3.3, 3.6, 4.0, 4.5):
                seed += 1
                row = unknown_storeys_tower(lobby_m or storey_m, storey_m, k_m, imu, seed)
                total += row
                print(f'{imu:9s} lobby {lobby_m or storey_m:3.1f} m, storeys {storey_m:3.1f} m: '
                      f'{" ".join(f"{n:4d}" for n in row)}')
                if storey_miss(row):
                    failures.append(f'storeys {imu} {storey_m} m, lobby {lobby_m or storey_m} m')
        print(f'{imu:9s} all: {" ".join(f"{n:4d}" for n in total)}')


def case_drawn_towers(failures, draw_seeds, towers):
    """Run towers drawn at random without a building file: a certain floor never wrong."""
    print('case drawn (towers drawn at random, no building file; the columns of case storeys)')
    total = {imu: np.zeros(8, dtype=int) for imu in IMUS}
    for draw_seed in draw_seeds:
        rng = np.random.default_rng(draw_seed)
        for k in range(towers):
            route = DRAWN_ROUTES[rng.integers(len(DRAWN_ROUTES))]
            storey_m = float(rng.uniform(2.8, 4.5))
            lobby_m = storey_m if rng.random() < 0.4 else float(rng.uniform(storey_m, 5.8))
            k_m = float(rng.uniform(0.14, 0.19))
            per_stride = int(rng.choice([1, 2, 2, 3]))
            walk_seed = int(rng.integers(1 << 30))
            for imu in IMUS:
                row = unknown_storeys_tower(lobby_m, storey_m, k_m, imu, walk_seed, route,
                                            per_stride)
                total[imu] += row
                print(f'{draw_seed}/{k:<3d} {imu:9s} route {"-".join(map(str, route)):17s} '
                      f'storeys {storey_m:.2f} m, lobby {lobby_m:.2f} m, K {k_m:.3f} m, '
                      f'{per_stride} a stride: {" ".join(f"{n:4d}" for n in row)}')
                if storey_miss(row):
                    failures.append(f'drawn tower {draw_seed}/{k} {imu}')
    for imu in IMUS:
        print(f'{imu:9s} all: {" ".join(f"{n:5d}" for n in total[imu])}')


def case_landings(failures):
    """Run towers whose landings are walked round, no building file: no landing a floor."""
    print('case landings (storeys of three flights, each landing walked round; no building '
          'file; the columns of case storeys)')
    seed = 700
    total = {imu: np.zeros(8, dtype=int) for imu in IMUS}
    for imu in IMUS:
        for storey_m in (3.0, 3.6, 4.2, 4.5):
            for k_m in (0.15, 0.18):
                seed += 1
                row = landing_tower(storey_m, k_m, imu, seed)
                total[imu] += row
                print(f'{imu:9s} storeys {storey_m:3.1f} m, K {k_m:.2f} m: '
                      f'{" ".join(f"{n:4d}" for n in row)}')
                if storey_miss(row):
                    failures.append(f'landings {imu} {storey_m} m K {k_m}')
        print(f'{imu:9s} all: {" ".join(f"{n:5d}" for n in total[imu])}')


def landing_tower(storey_m, k_m, imu, seed, floors=4) -> np.ndarray:
    """
    Return the counts of ``case_unknown_storeys`` for a walk up a tower and down again.

    Each storey is three flights of n steps (n K about a third of the storey) with a 90 deg
    landing between them; on each landing the wearer walks round a small circle, four strides
    of 0.5 m (a landing two thirds up is a storey's height above the floor below for storeys
    of 3.5 m or more); on each floor a corridor out and back.
    """
    n = int(round(storey_m / k_m / 3))
    corridor = [sim.Segment.level(CORRIDOR_STRIDES), sim.Segment.turn(180.0),
                sim.Segment.level(CORRIDOR_STRIDES), sim.Segment.turn(180.0)]
    segments = list(corridor)
    for direction in (1, -1):
        for _ in range(floors - 1):
            for flight in range(3):
                segments.append(sim.Segment.stairs(n, direction, step_height_m=k_m))
                if flight < 2:
                    segments += [sim.Segment.level(4, turn_deg=360.0, stride_length_m=0.5),
                                 sim.Segment.level(1, turn_deg=90.0, stride_length_m=0.7)]
            segments += corridor
    walk = sim.simulate_walk(tuple(segments), rng=np.random.default_rng(seed),
                             rate_hz=RATE_HZ, imu=imu, step_height_m=k_m)
    elevations_m = sim.tower_floor_elevations_m([3 * n] * (floors - 1), k_m)
    return storey_counts(replay(walk), elevations_m)


def unknown_storeys_tower(lobby_m, storey_m, k_m, imu, seed, route=STOREYS_ROUTE,
                          steps_per_stride=2) -> np.ndarray:
    """Return a tower's counts of ``case_unknown_storeys`` (the columns it prints)."""
    steps = storey_steps(k_m, 6, lobby_m, storey_m)
    segments = sim.tower_walk(route, storey_steps=steps, step_height_m=k_m,
                              steps_per_stride=steps_per_stride)
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(seed), rate_hz=RATE_HZ,
                             imu=imu, step_height_m=k_m)
    return storey_counts(replay(walk), sim.tower_floor_elevations_m(steps, k_m))


def storey_miss(row) -> bool:
    """
    Return whether a row of :func:`storey_counts` misses its requirement.

    A wrong floor said to be certain, a range without the true floor, or a landing said to be
    on a floor.
    """
    return bool(row[1] or row[5] or row[7])


def storey_counts(out, elevations_m) -> np.ndarray:
    """Return the counts ``case_unknown_storeys`` prints for a replayed walk."""
    mask, truth = on_floor_level_cycles(out, elevations_m)
    right, certain = out['floor'][mask] == truth[mask], out['certain'][mask]
    off_floor = (out['true_mode'] == 0) & ~mask
    ranged = ~certain & np.isfinite(out['lowest'][mask])
    within = (out['lowest'][mask] <= truth[mask]) & (truth[mask] <= out['highest'][mask])
    return np.array([np.sum(right & certain), np.sum(~right & certain),
                     np.sum(~right & ~certain), np.sum(right & ~certain),
                     np.sum(ranged), np.sum(ranged & ~within),
                     np.sum(off_floor), np.sum(out['certain'][off_floor])])


def case_random(failures, seeds, label, rate_hz=RATE_HZ, mounting_rpy_deg=MOUNTING_RPY_DEG,
                tread_range_m=TREAD_RANGE_M):
    """Run 10-minute ``sim.random_walk`` s without a building file: error at every cycle."""
    print(f'case random ({label}: random_walk seeds {",".join(map(str, seeds))}, {rate_hz:g} Hz, '
          f'mounting roll pitch yaw {mounting_rpy_deg} deg, treads {tread_range_m} m, '
          'no building file, every cycle)')
    print(f'{"imu":9s} {"walk":22s} {"dur s":>6s} {"cycles":>6s} {"max|err|":>8s} '
          f'{"final":>7s} {"limit":>5s}')
    summaries = []
    for imu in IMUS:
        limit = 0.15 if imu == 'tactical' else 0.30
        max_errors, misses = [], []
        for rseed in seeds:
            plan = sim.random_walk(600.0, np.random.default_rng(rseed),
                                   tread_range_m=tread_range_m)
            walk = sim.simulate_walk(plan, rng=np.random.default_rng(rseed), rate_hz=rate_hz,
                                     imu=imu, mounting_rpy_deg=mounting_rpy_deg)
            out = replay(walk)
            err = out['height'] - out['true_height']
            max_errors.append(np.abs(err).max())
            print(f'{imu:9s} {f"random_walk seed {rseed}":22s} {out["stamp_s"][-1]:6.0f} '
                  f'{len(err):6d} {max_errors[-1]:8.3f} {err[-1]:+7.3f} {limit:5.2f}')
            if max_errors[-1] > limit:
                failures.append(f'{label} {imu} random_walk seed {rseed}')
                misses.append(rseed)
        summaries.append(f'{imu:9s} {len(seeds)} walks: mean of the max errors '
                         f'{np.mean(max_errors):.4f} m, largest {np.max(max_errors):.3f} m '
                         f'(seed {seeds[int(np.argmax(max_errors))]}), misses {misses or "none"}')
    print('\n'.join(summaries))


def case_seed(failures):
    """Run the seed's 640 s walk with the default parameters."""
    print('case seed (building_walk: down 36 x 0.15 m, 500 s corridors, back up)')
    for imu in IMUS:
        walk = sim.simulate_walk(sim.building_walk(), rng=np.random.default_rng(0),
                                 rate_hz=RATE_HZ, imu=imu, step_height_m=0.15)
        out = replay(walk)
        err = out['height'] - out['true_height']
        print(f'{imu:9s} max|err| {np.abs(err).max():.3f} m, final {err[-1]:+.3f} m, K at the '
              f'end {out["k"][-1]:.3f} m')
        if np.abs(err).max() > 0.15 or abs(err[-1]) > 1e-9:
            failures.append(f'seed {imu}')


def plot_convergence(out_dir: Path):
    """Write riser_convergence.png: K per cycle over the first flights, and the height error."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    walk, _ = tower(5, 0.15, 'tactical', 7, (0, 2, 0))
    out = replay(walk)
    stairs = np.flatnonzero(out['mode'] != 0)
    end = min(len(out['k']), stairs[-1] + 3) if len(stairs) else len(out['k'])
    t = out['stamp_s'][:end]
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(8, 5.5))
    top.step(t, 1000 * out['k'][:end], where='post', label='estimate K')
    top.axhline(150, color='k', ls='--', lw=0.8, label='true riser 150 mm')
    top.axhline(170, color='grey', ls=':', lw=0.8, label='prior 170 mm')
    top.fill_between(t, 125, 215, where=out['mode'][:end] != 0, color='orange', alpha=0.15,
                     step='post', label='stair cycles')
    top.set_ylabel('riser height K, mm')
    top.set_ylim(125, 215)
    top.legend(loc='upper right', fontsize=8)
    top.set_title('Online riser height, tower walk 0 -> 2 -> 0 (tactical IMU, 100 Hz)')
    bottom.plot(t, 100 * (out['height'] - out['true_height'])[:end], '.-')
    bottom.set_ylabel('height error, cm')
    bottom.set_xlabel('time, s')
    fig.tight_layout()
    path = out_dir / 'riser_convergence.png'
    fig.savefig(path, dpi=110)
    print(f'wrote {path}')


def main(argv=None) -> int:
    """Run the cases; return 1 when one misses its requirement."""
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--out', default=None, help='directory for riser_convergence.png')
    parser.add_argument('--cases', default='seed,floors,nofile,random,heldout',
                        help='comma-separated subset of seed, floors (includes file), nofile '
                        '(towers), storeys (towers of storeys nobody gave), landings (towers '
                        'whose landings are walked round), drawn (towers '
                        'drawn at random, --draw-seeds), random (random '
                        'walks, seeds --seeds), heldout (random walks, seeds --held-out-seeds)')
    parser.add_argument('--seeds', default='11,12,13',
                        help='random_walk seeds the estimator parameters were chosen on')
    parser.add_argument('--held-out-seeds', default='14,15,16,17,18,19,20',
                        help='random_walk seeds not used to choose anything')
    parser.add_argument('--draw-seeds', default='7,11',
                        help='seeds of the towers drawn at random (case drawn)')
    parser.add_argument('--towers', type=int, default=40,
                        help='towers drawn per seed of --draw-seeds (case drawn)')
    parser.add_argument('--rate-hz', type=float, default=RATE_HZ,
                        help='IMU sample rate of the random walks (random, heldout), Hz')
    parser.add_argument('--mounting-rpy-deg', type=float, nargs=3, default=MOUNTING_RPY_DEG,
                        metavar=('ROLL', 'PITCH', 'YAW'),
                        help='IMU mounting on the foot for the random walks, deg')
    parser.add_argument('--tread-range-m', type=float, nargs=2, default=TREAD_RANGE_M,
                        metavar=('LOW', 'HIGH'),
                        help='tread depth of the stairs of the random walks, drawn per storey, m')
    args = parser.parse_args(argv)
    failures = []
    cases = args.cases.split(',')
    if 'seed' in cases:
        case_seed(failures)
    if 'floors' in cases:
        case_floors_and_file(failures)
    if 'nofile' in cases:
        case_no_file(failures)
    if 'storeys' in cases:
        case_unknown_storeys(failures)
    if 'landings' in cases:
        case_landings(failures)
    if 'drawn' in cases:
        case_drawn_towers(failures, [int(v) for v in args.draw_seeds.split(',')], args.towers)
    if 'random' in cases:
        case_random(failures, [int(v) for v in args.seeds.split(',')], 'random', args.rate_hz,
                    tuple(args.mounting_rpy_deg), tuple(args.tread_range_m))
    if 'heldout' in cases:
        case_random(failures, [int(v) for v in args.held_out_seeds.split(',')], 'heldout',
                    args.rate_hz, tuple(args.mounting_rpy_deg), tuple(args.tread_range_m))
    if args.out:
        Path(args.out).mkdir(parents=True, exist_ok=True)
        plot_convergence(Path(args.out))
    print('all requirements met' if not failures else f'missed: {"; ".join(failures)}')
    return 1 if failures else 0


MODEL = load_model('')
PIPELINE = load_pipeline_params()

if __name__ == '__main__':
    sys.exit(main())
