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
Stair-mode labels of gait cycles from simulator truth, per-sample labels or per-cycle labels.

A gait cycle of the navigator runs from ``start_stamp_ns`` (last stance sample before the
swing) to ``stamp_ns`` (first stance sample after it). Its label is the stair mode C of eq. 13:
+1 up, 0 level, -1 down. Three ways to get it, one function each:

- :func:`match_nearest` -- per-stride (simulator truth) or per-cycle (user CSV) labels: the label
  whose stamp is nearest the cycle's closing stamp, if it is within a tolerance; other cycles
  are unlabelled.
- :func:`majority_labels` -- per-sample labels (HuGaDB activities, user CSV): the label held by
  at least ``min_fraction`` of the samples from the cycle's start to its closing stamp; other
  cycles (mixed, or mostly another activity) are unlabelled.
- :func:`non_stride_cycles` -- cycles whose swing is shorter than any stride (the zero-velocity
  detector flickering while the foot rests): the foot stayed on its step, so with per-sample
  labels the training tool labels them 0 whatever the activity around them (see
  ``training_data.py``).

Labels are int8 arrays in {-1, 0, +1} with a boolean ``labelled`` mask beside them; the value
under a False mask is :data:`UNLABELLED`. Per-sample label arrays use :data:`OTHER` for samples of
any other activity (standing, sitting, ...).

