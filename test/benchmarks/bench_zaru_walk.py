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
Where ZARU changes a gdin_hallway walk: its stands, the learned gyro bias and the heading.

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_zaru_walk.py
[--walk 35] [--rail-noise 0.5] [--no-rail-fill]``. The walk goes through the navigator twice
(heading aids off, then ZARU alone; gyro range declared, as in ``bench_gdin_hallway.py``;
clipped samples rebuilt, ``rail.enabled``, unless ``--no-rail-fill``), and prints: the
samples at the gyro's rail per axis and sign; every run of samples where ZARU fired (time,
samples, mean rate, z bias before and after); at each gait-cycle end, the cycle's length, the
learned gyro bias of both runs and their yaw difference; the final error as % of the path.
"""

import argparse
import math

from anfis_elevation_ros.core.ekf import EkfParams
from anfis_elevation_ros.core.frames import dcm_to_rpy, quat_to_dcm
from anfis_elevation_ros.core.gyro_rail import GyroRailParams
from anfis_elevation_ros.core.heading_aids import HeadingAidParams
from anfis_elevation_ros.core.navigator import FootNavigator, GYR_RAIL_FRACTION, NavigatorParams
from anfis_elevation_ros.tools.datasets import shared_data_dir
from anfis_elevation_ros.tools.gdin_hallway import GYRO_RANGE_RPS, load_gdin_walk
from bench_gdin_hallway import aligned
import numpy as np


def trace(walk, zaru, rail_noise_rps, rail_fill):
    """Run the walk; return per-sample ZARU count, z bias and yaw, and the cycles' ends."""
    params = NavigatorParams(heading=HeadingAidParams(hde_enabled=False, zaru_enabled=zaru),
                             gyro_range_rps=GYRO_RANGE_RPS,
                             ekf=EkfParams(gyr_rail_noise_rps=rail_noise_rps),
                             rail=GyroRailParams(enabled=rail_fill))
    nav, rec = FootNavigator(params), walk.recording
    n = len(rec.stamp_ns)
    zaru_count, bias, yaw = np.zeros(n, int), np.full((n, 3), np.nan), np.full(n, np.nan)
    start, ends, end_samples = None, [], []
    for k in range(n):
        # Held clipped samples come out together when released (core/gyro_rail.py): each at
        # its own index, with the state after the release (ZARU never fires in a swing).
        for point, cycle in nav.step(rec.stamp_ns[k], rec.acc_b[k], rec.gyr_b[k]):
            i = int(np.searchsorted(rec.stamp_ns, point.stamp_ns))
            start = point.pos_n[:2] if start is None else start
            zaru_count[i], bias[i] = nav.status.zaru_samples, nav.gyro_bias_b
            yaw[i] = dcm_to_rpy(quat_to_dcm(point.quat_nb))[2]
            if cycle is not None:
                ends.append(cycle.pos_n[:2] - start)
                end_samples.append(i)
    return zaru_count, bias, yaw, np.array(ends), np.array(end_samples)


def runs(mask):
    """Return (first, stop) index pairs of the runs of True in mask."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(int), [0]))))
    return list(zip(edges[::2], edges[1::2]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--walk', default='35', help='walk number (default 35)')
    parser.add_argument('--rail-noise', type=float, default=EkfParams().gyr_rail_noise_rps,
                        help='ekf.gyr_rail_noise_rps, rad/s')
    parser.add_argument('--no-rail-fill', action='store_true', help='rail.enabled false')
    args = parser.parse_args()
    walk = load_gdin_walk(
        shared_data_dir() / 'gdin_hallway' / f'SensorConnectData_{args.walk}.csv')
    rec = walk.recording
    t_s = (rec.stamp_ns - rec.stamp_ns[0]) * 1e-9
    rail = GYR_RAIL_FRACTION * GYRO_RANGE_RPS
    print('samples at the rail (+, -) per axis x, y, z:',
          [(int(np.sum(g >= rail)), int(np.sum(g <= -rail))) for g in rec.gyr_b.T])
    plain = trace(walk, False, args.rail_noise, not args.no_rail_fill)
    zaru = trace(walk, True, args.rail_noise, not args.no_rail_fill)
    count, bias = zaru[0], np.degrees(zaru[1])
    print('ZARU runs: t0-t1 s, samples, mean rate x y z deg/s, z bias before -> after deg/s')
    for first, stop in runs(np.diff(count, prepend=0) > 0):
        print(f'  {t_s[first]:6.2f}-{t_s[stop - 1]:6.2f} {stop - first:5d} '
              f'{np.array2string(np.degrees(rec.gyr_b[first:stop].mean(axis=0)), precision=2)}'
              f' {bias[first - 1, 2]:+.2f} -> {bias[stop - 1, 2]:+.2f}')
    if len(plain[3]) != len(zaru[3]) or np.any(plain[4] != zaru[4]):
        print('the two runs cut different cycles; per-cycle table skipped')
    else:
        clipped = np.cumsum(np.any(np.abs(rec.gyr_b) >= rail, axis=1))
        print('cycle end t s, rail samples so far | length m, gyro bias deg/s: plain | ZARU | '
              'yaw ZARU - plain deg')
        for i, k in enumerate(plain[4]):
            cells = []
            for ends, b in ((plain[3], plain[1]), (zaru[3], zaru[1])):
                length = np.linalg.norm(ends[i] - ends[i - 1]) if i else np.linalg.norm(ends[0])
                cells.append(f'{length:5.2f} {np.array2string(np.degrees(b[k]), precision=2)}')
            dyaw = math.degrees(math.remainder(zaru[2][k] - plain[2][k], 2 * math.pi))
            print(f'  {t_s[k]:6.2f} {clipped[k]:4d} | ' + ' | '.join(cells) + f' | {dyaw:+.2f}')
    for name, (_, _, _, ends, _) in (('plain', plain), ('ZARU', zaru)):
        est = aligned(np.vstack([np.zeros(2), ends]), walk.stride_pos_m)
        final = np.linalg.norm(est[-1] - walk.stride_pos_m[-1])
        print(f'{name}: {len(ends)} cycles of {walk.n_strides} strides, final error '
              f'{100.0 * final / walk.path_length_m:.1f} % of the path')


if __name__ == '__main__':
    main()
