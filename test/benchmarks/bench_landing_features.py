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
Features of the foot's landing and push-off for the forest on a new wearer (a script).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_landing_features.py``
(``--help`` for the options). HuGaDB alone (the feet whose gyro does not clip, subjects 1, 2,
3, 6, 7, 8, 9), the default gate and navigator, the ``train`` labels; the forest of
``train --backend forest`` (100 trees, half the features per split, balanced), deciding by the
largest class probability. Candidate features per gait cycle, from the navigator's own swing
samples (the samples eq. 8-12 use; p_j = theta_j - theta_0 the foot pitch relative to the
stance the swing left, toe up positive; h_j the height; v_j the velocity):

- ``pitch_toe_off_rad`` p at the first swing sample; ``pitch_touchdown_rad`` p at the last;
- ``min_pitch_rad`` min_j p_j over the swing; ``mean_pitch_rad`` its mean;
- ``pitch_q1/q2/q3_rad`` p at 1/4, 1/2, 3/4 of the swing (linear interpolation);
- ``peak_height_phase`` (argmax_j h_j) / n, the part of the swing at which the foot is highest;
- ``mid_height_above_end_m`` h at half the swing minus h_n (the closing, corrected, sample);
- ``touchdown_descent_rad`` atan2(-v_z, |v_h|) at the last swing sample; ``lift_rad`` and
  ``landing_rad`` atan2(mean v_z, mean |v_h|) over the first / last third of the swing.

