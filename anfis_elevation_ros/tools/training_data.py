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
Labels of the training cycles, and their collection from the recordings.

Each valid gait cycle the navigator closes (``training_recordings.py``) gets a label (eq. 13
mode: +1 up, 0 level, -1 down):

- simulated runs (``--sim-seeds``): a cycle takes the mode of the true stride whose end stamp
  is nearest its closing stamp, within ``--match-tolerance-s``.
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

:func:`collect` navigates every recording (through the feature cache) and labels its cycles, in
parallel with ``jobs`` > 1 and with the same result.

References
----------
[1] Chereshnev, Kertesz-Farkas, "HuGaDB: Human Gait Database for Activity Recognition from
    Wearable Inertial Sensor Networks", AIST 2017.

"""

from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
import fnmatch
from pathlib import Path
import sys
import time

import numpy as np

from . import labels as lab
from .training_recordings import BagSpec, HugadbSpec, navigated, NavigatedRecording, Pipeline
from .training_recordings import SimSpec
from ..core.errors import InputError
from ..core.validation import check_range

DEFAULT_MATCH_TOLERANCE_S = 0.1
DEFAULT_MIN_MAJORITY = 0.7
DEFAULT_MIN_STRIDE_S = 0.3
PROGRESS_PERIOD_S = 5.0
SOURCES = ('sim', 'hugadb', 'bag')


# ---------------------------------------------------------------------------------------------
# Labels
# ---------------------------------------------------------------------------------------------

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


__all__ = ['CycleSet', 'LabelRules', 'collect', 'hugadb_specs', 'label_recording']
