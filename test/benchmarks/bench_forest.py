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
Benchmark of both stair classifiers: training time and per-cycle inference (a script).

Run from the repository root: ``python test/benchmarks/bench_forest.py`` (``--cycles``,
``--trees``; needs scikit-learn, the ``train`` extra, and ``../shared/data/hugadb`` or
``ANFIS_SHARED_DATA``). The training cycles are the HuGaDB cycles of every subject through the
navigator (feature cache of ``train``), repeated with 1 % noise up to ``--cycles``. Targets:
the forest (default ``ForestOptions``) trained on 10,000 cycles in <= 10 s, inference of one
cycle at a time (as the classifier node calls it) <= 50 us for both backends. Prints the
figures and exits 1 if a target is missed. Times are process CPU times (the best of a few
repeats for inference), so that other load on the machine does not count; wall times are
printed beside them.
"""

import argparse
import sys
import time
import timeit

from anfis_elevation_ros.tools.cross_validation import fit_model, stack, TrainOptions
from anfis_elevation_ros.tools.datasets import shared_data_dir
from anfis_elevation_ros.tools.train_forest import ForestOptions
from anfis_elevation_ros.tools.training_data import collect, hugadb_specs, LabelRules
from anfis_elevation_ros.tools.training_recordings import default_cache_dir, Pipeline
import numpy as np

TRAIN_TARGET_S = 10.0
INFERENCE_TARGET_US = 50.0


def training_cycles(n_cycles: int, seed: int):
    """Return HuGaDB cycles (all subjects) repeated with 1 % noise up to ``n_cycles``."""
    specs = hugadb_specs(shared_data_dir() / 'hugadb')
    sets = collect(specs, Pipeline(), LabelRules(), default_cache_dir())
    features, labels, _ = stack([s for s in sets if len(s.labels)])
    rng = np.random.default_rng(seed)
    pick = rng.integers(0, len(labels), n_cycles)
    noise = 1.0 + 0.01 * rng.standard_normal((n_cycles, features.shape[1]))
    return features[pick] * noise, labels[pick], len(labels)


def per_cycle_us(model, features: np.ndarray):
    """Best-of-5 CPU and wall time of ``model.predict`` on one (1, N_FEATURES) cycle, us."""
    rows = [features[i:i + 1] for i in range(min(len(features), 2000))]
    model.predict(rows[0])                                     # compile / warm up
    cpu = min(timeit.repeat(lambda: [model.predict(r) for r in rows], number=1, repeat=5,
                            timer=time.process_time))
    wall = min(timeit.repeat(lambda: [model.predict(r) for r in rows], number=1, repeat=5))
    return 1e6 * cpu / len(rows), 1e6 * wall / len(rows)


def main(argv=None) -> int:
    """Run the benchmark; return 1 when a target is missed."""
    parser = argparse.ArgumentParser(description=__doc__.strip().split('\n\n')[0])
    parser.add_argument('--cycles', type=int, default=10_000)
    parser.add_argument('--trees', type=int, default=ForestOptions.n_trees)
    parser.add_argument('--max-features', type=float, default=ForestOptions.max_features,
                        help='share of the features tried at a split')
    parser.add_argument('--seed', type=int, default=0)
    args = parser.parse_args(argv)
    features, labels, real = training_cycles(args.cycles, args.seed)
    print(f'{args.cycles} training cycles drawn from {real} HuGaDB cycles')
    timings = {}
    for backend in ('forest', 'anfis'):
        forest = ForestOptions(n_trees=args.trees, max_features=args.max_features)
        options = TrainOptions(backend=backend, forest=forest)
        started, started_wall = time.process_time(), time.perf_counter()
        model = fit_model(features, labels, options)
        fit_s, fit_wall_s = time.process_time() - started, time.perf_counter() - started_wall
        cpu_us, wall_us = per_cycle_us(model, features)
        timings[backend] = (fit_s, cpu_us)
        print(f'{backend}: training {fit_s:.2f} s CPU ({fit_wall_s:.2f} s wall), inference '
              f'{cpu_us:.1f} us CPU ({wall_us:.1f} us wall) per cycle')
    missed = []
    if timings['forest'][0] > TRAIN_TARGET_S:
        missed.append(f'forest training {timings["forest"][0]:.2f} s > {TRAIN_TARGET_S} s')
    missed += [f'{backend} inference {us:.1f} us > {INFERENCE_TARGET_US} us'
               for backend, (_, us) in timings.items() if us > INFERENCE_TARGET_US]
    print('targets met' if not missed else 'MISSED: ' + '; '.join(missed))
    return 1 if missed else 0


if __name__ == '__main__':
    sys.exit(main())
