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
Training and cross-validation of the stair classifier on labelled cycle sets.

The cross-validation (``--cv subject``: one fold per real subject -- HuGaDB subject or bag -- with
the simulated runs spread over the folds; ``--cv recording``: one fold per recording), the choice
of the setting that maximises the pooled out-of-fold accuracy -- the ANFIS's threshold sigma_th of
eq. 13 on a grid, the forest's share of features tried at a split (``--max-features``) among its
candidates -- and the final model, trained on everything with it (:func:`fit_model`). The pooled
accuracy at that setting has seen the test folds once (the setting was picked on them); the honest
figure is ``cv['nested']``: each fold scored with the setting an inner cross-validation over the
other folds picks (:func:`nested_cv`). The fold assignment and the training depend only on their
arguments.

References
----------
[1] Patent CN111649742A, steps S4 (gait features, eq. 8-12) and S7 (ANFIS, eq. 13).

"""

from dataclasses import dataclass, replace
import math

import numpy as np

from . import labels as lab
from .metrics import confusion_matrix
from .train_forest import fit_forest, ForestOptions
from .training_data import Progress, SOURCES
from ..core.anfis import Anfis
from ..core.classifier import AnfisClassifier, BACKENDS
from ..core.errors import InputError
from ..core.gait import feature_index, N_FEATURES, PATENT_FEATURE_NAMES
from ..core.height import stair_mode
from ..core.validation import check_range

DEFAULT_EPOCHS = 3
DEFAULT_TRAIN_RIDGE = 1e-3
DEFAULT_RANGE_QUANTILE = 0.005
THRESHOLD_GRID = tuple(round(0.05 * k, 2) for k in range(1, 20))
"""Candidate sigma_th of eq. 13 for the ANFIS (0.05 ... 0.95): ElevationParams accepts [0, 1]."""


@dataclass(frozen=True)
class TrainOptions:
    """
    Classifier training settings: the backend, the ANFIS settings, the forest's.

    Notes
    -----
    Chosen by leave-one-subject-out CV on seeds 1-40 + HuGaDB (navigator of 2026-11-22):
    HuGaDB accuracy 0.924 (1 epoch, ridge 1e-2), 0.926 (1 or 3 epochs, ridge 1e-3), 0.924
    (5 epochs, ridge 1e-4), 0.926 (15 epochs, ridge 1e-4), 0.917 (ridge 1e-1); simulated runs
    1.000 throughout. More epochs lower the training error but not the out-of-fold one. The
    universe from the 0.5 %/99.5 % quantiles gave 0.924 against 0.915 from the full range and
    0.921 from 2 %/98 %; generalised bells 0.922, 2 membership functions per input 0.916.

    Re-measured with sigma_th chosen inside the training folds (2026-11, same data): 0.926 with
    these defaults (``nested_threshold_cv``). With an inner leave-one-subject-out over the other
    HuGaDB subjects only (defaults 0.927) nothing moved it by more than the 0.3 % a dozen
    cycles make (4288 cycles): 1 or 10 epochs 0.927/0.926, ridge 1e-2 0.924,
    range quantile 0.02 0.925, class-balanced training 0.923, half or a quarter of the
    simulated cycles 0.924/0.925, none 0.917, middle membership functions started at the
    median or 30 % quantile 0.925/0.928 (``test/benchmarks/bench_hugadb_errors.py`` shows
    why: the HuGaDB features themselves overlap).

    """

    n_mfs: int = 3
    mf: str = 'triangle'
    epochs: int = DEFAULT_EPOCHS
    ridge: float = DEFAULT_TRAIN_RIDGE
    range_quantile: float = DEFAULT_RANGE_QUANTILE
    backend: str = 'anfis'
    forest: ForestOptions = ForestOptions()

    def __post_init__(self):
        if self.backend not in BACKENDS:
            raise InputError(f'backend {self.backend!r} is not one of {sorted(BACKENDS)}')
        check_range('epochs', self.epochs, 1, 1000)
        check_range('range_quantile', self.range_quantile, 0.0, 0.5, open_high=True)
        check_range('ridge', self.ridge, 0.0, math.inf)


def input_universe(features: np.ndarray, quantile: float) -> np.ndarray:
    """
    Universe (lo, hi) of each input: the [q, 1 - q] quantiles of the training features.

    A few wild cycles (a swing the navigator got badly wrong) would otherwise stretch the grid
    partition so that all ordinary cycles fall under one membership function; inputs beyond
    the universe are clipped into it (see ``core/anfis.py``).

    Parameters
    ----------
    features : (N, n) array
        Training features.
    quantile : float in [0, 0.5)
        q; 0 gives the full range.

    Returns
    -------
    (n, 2) array.

    """
    lo = np.quantile(features, quantile, axis=0, method='linear')
    hi = np.quantile(features, 1.0 - quantile, axis=0, method='linear')
    flat = ~(hi > lo)
    if np.any(flat):
        names = [PATENT_FEATURE_NAMES[i] for i in np.flatnonzero(flat)]
        raise InputError(f'features {names} do not vary in the training data; add recordings')
    return np.stack((lo, hi), axis=1)


def fit_model(features: np.ndarray, labels: np.ndarray, options: TrainOptions):
    """
    Fit the stair classifier of ``options.backend`` on labelled cycles (modes -1 / 0 / +1).

    ANFIS: on eq. (8)-(12), targets the modes; forest: :func:`.train_forest.fit_forest`.
    ``features`` are whole cycle feature vectors, (N, N_FEATURES); returns an AnfisClassifier
    or a Forest.
    """
    if options.backend == 'forest':
        return fit_forest(features, labels, options.forest)
    x = features[:, feature_index(PATENT_FEATURE_NAMES)]
    model = Anfis(len(PATENT_FEATURE_NAMES), options.n_mfs, options.mf)
    model.fit(x, labels.astype(float), epochs=options.epochs, ridge=options.ridge,
              input_range=input_universe(x, options.range_quantile))
    return AnfisClassifier(model, PATENT_FEATURE_NAMES)


def assign_folds(sets: list, scheme: str, max_folds: int = 0, seed: int = 0):
    """
    Cross-validation fold of every cycle set.

    ``subject``: one fold per real subject (HuGaDB subject, bag) with the simulated runs dealt
    over those folds; with fewer than two real subjects it is ``recording``. ``recording``: one
    fold per recording (both feet of a HuGaDB file together). Groups are dealt round-robin in a
    seeded random order; ``max_folds`` > 0 merges groups the same way into at most that many
    folds.

    Parameters
    ----------
    sets : list of CycleSet
        The data.
    scheme : {'subject', 'recording'}
        Cross-validation scheme.
    max_folds : int >= 0
        Upper bound of the number of folds (0: no bound).
    seed : int
        Seed of the dealing order.

    Returns
    -------
    folds : (len(sets),) int array
        Fold index of each set.
    names : list of str
        A name per fold (its real subject, or its groups joined by '+').

    """
    rng = np.random.default_rng([int(seed), 3])
    real = sorted({s.subject for s in sets if s.source != 'sim'})
    if scheme == 'subject' and len(real) >= 2:
        anchors = real
        key = {s.name: s.subject for s in sets if s.source != 'sim'}
        others = sorted({s.subject for s in sets if s.source == 'sim'})
    else:
        anchors = []
        key = {}
        others = sorted({s.recording for s in sets})
    others = [others[i] for i in rng.permutation(len(others))]
    n_folds = len(anchors) or len(others)
    if max_folds and max_folds < n_folds:
        n_folds = max_folds
    if n_folds < 2:
        raise InputError(f'cross-validation needs at least 2 groups of recordings, got '
                         f'{n_folds}; add recordings or use --cv none')
    members = [[] for _ in range(n_folds)]
    for i, group in enumerate(anchors + others):
        members[i % n_folds].append(group)
    fold_of = {group: i for i, groups in enumerate(members) for group in groups}
    folds = np.array([fold_of[key.get(s.name, s.subject if anchors else s.recording)]
                      for s in sets], dtype=np.int64)
    if anchors and n_folds == len(anchors):
        names = [groups[0] + (f' (+{len(groups) - 1} sim)' if len(groups) > 1 else '')
                 for groups in members]
    else:
        names = ['+'.join(groups[:3]) + (f'+{len(groups) - 3} more' if len(groups) > 3 else '')
                 for groups in members]
    return folds, names


def stack(sets: list):
    """Concatenate the cycles of several sets: features (N, N_FEATURES), labels, set index."""
    features = np.concatenate([s.features for s in sets]).reshape(-1, N_FEATURES)
    labels = np.concatenate([s.labels for s in sets]).astype(np.int64)
    owner = np.concatenate([np.full(len(s.labels), i, dtype=np.int64)
                            for i, s in enumerate(sets)])
    return features, labels, owner


def cross_validate(sets: list, folds: np.ndarray, options: TrainOptions,
                   progress: Progress = None) -> np.ndarray:
    """
    Out-of-fold model output of every cycle: each fold predicted by a model trained without it.

    Returns
    -------
    (N,) array in the order of :func:`stack`.

    """
    progress = progress or Progress(quiet=True)
    features, labels, owner = stack(sets)
    cycle_fold = folds[owner]
    output = np.empty(len(labels))
    n_folds = int(folds.max()) + 1
    for k in range(n_folds):
        test = cycle_fold == k
        model = fit_model(features[~test], labels[~test], options)
        output[test] = model.predict(features[test])
        progress.log(f'fold {k + 1}/{n_folds}: trained on {int(np.sum(~test))} cycles, '
                     f'accuracy {np.mean(stair_mode(output[test], 0.5) == labels[test]):.4f} '
                     f'on {int(np.sum(test))} (sigma_th 0.5)')
    return output


def choose_threshold(labels: np.ndarray, output: np.ndarray, grid=THRESHOLD_GRID):
    """
    sigma_th of eq. 13 with the highest accuracy; ties go to the value nearest 0.5.

    Parameters
    ----------
    labels : (N,) int array
        True modes.
    output : (N,) array
        ANFIS outputs (out-of-fold).
    grid : sequence of float
        Candidates in [0, 1].

    Returns
    -------
    threshold : float
    accuracies : list of float, accuracy at each grid value.

    """
    accuracies = [float(np.mean(stair_mode(output, t) == labels)) for t in grid]
    best = max(accuracies)
    threshold = min((t for t, a in zip(grid, accuracies) if a == best),
                    key=lambda t: (abs(t - 0.5), t))
    return float(threshold), accuracies


def choose_setting(labels: np.ndarray, outputs: list, grid=THRESHOLD_GRID):
    """
    Return the candidate and sigma_th of highest accuracy; ties go to the earlier candidate.

    ``outputs`` holds each candidate's outputs of the same cycles; sigma_th is chosen on each by
    :func:`choose_threshold`. Returns (candidate index, sigma_th, that candidate's accuracy at
    every grid value).
    """
    best = None
    for index, output in enumerate(outputs):
        threshold, accuracies = choose_threshold(labels, output, grid)
        if best is None or max(accuracies) > max(best[2]):
            best = (index, threshold, accuracies)
    return best


def nested_cv(sets: list, folds: np.ndarray, candidates: list, outputs: list,
              progress: Progress = None, grid=THRESHOLD_GRID):
    """
    Score each fold with a setting chosen without it: the honest cross-validated accuracy.

    For fold k, an inner cross-validation over the other folds (fold j != k predicted by a model
    trained on the folds other than j and k) gives each candidate's out-of-fold outputs of all
    training cycles; (candidate_k, sigma_th_k) = :func:`choose_setting` on them, and fold k's
    outer outputs of candidate_k (``outputs``, from :func:`cross_validate`) are thresholded at
    sigma_th_k. K folds cost K (K - 1) more fits per candidate; none when there is nothing to
    choose (one candidate, one sigma_th).

    Parameters
    ----------
    sets : list of CycleSet
        The data.
    folds : (len(sets),) int array
        Fold of each set (:func:`assign_folds`).
    candidates : list of TrainOptions
        The training settings to choose among (the ANFIS: one).
    outputs : list of (N,) arrays
        Out-of-fold outputs of each candidate's outer models, :func:`stack` order.
    progress : Progress or None
        Progress reporter.
    grid : sequence of float
        sigma_th candidates.

    Returns
    -------
    choices : (K,) int array, candidate_k of each fold (None when K < 3: no inner folds to train).
    thresholds : (K,) array, sigma_th_k of each fold (None too).
    predicted : (N,) int array, modes of the cycles, each fold at its own setting (None too).

    """
    progress = progress or Progress(quiet=True)
    features, labels, owner = stack(sets)
    cycle_fold = folds[owner]
    n_folds = int(folds.max()) + 1
    if n_folds < 3:
        return None, None, None
    if len(candidates) == 1 and len(grid) == 1:     # nothing to choose: no inner fits
        return (np.zeros(n_folds, dtype=np.int64), np.full(n_folds, float(grid[0])),
                stair_mode(outputs[0], float(grid[0])))
    choices = np.empty(n_folds, dtype=np.int64)
    thresholds = np.empty(n_folds)
    predicted = np.empty(len(labels), dtype=np.int64)
    for k in range(n_folds):
        known = cycle_fold != k
        inner = [np.full(len(labels), np.nan) for _ in candidates]
        for j in range(n_folds):
            if j == k:
                continue
            train_mask = known & (cycle_fold != j)
            for options, output in zip(candidates, inner):
                model = fit_model(features[train_mask], labels[train_mask], options)
                output[cycle_fold == j] = model.predict(features[cycle_fold == j])
        choices[k], thresholds[k], _ = choose_setting(
            labels[known], [output[known] for output in inner], grid)
        test = ~known
        predicted[test] = stair_mode(outputs[choices[k]][test], thresholds[k])
        progress.log(f'nested choice, fold {k + 1}/{n_folds}: {describe(candidates[choices[k]])}'
                     f' sigma_th {thresholds[k]:g}, accuracy '
                     f'{np.mean(predicted[test] == labels[test]):.4f} on {int(np.sum(test))}')
    return choices, thresholds, predicted


def candidate_options(options: TrainOptions, max_features) -> list:
    """Return the settings to choose among: one forest per ``max_features`` share; an ANFIS."""
    if options.backend != 'forest':
        return [options]
    return [replace(options, forest=replace(options.forest, max_features=float(share)))
            for share in max_features]


def describe(options: TrainOptions) -> str:
    """Name a candidate of :func:`candidate_options`: 'max_features 0.125' or 'anfis'."""
    if options.backend == 'forest':
        return f'max_features {options.forest.max_features:g}'
    return options.backend


def summarise(labels: np.ndarray, predicted: np.ndarray) -> dict:
    """Accuracy, cycle count and confusion matrix (rows true -1, 0, +1; columns predicted)."""
    if len(labels) == 0:
        return {'cycles': 0, 'accuracy': None, 'confusion': None}
    return {'cycles': int(len(labels)),
            'accuracy': round(float(np.mean(labels == predicted)), 6),
            'confusion': confusion_matrix(labels, predicted, lab.MODES).tolist()}


def cv_report(sets, folds, fold_names, output, threshold, accuracies,
              nested=(None, None, None), candidates=(), grid=THRESHOLD_GRID) -> dict:
    """
    Cross-validation results: pooled, per source, per fold, per subject, non-stride cycles.

    ``nested`` is the (choices, thresholds, predicted) of :func:`nested_cv` and ``candidates``
    its settings; when given, ``report['nested']`` holds the per-fold setting and sigma_th and
    the accuracies (all, by source, by subject).
    """
    _, labels, owner = stack(sets)
    predicted = stair_mode(output, threshold)
    non_stride = np.concatenate([s.non_stride for s in sets])
    source = np.array([sets[i].source for i in owner])
    subject = np.array([sets[i].subject for i in owner])
    cycle_fold = folds[owner]
    report = {'threshold_grid': list(grid),
              'grid_accuracy': [round(a, 6) for a in accuracies],
              'all': summarise(labels, predicted),
              'strides_only': summarise(labels[~non_stride], predicted[~non_stride]),
              'non_stride': summarise(labels[non_stride], predicted[non_stride]),
              'by_source': {}, 'by_fold': {}, 'by_subject': {}}
    for name in SOURCES:
        mask = source == name
        if np.any(mask):
            report['by_source'][name] = summarise(labels[mask], predicted[mask])
            strides = mask & ~non_stride
            report['by_source'][name]['strides_only_accuracy'] = summarise(
                labels[strides], predicted[strides])['accuracy']
    for k, name in enumerate(fold_names):
        mask = cycle_fold == k
        report['by_fold'][name] = summarise(labels[mask], predicted[mask])['accuracy']
    for name in sorted(set(subject.tolist())):
        if not name.startswith('sim/'):
            mask = subject == name
            report['by_subject'][name] = summarise(labels[mask], predicted[mask])
    choices, thresholds, nested_predicted = nested
    if thresholds is not None:
        report['nested'] = {
            'settings': [describe(candidates[c]) for c in choices],
            'thresholds': [float(t) for t in thresholds],
            'all': summarise(labels, nested_predicted),
            'by_source': {name: summarise(labels[source == name], nested_predicted[source == name])
                          for name in SOURCES if np.any(source == name)},
            'by_subject': {name: summarise(labels[subject == name],
                                           nested_predicted[subject == name])['accuracy']
                           for name in sorted(set(subject.tolist()))
                           if not name.startswith('sim/')}}
    return report


__all__ = ['TrainOptions', 'assign_folds', 'candidate_options', 'choose_setting',
           'choose_threshold', 'cross_validate', 'cv_report', 'fit_model', 'input_universe',
           'nested_cv', 'stack']
