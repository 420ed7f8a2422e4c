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
Where the z-gyro biases the filter learns on the pyshoe VICON trials come from (issue 14).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_gyro_bias.py``
(a script, about 40 s). Per trial, in deg/s: the gyro bias the navigator starts with (the mean
rate of its start-up stance, ``init_stance_s``, when no rate in it exceeds ``still_gyr_rps``),
the bias as the trial's still periods measure it (the mean rate over every 0.5 s window whose
rates all stay below ``STILL_RPS``), and, with the zero angular rate update over still stands
off and on (``heading.zaru_enabled``), the bias learned at the end and the error of the trial
(``pyshoe_position_error``); then the errors per session. One sensor, two sessions
(2017-11-22, 2017-11-27): its true bias cannot move by degrees per second between trials an
hour apart. ``--gyro-range-rps R`` declares the gyro's range (``gyro_range_rps``), whose
clipped samples are then rebuilt (``rail.enabled``, ``core/gyro_rail.py``;
``--no-rail-fill`` turns it off); with
a range, each row also gives the largest jump of the learned z bias at the rail (deg/s: its
change from ``JUMP_BEFORE_S`` before a sample within 1 % of the range to ``JUMP_AFTER_S``
after it).
"""

import argparse

from anfis_elevation_ros.core.gyro_rail import GyroRailParams
from anfis_elevation_ros.core.heading_aids import HeadingAidParams
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.tools.datasets import dataset_files, load_pyshoe_vicon
from anfis_elevation_ros.tools.metrics import pyshoe_position_error
import numpy as np

STILL_RPS = 0.1
STILL_WINDOW_S = 0.5
JUMP_BEFORE_S, JUMP_AFTER_S = 0.05, 0.5


def still_bias_dps(stamp_ns, gyr_b):
    """Return the mean rate over the samples of still windows (deg/s), NaN if none."""
    rate_hz = 1e9 / np.median(np.diff(stamp_ns))
    window = int(round(STILL_WINDOW_S * rate_hz))
    quiet = np.linalg.norm(gyr_b, axis=1) < STILL_RPS
    still = np.convolve(quiet, np.ones(window), 'same') >= window
    return np.degrees(gyr_b[still].mean(axis=0)) if still.any() else np.full(3, np.nan)


def run_trial(recording, truth, params):
    """
    Run one trial; return its start-up and learned z biases, error, ZARU samples, bias jump.

    Biases in deg/s, error in m; the jump (deg/s) is NaN without a declared range.
    """
    navigator = FootNavigator(params)
    start_bias = None
    track, bias_z = [], []
    for k in range(len(recording)):
        # Clipped samples held by the navigator come out together, in order.
        for point, _ in navigator.step(int(recording.stamp_ns[k]), recording.acc_b[k],
                                       recording.gyr_b[k]):
            track.append(point.pos_n)
            bias_z.append(np.degrees(navigator.gyro_bias_b[2]))
            if start_bias is None:
                start_bias = bias_z[-1]
    track += [point.pos_n for point, _ in navigator.flush()]
    bias_z += [np.degrees(navigator.gyro_bias_b[2])] * (len(track) - len(bias_z))
    first = len(recording) - len(track)
    error = pyshoe_position_error(np.array(track), truth[first:])
    return (start_bias, bias_z[-1], error, navigator.status.zaru_samples,
            bias_jump_dps(recording, np.array(bias_z), first, params.gyro_range_rps))


def bias_jump_dps(recording, bias_z_dps, first, range_rps):
    """Return the largest change of the learned z bias across a rail sample (NaN if none)."""
    if range_rps == 0.0:
        return np.nan
    rate_hz = 1e9 / np.median(np.diff(recording.stamp_ns))
    before, after = int(round(JUMP_BEFORE_S * rate_hz)), int(round(JUMP_AFTER_S * rate_hz))
    rail = np.flatnonzero(np.any(np.abs(recording.gyr_b[first:]) >= 0.99 * range_rps, axis=1))
    jumps = [abs(bias_z_dps[min(k + after, len(bias_z_dps) - 1)] - bias_z_dps[max(k - before, 0)])
             for k in rail]
    return max(jumps) if jumps else np.nan


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--gyro-range-rps', type=float, default=0.0,
                        help='gyro_range_rps (the sensor clips near 9.25)')
    parser.add_argument('--no-rail-fill', action='store_true', help='rail.enabled false')
    args = parser.parse_args()
    common = {'gyro_range_rps': args.gyro_range_rps,
              'rail': GyroRailParams(enabled=not args.no_rail_fill)}
    variants = {'ZARU off': NavigatorParams(heading=HeadingAidParams(zaru_enabled=False),
                                            **common),
                'ZARU on': NavigatorParams(heading=HeadingAidParams(zaru_enabled=True),
                                           **common)}
    print('trial              start-up z  still z | learned z (deg/s), error m: '
          + ' | '.join(variants) + ' | ZARU samples')
    learned = {name: [] for name in variants}
    errors = {name: {} for name in variants}
    jumps = {name: {} for name in variants}
    measured = []
    for path in dataset_files('pyshoe_vicon'):
        recording, truth = load_pyshoe_vicon(path)
        still = still_bias_dps(recording.stamp_ns, recording.gyr_b)
        measured.append(still[2])
        row = []
        for name, params in variants.items():
            start_bias, bias, error, zaru, jump = run_trial(recording, truth, params)
            learned[name].append(bias)
            errors[name][path.stem] = error
            jumps[name][path.stem] = jump
            row.append(f'{bias:+9.2f} {error:7.3f}'
                       + (f' jump {jump:4.2f}' if args.gyro_range_rps else ''))
        print(f'{path.stem}  {start_bias:+9.2f}  {still[2]:+7.2f} | ' + ' | '.join(row)
              + f' | {zaru:5d}')
    measured = np.array(measured)
    print(f'z bias measured still {np.nanmin(measured):+.2f} .. {np.nanmax(measured):+.2f} deg/s')
    for name in variants:
        by_session = {}
        for stem, error in errors[name].items():
            by_session.setdefault(stem[:10], []).append(error)
        sessions = ', '.join(f'{day} median {np.median(e):.3f} m mean {np.mean(e):.3f} m'
                             for day, e in by_session.items())
        print(f'{name}: z bias learned {min(learned[name]):+.2f} .. {max(learned[name]):+.2f} '
              f'deg/s; {sessions}')
        if args.gyro_range_rps:
            second = [j for stem, j in jumps[name].items()
                      if stem[:10] == '2017-11-27' and np.isfinite(j)]
            print(f'{name}: bias jump at the rail, second session: median '
                  f'{np.median(second):.2f}, max {max(second):.2f} deg/s '
                  f'({len(second)} trials clip)')


if __name__ == '__main__':
    main()
