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
Benchmark of the ANFIS core: one hybrid epoch and inference per cycle (a script, not a test).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_anfis.py`` (options
``--cycles``, ``--seed``; no PYTHONPATH once the package is installed). Targets: one hybrid
epoch on 10,000 cycles with 5 inputs x 3 triangles (243 rules, 1458 consequents) <= 2 s;
inference <= 50 us per cycle, in a batch and in single-cycle calls. Prints the figures and exits 1
if a target is missed. Timings are the best of a few repeats (the least disturbed by other load).
"""

import argparse
import sys
import time
import timeit

from anfis_elevation_ros import Anfis
from anfis_elevation_ros.core.anfis import (
    anfis_output, firing_strengths, gradient_step, least_squares_consequents, membership_grades,
    normalised_firing_strengths, premise_gradient, project_mf_params, rule_outputs,
    update_step_size)
from anfis_elevation_ros.core.height import ElevationParams, ElevationTracker
import numpy as np

EPOCH_TARGET_S = 2.0
INFERENCE_TARGET_US = 50.0


def synthetic_cycles(rng: np.random.Generator, n_cycles: int):
    """Cycles with the five features of eq. 8-12 and targets -1 (down), 0 (level), +1 (up)."""
    mode = rng.integers(-1, 2, n_cycles)
    dh = 0.17 * mode + 0.03 * rng.standard_normal(n_cycles)
    features = np.stack((dh / 2.0 + 0.02 * rng.standard_normal(n_cycles),
                         np.abs(dh) / 3.0 + 0.01 * rng.standard_normal(n_cycles),
                         dh,
                         np.abs(dh) + 0.03 + 0.02 * rng.standard_normal(n_cycles),
                         0.3 + 0.1 * mode + 0.1 * rng.standard_normal(n_cycles)), axis=1)
    return features, mode.astype(float)


def hybrid_epoch(model: Anfis, x, y, mf_params, step_size, errors):
    """One epoch exactly as Anfis.fit runs it: forward + LSE, error, step rules, GD, projection."""
    mu = membership_grades(x, mf_params, model.mf)
    wbar, _ = normalised_firing_strengths(firing_strengths(mu))
    consequents = least_squares_consequents(wbar, x, y)
    errors.append(float(np.sqrt(np.mean((anfis_output(wbar, rule_outputs(x, consequents)) - y)
                                        ** 2))))
    step_size = update_step_size(step_size, errors, 0, 0)[0]
    grad, _ = premise_gradient(x, y, mf_params, model.mf, consequents)
    return project_mf_params(gradient_step(mf_params, grad, step_size), model.mf,
                             model.input_range_)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--cycles', type=int, default=10000, help='training cycles')
    parser.add_argument('--seed', type=int, default=0, help='seed of the synthetic cycles')
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    x, y = synthetic_cycles(rng, args.cycles)
    model = Anfis(5, 3, 'triangle').fit(x, y, epochs=1)
    print(f'ANFIS 5 inputs x 3 triangle MFs: {model.n_rules} rules, '
          f'{model.consequents_.size} consequents; {args.cycles} synthetic cycles; '
          f'numpy {np.__version__}')

    epoch_times = []
    for _ in range(3):
        start = time.perf_counter()
        hybrid_epoch(model, x, y, model.mf_params_, 0.01, [])
        epoch_times.append(time.perf_counter() - start)
    start = time.perf_counter()
    lse_only = least_squares_consequents(model.firing_strengths(x), x, y)
    lse_s = time.perf_counter() - start
    start = time.perf_counter()
    Anfis(5, 3).fit(x, y, epochs=5)
    fit_s = time.perf_counter() - start
    epoch_s = min(epoch_times)
    print(f'hybrid epoch: {epoch_s:.3f} s (best of 3; least-squares step alone {lse_s:.3f} s, '
          f'{lse_only.size} unknowns); fit(epochs=5): {fit_s:.3f} s '
          f'[target <= {EPOCH_TARGET_S} s]')

    batch = x[:10000]
    repeats = 5
    batch_s = min(timeit.repeat(lambda: model.predict(batch), number=1, repeat=repeats))
    batch_us = batch_s / len(batch) * 1e6
    single = x[:1]
    calls = 2000
    single_us = min(timeit.repeat(lambda: model.predict(single), number=calls,
                                  repeat=repeats)) / calls * 1e6
    tracker = ElevationTracker(model, ElevationParams())
    features = x[0]
    tracker_us = min(timeit.repeat(lambda: tracker.update(0, features, 0.0, 0.0), number=calls,
                                   repeat=repeats)) / calls * 1e6
    print(f'inference: batch of {len(batch)}: {batch_us:.2f} us per cycle; single-cycle '
          f'predict: {single_us:.1f} us; ElevationTracker.update: {tracker_us:.1f} us '
          f'[target <= {INFERENCE_TARGET_US} us]')

    missed = [name for name, value, target in (
        ('epoch', epoch_s, EPOCH_TARGET_S), ('batch inference', batch_us, INFERENCE_TARGET_US),
        ('single-cycle inference', single_us, INFERENCE_TARGET_US)) if value > target]
    print('targets met' if not missed else f'targets missed: {", ".join(missed)}')
    return 1 if missed else 0


if __name__ == '__main__':
    sys.exit(main())
