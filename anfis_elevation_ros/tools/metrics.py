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
Accuracy metrics: pyshoe's 2D position error and small classification helpers.

Public API
----------
pyshoe_align(est_pos, gt_pos)                  -> (est_aligned (N, 2), gt_shifted (N, 2))
pyshoe_position_error(est_pos, gt_pos)         -> float, m (pyshoe's time-averaged 2D RMSE)
confusion_matrix(true, pred, labels=(-1, 0, 1)) -> (L, L) int array, rows true, columns predicted
accuracy(true, pred)                           -> float in [0, 1]

References
----------
1. Wagstaff, Peretroukhin, Kelly, "Robust data-driven zero-velocity detection for foot-mounted
   inertial navigation", IEEE Sensors Journal 20(2), 2020; code: github.com/utiasSTARS/pyshoe,
   ``ins_tools/util.py`` (``align_plots``, ``compute_error``) as called by
   ``process_error_vicon.py``.

"""

import numpy as np

from ..core.errors import InputError

#: pyshoe's alignment distance: the estimate is aligned where it is first this far from its start.
PYSHOE_ALIGN_DIST_M = 0.8
#: pyshoe's alignment sample when the estimate never gets that far ("arbitrary point").
PYSHOE_FALLBACK_INDEX = 300


def _horizontal_tracks(est_pos, gt_pos):
    est = np.asarray(est_pos, dtype=float)
    gt = np.asarray(gt_pos, dtype=float)
    if est.ndim != 2 or est.shape[1] not in (2, 3):
        raise InputError(f'est_pos must have shape (N, 2) or (N, 3), got {est.shape}')
    if gt.ndim != 2 or gt.shape[1] not in (2, 3):
        raise InputError(f'gt_pos must have shape (N, 2) or (N, 3), got {gt.shape}')
    if len(est) != len(gt):
        raise InputError(
            f'est_pos has {len(est)} samples and gt_pos {len(gt)}; the metric needs the truth '
            'at every estimate sample (resample one of them)')
    if len(est) < 2:
        raise InputError(f'need at least 2 samples, got {len(est)}')
    if not (np.all(np.isfinite(est[:, :2])) and np.all(np.isfinite(gt[:, :2]))):
        raise InputError('est_pos and gt_pos must be finite')
    return est[:, :2], gt[:, :2]


def pyshoe_align(est_pos, gt_pos, *, align_dist_m: float = PYSHOE_ALIGN_DIST_M,
                 fallback_index=PYSHOE_FALLBACK_INDEX):
    """
    Shift both tracks to start at 0 and rotate the estimate about z onto the truth, as pyshoe.

    e_k = est_k - est_0,  t_k = gt_k - gt_0  (horizontal parts)
    i   = first k with |e_{k+1}| >= align_dist_m   (fallback_index if there is none)
    a   = signed angle from e_i to t_i = atan2(e_i x t_i, e_i . t_i)
    returns R(a) e_k and t_k

    Note that the distance test is on the ESTIMATE, not on the truth, and that the alignment
    sample i is the one just BEFORE the first estimate sample at least ``align_dist_m`` from the
    start (pyshoe tests ``cumsum(diff(x))[k]``, the distance of sample k + 1, and uses sample k).

    Parameters
    ----------
    est_pos : (N, 2) or (N, 3) array
        Estimated position [m]; z is ignored.
    gt_pos : (N, 2) or (N, 3) array
        True position [m] at the same samples, right-handed frame with z up.
    align_dist_m : float
        Distance from the start [m] that selects the alignment sample, pyshoe: 0.8.
    fallback_index : int or None
        Alignment sample when the estimate never gets ``align_dist_m`` from its start
        (pyshoe: 300); None raises InputError instead.

    Returns
    -------
    est_aligned : (N, 2) array
        Shifted and rotated estimate [m].
    gt_shifted : (N, 2) array
        Shifted truth [m].

    Raises
    ------
    InputError
        Shapes differ, fewer than 2 samples, non-finite values, the fallback is needed but is None
        or beyond the track, or the estimate or the truth at the alignment sample is at its start
        (no direction to align; pyshoe would return NaN).

    """
    est, gt = _horizontal_tracks(est_pos, gt_pos)
    est = est - est[0]
    gt = gt - gt[0]
    reached = np.flatnonzero(np.hypot(est[1:, 0], est[1:, 1]) >= align_dist_m)
    if reached.size:
        index = int(reached[0])
    elif fallback_index is None:
        raise InputError(
            f'the estimate never gets {align_dist_m} m from its start; no alignment sample')
    elif not 0 <= fallback_index < len(est):
        raise InputError(
            f'the estimate never gets {align_dist_m} m from its start and the fallback alignment '
            f'sample {fallback_index} is outside the {len(est)} samples')
    else:
        index = int(fallback_index)
    vec_est, vec_gt = est[index], gt[index]
    if not (np.any(vec_est != 0.0) and np.any(vec_gt != 0.0)):
        raise InputError(
            f'at the alignment sample {index} the estimate {vec_est} or the truth {vec_gt} is at '
            'its start: no heading to align')
    angle = np.arctan2(vec_est[0] * vec_gt[1] - vec_est[1] * vec_gt[0], vec_est @ vec_gt)
    cos_a, sin_a = np.cos(angle), np.sin(angle)
    rotation = np.array([[cos_a, -sin_a], [sin_a, cos_a]])
    return est @ rotation.T, gt


def pyshoe_position_error(est_pos, gt_pos, *, align_dist_m: float = PYSHOE_ALIGN_DIST_M,
                          fallback_index=PYSHOE_FALLBACK_INDEX) -> float:
    """
    Time-averaged 2D RMSE of pyshoe's VICON evaluation (ARMSE, metres).

    ARMSE = 1/N * sum_k sqrt(((x_k - X_k)^2 + (y_k - Y_k)^2) / 2)

    where (x_k, y_k) is the estimate and (X_k, Y_k) the truth after :func:`pyshoe_align`: both
    tracks shifted to start at 0 and the estimate rotated about z so that its sample i points the
    same way as the truth's sample i, i being the sample just before the first estimate sample
    at least 0.8 m (horizontally) from the start, or sample 300 when the estimate never gets
    0.8 m away. Note the divisor 2: it is the RMS over the two axes of each sample's error, not
    the horizontal distance (a 1 m error along x gives 0.707 m), then the mean over samples.

    Matches pyshoe's ``compute_error(x, gt, '2d')`` after ``align_plots(x, gt)``
    (``ins_tools/util.py``), except that (a) pyshoe rounds the result to 3 decimals (mm) and
    this function does not, and (b) the angle is atan2(cross, dot), which equals pyshoe's
    sign(cross) * arccos(dot / norms) except when the two alignment vectors are exactly
    antiparallel (pyshoe's sign(0) = 0 then skips the rotation). Degenerate alignments, where
    pyshoe divides by zero and returns NaN, raise InputError here.

    Parameters
    ----------
    est_pos : (N, 2) or (N, 3) array
        Estimated position [m] (ENU; z ignored).
    gt_pos : (N, 2) or (N, 3) array
        True position [m] at the same N samples, right-handed frame with z up.
    align_dist_m : float
        Alignment distance [m], pyshoe: 0.8.
    fallback_index : int or None
        Alignment sample when the estimate never gets that far, pyshoe: 300; None raises
        InputError instead.

    Returns
    -------
    float
        The ARMSE [m].

    """
    est, gt = pyshoe_align(est_pos, gt_pos, align_dist_m=align_dist_m,
                           fallback_index=fallback_index)
    diff = est - gt
    return float(np.mean(np.sqrt(np.mean(diff * diff, axis=1))))


def _labels_1d(values, name):
    array = np.asarray(values)
    if array.ndim != 1:
        raise InputError(f'{name} must be a 1-D sequence of labels, got shape {array.shape}')
    return array


def confusion_matrix(true, pred, labels=(-1, 0, 1)) -> np.ndarray:
    """
    Count (true, predicted) label pairs: C[i, j] = #{k : true_k = labels[i], pred_k = labels[j]}.

    Parameters
    ----------
    true : (N,) sequence
        True labels (e.g. -1 down, 0 level, 1 up).
    pred : (N,) sequence
        Predicted labels.
    labels : sequence of L labels
        The classes, in the order of the rows and columns.

    Returns
    -------
    (L, L) int64 array
        Rows are true classes, columns predicted classes.

    Raises
    ------
    InputError
        Lengths differ, or a label is not in ``labels``.

    """
    true = _labels_1d(true, 'true')
    pred = _labels_1d(pred, 'pred')
    if len(true) != len(pred):
        raise InputError(f'true has {len(true)} labels and pred {len(pred)}')
    labels = list(labels)
    if len(set(labels)) != len(labels):
        raise InputError(f'labels must be distinct, got {labels}')
    unknown = sorted((set(true.tolist()) | set(pred.tolist())) - set(labels), key=str)
    if unknown:
        raise InputError(f'labels {unknown} are not among the classes {labels}')
    index = {label: i for i, label in enumerate(labels)}
    rows = np.array([index[label] for label in true.tolist()], dtype=np.int64)
    cols = np.array([index[label] for label in pred.tolist()], dtype=np.int64)
    matrix = np.zeros((len(labels), len(labels)), dtype=np.int64)
    np.add.at(matrix, (rows, cols), 1)
    return matrix


def accuracy(true, pred) -> float:
    """Fraction of samples whose predicted label equals the true one: #{true_k = pred_k} / N."""
    true = _labels_1d(true, 'true')
    pred = _labels_1d(pred, 'pred')
    if len(true) != len(pred):
        raise InputError(f'true has {len(true)} labels and pred {len(pred)}')
    if len(true) == 0:
        raise InputError('accuracy of zero samples is undefined')
    return float(np.mean(true == pred))
