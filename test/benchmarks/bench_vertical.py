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
Benchmark of the raw EKF height on real data with truth: the 36 pyshoe VICON trials (a script).

Run from the repository root: ``python test/benchmarks/bench_vertical.py`` (about a minute).
The pyshoe metric (``tools/metrics.py``) is horizontal only; VICON also gives the foot's
height. For every stance of at least 10 samples the vertical error e = z_est - z_vicon is
taken as its median over the last 5 stance samples (the foot is flat, so the offset between
the marker and the IMU is constant there), relative to the first stance. Printed: the rms and
the mean of its change per stride (the per-stride height drift) and, over the trials, the
median and mean of |e| at the last stance (no trial changes height overall), and pyshoe's 2D
metric of the same runs.
"""

from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.tools.datasets import dataset_files, load_pyshoe_vicon
from anfis_elevation_ros.tools.metrics import pyshoe_position_error
import numpy as np

MIN_STANCE_SAMPLES = 10
SETTLED_SAMPLES = 5


def stance_runs(stance: np.ndarray) -> tuple:
    """Return (start, end) index arrays of the runs of True (end exclusive)."""
    edges = np.diff(np.r_[0, stance.astype(np.int8), 0])
    return np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)


def vertical_errors(params: NavigatorParams) -> tuple:
    """Per-stride changes of the stance height error, each trial's final |e| and 2D metric."""
    steps, finals, horizontal = [], [], []
    for path in dataset_files('pyshoe_vicon'):
        recording, truth = load_pyshoe_vicon(path)
        track, _ = FootNavigator(params).run(recording.stamp_ns, recording.acc_b,
                                             recording.gyr_b)
        first = len(recording.stamp_ns) - len(track)
        stance = np.r_[np.zeros(first, bool), [p.stance for p in track]]
        error = np.r_[np.full(first, np.nan), [p.pos_n[2] for p in track]] - truth[:, 2]
        start, end = stance_runs(stance)
        end = end[end - start >= MIN_STANCE_SAMPLES]
        settled = np.array([np.nanmedian(error[k - SETTLED_SAMPLES:k]) for k in end])
        steps.append(np.diff(settled))
        finals.append(abs(settled[-1] - settled[0]))
        horizontal.append(pyshoe_position_error(np.array([p.pos_n for p in track]),
                                                truth[first:]))
    return np.concatenate(steps), np.array(finals), np.array(horizontal)


def main():
    steps, finals, horizontal = vertical_errors(NavigatorParams())
    rms_mm = 1e3 * np.sqrt(np.mean(steps ** 2))
    print(f'pyshoe VICON height, {len(finals)} trials, {len(steps)} strides: per-stride error '
          f'rms {rms_mm:.1f} mm, mean {1e3 * steps.mean():+.2f} mm; final |error| median '
          f'{np.median(finals):.3f} m, mean {finals.mean():.3f} m (2D metric: median '
          f'{np.median(horizontal):.4f} m, mean {horizontal.mean():.4f} m)')


if __name__ == '__main__':
    main()
