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

Every recording goes through ``FootNavigator`` -- the pipeline the IMU node runs -- and each
valid gait cycle it closes gets a label (eq. 13 mode: +1 up, 0 level, -1 down):

- simulated runs (``--sim-seeds``): generated in-process, one per seed, with the IMU preset,
  rate, mounting and walk drawn from the seed (:func:`sim_spec`); a cycle takes the mode of
  the true stride whose end stamp is nearest its closing stamp, within ``--match-tolerance-s``.
- HuGaDB (``--hugadb DIR``): the human-labelled walks, feet whose gyro does not clip
  (``file_index.csv``; with ``--hugadb-clipped-gyro`` also the feet whose gyro is a +-250 deg/s
  one that clips in every swing -- the only feet of subjects 4 and 5); a cycle takes the
  activity most of its samples have (walking -> 0, going up -> +1, going down -> -1) if at
  least ``--min-majority`` of them have it.
- bags (``--bag BAG LABELS.csv``): a ``stamp_ns,label`` CSV per bag, labelling samples (or
  segments from their first stamp on) with ``--bag-labels sample`` or cycles (closing stamps,
  matched like the simulator's strides) with ``--bag-labels cycle``.

Cycles the navigator marks invalid are not used; cycles without a label are left out (both are
counted). With per-sample labels (HuGaDB, ``--bag-labels sample``) a cycle whose swing is shorter
than ``--min-stride-s`` is the detector flickering while the foot rests on a step, not a stride
(on HuGaDB its features are all within a few mm of 0): it is labelled level whatever the activity
around it, so that the model learns that a foot that did not move climbed no step. Simulator
truth and per-cycle labels say what each cycle is, so the rule does not apply to them.

Then: cross-validation (``--cv subject``: one fold per real subject -- HuGaDB subject or bag --
with the simulated runs spread over the folds; ``--cv recording``: one fold per recording), the
setting that maximises the pooled out-of-fold accuracy -- the ANFIS's threshold sigma_th of eq.
13 on a grid, the forest's share of features tried at a split (``--max-features``) among its
candidates -- and the final model trained on everything with it, saved as JSON with
``metadata`` holding ``mode_threshold`` (sigma_th), the command, the data counts and the CV
results. The pooled accuracy at that setting has seen the test folds once (the setting was
picked on them); the honest figure is ``cv['nested']``: each fold scored with the setting an
inner cross-validation over the other folds picks (:func:`nested_cv`).

The default model ``config/forest_default.json`` is made, from the project root, by
:data:`DEFAULT_COMMAND`; the ANFIS alternative ``config/anfis_default.json`` by
:data:`ANFIS_COMMAND`. Runs are deterministic: the simulated runs, the fold assignment and the
training depend only on the arguments. Navigator outputs are cached per recording (``.npz``,
no pickle) under ``--cache-dir``, keyed by the recording's content, the navigator parameters and
the source code of the navigator pipeline, so a changed navigator is never served stale features.

References
----------
[1] Patent CN111649742A, steps S4 (gait features, eq. 8-12) and S7 (ANFIS, eq. 13).
[2] Chereshnev, Kertesz-Farkas, "HuGaDB: Human Gait Database for Activity Recognition from
    Wearable Inertial Sensor Networks", AIST 2017.

"""

import argparse
import ast
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, field, replace
import fnmatch
import functools
import hashlib
import io
import json
import math
import os
from pathlib import Path
import shlex
import sys
import tempfile
import time
import tokenize

import numpy as np

from . import labels as lab
from .metrics import confusion_matrix
from .replay import navigated_samples
from .train_forest import fit_forest, ForestOptions
from .. import sim
from ..core.anfis import Anfis
from ..core.classifier import AnfisClassifier, BACKENDS
from ..core.errors import InputError
from ..core.gait import feature_index, N_FEATURES, PATENT_FEATURE_NAMES
from ..core.height import stair_mode
from ..core.input_gate import GateParams, InputGate
from ..core.navigator import FootNavigator, NavigatorParams
from ..core.validation import check_range

PROG = 'python -m anfis_elevation_ros train'
DEFAULT_COMMAND = (f'{PROG} --sim-seeds 1-40 --hugadb ../shared/data/hugadb --backend forest '
                   '--seed 0 --out config/forest_default.json')
"""The command, run from the project root, that produces ``config/forest_default.json``."""
ANFIS_COMMAND = (f'{PROG} --sim-seeds 1-40 --hugadb ../shared/data/hugadb --seed 0 '
                 '--out config/anfis_default.json')
"""The command that produces ``config/anfis_default.json``, the ANFIS alternative."""

SIM_IMU_PRESETS = ('ideal', 'tactical', 'consumer')
SIM_RATE_RANGE_HZ = (100, 400)
SIM_STEP_HEIGHT_RANGE_M = (0.14, 0.19)
SIM_PLAN_STREAM, SIM_SPEC_STREAM = 1, 2   # second words of the seed sequences (see sim_spec)
DEFAULT_SIM_DURATION_S = 150.0
DEFAULT_MATCH_TOLERANCE_S = 0.1
DEFAULT_MIN_MAJORITY = 0.7
DEFAULT_MIN_STRIDE_S = 0.3
DEFAULT_EPOCHS = 3
DEFAULT_TRAIN_RIDGE = 1e-3
DEFAULT_RANGE_QUANTILE = 0.005
THRESHOLD_GRID = tuple(round(0.05 * k, 2) for k in range(1, 20))
"""Candidate sigma_th of eq. 13 for the ANFIS (0.05 ... 0.95): ElevationParams accepts [0, 1]."""
FOREST_THRESHOLD_GRID = (0.0,)
"""sigma_th of a forest: 0, seed 001's majority vote (``core/forest.py``, majority_vote_output).
Chosen for accuracy on a grid, sigma_th gave up recall of stairs up on HuGaDB's new wearers
(``bench_hugadb_errors.py --parts decision``)."""
MAX_FEATURES_CANDIDATES = (0.125, 0.25, 0.5)
"""The forest's shares of the features tried at a split that ``train`` chooses among (2, 4 and 8
of the 16), by cross-validation; a single ``--max-features`` value is used as given. Not one
feature a split (1/16): within 0.001 of 1/8 on HuGaDB's new wearers, but its trees called clear
stair strides of sensors it never saw level (x-io's real stairs, dh +0.20 and +0.43 m; README)."""
CACHE_VERSION = 1
PIPELINE_MODULES = ('core.input_gate', 'core.navigator', 'core.imu_data')
"""Modules whose source, with that of every module of the package they import, keys the cache."""
SIM_PACKAGE = 'sim'
PACKAGE_ROOT = Path(__file__).resolve().parents[1]
PROGRESS_PERIOD_S = 5.0
SOURCES = ('sim', 'hugadb', 'bag')


# ---------------------------------------------------------------------------------------------
# Recordings
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SimSpec:
    """
    One simulated training run; everything is drawn from ``seed`` (see :func:`sim_spec`).

    The same run is ``python -m anfis_elevation_ros simulate --scenario random --seed SEED
    --duration-s D --rate-hz R --imu I --mounting-rpy-deg ROLL PITCH YAW``.
    """

    seed: int
    imu: str
    rate_hz: float
    mounting_rpy_deg: tuple
    duration_s: float

    @property
    def name(self) -> str:
        """Return the recording name, 'sim/seed<seed>'."""
        return f'sim/seed{self.seed}'


@dataclass(frozen=True)
class HugadbSpec:
    """One foot of one HuGaDB file; ``gyro_range_dps`` is that foot's gyro full scale."""

    path: str
    foot: str
    subject: int
    gyro_range_dps: int = 2000

    @property
    def name(self) -> str:
        """Return the recording name, 'hugadb/<file stem>/<foot>'."""
        return f'hugadb/{Path(self.path).stem}/{self.foot}'


@dataclass(frozen=True)
class BagSpec:
    """One bag and its label CSV (labels per 'sample' or per 'cycle')."""

    bag: str
    labels: str
    kind: str
    topic: str = None

    @property
    def name(self) -> str:
        """Return the recording name, 'bag/<bag name>'."""
        return f'bag/{Path(self.bag).name}'


@dataclass(frozen=True)
class NavigatedRecording:
    """
    What the navigator made of one recording, plus the raw material of its labels.

    Attributes
    ----------
    features : (N, N_FEATURES) array, every feature of every cycle, FEATURE_NAMES order.
    start_ns, stamp_ns : (N,) int64, start and closing stamps of the cycles.
    valid : (N,) bool, the navigator's validity flag.
    n_samples : int, IMU samples in the recording.
    n_rejected : int, samples the input gate refused.
    truth_stamp_ns, truth_label : (M,) int64, simulator: end stamp and mode of each true stride;
        HuGaDB: every sample's stamp and stair mode (labels.OTHER for other activities);
        bag: every sample's stamp and no labels (the CSV is read when labelling).

    """

    features: np.ndarray
    start_ns: np.ndarray
    stamp_ns: np.ndarray
    valid: np.ndarray
    n_samples: int
    n_rejected: int
    truth_stamp_ns: np.ndarray
    truth_label: np.ndarray


@dataclass(frozen=True)
class LabelRules:
    """How cycles get their labels (see the module docstring)."""

    match_tolerance_s: float = DEFAULT_MATCH_TOLERANCE_S
    min_majority: float = DEFAULT_MIN_MAJORITY
    min_stride_s: float = DEFAULT_MIN_STRIDE_S

    def __post_init__(self):
        check_range('match_tolerance_s', self.match_tolerance_s, 0.0, 1.0, open_low=True)
        check_range('min_majority', self.min_majority, 0.5, 1.0, open_low=True)
        check_range('min_stride_s', self.min_stride_s, 0.0, 1.0)


@dataclass(frozen=True)
class CycleSet:
    """
    The labelled cycles of one recording.

    Attributes
    ----------
    name : recording name ('sim/seed3', 'hugadb/<file>/<foot>', 'bag/<name>').
    source : 'sim', 'hugadb' or 'bag'.
    subject : subject key for leave-one-subject-out ('hugadb/s01', 'bag/<name>', 'sim/seed3').
    recording : recording key for leave-one-recording-out (both feet of a HuGaDB file share
        one).
    features : (n, N_FEATURES) array, the labelled valid cycles.
    labels : (n,) int8, their modes.
    non_stride : (n,) bool, cycles labelled level by the non-stride rule.
    counts : dict, samples, cycles, invalid, unlabelled, non_stride, used.

    """

    name: str
    source: str
    subject: str
    recording: str
    features: np.ndarray
    labels: np.ndarray
    non_stride: np.ndarray
    counts: dict = field(default_factory=dict)


def sim_spec(seed: int, duration_s: float = DEFAULT_SIM_DURATION_S) -> SimSpec:
    """
    Draw the set-up of simulated run ``seed``: IMU preset, rate and mounting.

    From ``np.random.default_rng([seed, 2])``: the preset uniformly from 'ideal', 'tactical',
    'consumer'; the rate uniformly from the integers 100..400 Hz; the mounting roll from
    U(-25, 25) deg (plus 180 deg, IMU upside down, with probability 0.2), pitch from U(-50, 50)
    deg and yaw from U(-180, 180) deg, rounded to 0.1 deg. The walk itself is
    ``sim.random_walk(duration_s, default_rng([seed, 1]))``: stairs of 0.14-0.19 m risers with
    1-4 steps per stride, level walks, turns and stops; the simulation uses
    ``default_rng(seed)``.

    Parameters
    ----------
    seed : int >= 0
        The run's seed.
    duration_s : float
        Length of the walk, s.

    Returns
    -------
    SimSpec

    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f'simulation seed must be an integer >= 0, got {seed!r}')
    rng = np.random.default_rng([int(seed), SIM_SPEC_STREAM])
    imu = SIM_IMU_PRESETS[int(rng.integers(len(SIM_IMU_PRESETS)))]
    rate_hz = float(rng.integers(SIM_RATE_RANGE_HZ[0], SIM_RATE_RANGE_HZ[1] + 1))
    roll = rng.uniform(-25.0, 25.0) + (180.0 if rng.uniform() < 0.2 else 0.0)
    pitch = rng.uniform(-50.0, 50.0)
    yaw = rng.uniform(-180.0, 180.0)
    mounting = tuple(round(float(a), 1) for a in (roll, pitch, yaw))
    return SimSpec(int(seed), imu, rate_hz, mounting, float(duration_s))


def simulate_run(spec: SimSpec) -> sim.SimulatedWalk:
    """Simulate the walk of a :class:`SimSpec` (the same as the ``simulate`` tool's)."""
    plan = sim.random_walk(spec.duration_s, np.random.default_rng([spec.seed, SIM_PLAN_STREAM]),
                           step_height_range_m=SIM_STEP_HEIGHT_RANGE_M)
    return sim.simulate_walk(plan, rng=np.random.default_rng(spec.seed), rate_hz=spec.rate_hz,
                             imu=spec.imu, mounting_rpy_deg=spec.mounting_rpy_deg)


@dataclass(frozen=True)
class Pipeline:
    """The parameters of the part of the pipeline that makes features: input gate, navigator."""

    navigator: NavigatorParams = field(default_factory=NavigatorParams)
    gate: GateParams = field(default_factory=GateParams)


def pipeline_from_yaml(path=None) -> Pipeline:
    """Gate and navigator parameters from the nodes' parameter YAML (None: the defaults)."""
    if path is None:
        return Pipeline()
    from ..core.params import load_pipeline_params
    params = load_pipeline_params(path)
    return Pipeline(params.navigator, params.gate)


def navigate(recording, pipeline: Pipeline):
    """
    Run the IMU node's input gate and navigator over a recording; return its cycles as arrays.

    Each sample goes through ``InputGate.check`` and, if accepted, ``FootNavigator.step``, as
    in the IMU node and in ``replay``.

    Parameters
    ----------
    recording : ImuRecording or SimulatedWalk
        Anything with ``stamp_ns``, ``acc_b`` (m/s^2) and ``gyr_b`` (rad/s).
    pipeline : Pipeline
        Gate and navigator parameters.

    Returns
    -------
    features : (N, N_FEATURES) array, start_ns : (N,) int64, stamp_ns : (N,) int64,
    valid : (N,) bool, rejected : int (samples the gate refused)

    """
    gate = InputGate(pipeline.gate)
    navigator = FootNavigator(pipeline.navigator)
    cycles = [cycle for _, _, cycle in navigated_samples(recording, gate, navigator)
              if cycle is not None]
    features = np.array([c.features for c in cycles], dtype=float).reshape(-1, N_FEATURES)
    start_ns = np.array([c.start_stamp_ns for c in cycles], dtype=np.int64)
    stamp_ns = np.array([c.stamp_ns for c in cycles], dtype=np.int64)
    valid = np.array([c.valid for c in cycles], dtype=bool)
    return features, start_ns, stamp_ns, valid, gate.rejected_total


def navigate_spec(spec, pipeline: Pipeline) -> NavigatedRecording:
    """Load or simulate the recording of a spec and run the gate and navigator over it."""
    if isinstance(spec, SimSpec):
        walk = simulate_run(spec)
        truth = (walk.strides.stamp_ns, walk.strides.mode.astype(np.int64))
        recording = walk
    elif isinstance(spec, HugadbSpec):
        from .datasets import load_hugadb
        recording, activity = load_hugadb(spec.path, spec.foot,
                                          gyro_range_dps=spec.gyro_range_dps)
        truth = (recording.stamp_ns, lab.hugadb_activity_labels(activity))
    else:
        from .bags import read_imu_bag
        recording = read_imu_bag(spec.bag, spec.topic)
        truth = (recording.stamp_ns, np.zeros(0, dtype=np.int64))
    features, start_ns, stamp_ns, valid, rejected = navigate(recording, pipeline)
    return NavigatedRecording(features, start_ns, stamp_ns, valid, len(recording.stamp_ns),
                              rejected, np.asarray(truth[0], dtype=np.int64),
                              np.asarray(truth[1], dtype=np.int64))


# ---------------------------------------------------------------------------------------------
# Feature cache
# ---------------------------------------------------------------------------------------------

def _module_file(name: str) -> Path:
    """File of a module of this package named relative to it ('core.navigator', 'sim')."""
    path = PACKAGE_ROOT.joinpath(*name.split('.'))
    return path.with_suffix('.py') if path.with_suffix('.py').is_file() else path / '__init__.py'


def _module_closure(roots) -> list:
    """
    Modules of this package that the given ones import, directly or not (themselves included).

    Names are relative to the package ('core.navigator'); only relative imports count (the
    package's own modules import each other that way).
    """
    seen, todo = set(), list(roots)
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        path = _module_file(name)
        package = name.split('.') if path.name == '__init__.py' else name.split('.')[:-1]
        for node in ast.walk(ast.parse(path.read_text(encoding='utf-8'))):
            if not isinstance(node, ast.ImportFrom) or node.level == 0:
                continue
            base = package[:len(package) - node.level + 1]
            if node.module:
                todo.append('.'.join(base + node.module.split('.')))
            else:
                todo.extend('.'.join(base + [alias.name]) for alias in node.names
                            if _module_file('.'.join(base + [alias.name])).is_file())
    return sorted(seen)


def _code_of(path: Path) -> str:
    """
    Return the code of a module: its lines without docstrings, comments and blank lines.

    Plain text, so the result does not depend on the Python version (``ast.dump`` does).
    """
    source = path.read_text(encoding='utf-8')
    docstring_lines = set()
    for node in ast.walk(ast.parse(source)):
        body = getattr(node, 'body', None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) \
                and isinstance(body[0].value, ast.Constant) \
                and isinstance(body[0].value.value, str):
            docstring_lines.update(range(body[0].lineno, body[0].end_lineno + 1))
    comment_column = {token.start[0]: token.start[1] for token in
                      tokenize.generate_tokens(io.StringIO(source).readline)
                      if token.type == tokenize.COMMENT}
    kept = []
    for number, line in enumerate(source.splitlines(), start=1):
        if number not in docstring_lines:
            line = line[:comment_column.get(number, len(line))].rstrip()
            if line:
                kept.append(line)
    return '\n'.join(kept)


@functools.lru_cache(maxsize=None)
def pipeline_fingerprint(with_sim: bool = False, sim_only: bool = False) -> str:
    """
    SHA-256 of the code of the feature pipeline: input gate, navigator and their core imports.

    Docstrings and comments do not count, so documentation edits keep cached features and the
    default model current. With ``with_sim`` the simulator (and its imports) count too; with
    ``sim_only`` only they do.
    """
    sim_roots = (SIM_PACKAGE,) if with_sim or sim_only else ()
    roots = sim_roots if sim_only else PIPELINE_MODULES + sim_roots
    digest = hashlib.sha256()
    for name in _module_closure(roots):
        digest.update(name.encode())
        digest.update(_code_of(_module_file(name)).encode())
    return digest.hexdigest()


def _file_digest(path: Path) -> str:
    digest = hashlib.sha256()
    paths = sorted(p for p in path.rglob('*') if p.is_file()) if path.is_dir() else [path]
    for item in paths:
        digest.update(item.name.encode())
        with open(item, 'rb') as stream:
            for block in iter(lambda: stream.read(1 << 20), b''):
                digest.update(block)
    return digest.hexdigest()


def cache_key(spec, pipeline: Pipeline) -> str:
    """Key of a recording's navigator output: its content, the parameters and the code."""
    if isinstance(spec, SimSpec):
        identity = {'sim': asdict(spec)}
    elif isinstance(spec, HugadbSpec):
        identity = {'hugadb': _file_digest(Path(spec.path)), 'foot': spec.foot}
        if spec.gyro_range_dps != HugadbSpec.gyro_range_dps:
            identity['gyro_range_dps'] = spec.gyro_range_dps
    else:
        identity = {'bag': _file_digest(Path(spec.bag)), 'topic': spec.topic}
    text = json.dumps({'version': CACHE_VERSION, 'recording': identity,
                       'params': repr(pipeline),
                       'code': pipeline_fingerprint(isinstance(spec, SimSpec))},
                      sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


_ARRAYS = ('features', 'start_ns', 'stamp_ns', 'valid', 'truth_stamp_ns', 'truth_label')
_COUNTS = ('n_samples', 'n_rejected')


def _load_cached(path: Path):
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in _ARRAYS}
            arrays.update({name: int(data[name]) for name in _COUNTS})
    except (OSError, KeyError, ValueError):
        return None
    return NavigatedRecording(**arrays)


def _save_cached(path: Path, result: NavigatedRecording):
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f'{path.stem}.tmp{os.getpid()}.npz')
    try:
        np.savez_compressed(tmp, **{name: getattr(result, name) for name in _ARRAYS},
                            **{name: np.int64(getattr(result, name)) for name in _COUNTS})
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def navigated(spec, pipeline: Pipeline, cache_dir) -> tuple:
    """Navigator output of a recording, from the cache when there; returns (result, cached)."""
    path = None if cache_dir is None else Path(cache_dir) / f'{cache_key(spec, pipeline)}.npz'
    if path is not None and path.is_file():
        result = _load_cached(path)
        if result is not None:
            return result, True
    result = navigate_spec(spec, pipeline)
    if path is not None:
        _save_cached(path, result)
    return result, False


def default_cache_dir() -> Path:
    """``<system temp dir>/anfis_elevation_ros_train_cache``."""
    return Path(tempfile.gettempdir()) / 'anfis_elevation_ros_train_cache'


# ---------------------------------------------------------------------------------------------
# Labels
# ---------------------------------------------------------------------------------------------

def label_recording(spec, nav: NavigatedRecording, rules: LabelRules) -> CycleSet:
    """
    Label the valid cycles of one recording (rules in the module docstring).

    Parameters
    ----------
    spec : SimSpec, HugadbSpec or BagSpec
        The recording.
    nav : NavigatedRecording
        Its navigator output.
    rules : LabelRules
        Tolerance, majority and non-stride settings.

    Returns
    -------
    CycleSet holding the valid, labelled cycles and the counts of the others.

    """
    tolerance_ns = int(round(rules.match_tolerance_s * 1e9))
    if isinstance(spec, SimSpec):
        source, subject, recording = 'sim', spec.name, spec.name
        labels, labelled = lab.match_nearest(nav.stamp_ns, nav.truth_stamp_ns, nav.truth_label,
                                             tolerance_ns)
    elif isinstance(spec, HugadbSpec):
        source, subject = 'hugadb', f'hugadb/s{spec.subject:02d}'
        recording = f'hugadb/{Path(spec.path).stem}'
        labels, labelled = lab.majority_labels(nav.start_ns, nav.stamp_ns, nav.truth_stamp_ns,
                                               nav.truth_label, rules.min_majority)
    else:
        source, subject, recording = 'bag', spec.name, spec.name
        label_stamp_ns, label_value = lab.read_label_csv(spec.labels)
        if spec.kind == 'cycle':
            labels, labelled = lab.match_nearest(nav.stamp_ns, label_stamp_ns, label_value,
                                                 tolerance_ns)
        else:
            per_sample = lab.labels_in_force(label_stamp_ns, label_value, nav.truth_stamp_ns)
            labels, labelled = lab.majority_labels(nav.start_ns, nav.stamp_ns,
                                                   nav.truth_stamp_ns, per_sample,
                                                   rules.min_majority)
    if isinstance(spec, HugadbSpec) or (isinstance(spec, BagSpec) and spec.kind == 'sample'):
        non_stride = lab.non_stride_cycles(nav.start_ns, nav.stamp_ns, rules.min_stride_s)
    else:
        non_stride = np.zeros(len(nav.valid), dtype=bool)
    labels = np.where(non_stride, 0, labels).astype(np.int8)
    use = nav.valid & (labelled | non_stride)
    counts = {'samples': int(nav.n_samples), 'rejected_samples': int(nav.n_rejected),
              'cycles': int(len(nav.valid)),
              'invalid': int(np.sum(~nav.valid)),
              'unlabelled': int(np.sum(nav.valid & ~labelled & ~non_stride)),
              'non_stride': int(np.sum(nav.valid & non_stride)), 'used': int(np.sum(use))}
    return CycleSet(spec.name, source, subject, recording, nav.features[use], labels[use],
                    non_stride[use], counts)


# ---------------------------------------------------------------------------------------------
# Data collection
# ---------------------------------------------------------------------------------------------

def hugadb_specs(folder, subjects=None, pattern: str = '*', clipped_gyro: bool = False) -> list:
    """
    List the HuGaDB recordings to use: every foot whose gyro does not clip (file_index.csv).

    Parameters
    ----------
    folder : str or Path
        The ``hugadb`` folder (holds ``file_index.csv`` and the ``.txt`` files).
    subjects : iterable of int or None
        Subjects to keep (None: all).
    pattern : str
        fnmatch pattern on the file names.
    clipped_gyro : bool
        Also list the feet whose gyro the index flags: +-250 deg/s gyros that clip in every
        swing (``datasets.HUGADB_GYR_COUNTS_PER_DPS``); subjects 4 and 5 have no other.

    Returns
    -------
    list of HugadbSpec, sorted by file then foot ('left' before 'right').

    """
    from .datasets import hugadb_index
    folder = Path(folder)
    if not (folder / 'file_index.csv').is_file():
        raise InputError(f'{folder} holds no file_index.csv; pass the HuGaDB folder of the '
                         'shared data (../shared/data/hugadb)')
    specs = []
    for row in sorted(hugadb_index(folder), key=lambda r: r.file):
        if subjects is not None and row.subject not in subjects:
            continue
        if not fnmatch.fnmatch(row.file, pattern):
            continue
        path = folder / row.file
        if not path.is_file():
            raise InputError(f'{path} is listed in file_index.csv but missing')
        specs.extend(HugadbSpec(str(path), foot, row.subject, row.gyro_range_dps(foot))
                     for foot in ('left', 'right') if clipped_gyro or row.gyro_ok(foot))
    if not specs:
        raise InputError(f'no usable HuGaDB recording in {folder} (subjects {subjects}, '
                         f'files {pattern!r})')
    return specs


class Progress:
    """Throttled progress lines on stderr (at most one per ``period_s``, plus summaries)."""

    def __init__(self, quiet: bool = False, period_s: float = PROGRESS_PERIOD_S):
        self.quiet = quiet
        self.period_s = period_s
        self._next = time.monotonic() + period_s
        self.started = time.monotonic()

    def log(self, message: str):
        """Print a line now."""
        if not self.quiet:
            print(f'[train {time.monotonic() - self.started:6.1f} s] {message}', file=sys.stderr,
                  flush=True)

    def tick(self, message: str):
        """Print a line if the last one is older than the period."""
        if time.monotonic() >= self._next:
            self._next = time.monotonic() + self.period_s
            self.log(message)


def _navigated_task(args):
    spec, pipeline, cache_dir = args
    return navigated(spec, pipeline, cache_dir)


def collect(specs, pipeline: Pipeline, rules: LabelRules, cache_dir=None, jobs: int = 1,
            progress: Progress = None) -> list:
    """
    Navigate and label every recording (in parallel with ``jobs`` > 1; same result).

    Parameters
    ----------
    specs : list of SimSpec, HugadbSpec, BagSpec
        The recordings.
    pipeline : Pipeline
        Gate and navigator parameters.
    rules : LabelRules
        Label rules.
    cache_dir : str or Path or None
        Feature cache folder (None: no cache).
    jobs : int >= 1
        Worker processes.
    progress : Progress or None
        Progress reporter.

    Returns
    -------
    list of CycleSet in the order of ``specs``.

    """
    progress = progress or Progress(quiet=True)
    tasks = [(spec, pipeline, cache_dir) for spec in specs]
    results = []
    samples = cached = 0
    started = time.monotonic()

    def account(spec, result):
        nonlocal samples, cached
        nav, from_cache = result
        cached += from_cache
        samples += 0 if from_cache else nav.n_samples
        results.append(label_recording(spec, nav, rules))
        rate = samples / max(time.monotonic() - started, 1e-9)
        progress.tick(f'navigated {len(results)}/{len(specs)} recordings ({cached} cached, '
                      f'{samples} samples at {rate:.0f}/s), last {spec.name}')

    if jobs > 1 and len(tasks) > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            for spec, result in zip(specs, pool.map(_navigated_task, tasks)):
                account(spec, result)
    else:
        for task in tasks:
            account(task[0], _navigated_task(task))
    progress.log(f'navigated {len(specs)} recordings ({cached} from the cache, {samples} '
                 f'samples navigated) in {time.monotonic() - started:.1f} s')
    return results


# ---------------------------------------------------------------------------------------------
# Training and cross-validation
# ---------------------------------------------------------------------------------------------

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


# ---------------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------------

def parse_int_list(text: str) -> list:
    """Parse '1-40' or '1,3,5-7' into a sorted list of distinct non-negative integers."""
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
    if any(v < 0 for v in values):
        raise argparse.ArgumentTypeError(f'{text!r}: seeds and subjects must be >= 0')
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
                      help='simulated runs to generate, e.g. 1-40 (see sim_spec in train.py)')
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


__all__ = ['DEFAULT_COMMAND', 'CycleSet', 'HugadbSpec', 'LabelRules', 'SimSpec', 'TrainOptions',
           'assign_folds', 'candidate_options', 'choose_setting', 'choose_threshold', 'collect',
           'cross_validate', 'cv_report', 'fit_model', 'hugadb_specs', 'input_universe',
           'label_recording', 'navigate', 'navigated', 'nested_cv', 'sim_spec', 'simulate_run',
           'stack']