Protocol: features are chosen by greedy forward selection with leave-one-subject-out over
subjects 1, 2, 3, 6 only (``--select-subjects``), then every set is scored on subjects 7, 8, 9,
each predicted by a forest trained on the six other subjects (``--check-subjects``); the seven-
fold leave-one-subject-out of all subjects is printed too (that one has seen the choice).
``--backend anfis``: the ANFIS of ``train`` (its defaults, sigma_th 0.5) on the patent's five,
and on the five with each candidate in place of max pitch (an input more would triple the 3^5
rules, more consequents than cycles); a swap is kept if it is best on the selection subjects.
The cycles are cached (``--cache``; the default name holds a digest of the pipeline's code and
of this script).
"""

import argparse
import dataclasses
import hashlib
import math
from pathlib import Path
import sys
import time

from anfis_elevation_ros.core import gait
from anfis_elevation_ros.core.anfis import Anfis
from anfis_elevation_ros.core.gait import FEATURE_NAMES, foot_inclination, PATENT_FEATURE_NAMES
from anfis_elevation_ros.core.height import stair_mode
from anfis_elevation_ros.tools.cross_validation import input_universe, TrainOptions
from anfis_elevation_ros.tools.datasets import shared_data_dir
from anfis_elevation_ros.tools.metrics import confusion_matrix
from anfis_elevation_ros.tools.train_forest import ForestOptions
from anfis_elevation_ros.tools.training_data import hugadb_specs, label_recording, LabelRules
from anfis_elevation_ros.tools.training_recordings import default_cache_dir, navigate_spec
from anfis_elevation_ros.tools.training_recordings import Pipeline, pipeline_fingerprint
import numpy as np

CANDIDATES = ('pitch_toe_off_rad', 'pitch_touchdown_rad', 'min_pitch_rad', 'mean_pitch_rad',
              'pitch_q1_rad', 'pitch_q2_rad', 'pitch_q3_rad', 'peak_height_phase',
              'mid_height_above_end_m', 'touchdown_descent_rad', 'lift_rad', 'landing_rad')
MIN_GAIN = 0.002


def candidate_features(heights, up_b, vel_n, up_b_stance, forward_b) -> np.ndarray:
    """Candidate features of one cycle (CANDIDATES order) from its swing samples."""
    pitch = foot_inclination(up_b, forward_b) - foot_inclination(up_b_stance, forward_b)
    n = len(heights)
    swing = pitch[:-1] if n > 1 else pitch        # the closing sample is a stance sample
    phase = np.linspace(0.0, 1.0, len(swing))
    quarters = np.interp((0.25, 0.5, 0.75), phase, swing) if len(swing) > 1 else [swing[0]] * 3
    speed_h = np.hypot(vel_n[:, 0], vel_n[:, 1])
    last = max(0, n - 2)
    third = max(1, (n - 1) // 3)
    mid = float(np.interp(0.5, np.linspace(0.0, 1.0, n), heights))
    return np.array([
        swing[0], swing[-1], swing.min(), swing.mean(), *quarters,
        float(np.argmax(heights)) / n, mid - heights[-1],
        math.atan2(-vel_n[last, 2], speed_h[last]),
        math.atan2(vel_n[:third, 2].mean(), speed_h[:third].mean()),
        math.atan2(vel_n[last - third + 1:last + 1, 2].mean(),
                   speed_h[last - third + 1:last + 1].mean())])


class Recorder:
    """Wraps ``GaitSegmenter._close`` to compute the candidates of every cycle it closes."""

    def __init__(self):
        """Install the wrapper; ``rows`` collects one candidate vector per closed cycle."""
        self.rows = []
        self._original = gait.GaitSegmenter._close
        recorder = self

        def close(segmenter, stamp_ns, pos_n):
            heights = np.asarray(segmenter._heights)
            up_b = np.asarray(segmenter._up_b)
            vel_n = np.asarray(segmenter._motion)[:, 6:9]
            up_stance = segmenter._stance_C_nb[2, :]
            mounting = segmenter._mounting
            chosen = {}
            forward = mounting.forward_for_cycle

            def remember(*args):
                chosen['forward'] = forward(*args)
                return chosen['forward']

            mounting.forward_for_cycle = remember
            try:
                cycle = recorder._original(segmenter, stamp_ns, pos_n)
            finally:
                del mounting.forward_for_cycle
            if cycle is not None:
                forward_b = chosen.get('forward')
                if forward_b is None:
                    forward_b = np.eye(3)[int(np.argmin(np.abs(up_stance)))]
                recorder.rows.append(candidate_features(heights, up_b, vel_n, up_stance,
                                                        forward_b))
            return cycle

        gait.GaitSegmenter._close = close


def hugadb_sets(folder: Path, cache: Path) -> list:
    """Labelled cycle sets of the HuGaDB feet, features = the 16 then the candidates."""
    if cache.is_file():
        with np.load(cache, allow_pickle=False) as data:
            return [(str(name), int(subject), data[f'x{i}'], data[f'y{i}'])
                    for i, (name, subject) in enumerate(zip(data['names'], data['subjects']))]
    recorder = Recorder()
    rules, pipeline, out = LabelRules(), Pipeline(), []
    for spec in hugadb_specs(folder):
        recorder.rows.clear()
        nav = navigate_spec(spec, pipeline)
        extra = np.array(recorder.rows).reshape(-1, len(CANDIDATES))
        assert len(extra) == len(nav.valid)
        nav = dataclasses.replace(nav, features=np.hstack((nav.features, extra)))
        cycle_set = label_recording(spec, nav, rules)
        if len(cycle_set.labels):
            out.append((cycle_set.name, spec.subject, cycle_set.features,
                        cycle_set.labels.astype(np.int64)))
    np.savez(cache, names=[o[0] for o in out], subjects=[o[1] for o in out],
             **{f'x{i}': o[2] for i, o in enumerate(out)},
             **{f'y{i}': o[3] for i, o in enumerate(out)})
    return out


def fit_predict(x_train, y_train, x_test, seed: int, backend: str) -> np.ndarray:
    """
    Modes predicted by ``train``'s classifier with its default options.

    Forest: the mode of largest probability; ANFIS (3 triangles per input, 3 epochs): eq. (13)
    at sigma_th 0.5 (the seed does not change it).
    """
    if backend == 'anfis':
        options = TrainOptions()
        model = Anfis(x_train.shape[1], options.n_mfs, options.mf)
        model.fit(x_train, y_train.astype(float), epochs=options.epochs, ridge=options.ridge,
                  input_range=input_universe(x_train, options.range_quantile))
        return stair_mode(model.predict(x_test), 0.5)
    from sklearn.ensemble import RandomForestClassifier
    options = ForestOptions(seed=seed)
    forest = RandomForestClassifier(
        n_estimators=options.n_trees, max_features=options.max_features,
        min_samples_leaf=options.min_samples_leaf, class_weight=options.class_weight,
        random_state=options.seed, n_jobs=1)
    forest.fit(x_train, y_train)
    return forest.classes_[np.argmax(forest.predict_proba(x_test), axis=1)]


def held_out(x, y, subject, columns, train_subjects, test_subjects, seed=0, backend='forest'):
    """Labels and predictions of test_subjects, one model per subject left out."""
    labels, predicted = [], []
    for s in test_subjects:
        fit = np.isin(subject, train_subjects) & (subject != s)
        test = subject == s
        labels.append(y[test])
        predicted.append(fit_predict(x[fit][:, columns], y[fit], x[test][:, columns], seed,
                                     backend))
    return np.concatenate(labels), np.concatenate(predicted)


def score(labels, predicted) -> tuple:
    """Accuracy, recall of down / level / up, confusion (rows true -1/0/+1)."""
    matrix = confusion_matrix(labels, predicted)
    recall = np.diag(matrix) / np.maximum(matrix.sum(axis=1), 1)
    return float(np.mean(labels == predicted)), recall, matrix


def describe(name, runs) -> str:
    """One line over forest seeds: mean accuracy (range); recalls and confusion summed."""
    accuracies = [score(*run)[0] for run in runs]
    _, recall, matrix = score(np.concatenate([r[0] for r in runs]),
                              np.concatenate([r[1] for r in runs]))
    spread = f'{min(accuracies):.4f}-{max(accuracies):.4f}' if len(runs) > 1 else ' ' * 13
    return (f'{name:44s} {np.mean(accuracies):.4f} {spread}  '
            f'{recall[0]:.3f}/{recall[1]:.3f}/{recall[2]:.3f}  '
            f'{" ".join(str(r) for r in matrix.tolist())}')


def columns_of(names) -> list:
    """Columns of the stacked matrix of named features."""
    every = FEATURE_NAMES + CANDIDATES
    return [every.index(name) for name in names]


def forward_selection(x, y, subject, select):
    """Greedy forward selection of candidates by leave-one-subject-out over ``select``."""
    chosen = []
    best = score(*held_out(x, y, subject, columns_of(FEATURE_NAMES), select, select))[0]
    print(f'  selection on subjects {select}: the 16 features {best:.4f}')
    while len(chosen) < len(CANDIDATES):
        trial = {}
        for name in CANDIDATES:
            if name not in chosen:
                names = FEATURE_NAMES + tuple(chosen) + (name,)
                trial[name] = score(*held_out(x, y, subject, columns_of(names), select,
                                              select))[0]
        name = max(trial, key=trial.get)
        print('    + ' + ', '.join(f'{k} {v:.4f}' for k, v in sorted(
            trial.items(), key=lambda kv: -kv[1])), flush=True)
        if trial[name] < best + MIN_GAIN:
            break
        chosen.append(name)
        best = trial[name]
        print(f'  chosen {chosen}: {best:.4f}', flush=True)
    return chosen


def best_swap(x, y, subject, select, swaps) -> tuple:
    """ANFIS: the swapped input set best by leave-one-subject-out over ``select``, if any."""
    best = score(*held_out(x, y, subject, columns_of(PATENT_FEATURE_NAMES), select, select, 0,
                           'anfis'))[0]
    print(f'  selection on subjects {select}: the 5 features {best:.4f}')
    trial = {name: score(*held_out(x, y, subject, columns_of(names), select, select, 0,
                                   'anfis'))[0] for name, names in swaps.items()}
    ranked = sorted(trial, key=trial.get, reverse=True)
    print('    ' + ', '.join(f'{k} {trial[k]:.4f}' for k in ranked), flush=True)
    name = ranked[0]
    return swaps[name] if trial[name] >= best + MIN_GAIN else PATENT_FEATURE_NAMES


def main(argv=None) -> int:
    """Print the comparison."""
    parser = argparse.ArgumentParser(description=__doc__.strip().split('\n\n')[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--hugadb', type=Path, default=None,
                        help='HuGaDB folder (default: hugadb of the shared data)')
    parser.add_argument('--cache', type=Path, default=None,
                        help='cycle cache (default: landing-<code digest>.npz in '
                        "train's cache folder)")
    parser.add_argument('--select-subjects', default='1,2,3,6')
    parser.add_argument('--check-subjects', default='7,8,9')
    parser.add_argument('--sets', default='',
                        help='extra feature sets (names, "," within a set) to score, ";" '
                        'between sets')
    parser.add_argument('--seeds', type=int, default=1, help='forest seeds per set')
    parser.add_argument('--backend', choices=('forest', 'anfis'), default='forest',
                        help='anfis: the patent five, each candidate in place of max pitch')
    args = parser.parse_args(argv)
    folder = args.hugadb or shared_data_dir() / 'hugadb'
    started = time.monotonic()
    code = hashlib.sha256((pipeline_fingerprint() + Path(__file__).read_text()).encode())
    cache = args.cache or default_cache_dir() / f'landing-{code.hexdigest()[:16]}.npz'
    cache.parent.mkdir(parents=True, exist_ok=True)
    sets = hugadb_sets(folder, cache)
    x = np.vstack([s[2] for s in sets])
    y = np.concatenate([s[3] for s in sets])
    subject = np.concatenate([np.full(len(s[3]), s[1]) for s in sets])
    select = [int(s) for s in args.select_subjects.split(',')]
    check = [int(s) for s in args.check_subjects.split(',')]
    every = select + check
    print(f'HuGaDB: {len(y)} cycles of subjects {every} ({time.monotonic() - started:.0f} s)')
    for name in CANDIDATES:
        column = x[:, columns_of([name])[0]]
        print(f'  {name:24s} median down / level / up ' + ' / '.join(
            f'{np.median(column[y == m]):+.3f}' for m in (-1, 0, 1)))
    forest = args.backend == 'forest'
    if forest:
        chosen = FEATURE_NAMES + tuple(forward_selection(x, y, subject, select))
        main_sets = {'the 16 (today)': FEATURE_NAMES, 'the 16 + chosen': chosen,
                     'the 16 + all candidates': FEATURE_NAMES + CANDIDATES}
        singles = {f'the 16 + {name}': FEATURE_NAMES + (name,) for name in CANDIDATES}
    else:
        # An input more triples the rules (3^6 rules of 7 consequents > the cycles): swap one.
        singles = {f'the 5, {name} for max pitch': PATENT_FEATURE_NAMES[:4] + (name,)
                   for name in CANDIDATES}
        chosen = best_swap(x, y, subject, select, singles)
        main_sets = {'the 5 (today)': PATENT_FEATURE_NAMES, 'the 5 with the chosen swap': chosen}
    for text in filter(None, args.sets.split(';')):
        main_sets[text] = tuple(text.split(','))
    seeds = range(args.seeds) if forest else [0]
    print(f'\n{f"forest seeds {list(seeds)}" if forest else "ANFIS, sigma_th 0.5"}: mean '
          'accuracy (range), recall down/level/up and confusion (rows true -1/0/+1) over the '
          'seeds')
    for title, train_subjects, test_subjects, rows in (
            (f'held out: subjects {check}, trained on the six others', every, check,
             {**main_sets, **singles}),
            (f'leave-one-subject-out over {every} (saw the choice)', every, every, main_sets)):
        print(title)
        for name, names in rows.items():
            runs = [held_out(x, y, subject, columns_of(names), train_subjects, test_subjects,
                             seed, args.backend) for seed in seeds]
            print(describe(f'  {name}', runs), flush=True)
    print(f'({time.monotonic() - started:.0f} s)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
