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
``train`` subcommand: the stair classifier from labelled gait cycles, cross-validated.

``--backend anfis`` (default) fits the patent's ANFIS on eq. (8)-(12); ``--backend forest``
grows seed 001's random forest on the motion features (``tools/train_forest.py``, needs
scikit-learn). Both go through the same labels, folds, sigma_th choice and model metadata, and
``core/classifier.py`` loads either by the model file's ``format``.

Every recording -- simulated runs (``--sim-seeds``), HuGaDB (``--hugadb DIR``), bags with a label
CSV (``--bag BAG LABELS.csv``) -- goes through ``FootNavigator``, the pipeline the IMU node runs
(``training_recordings.py``), and each valid gait cycle it closes gets a label (eq. 13 mode: +1
up, 0 level, -1 down; the rules are in ``training_data.py``). Then cross-validation
(``cross_validation.py``) chooses the setting -- the ANFIS's threshold sigma_th of eq. 13 on a
grid, the forest's share of features tried at a split (``--max-features``) among its candidates
-- and the final model trained on everything with it is saved as JSON with ``metadata`` holding
``mode_threshold`` (sigma_th), the command, the data counts and the CV results.

The default model ``config/forest_default.json`` is made, from the project root, by
:data:`DEFAULT_COMMAND`; the ANFIS alternative ``config/anfis_default.json`` by
:data:`ANFIS_COMMAND`. Runs are deterministic: the simulated runs, the fold assignment and the
training depend only on the arguments. Navigator outputs are cached per recording under
``--cache-dir``, keyed so that a changed navigator is never served stale features
(``training_recordings.py``).

References
----------
[1] Patent CN111649742A, steps S4 (gait features, eq. 8-12) and S7 (ANFIS, eq. 13).
[2] Chereshnev, Kertesz-Farkas, "HuGaDB: Human Gait Database for Activity Recognition from
    Wearable Inertial Sensor Networks", AIST 2017.

