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
The training recordings -- simulated runs, HuGaDB feet, bags -- through the feature pipeline.

Every recording goes through the IMU node's input gate and ``FootNavigator`` -- the pipeline the
IMU node runs (:func:`navigate`); :class:`NavigatedRecording` holds the cycles it closes and the
raw material of their labels (``training_data.py`` labels them):

- simulated runs (``--sim-seeds``): generated in-process, one per seed, with the IMU preset,
  rate, mounting and walk drawn from the seed (:func:`sim_spec`, :class:`SimSpec`).
- HuGaDB (``--hugadb DIR``): one foot of one file (:class:`HugadbSpec`).
- bags (``--bag BAG LABELS.csv``): a bag and its label CSV (:class:`BagSpec`).

Navigator outputs are cached per recording (``.npz``, no pickle) under ``--cache-dir``, keyed by
the recording's content, the navigator parameters and the source code of the navigator pipeline
(:func:`pipeline_fingerprint`), so a changed navigator is never served stale features.
"""

import ast
from dataclasses import asdict, dataclass, field
import functools
import hashlib
import io
import json
import os
from pathlib import Path
import tempfile
import tokenize

import numpy as np

from . import labels as lab
from .replay import navigated_samples
from .. import sim
from ..core.errors import InputError
from ..core.gait import N_FEATURES
from ..core.input_gate import GateParams, InputGate
from ..core.navigator import FootNavigator, NavigatorParams

SIM_IMU_PRESETS = ('ideal', 'tactical', 'consumer')
SIM_RATE_RANGE_HZ = (100, 400)
SIM_STEP_HEIGHT_RANGE_M = (0.14, 0.19)
SIM_PLAN_STREAM, SIM_SPEC_STREAM = 1, 2   # second words of the seed sequences (see sim_spec)
DEFAULT_SIM_DURATION_S = 150.0
CACHE_VERSION = 1
PIPELINE_MODULES = ('core.input_gate', 'core.navigator', 'core.imu_data')
"""Modules whose source, with that of every module of the package they import, keys the cache."""
SIM_PACKAGE = 'sim'
PACKAGE_ROOT = Path(__file__).resolve().parents[1]


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


__all__ = ['HugadbSpec', 'SimSpec', 'navigate', 'navigated', 'sim_spec', 'simulate_run']
