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
Per-stride height error of real foot motion seen through HuGaDB's sensor (a script, not a test).

Run from the repository root: ``python test/benchmarks/bench_clipping.py`` (about a minute).

HuGaDB has no height truth. The pyshoe VICON trials have it, at about 200 Hz from a sensor that
never reaches its range (at most 4.4 g). Degraded to HuGaDB's sensor, they show what its rate
and its +-2 g accelerometer alone do to feature (10), the height change of a gait cycle:

- ``original``: the recordings as they are;
- ``58.8 Hz means``: resampled to 58.8 Hz as an integrating sensor would (the mean over each
  interval, from the cumulative trapezoid integral);
- ``58.8 Hz points``: resampled by linear interpolation at the sample times (a sensor whose
  filter leaves the impacts in, aliased);
- each of the last two with the accelerometer clipped at +-2 g, as HuGaDB's is.

For every valid cycle, error = feature (10) - VICON height change between the cycle's two
stance samples. Prints the error percentiles, the rms and the clipped share of samples.
"""

from anfis_elevation_ros.core.navigator import FootNavigator
from anfis_elevation_ros.tools.datasets import dataset_files, load_pyshoe_vicon
from anfis_elevation_ros.tools.datasets import STANDARD_GRAVITY_MPS2
import numpy as np

HUGADB_RATE_HZ = 58.8
HUGADB_ACC_RANGE_MPS2 = 2.0 * STANDARD_GRAVITY_MPS2


def interval_means(stamp_ns: np.ndarray, x: np.ndarray, rate_hz: float) -> tuple:
    """Resample to ``rate_hz`` as the means over each interval; return (stamps, values)."""
    t_s = (stamp_ns - stamp_ns[0]) * 1e-9
    integral = np.concatenate([np.zeros((1, x.shape[1])), np.cumsum(
        0.5 * (x[1:] + x[:-1]) * np.diff(t_s)[:, None], axis=0)])
    dt_s = 1.0 / rate_hz
    edges = np.arange(0.0, t_s[-1], dt_s)
    at_edges = np.stack([np.interp(edges, t_s, column) for column in integral.T], axis=1)
    centres_ns = np.round((edges[:-1] + 0.5 * dt_s) * 1e9).astype(np.int64)
    return stamp_ns[0] + centres_ns, np.diff(at_edges, axis=0) / dt_s


def point_samples(stamp_ns: np.ndarray, x: np.ndarray, rate_hz: float) -> tuple:
    """Resample to ``rate_hz`` by linear interpolation at the sample times."""
    t_s = (stamp_ns - stamp_ns[0]) * 1e-9
    times_s = np.arange(0.0, t_s[-1], 1.0 / rate_hz)
    values = np.stack([np.interp(times_s, t_s, column) for column in x.T], axis=1)
    return stamp_ns[0] + np.round(times_s * 1e9).astype(np.int64), values


def height_change_errors(resample=None, acc_range_mps2: float = np.inf) -> tuple:
    """Return (errors of feature (10), m, clipped share of samples) over the 36 trials."""
    errors, clipped, samples = [], 0, 0
    for path in dataset_files('pyshoe_vicon'):
        recording, truth = load_pyshoe_vicon(path)
        stamp_ns, acc_b, gyr_b = recording.stamp_ns, recording.acc_b, recording.gyr_b
        if resample is not None:
            stamp_ns, acc_b = resample(recording.stamp_ns, recording.acc_b, HUGADB_RATE_HZ)
            gyr_b = resample(recording.stamp_ns, recording.gyr_b, HUGADB_RATE_HZ)[1]
        clipped += int(np.sum(np.any(np.abs(acc_b) >= acc_range_mps2, axis=1)))
        samples += len(acc_b)
        acc_b = np.clip(acc_b, -acc_range_mps2, acc_range_mps2)
        _, cycles = FootNavigator().run(stamp_ns, acc_b, gyr_b)
        for cycle in cycles:
            if cycle.valid:
                true_change = np.diff(np.interp([cycle.start_stamp_ns, cycle.stamp_ns],
                                                recording.stamp_ns, truth[:, 2]))[0]
                errors.append(cycle.height_change_m - true_change)
    return np.array(errors), clipped / samples


def main():
    """Print the height-change errors of each degradation."""
    rows = (('original', None, np.inf),
            ('58.8 Hz means', interval_means, np.inf),
            ('58.8 Hz means, +-2 g', interval_means, HUGADB_ACC_RANGE_MPS2),
            ('58.8 Hz points', point_samples, np.inf),
            ('58.8 Hz points, +-2 g', point_samples, HUGADB_ACC_RANGE_MPS2))
    print('pyshoe VICON, 36 trials: error of feature (10), the height change of a cycle, m')
    for name, resample, acc_range in rows:
        errors, clipped = height_change_errors(resample, acc_range)
        p10, p50, p90 = np.percentile(errors, (10, 50, 90))
        print(f'{name:22s} {len(errors)} cycles, p10 {p10:+.3f}, median {p50:+.3f}, p90 '
              f'{p90:+.3f}, rms {np.sqrt(np.mean(errors ** 2)):.3f}; {100 * clipped:.1f} % '
              'of samples clipped', flush=True)


if __name__ == '__main__':
    main()
