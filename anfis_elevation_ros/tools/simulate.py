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
``simulate`` subcommand: a simulated foot-IMU walk as a bag plus truth CSV files.

Writes ``OUT/imu`` (rosbag2 directory, sensor_msgs/msg/Imu on /imu/data), ``OUT/truth.csv``
(per-sample truth) and ``OUT/strides.csv`` (per-stride truth); progress goes to stderr.
The ``seed003`` scenario (``sim/seed003.py``: 1,126 m through two floors, four switchback
stairwells a floor, its own tactical IMU unless ``--imu`` says otherwise) also writes its
building file, ``OUT/building.yaml`` (stair entries at the true first steps, the entrance):
``replay OUT/imu --building OUT/building.yaml`` then gives map coordinates and stair-entry
corrections. ``--unknown-stairwell D`` leaves a stairwell out of the file (the walk still
uses it). The truth files stay in the simulator's frame (start at 0, first strides along +x);
the building's map frame puts the entrance at (12.3, 4.1) facing +y (``seed003.map_from_sim``).

Example: ``python -m anfis_elevation_ros simulate --scenario building --seed 1 --out /tmp/sim``
"""

import argparse
from pathlib import Path
import sys
import time

import numpy as np

from .bags import write_imu_bag
from .. import sim
from ..core.building import save_building
from ..core.errors import InputError
from ..sim import seed003

TRUTH_COLUMNS = ('stamp_ns', 'x_m', 'y_m', 'z_m', 'qw', 'qx', 'qy', 'qz', 'stance')
STRIDE_COLUMNS = ('stamp_ns', 'mode', 'height_change_m', 'n_steps', 'height_m', 'step_height_m',
                  'swing_start_ns', 'start_x_m', 'start_y_m', 'start_z_m', 'end_x_m', 'end_y_m',
                  'end_z_m', 'heading_change_deg', 'segment_index')
SCENARIOS = ('building', 'random', 'sample', 'seed003')


def add_parser(subparsers):
    """Register the ``simulate`` subcommand."""
    parser = subparsers.add_parser(
        'simulate', help='simulate a foot-IMU walk: bag + truth CSV',
        description=__doc__.strip().split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--scenario', choices=SCENARIOS, default='sample',
                        help='building: 36 steps down, ~500 s level, back up (~640 s); random: '
                        'random mix for training (see --duration-s); sample: ~65 s demo; '
                        'seed003: 1,126 m, two floors, four stairwells, with its building file')
    parser.add_argument('--out', required=True, type=Path,
                        help='output directory (created; OUT/imu must not exist)')
    parser.add_argument('--rate-hz', type=float, default=200.0, help='IMU sample rate')
    parser.add_argument('--imu', choices=sorted(sim.IMU_PRESETS), default=None,
                        help="IMU error preset (default: consumer; seed003: that scenario's "
                        'tactical IMU, 150 deg/h gyro bias instability)')
    parser.add_argument('--seed', type=int, default=1, help='random seed (gait, IMU errors, '
                        'random scenario)')
    parser.add_argument('--storage', choices=('sqlite3', 'mcap'), default='sqlite3',
                        help='bag storage format')
    parser.add_argument('--duration-s', type=float, default=600.0,
                        help='random scenario: approximate duration')
    parser.add_argument('--step-height-m', type=float, default=None,
                        help='riser height K (building: 0.15, sample: 0.17; random: fixes K '
                        'instead of drawing it from 0.14-0.19 per staircase)')
    parser.add_argument('--mounting-rpy-deg', type=float, nargs=3, default=(0.0, 0.0, 0.0),
                        metavar=('ROLL', 'PITCH', 'YAW'),
                        help='IMU mounting on the foot, C_fb (v_f = C_fb v_b); 180 0 0 is '
                        'z down')
    parser.add_argument('--frame-id', default='imu_link', help='header.frame_id of the messages')
    parser.add_argument('--unknown-stairwell', default='', choices=('',) + seed003.STAIRWELLS,
                        help='seed003: leave this stairwell out of the building file')
    parser.add_argument('--topic', default='/imu/data', help='Imu topic name')
    parser.set_defaults(handler=run_simulate)
    return parser


def run_simulate(args) -> int:
    """Simulate, then write the bag and the truth files; return the exit code."""
    started = time.monotonic()
    segments, step_height_m = _scenario(args)
    bag_dir = args.out / 'imu'
    if bag_dir.exists():
        raise InputError(f'{bag_dir} exists; remove it or choose another --out')
    imu = args.imu or ('consumer' if args.scenario != 'seed003' else seed003.SEED003_IMU)
    if args.unknown_stairwell and args.scenario != 'seed003':
        raise InputError('--unknown-stairwell applies to --scenario seed003 only')
    _log(f'simulating scenario {args.scenario!r}: {len(segments)} segments, '
         f'{args.rate_hz:g} Hz, IMU {getattr(imu, "name", imu)!r}, seed {args.seed}')
    walk = sim.simulate_walk(segments, rng=np.random.default_rng(args.seed),
                             rate_hz=args.rate_hz, imu=imu,
                             mounting_rpy_deg=args.mounting_rpy_deg,
                             step_height_m=step_height_m)
    strides = walk.strides
    _log(f'{len(walk)} samples ({walk.duration_s:.1f} s), {len(strides)} strides '
         f'({int(np.sum(strides.mode > 0))} up, {int(np.sum(strides.mode < 0))} down), '
         f'floor heights {strides.height_m.min(initial=0.0):.2f} to '
         f'{strides.height_m.max(initial=0.0):.2f} m')
    args.out.mkdir(parents=True, exist_ok=True)
    gyr_std, acc_std = walk.imu.noise_std(walk.rate_hz)
    write_imu_bag(bag_dir, walk.to_recording(args.frame_id), topic=args.topic,
                  storage=args.storage, angular_velocity_variance=gyr_std ** 2,
                  linear_acceleration_variance=acc_std ** 2)
    _log(f'wrote {bag_dir} ({args.storage})')
    write_truth_csv(args.out / 'truth.csv', walk)
    write_strides_csv(args.out / 'strides.csv', walk)
    _log(f'wrote {args.out / "truth.csv"} and {args.out / "strides.csv"} in '
         f'{time.monotonic() - started:.1f} s')
    if args.scenario == 'seed003':
        building = seed003.seed003_building(walk, seed003.seed003_walk()[1],
                                            unknown=args.unknown_stairwell)
        save_building(args.out / 'building.yaml', building)
        _log(f'wrote {args.out / "building.yaml"} ({len(building.stairs)} stair entries)')
    return 0
    return 0


def _scenario(args) -> tuple:
    """Segments of the chosen scenario and the default riser height for simulate_walk."""
    k = args.step_height_m
    if args.scenario == 'building':
        return sim.building_walk(step_height_m=0.15 if k is None else k), 0.17
    if args.scenario == 'sample':
        return sim.sample_walk(), 0.17 if k is None else k
    if args.scenario == 'seed003':
        if k is not None:
            raise InputError('--step-height-m does not apply to --scenario seed003 (its risers '
                             f'are {seed003.STEP_HEIGHT_M} m, in its building file)')
        return seed003.seed003_walk()[0], seed003.STEP_HEIGHT_M
    bounds = (0.14, 0.19) if k is None else (k, k)
    plan_rng = np.random.default_rng([args.seed, 1])   # independent of the simulation stream
    return sim.random_walk(args.duration_s, plan_rng, step_height_range_m=bounds), 0.17


def write_truth_csv(path, walk: sim.SimulatedWalk):
    """Per-sample truth: stamp_ns,x_m,y_m,z_m,qw,qx,qy,qz,stance (IMU pose, ENU, q_nb)."""
    columns = [walk.stamp_ns, *walk.pos_n.T, *walk.quat_nb.T, walk.stance.astype(int)]
    formats = ['%d'] + ['%.6f'] * 3 + ['%.9f'] * 4 + ['%d']
    _write_csv(path, TRUTH_COLUMNS, columns, formats)


def write_strides_csv(path, walk: sim.SimulatedWalk):
    """Per-stride truth (one row per stride, stamp of its first stance sample); see StrideTruth."""
    s = walk.strides
    columns = [s.stamp_ns, s.mode, s.height_change_m, s.n_steps, s.height_m, s.step_height_m,
               s.swing_start_ns, *s.start_pos_n.T, *s.end_pos_n.T,
               np.degrees(s.heading_change_rad), s.segment_index]
    formats = ['%d', '%d', '%.6f', '%d', '%.6f', '%.6f', '%d'] + ['%.6f'] * 7 + ['%d']
    _write_csv(path, STRIDE_COLUMNS, columns, formats)


def _write_csv(path, names, columns, formats):
    table = np.empty((len(columns[0]), len(columns)), dtype=object)
    for j, column in enumerate(columns):
        table[:, j] = np.asarray(column).tolist()
    np.savetxt(path, table, fmt=formats, delimiter=',', header=','.join(names), comments='')


def _log(message: str):
    print(f'[simulate] {message}', file=sys.stderr, flush=True)