Public API: :func:`match_nearest`, :func:`majority_labels`, :func:`non_stride_cycles`,
:func:`labels_in_force`, :func:`hugadb_activity_labels`, :func:`read_label_csv`,
:data:`MODES`, :data:`OTHER`, :data:`UNLABELLED`.
"""

import csv
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.validation import check_range

MODES = (-1, 0, 1)
"""Stair modes of eq. 13: down, level, up."""
OTHER = 2
"""Per-sample label of a sample that belongs to no stair mode (standing, other activities)."""
UNLABELLED = 3
"""Value of a cycle label under a False ``labelled`` mask."""
HUGADB_MODE = {1: 0, 3: 1, 4: -1}
"""HuGaDB activity id -> stair mode: walking -> level, going up -> +1, going down -> -1."""
LABEL_COLUMNS = ('stamp_ns', 'label')
"""Header of a label CSV (per sample or per cycle)."""


def match_nearest(cycle_stamp_ns, label_stamp_ns, label, tolerance_ns: int):
    """
    Label each cycle with the label whose stamp is nearest its closing stamp, within a tolerance.

    j*(i) = argmin_j |t_label_j - t_cycle_i|;  label_i = label_j*  if |t_label_j* - t_cycle_i|
    <= tolerance, else unlabelled (ties go to the earlier label stamp).

    Parameters
    ----------
    cycle_stamp_ns : (N,) int array
        Closing stamps of the cycles, ns.
    label_stamp_ns : (M,) int array
        Stamps of the labels, ns, non-decreasing (for simulator truth: the first stance
        sample after each stride's swing).
    label : (M,) int array
        Stair mode of each label stamp, values in {-1, 0, +1} (others leave the cycle
        unlabelled).
    tolerance_ns : int >= 0
        Largest accepted |stamp difference|, ns.

    Returns
    -------
    labels : (N,) int8 array
        Mode of each cycle, :data:`UNLABELLED` where unmatched.
    labelled : (N,) bool array
        True where a label was matched.

    """
    cycle_stamp_ns = np.asarray(cycle_stamp_ns, dtype=np.int64)
    label_stamp_ns = np.asarray(label_stamp_ns, dtype=np.int64)
    label = np.asarray(label, dtype=np.int64)
    if label_stamp_ns.shape != label.shape or label_stamp_ns.ndim != 1:
        raise InputError(f'label stamps {label_stamp_ns.shape} and labels {label.shape} must be '
                         'two 1-D arrays of one length')
    if np.any(np.diff(label_stamp_ns) < 0):
        raise InputError('label stamps must not decrease')
    labels = np.full(cycle_stamp_ns.shape, UNLABELLED, dtype=np.int8)
    labelled = np.zeros(cycle_stamp_ns.shape, dtype=bool)
    if len(label_stamp_ns) == 0 or len(cycle_stamp_ns) == 0:
        return labels, labelled
    after = np.searchsorted(label_stamp_ns, cycle_stamp_ns, side='left')
    before = np.clip(after - 1, 0, len(label_stamp_ns) - 1)
    after = np.clip(after, 0, len(label_stamp_ns) - 1)
    d_before = np.abs(cycle_stamp_ns - label_stamp_ns[before])
    d_after = np.abs(label_stamp_ns[after] - cycle_stamp_ns)
    nearest = np.where(d_before <= d_after, before, after)
    distance = np.minimum(d_before, d_after)
    mode = label[nearest]
    labelled = (distance <= tolerance_ns) & np.isin(mode, MODES)
    labels[labelled] = mode[labelled]
    return labels, labelled


def majority_labels(start_ns, stamp_ns, sample_stamp_ns, sample_label,
                    min_fraction: float = 0.7):
    """
    Label each cycle with the stair mode most of its samples have, if it holds a clear majority.

    S_i = {k : start_i <= t_k <= end_i};  n_c = #{k in S_i : l_k = c} for c in {-1, 0, +1, OTHER}
    label_i = c* = argmax_c n_c  if c* != OTHER and n_c* >= min_fraction * |S_i|, else unlabelled

    Parameters
    ----------
    start_ns, stamp_ns : (N,) int arrays
        Start (last stance sample before the swing) and closing stamps of the cycles, ns.
    sample_stamp_ns : (K,) int array
        Sample stamps, ns, increasing.
    sample_label : (K,) int array
        Label of each sample: -1, 0, +1 or :data:`OTHER`.
    min_fraction : float in (0.5, 1]
        Share of the cycle's samples the majority label needs.

    Returns
    -------
    labels : (N,) int8 array
        Mode of each cycle, :data:`UNLABELLED` where there is no clear stair-mode majority.
    labelled : (N,) bool array
        True where a label was given.

    """
    check_range('min_fraction', min_fraction, 0.5, 1.0, open_low=True)
    start_ns = np.asarray(start_ns, dtype=np.int64)
    stamp_ns = np.asarray(stamp_ns, dtype=np.int64)
    sample_stamp_ns = np.asarray(sample_stamp_ns, dtype=np.int64)
    sample_label = np.asarray(sample_label, dtype=np.int64)
    if sample_stamp_ns.shape != sample_label.shape:
        raise InputError(f'{len(sample_stamp_ns)} sample stamps but {len(sample_label)} labels')
    classes = MODES + (OTHER,)
    if not np.all(np.isin(sample_label, classes)):
        raise InputError(f'sample labels must be in {classes}')
    first = np.searchsorted(sample_stamp_ns, start_ns, side='left')
    last = np.searchsorted(sample_stamp_ns, stamp_ns, side='right')
    # counts[i, c] = samples of class c in cycle i, from cumulative sums per class.
    one_hot = (sample_label[:, None] == np.array(classes)[None, :]).astype(np.int64)
    cumulative = np.vstack((np.zeros((1, len(classes)), dtype=np.int64),
                            np.cumsum(one_hot, axis=0)))
    counts = cumulative[last] - cumulative[first]
    total = counts.sum(axis=1)
    winner = np.argmax(counts, axis=1)
    winner_count = counts[np.arange(len(counts)), winner]
    labelled = ((winner < len(MODES)) & (total > 0)
                & (winner_count >= min_fraction * total - 1e-9))
    labels = np.full(start_ns.shape, UNLABELLED, dtype=np.int8)
    labels[labelled] = np.array(MODES)[winner[labelled]]
    return labels, labelled


def non_stride_cycles(start_ns, stamp_ns, min_stride_s: float):
    """
    Flag cycles whose swing is shorter than any stride: the foot never left its step.

    non_stride_i = (end_i - start_i) < min_stride_s

    Parameters
    ----------
    start_ns, stamp_ns : (N,) int arrays
        Start and closing stamps of the cycles, ns.
    min_stride_s : float > 0
        Shortest swing of a real stride, s.

    Returns
    -------
    (N,) bool array.

    """
    duration_ns = np.asarray(stamp_ns, dtype=np.int64) - np.asarray(start_ns, dtype=np.int64)
    return duration_ns < int(round(min_stride_s * 1e9))


def labels_in_force(label_stamp_ns, label, sample_stamp_ns):
    """
    Per-sample labels from labels given at some stamps: each holds until the next one.

    l(t_k) = label_j,  j = max{j : t_label_j <= t_k};  OTHER before the first label stamp.
    Labels given at every sample come back unchanged; labels given at change points (a label
    per segment) fill the samples between them.

    Parameters
    ----------
    label_stamp_ns : (M,) int array
        Stamps of the labels, ns, non-decreasing.
    label : (M,) int array
        Label at each stamp; values outside {-1, 0, +1} become :data:`OTHER`.
    sample_stamp_ns : (K,) int array
        Stamps of the samples to label, ns.

    Returns
    -------
    (K,) int64 array of -1, 0, +1 or OTHER.

    """
    label_stamp_ns = np.asarray(label_stamp_ns, dtype=np.int64)
    label = np.asarray(label, dtype=np.int64)
    if np.any(np.diff(label_stamp_ns) < 0):
        raise InputError('label stamps must not decrease')
    label = np.where(np.isin(label, MODES), label, OTHER)
    index = np.searchsorted(label_stamp_ns, np.asarray(sample_stamp_ns, dtype=np.int64),
                            side='right') - 1
    return np.where(index >= 0, label[np.maximum(index, 0)], OTHER).astype(np.int64)


def hugadb_activity_labels(activity) -> np.ndarray:
    """
    Stair mode of each HuGaDB sample: walking (1) -> 0, going up (3) -> +1, down (4) -> -1.

    Every other activity (standing, sitting, running, ...) becomes :data:`OTHER`.

    Parameters
    ----------
    activity : (K,) int array
        HuGaDB activity id per sample (``load_hugadb``).

    Returns
    -------
    (K,) int64 array.

    """
    activity = np.asarray(activity, dtype=np.int64)
    result = np.full(activity.shape, OTHER, dtype=np.int64)
    for act, mode in HUGADB_MODE.items():
        result[activity == act] = mode
    return result


def read_label_csv(path):
    """
    Read a label CSV: a header ``stamp_ns,label``, then one row per labelled stamp.

    ``stamp_ns`` is an integer stamp in ns (the bag's header stamps), non-decreasing; ``label``
    an integer: -1 down, 0 level, +1 up, any other integer another activity (such samples or
    cycles are not used). Rows may label every sample, every cycle (at its closing stamp, as
    ``replay`` writes ``cycles.csv``) or the start of each segment (per-sample mode).

    Parameters
    ----------
    path : str or Path
        The CSV file.

    Returns
    -------
    stamp_ns : (M,) int64 array
    label : (M,) int64 array

    Raises
    ------
    InputError : missing file columns, non-integer cells, decreasing stamps, no rows.

    """
    path = Path(path)
    with open(path, newline='') as stream:
        rows = [row for row in csv.reader(stream) if row and any(cell.strip() for cell in row)]
    if not rows:
        raise InputError(f'{path}: empty; expected a header "stamp_ns,label" and rows')
    header = [cell.strip() for cell in rows[0]]
    missing = [name for name in LABEL_COLUMNS if name not in header]
    if missing:
        raise InputError(f'{path}: header {header} lacks {missing}; expected "stamp_ns,label"')
    stamp_col, label_col = (header.index(name) for name in LABEL_COLUMNS)
    stamps, labels = [], []
    for line, row in enumerate(rows[1:], start=2):
        try:
            stamps.append(int(row[stamp_col].strip()))
            labels.append(int(row[label_col].strip()))
        except (IndexError, ValueError):
            raise InputError(f'{path}:{line}: expected integer stamp_ns and label, got '
                             f'{row!r}') from None
    if not stamps:
        raise InputError(f'{path}: no label rows after the header')
    stamp_ns = np.array(stamps, dtype=np.int64)
    bad = np.flatnonzero(np.diff(stamp_ns) < 0)
    if bad.size:
        raise InputError(f'{path}:{int(bad[0]) + 3}: stamp_ns decreases; sort the rows by time')
    return stamp_ns, np.array(labels, dtype=np.int64)
