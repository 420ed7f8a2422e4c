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
hour apart.
"""

from anfis_elevation_ros.core.heading_aids import HeadingAidParams
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.tools.datasets import dataset_files, load_pyshoe_vicon
from anfis_elevation_ros.tools.metrics import pyshoe_position_error
import numpy as np

STILL_RPS = 0.1
STILL_WINDOW_S = 0.5


def still_bias_dps(stamp_ns, gyr_b):
    """Return the mean rate over the samples of still windows (deg/s), NaN if none."""
    rate_hz = 1e9 / np.median(np.diff(stamp_ns))
    window = int(round(STILL_WINDOW_S * rate_hz))
    quiet = np.linalg.norm(gyr_b, axis=1) < STILL_RPS
    still = np.convolve(quiet, np.ones(window), 'same') >= window
    return np.degrees(gyr_b[still].mean(axis=0)) if still.any() else np.full(3, np.nan)


def run_trial(recording, truth, params):
    """Return (start-up z bias, learned z bias (deg/s), error m, ZARU samples) of one trial."""
    navigator = FootNavigator(params)
    start_bias = None
    track = []
    for k in range(len(recording)):
        out = navigator.step(int(recording.stamp_ns[k]), recording.acc_b[k], recording.gyr_b[k])
        if out is not None:
            track.append(out[0].pos_n)
            if start_bias is None:
                start_bias = np.degrees(navigator.gyro_bias_b[2])
    first = len(recording) - len(track)
    error = pyshoe_position_error(np.array(track), truth[first:])
    return (start_bias, np.degrees(navigator.gyro_bias_b[2]), error,
            navigator.status.zaru_samples)


def main():
    variants = {'ZARU off': NavigatorParams(heading=HeadingAidParams(zaru_enabled=False)),
                'ZARU on': NavigatorParams(heading=HeadingAidParams(zaru_enabled=True))}
    print('trial              start-up z  still z | learned z (deg/s), error m: '
          + ' | '.join(variants) + ' | ZARU samples')
    learned = {name: [] for name in variants}
    errors = {name: {} for name in variants}
    measured = []
    for path in dataset_files('pyshoe_vicon'):
        recording, truth = load_pyshoe_vicon(path)
        still = still_bias_dps(recording.stamp_ns, recording.gyr_b)
        measured.append(still[2])
        row = []
        for name, params in variants.items():
            start_bias, bias, error, zaru = run_trial(recording, truth, params)
            learned[name].append(bias)
            errors[name][path.stem] = error
            row.append(f'{bias:+9.2f} {error:7.3f}')
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


if __name__ == '__main__':
    main()
