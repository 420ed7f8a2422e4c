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
Benchmark of the navigator on the gdin_hallway walks: strides detected and horizontal error.

Run from the repository root: ``python test/benchmarks/bench_gdin_hallway.py``. Per walk: gait
cycles against ``numberOfStrides``, the final-position error as % of the path (truth polyline
through the stride positions), and the mean and largest error of the stride-end positions
(only when every stride was detected, so that cycle i is stride i), for the plain filter and
with each heading aid (``heading.zaru_enabled``, ``heading.hde_enabled``, both) side by side,
with the gyro's range declared (``gyro_range_rps``: clipped samples are rebuilt first,
``rail.enabled``, ``core/gyro_rail.py``; with ``--no-rail-fill`` they add attitude noise only).
The track's
heading is aligned to the truth on the first ``ALIGN_CYCLES`` cycle ends (least-squares
rotation about the start): the IMU's initial heading is unknown, as in any foot-mounted INS
benchmark. Each cycle end is paired with the truth polyline's point at the same distance walked,
so a first cycle that spans two strides is fitted to the second stride's end, not the first's.
"""

import sys

from anfis_elevation_ros.core.gyro_rail import GyroRailParams
from anfis_elevation_ros.core.heading_aids import HeadingAidParams
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.core.stride_gate import StrideGateParams
from anfis_elevation_ros.tools.datasets import dataset_files
from anfis_elevation_ros.tools.gdin_hallway import GYRO_RANGE_RPS, load_gdin_walk
import numpy as np

ALIGN_CYCLES = 3
AIDS = {'plain': HeadingAidParams(hde_enabled=False, zaru_enabled=False),
        'zaru': HeadingAidParams(hde_enabled=False, zaru_enabled=True),
        'hde': HeadingAidParams(hde_enabled=True, zaru_enabled=False),
        'both': HeadingAidParams(hde_enabled=True, zaru_enabled=True)}


def path_lengths(xy):
    """Return the distance walked to each point of a polyline (N, 2) -> (N,)."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])


def aligned(est_xy, truth_xy):
    """
    Return est_xy rotated about the origin to fit truth_xy on the first cycle ends.

    Cycle end i is paired with the point of the truth polyline at the same distance walked.
    """
    e = est_xy[1:ALIGN_CYCLES + 1]
    walked = path_lengths(est_xy)[1:ALIGN_CYCLES + 1]
    truth_walked = path_lengths(truth_xy)
    t = np.column_stack([np.interp(walked, truth_walked, truth_xy[:, 0]),
                         np.interp(walked, truth_walked, truth_xy[:, 1])])
    angle = np.arctan2(np.sum(e[:, 0] * t[:, 1] - e[:, 1] * t[:, 0]),
                       np.sum(e[:, 0] * t[:, 0] + e[:, 1] * t[:, 1]))
    c, s = np.cos(angle), np.sin(angle)
    return est_xy @ np.array([[c, s], [-s, c]])


def walk_figures(walk, params):
    """Return (cycles, final error % of path, mean and largest stride error m or NaN)."""
    rec = walk.recording
    track, cycles = FootNavigator(params).run(rec.stamp_ns, rec.acc_b, rec.gyr_b)
    est = np.vstack([c.pos_n[:2] for c in cycles]) - track[0].pos_n[:2]
    est = aligned(np.vstack([np.zeros(2), est]), walk.stride_pos_m)
    final = np.linalg.norm(est[-1] - walk.stride_pos_m[-1])
    mean = largest = np.nan
    if len(cycles) == walk.n_strides:
        errors = np.linalg.norm(est - walk.stride_pos_m, axis=1)
        mean, largest = float(np.mean(errors)), float(np.max(errors))
    return len(cycles), 100.0 * final / walk.path_length_m, mean, largest


def main():
    # --no-stride-gate: stride_gate.enabled false (core/stride_gate.py; on by default).
    # --no-late-stances: stride_gate.late_stances false (on by default).
    # --no-late-cycles: stride_gate.late_max_slope 0 (late stances close no cycle).
    gate = StrideGateParams(enabled='--no-stride-gate' not in sys.argv,
                            late_stances='--no-late-stances' not in sys.argv,
                            **({'late_max_slope': 0.0} if '--no-late-cycles' in sys.argv else {}))
    # --no-rail-fill: rail.enabled false (clipped samples add attitude noise only).
    rail = GyroRailParams(enabled='--no-rail-fill' not in sys.argv)
    finals = {name: [] for name in AIDS}
    strides = {name: [] for name in AIDS}       # (mean, largest) stride error of each walk
    print('walk cycles/strides path_m | final % of path, mean and largest stride error m: '
          + ' | '.join(AIDS))
    for path in dataset_files('gdin_hallway'):
        walk = load_gdin_walk(path)
        row = []
        for name, aid in AIDS.items():
            cycles, final_pct, mean_m, largest_m = walk_figures(
                walk, NavigatorParams(heading=aid, gyro_range_rps=GYRO_RANGE_RPS,
                                      stride_gate=gate, rail=rail))
            finals[name].append(final_pct)
            strides[name].append((mean_m, largest_m))
            row.append(f'{final_pct:5.1f} {mean_m:5.2f} {largest_m:5.2f}')
        print(f'{path.stem[-2:]} {cycles:4d}/{walk.n_strides:<4d} {walk.path_length_m:6.1f} | '
              + ' | '.join(row))
    for name, values in finals.items():
        worse = sum(v > p + 0.05 for v, p in zip(values, finals['plain']))
        # NaN (a walk with strides missed) compares False: counted as not worse.
        worse_strides = sum(m > pm + 0.005 or x > px + 0.005 for (m, x), (pm, px)
                            in zip(strides[name], strides['plain']))
        print(f'{name:5s}: median final error {np.median(values):.1f} % of path, mean '
              f'{np.mean(values):.1f} %, {worse} walks worse than plain; '
              f'{worse_strides} worse by the mean or largest stride error')


if __name__ == '__main__':
    main()