"""

import argparse
from dataclasses import asdict
import hashlib
from pathlib import Path
import shlex

import numpy as np

from . import labels as lab
from .cross_validation import assign_folds, candidate_options, choose_setting, cross_validate
from .cross_validation import cv_report, DEFAULT_EPOCHS, DEFAULT_RANGE_QUANTILE
from .cross_validation import DEFAULT_TRAIN_RIDGE, describe, fit_model, nested_cv, stack
from .cross_validation import THRESHOLD_GRID, TrainOptions
from .train_forest import ForestOptions
from .training_data import collect, DEFAULT_MATCH_TOLERANCE_S, DEFAULT_MIN_MAJORITY
from .training_data import DEFAULT_MIN_STRIDE_S, hugadb_specs, LabelRules, Progress, SOURCES
from .training_recordings import BagSpec, default_cache_dir, DEFAULT_SIM_DURATION_S, HugadbSpec
from .training_recordings import pipeline_fingerprint, pipeline_from_yaml, sim_spec, SimSpec
from ..core.classifier import BACKENDS
from ..core.errors import InputError

PROG = 'python -m anfis_elevation_ros train'
DEFAULT_COMMAND = (f'{PROG} --sim-seeds 1-40 --hugadb ../shared/data/hugadb --backend forest '
                   '--seed 0 --out config/forest_default.json')
"""The command, run from the project root, that produces ``config/forest_default.json``."""
ANFIS_COMMAND = (f'{PROG} --sim-seeds 1-40 --hugadb ../shared/data/hugadb --seed 0 '
                 '--out config/anfis_default.json')
"""The command that produces ``config/anfis_default.json``, the ANFIS alternative."""
FOREST_THRESHOLD_GRID = (0.0,)
"""sigma_th of a forest: 0, seed 001's majority vote (``core/forest.py``, majority_vote_output).
Chosen for accuracy on a grid, sigma_th gave up recall of stairs up on HuGaDB's new wearers
(``bench_hugadb_errors.py --parts decision``)."""
MAX_FEATURES_CANDIDATES = (0.125, 0.25, 0.5)
"""The forest's shares of the features tried at a split that ``train`` chooses among (2, 4 and 8
of the 16), by cross-validation; a single ``--max-features`` value is used as given. Not one
feature a split (1/16): within 0.001 of 1/8 on HuGaDB's new wearers, but its trees called clear
stair strides of sensors it never saw level (x-io's real stairs, dh +0.20 and +0.43 m;
doc/classifier_notebook.md, "One feature a split is no longer a candidate")."""


def parse_int_list(text: str) -> list:
    """
    Parse '1-40' or '1,3,5-7' into a sorted list of distinct non-negative integers.

    A '-' always separates a range, so no negative number parses.
    """
    values = set()
    try:
        for part in text.split(','):
            part = part.strip()
            if '-' in part:
                first, last = (int(v) for v in part.split('-', 1))
                if last < first:
                    raise ValueError
                values.update(range(first, last + 1))
            else:
                values.add(int(part))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f'{text!r} is not a list of integers and ranges such as 1-40 or 1,3,5-7') from None
    return sorted(values)


def parse_share_list(text: str) -> list:
    """Parse '0.125' or '0.0625,0.125' into shares in (0, 1], in the order given."""
    try:
        shares = [float(part) for part in text.split(',')]
    except ValueError:
        raise argparse.ArgumentTypeError(f'{text!r} is not a comma-separated list of numbers') \
            from None
    if not all(0.0 < share <= 1.0 for share in shares):
        raise argparse.ArgumentTypeError(f'{text!r}: every share must be in (0, 1]')
    return shares


def add_parser(subparsers):
    """Register the ``train`` subcommand."""
    parser = subparsers.add_parser(
        'train', help='train the stair classifier (ANFIS or forest) from labelled cycles, '
        'cross-validated',
        description=__doc__.strip().split('\n\n')[0] + f' Default model: {DEFAULT_COMMAND}',
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    data = parser.add_argument_group('data')
    data.add_argument('--sim-seeds', type=parse_int_list, default=[],
                      help='simulated runs to generate, e.g. 1-40 (see sim_spec in '
                      'training_recordings.py)')
    data.add_argument('--sim-duration-s', type=float, default=DEFAULT_SIM_DURATION_S,
                      help='length of each simulated run')
    data.add_argument('--hugadb', type=Path, default=None,
                      help='HuGaDB folder (with file_index.csv), e.g. ../shared/data/hugadb')
    data.add_argument('--hugadb-subjects', type=parse_int_list, default=None,
                      help='HuGaDB subjects to use, e.g. 1-9 (default: all)')
    data.add_argument('--hugadb-files', default='*',
                      help='fnmatch pattern selecting HuGaDB files')
    data.add_argument('--hugadb-clipped-gyro', action='store_true',
                      help='also use the HuGaDB feet whose gyro is a +-250 deg/s one that clips '
                      'in every swing (the only feet of subjects 4 and 5)')
    data.add_argument('--bag', nargs=2, action='append', default=[], metavar=('BAG', 'LABELS'),
                      help='a bag and its stamp_ns,label CSV (repeatable)')
    data.add_argument('--bag-labels', choices=('sample', 'cycle'), default='sample',
                      help='the CSVs label samples (or segments from their stamp on) or cycles '
                      '(closing stamps)')
    data.add_argument('--topic', default=None, help='Imu topic of the bags (default: the only '
                      'one)')
    rules = parser.add_argument_group('labels')
    rules.add_argument('--match-tolerance-s', type=float, default=DEFAULT_MATCH_TOLERANCE_S,
                       help='largest |cycle end - stride end| for a stride or cycle label')
    rules.add_argument('--min-majority', type=float, default=DEFAULT_MIN_MAJORITY,
                       help="share of a cycle's samples its per-sample label needs")
    rules.add_argument('--min-stride-s', type=float, default=DEFAULT_MIN_STRIDE_S,
                       help='shorter swings are no stride and are labelled level (0: off)')
    fit = parser.add_argument_group('training')
    fit.add_argument('--backend', choices=sorted(BACKENDS), default='anfis',
                     help="stair classifier: the patent's ANFIS or seed 001's random forest "
                     '(needs scikit-learn to train)')
    fit.add_argument('--trees', type=int, default=ForestOptions.n_trees,
                     help='forest: number of trees')
    fit.add_argument('--max-features', type=parse_share_list,
                     default=list(MAX_FEATURES_CANDIDATES),
                     help='forest: share of the features tried at each split; several '
                     '(comma-separated) are chosen among by cross-validation')
    fit.add_argument('--min-samples-leaf', type=int, default=ForestOptions.min_samples_leaf,
                     help='forest: fewest training cycles at a leaf')
    fit.add_argument('--class-weight', choices=('balanced', 'none'),
                     default=ForestOptions.class_weight,
                     help='forest: weight each mode by the inverse of its share, or not')
    fit.add_argument('--cv', choices=('subject', 'recording', 'none'), default='subject',
                     help='cross-validation: leave one subject out, one recording out, or none')
    fit.add_argument('--folds', type=int, default=0,
                     help='merge the CV groups into at most this many folds (0: no limit)')
    fit.add_argument('--epochs', type=int, default=DEFAULT_EPOCHS, help='hybrid-learning epochs')
    fit.add_argument('--ridge', type=float, default=DEFAULT_TRAIN_RIDGE,
                     help='least-squares ridge factor of the ANFIS consequents')
    fit.add_argument('--range-quantile', type=float, default=DEFAULT_RANGE_QUANTILE,
                     help='input universe = [q, 1-q] quantiles of the training features')
    fit.add_argument('--threshold', type=float, default=None,
                     help='fixed sigma_th of eq. 13 instead of the CV-best grid value (ANFIS) '
                     'or 0, the majority vote (forest)')
    fit.add_argument('--seed', type=int, default=0, help='seed of the CV fold assignment')
    fit.add_argument('--params', type=Path, default=None,
                     help='ROS 2 parameter YAML of the nodes (config/params.yaml): its imu_node '
                     'navigator and gate parameters make the features (default: the defaults)')
    run = parser.add_argument_group('run')
    run.add_argument('--out', type=Path, required=True, help='model JSON to write')
    run.add_argument('--cache-dir', type=Path, default=default_cache_dir(),
                     help='navigator-feature cache')
    run.add_argument('--no-cache', action='store_true', help='do not read or write the cache')
    run.add_argument('--jobs', type=int, default=1, help='worker processes for the navigator')
    run.add_argument('--quiet', action='store_true', help='no progress on stderr')
    defaults = vars(parser.parse_args(['--out', '-']))     # every option's default, in order
    defaults['out'] = None
    parser.set_defaults(handler=run_train, train_defaults=defaults)
    return parser


def _specs_from_args(args) -> list:
    specs = [sim_spec(seed, args.sim_duration_s) for seed in args.sim_seeds]
    if args.hugadb is not None:
        subjects = None if args.hugadb_subjects is None else set(args.hugadb_subjects)
        specs += hugadb_specs(args.hugadb, subjects, args.hugadb_files, args.hugadb_clipped_gyro)
    for bag, labels_csv in args.bag:
        for path in (bag, labels_csv):
            if not Path(path).exists():
                raise InputError(f'{path} does not exist')
        specs.append(BagSpec(str(bag), str(labels_csv), args.bag_labels, args.topic))
    if not specs:
        raise InputError('no training data: give --sim-seeds, --hugadb and/or --bag')
    return specs


def _counts(sets) -> dict:
    counts = {}
    for name in SOURCES:
        members = [s for s in sets if s.source == name]
        if members:
            total = {key: sum(s.counts[key] for s in members) for key in members[0].counts}
            labels = np.concatenate([s.labels for s in members])
            total['recordings'] = len(members)
            total['recordings_without_labelled_cycles'] = sum(len(s.labels) == 0
                                                              for s in members)
            total['by_mode'] = {str(m): int(np.sum(labels == m)) for m in lab.MODES}
            counts[name] = total
    return counts


def run_train(args) -> int:
    """Collect, label, cross-validate, choose sigma_th, train and save; return the exit code."""
    progress = Progress(args.quiet)
    if args.jobs < 1:
        raise InputError(f'--jobs {args.jobs} must be >= 1')
    if args.folds < 0:
        raise InputError(f'--folds {args.folds} must be >= 0')
    if args.threshold is not None and not 0.0 <= args.threshold <= 1.0:
        raise InputError(f'--threshold {args.threshold} is outside [0, 1]')
    rules = LabelRules(args.match_tolerance_s, args.min_majority, args.min_stride_s)
    options = TrainOptions(epochs=args.epochs, ridge=args.ridge,
                           range_quantile=args.range_quantile, backend=args.backend,
                           forest=ForestOptions(args.trees, ForestOptions.max_features,
                                                args.min_samples_leaf, args.class_weight,
                                                args.seed))
    candidates = candidate_options(options, args.max_features)
    if len(candidates) > 1 and args.cv == 'none':
        raise InputError('choosing among several --max-features needs cross-validation: give '
                         'one value with --cv none')
    pipeline = pipeline_from_yaml(args.params)
    specs = _specs_from_args(args)
    progress.log(f'{len(specs)} recordings: {len(args.sim_seeds)} simulated, '
                 f'{sum(isinstance(s, HugadbSpec) for s in specs)} HuGaDB feet, '
                 f'{len(args.bag)} bags')
    sets = collect(specs, pipeline, rules, None if args.no_cache else args.cache_dir, args.jobs,
                   progress)
    counts = _counts(sets)
    sets = [s for s in sets if len(s.labels)]
    if not sets:
        raise InputError('no labelled cycle in the data')
    features, labels, _ = stack(sets)
    for name, total in counts.items():
        progress.log(f'{name}: {total["used"]} cycles used of {total["cycles"]} '
                     f'(invalid {total["invalid"]}, unlabelled {total["unlabelled"]}, '
                     f'non-stride {total["non_stride"]}); by mode {total["by_mode"]}')
    if len(set(labels.tolist())) < 2:
        raise InputError('the labelled cycles hold a single mode; add stairs and level walking')

    cv = None
    grid = FOREST_THRESHOLD_GRID if options.backend == 'forest' else THRESHOLD_GRID
    if args.threshold is not None:
        grid = (args.threshold,)
    if args.cv != 'none':
        folds, fold_names = assign_folds(sets, args.cv, args.folds, args.seed)
        outputs = [cross_validate(sets, folds, candidate, progress) for candidate in candidates]
        chosen, threshold, accuracies = choose_setting(labels, outputs, grid)
        options = candidates[chosen]
        nested = nested_cv(sets, folds, candidates, outputs, progress, grid)
        cv = cv_report(sets, folds, fold_names, outputs[chosen], threshold, accuracies, nested,
                       candidates, grid)
        cv['scheme'] = args.cv
        cv['folds'] = len(fold_names)
        cv['candidates'] = [describe(candidate) for candidate in candidates]
        progress.log(f'chosen on every fold: {describe(options)}, sigma_th {threshold:g}')
    else:
        threshold = grid[0] if len(grid) == 1 else 0.5
    model = fit_model(features, labels, options)
    metadata = {
        'command': reproducing_command(args, args.train_defaults),
        'mode_threshold': threshold,
        'mode_threshold_source': 'cv_best' if cv and args.threshold is None else (
            'given' if args.threshold is not None else 'default'),
        'feature_names': list(model.feature_names),
        'targets': {'down': -1, 'level': 0, 'up': 1},
        'data': {
            'sim_seeds': args.sim_seeds,
            'sim': [asdict(s) for s in specs if isinstance(s, SimSpec)],
            'hugadb_recordings': [s.name for s in specs if isinstance(s, HugadbSpec)],
            'bags': [[s.bag, s.labels, s.kind] for s in specs if isinstance(s, BagSpec)],
            'counts': counts,
        },
        'labels': asdict(rules),
        'training': {**asdict(options), 'cycles': int(len(labels)),
                     'input_range_from': 'quantiles'},
        'pipeline_params': 'defaults' if args.params is None else str(args.params),
        'pipeline_params_sha256': hashlib.sha256(repr(pipeline).encode()).hexdigest(),
        'pipeline_code_sha256': pipeline_fingerprint(),
        'sim_code_sha256': pipeline_fingerprint(sim_only=True),
        'cv': cv,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    model.save(args.out, metadata=metadata)
    progress.log(f'wrote {args.out}: {len(labels)} cycles, sigma_th {threshold:g}')
    _print_summary(metadata)
    return 0


RUN_OPTIONS = ('cache_dir', 'no_cache', 'jobs', 'quiet')
"""Arguments that do not change the model; the recorded command leaves them out."""


def format_int_list(values) -> str:
    """Inverse of :func:`parse_int_list`: [1, 2, 3, 7] -> '1-3,7'."""
    parts = []
    values = sorted(values)
    i = 0
    while i < len(values):
        j = i
        while j + 1 < len(values) and values[j + 1] == values[j] + 1:
            j += 1
        parts.append(str(values[i]) if i == j else f'{values[i]}-{values[j]}')
        i = j + 1
    return ','.join(parts)


def reproducing_command(args, parser_defaults: dict) -> str:
    """
    Return the command that reproduces a run's model: options that differ from defaults.

    Options are listed in the order of the parser, ``--seed`` and ``--out`` always; lists of
    integers in range form (1-40); run options that do not change the model (``--jobs``,
    ``--cache-dir``, ``--no-cache``, ``--quiet``) are left out.
    """
    words = []
    for dest, default in parser_defaults.items():
        value = getattr(args, dest)
        if dest in RUN_OPTIONS or (value == default and dest not in ('seed', 'out')):
            continue
        option = '--' + dest.replace('_', '-')
        if dest == 'bag':
            for bag, labels_csv in value:
                words += [option, str(bag), str(labels_csv)]
        elif isinstance(value, bool):
            words.append(option)
        elif dest == 'max_features':
            words += [option, ','.join(f'{share:g}' for share in value)]
        elif isinstance(value, list):
            words += [option, format_int_list(value)]
        else:
            words += [option, str(value)]
    return f'{PROG} {shlex.join(words)}'


def _print_summary(metadata: dict):
    cv = metadata['cv']
    print(f'model: sigma_th = {metadata["mode_threshold"]:g} '
          f'({metadata["mode_threshold_source"]}), {metadata["training"]["cycles"]} cycles')
    if cv is None:
        return
    print(f'cross-validation ({cv["scheme"]}, {cv["folds"]} folds): accuracy '
          f'{cv["all"]["accuracy"]:.4f} on {cv["all"]["cycles"]} cycles; strides only '
          f'{cv["strides_only"]["accuracy"]}')
    for name, result in cv['by_source'].items():
        print(f'  {name}: accuracy {result["accuracy"]:.4f} on {result["cycles"]} cycles '
              f'(strides only {result["strides_only_accuracy"]}); confusion (rows true -1/0/+1, '
              f'columns predicted): {result["confusion"]}')
    for name, result in cv['by_subject'].items():
        print(f'  {name}: accuracy {result["accuracy"]:.4f} on {result["cycles"]} cycles')
    nested = cv.get('nested')
    if nested:
        by_source = ', '.join(f'{name} {result["accuracy"]:.4f}'
                              for name, result in nested['by_source'].items())
        chosen = ', '.join(f'{setting} sigma_th {t:g}'
                           for setting, t in zip(nested['settings'], nested['thresholds']))
        print(f'chosen inside the training folds (nested; per fold: {chosen}): accuracy '
              f'{nested["all"]["accuracy"]:.4f}; {by_source}')
        for name, accuracy in nested['by_subject'].items():
            print(f'  {name}: {accuracy:.4f}')


__all__ = ['DEFAULT_COMMAND']
