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
First-order Takagi-Sugeno ANFIS with Jang's hybrid learning rule [1], numpy only.

The network has five layers [1]; each is one function below, with its equation in the docstring:

Layer 1  :func:`membership_grades`  mu_ij = mu(x_i; a_ij, b_ij, c_ij), triangular
         (:func:`triangle_membership`) or generalised bell (:func:`gbell_membership`).
Layer 2  :func:`firing_strengths`  w_r = prod_i mu_{i, j_i(r)} (product t-norm) over the grid rule
         base, rule r <-> (j_1, ..., j_n), first input varying slowest (:func:`grid_rule_indices`).
Layer 3  :func:`normalised_firing_strengths`  wbar_r = w_r / sum_s w_s.
Layer 4  :func:`rule_outputs`  f_r = p_r . x + r_r (first-order consequents).
Layer 5  :func:`anfis_output`  y = sum_r wbar_r f_r.

Hybrid learning, one epoch [1]: with the premise (membership) parameters fixed, the output is
linear in the consequents, which :func:`least_squares_consequents` solves in one ridge-regularised
least-squares step; then :func:`premise_gradient` back-propagates the squared error to the
membership parameters and :func:`gradient_step` moves them by a step of length k along the negative
gradient, k adapted by Jang's heuristic rules (:func:`update_step_size`). :func:`project_mf_params`
keeps the membership functions valid, and with checking data the parameters of the epoch with the
lowest checking error are kept, as MATLAB's ``anfis`` does [2]. Initial membership functions are a
grid partition of each input's training range as MATLAB ``genfis`` makes it
(:func:`grid_partition`) [2].

Inputs outside the universe. Every input is clipped into its universe (the training range, stored
with the model) before any layer is evaluated, so ``predict(x) == predict(clip(x, lo, hi))``: the
model saturates at the edge of the data it has seen instead of extrapolating its linear
consequents. The universe is always covered: the projection keeps each triangle reaching its
neighbours' peaks and the outer triangles reaching past the universe edges, and bells are positive
everywhere, so some rule always fires there. As a last guard the normalisation divides by
max(sum w, tiny); should no rule fire at all (only possible for a hand-made model, and
:meth:`Anfis.from_params` refuses uncovered triangles) all normalised strengths are 0 and the
output is 0.

Public API: :class:`Anfis` (``fit``, ``predict``, ``memberships``, ``firing_strengths``, ``save``,
``load``, ``from_params``), :class:`EpochReport`, and the layer and learning functions above.

References
----------
[1] J.-S. R. Jang, "ANFIS: adaptive-network-based fuzzy inference system", IEEE Transactions on
    Systems, Man, and Cybernetics 23(3), 665-685, 1993.
[2] The MathWorks, Fuzzy Logic Toolbox: ``genfis`` (grid partition defaults) and ``anfis``
    (step-size rules, initial step 0.01, rates 0.9 / 1.1; best-checking-error parameters).

"""

from dataclasses import dataclass
import json
import math
import os
from typing import Callable, Optional

import numpy as np

from .errors import InputError
from .json_file import read_json_file, write_text_atomically
from .validation import check_finite, check_positive, check_range

FORMAT_NAME = 'anfis_elevation_ros.anfis'
"""Value of the ``format`` key of a saved model."""
FORMAT_VERSION = 1
"""Value of the ``version`` key of a saved model; :meth:`Anfis.load` reads only this version."""
MF_TYPES = ('triangle', 'gbell')
"""Membership-function types; parameters (a, b, c) are feet-peak-foot or width-slope-centre."""
MAX_CONSEQUENT_PARAMS = 5000
"""Largest n_rules * (n_inputs + 1): the normal matrix of the least-squares step is its square."""
MAX_MODEL_BYTES = 10_000_000
"""Largest model file :meth:`Anfis.load` reads; the largest rule base takes about 0.2 MB."""
DEFAULT_RIDGE = 0.0
"""
Default ridge factor of :func:`least_squares_consequents`, relative to mean(diag(A^T A)).

0 is Jang's plain least squares, so the defaults reproduce his Mackey-Glass result (4 inputs x 2
bells, 500 epochs on his own files: checking RMSE 0.00138, against 0.0040 with 1e-4; Jang reports
0.0016). A rule base with many more unknowns than samples needs regularisation: the stair training
tool passes its own (``tools/train.py``, ``DEFAULT_TRAIN_RIDGE``).
"""
MIN_WIDTH_FRACTION = 1e-3
"""Smallest triangle half-width and bell width a, as a fraction of the input's universe width."""
MIN_GBELL_SLOPE = 0.5
"""Smallest bell slope b: 2b >= 1 keeps the bell differentiable in its centre c."""

_TINY = np.finfo(float).tiny
_LSQ_CHUNK_ROWS = 2048


# --------------------------------------------------------------------------------- layer 1

def triangle_membership(x, a, b, c) -> np.ndarray:
    """
    Triangular membership grade (MATLAB ``trimf``), Jang layer 1.

    mu(x; a, b, c) = max(0, min((x - a) / (b - a), (c - x) / (c - b))),   a < b < c

    Parameters
    ----------
    x : array
        Input values (any shape broadcasting with a, b, c), input units.
    a, b, c : arrays
        Left foot, peak and right foot, input units, a < b < c.

    Returns
    -------
    Array of the broadcast shape, grades in [0, 1].

    """
    return np.maximum(np.minimum((x - a) / (b - a), (c - x) / (c - b)), 0.0)


def gbell_membership(x, a, b, c) -> np.ndarray:
    """
    Generalised bell membership grade (MATLAB ``gbellmf``), Jang layer 1.

    mu(x; a, b, c) = 1 / (1 + |(x - c) / a|^(2 b)),   a > 0, b > 0

    Parameters
    ----------
    x : array
        Input values (any shape broadcasting with a, b, c), input units.
    a, b, c : arrays
        Half-width (input units, mu(c +- a) = 1/2), slope (dimensionless) and centre
        (input units).

    Returns
    -------
    Array of the broadcast shape, grades in (0, 1].

    """
    with np.errstate(over='ignore'):
        return 1.0 / (1.0 + np.abs((x - c) / a) ** (2.0 * b))


def triangle_membership_derivatives(x, a, b, c) -> np.ndarray:
    """
    Partial derivatives d mu / d(a, b, c) of :func:`triangle_membership`.

    rising side a < x <= b:  dmu/da = (x - b) / (b - a)^2,  dmu/db = -(x - a) / (b - a)^2,
                             dmu/dc = 0
    falling side b < x < c:  dmu/da = 0,  dmu/db = (c - x) / (c - b)^2,
                             dmu/dc = (x - b) / (c - b)^2
    elsewhere all are 0 (at the peak x = b the rising side's one-sided derivative is used).

    Parameters
    ----------
    x, a, b, c : arrays broadcasting together
        As in :func:`triangle_membership`.

    Returns
    -------
    Array of the broadcast shape + (3,): derivatives with respect to a, b, c (1 / input unit).

    """
    x, a, b, c = np.broadcast_arrays(x, a, b, c)
    rising = (x > a) & (x <= b)
    falling = (x > b) & (x < c)
    inv_left2 = 1.0 / (b - a) ** 2
    inv_right2 = 1.0 / (c - b) ** 2
    d_a = np.where(rising, (x - b) * inv_left2, 0.0)
    d_b = np.where(rising, -(x - a) * inv_left2, np.where(falling, (c - x) * inv_right2, 0.0))
    d_c = np.where(falling, (x - b) * inv_right2, 0.0)
    return np.stack((d_a, d_b, d_c), axis=-1)


def gbell_membership_derivatives(x, a, b, c) -> np.ndarray:
    """
    Partial derivatives d mu / d(a, b, c) of :func:`gbell_membership`.

    With z = (x - c) / a and mu = 1 / (1 + |z|^(2b)):
    dmu/da = 2 b mu (1 - mu) / a
    dmu/db = -2 ln|z| mu (1 - mu)                    (0 at z = 0)
    dmu/dc = 2 b mu^2 sign(z) |z|^(2b - 1) / a       (= 2 b mu (1 - mu) / (x - c) for x != c)

    Parameters
    ----------
    x, a, b, c : arrays broadcasting together
        As in :func:`gbell_membership`; b >= 1/2 keeps
        dmu/dc finite at z = 0.

    Returns
    -------
    Array of the broadcast shape + (3,): derivatives with respect to a, b, c.

    """
    x, a, b, c = np.broadcast_arrays(x, a, b, c)
    z = (x - c) / a
    abs_z = np.abs(z)
    mu = gbell_membership(x, a, b, c)
    spread = mu * (1.0 - mu)
    with np.errstate(divide='ignore', invalid='ignore', over='ignore'):
        log_abs_z = np.where(abs_z > 0.0, np.log(np.where(abs_z > 0.0, abs_z, 1.0)), 0.0)
        d_a = 2.0 * b * spread / a
        d_b = -2.0 * log_abs_z * spread
        d_c = 2.0 * b * mu * mu * np.sign(z) * abs_z ** (2.0 * b - 1.0) / a
    return np.stack((d_a, d_b, np.where(np.isfinite(d_c), d_c, 0.0)), axis=-1)


def membership_grades(x: np.ndarray, mf_params: np.ndarray, mf: str) -> np.ndarray:
    """
    Jang layer 1: membership grade of every input in each of its membership functions.

    mu_ij = mu(x_i; a_ij, b_ij, c_ij),   i = input, j = membership function of that input

    Parameters
    ----------
    x : (N, n_inputs) array
        Inputs (already clipped into the universe), input units.
    mf_params : (n_inputs, n_mfs, 3) array
        (a, b, c) of every membership function.
    mf : {'triangle', 'gbell'}
        Membership-function type.

    Returns
    -------
    (N, n_inputs, n_mfs) array of grades.

    """
    function = triangle_membership if mf == 'triangle' else gbell_membership
    return function(x[:, :, None], mf_params[:, :, 0], mf_params[:, :, 1], mf_params[:, :, 2])


# --------------------------------------------------------------------------------- layer 2

def grid_rule_indices(n_inputs: int, n_mfs: int) -> np.ndarray:
    """
    Membership function used by each rule of the grid rule base, first input varying slowest.

    rule r <-> (j_1, ..., j_n) with r = sum_i j_i * n_mfs^(n - i)   (row-major, like np.ndindex)

    Returns
    -------
    (n_mfs ** n_inputs, n_inputs) int array; row r holds j_1, ..., j_n of rule r.

    """
    return np.indices((n_mfs,) * n_inputs).reshape(n_inputs, -1).T.copy()


def firing_strengths(mu: np.ndarray) -> np.ndarray:
    """
    Jang layer 2: firing strength of every rule of the grid rule base, product t-norm.

    w_r = prod_i mu_{i, j_i(r)}   for rule r <-> (j_1, ..., j_n), see :func:`grid_rule_indices`

    Parameters
    ----------
    mu : (N, n_inputs, n_mfs) array
        Membership grades from :func:`membership_grades`.

    Returns
    -------
    (N, n_mfs ** n_inputs) array of firing strengths in [0, 1].

    """
    n_samples, n_inputs, _ = mu.shape
    w = mu[:, 0, :]
    for i in range(1, n_inputs):   # outer product per input, not per rule
        w = (w[:, :, None] * mu[:, i, None, :]).reshape(n_samples, -1)
    return w


# --------------------------------------------------------------------------------- layer 3

def normalised_firing_strengths(w: np.ndarray):
    """
    Jang layer 3: firing strengths normalised to sum 1 over the rules.

    wbar_r = w_r / max(sum_s w_s, tiny)

    tiny is the smallest normal float: if no rule fires (sum_s w_s = 0) every wbar_r is 0 and the
    output is 0. With clipped inputs and projected membership functions this does not happen.

    Parameters
    ----------
    w : (N, n_rules) array
        Firing strengths from :func:`firing_strengths`.

    Returns
    -------
    wbar : (N, n_rules) array, normalised firing strengths.
    total : (N,) array, max(sum_s w_s, tiny), needed by the gradient.

    """
    total = np.maximum(w.sum(axis=1), _TINY)
    return w / total[:, None], total


# --------------------------------------------------------------------------------- layers 4-5

def rule_outputs(x: np.ndarray, consequents: np.ndarray) -> np.ndarray:
    """
    Jang layer 4 (before weighting): first-order consequent of every rule.

    f_r = p_r . x + r_r = sum_i p_ri x_i + r_r

    Parameters
    ----------
    x : (N, n_inputs) array
        Inputs (clipped into the universe), input units.
    consequents : (n_rules, n_inputs + 1) array
        Row r = (p_r1, ..., p_rn, r_r).

    Returns
    -------
    (N, n_rules) array, output units.

    """
    return x @ consequents[:, :-1].T + consequents[:, -1]


def anfis_output(wbar: np.ndarray, f: np.ndarray) -> np.ndarray:
    """
    Jang layers 4-5: weighted rule outputs summed into the network output.

    y = sum_r wbar_r f_r

    Parameters
    ----------
    wbar : (N, n_rules) array
        Normalised firing strengths.
    f : (N, n_rules) array
        Rule outputs from :func:`rule_outputs`.

    Returns
    -------
    (N,) array, output units.

    """
    return np.einsum('nr,nr->n', wbar, f)


# --------------------------------------------------------------------------------- learning

def least_squares_consequents(wbar: np.ndarray, x: np.ndarray, y: np.ndarray,
                              ridge: float = DEFAULT_RIDGE) -> np.ndarray:
    """
    Hybrid learning, forward pass: all consequents by one ridge-regularised least-squares step.

    y = A theta,  A_n = (wbar_n1 x_n, wbar_n1, ..., wbar_nR x_n, wbar_nR),  theta = (p_1, r_1, ...)
    theta = (A^T A + lambda I)^-1 A^T y,   lambda = ridge * trace(A^T A) / P,  P = R (n + 1)

    Jang solves A theta = y by sequential least squares started from S_0 = gamma I with gamma
    large; that equals this ridge solution with lambda = 1 / gamma. Scaling lambda by the mean
    diagonal of A^T A keeps ``ridge`` dimensionless, and keeps P unknowns (1458 for 5 inputs x 3
    MFs) well posed when samples are fewer than unknowns or some rules hardly fire (with triangles
    A^T A is singular even then: linear interpolation between the peaks reproduces x, so the
    columns are dependent). A^T A is accumulated without holding A (N x P) whole, see
    :func:`_normal_equations`.

    Parameters
    ----------
    wbar : (N, R) array
        Normalised firing strengths.
    x : (N, n) array
        Inputs (clipped into the universe), input units.
    y : (N,) array
        Targets, output units.
    ridge : float >= 0
        Lambda relative to mean(diag(A^T A)); 0 gives plain least squares
        (minimum-norm solution if A^T A is singular).

    Returns
    -------
    (R, n + 1) array of consequents, row r = (p_r1, ..., p_rn, r_r).

    """
    n_samples, n_rules = wbar.shape
    x_ext = np.concatenate((x, np.ones((n_samples, 1))), axis=1)
    n_terms = x_ext.shape[1]
    n_params = n_rules * n_terms
    normal, rhs = _normal_equations(wbar, x_ext, y)
    if ridge > 0.0:
        scale = np.trace(normal) / n_params
        normal[np.diag_indices(n_params)] += ridge * (scale if scale > 0.0 else 1.0)
        try:
            theta = np.linalg.solve(normal, rhs)
        except np.linalg.LinAlgError:
            theta = np.linalg.lstsq(normal, rhs, rcond=None)[0]
    else:
        theta = np.linalg.lstsq(normal, rhs, rcond=None)[0]
    return theta.reshape(n_rules, n_terms)


def _normal_equations(wbar: np.ndarray, x_ext: np.ndarray, y: np.ndarray) -> tuple:
    """
    A^T A and A^T y of :func:`least_squares_consequents`, A_n = wbar_n (kron) (x_n, 1).

    Rows of A are grouped by the set of rules that fire (wbar_nr > 0). Within a group only those
    rules' columns are non-zero, so each group adds a small dense block; with triangles a sample
    fires at most 2^n of the m^n rules (32 of 243), which makes this ~(m/2)^(2n) times cheaper than
    the dense product. When most rules fire (bells) or the groups are many and small, the dense
    product is taken over row blocks instead. Both give the same sums up to rounding.
    """
    n_samples, n_rules = wbar.shape
    n_terms = x_ext.shape[1]
    n_params = n_rules * n_terms
    normal = np.zeros((n_params, n_params))
    rhs = np.zeros(n_params)
    active = wbar > 0.0
    if np.count_nonzero(active) < 0.25 * active.size:
        packed = np.ascontiguousarray(np.packbits(active, axis=1))
        keys = packed.view(np.dtype((np.void, packed.shape[1]))).ravel()
        _, first, group = np.unique(keys, return_index=True, return_inverse=True)
        if len(first) <= max(64, n_samples // 16):
            group = group.ravel()
            order = np.argsort(group, kind='stable')
            counts = np.bincount(group)
            ends = np.cumsum(counts)
            terms = np.arange(n_terms)
            for g, (start, end) in enumerate(zip(ends - counts, ends)):
                rows = order[start:end]
                rules = np.flatnonzero(active[first[g]])
                cols = (rules[:, None] * n_terms + terms).ravel()
                design = (wbar[np.ix_(rows, rules)][:, :, None]
                          * x_ext[rows, None, :]).reshape(len(rows), -1)
                normal[np.ix_(cols, cols)] += design.T @ design
                rhs[cols] += design.T @ y[rows]
            return normal, rhs
    for start in range(0, n_samples, _LSQ_CHUNK_ROWS):
        rows = slice(start, start + _LSQ_CHUNK_ROWS)
        design = (wbar[rows, :, None] * x_ext[rows, None, :]).reshape(-1, n_params)
        normal += design.T @ design     # symmetric rank-k update (BLAS syrk)
        rhs += design.T @ y[rows]
    return normal, rhs


def _sum_over_other_inputs(g: np.ndarray, mu: np.ndarray, i: int) -> np.ndarray:
    """Sum_{r: j_i(r) = j} g_r prod_{k != i} mu_{k, j_k(r)} for every j, shape (N, n_mfs)."""
    n_samples, n_inputs, n_mfs = mu.shape
    t = g
    for k in range(n_inputs - 1, i, -1):    # inputs after i are the fastest-varying rule axes
        t = np.einsum('zij,zj->zi', t.reshape(n_samples, -1, n_mfs), mu[:, k, :])
    for k in range(i):                      # then the slowest-varying axes before i
        t = np.einsum('zj,zjk->zk', mu[:, k, :], t.reshape(n_samples, n_mfs, -1))
    return t.reshape(n_samples, n_mfs)


def premise_gradient(x: np.ndarray, y: np.ndarray, mf_params: np.ndarray, mf: str,
                     consequents: np.ndarray) -> tuple:
    """
    Hybrid learning, backward pass: gradient of the squared error w.r.t. the premise parameters.

    E = sum_n (y_n - yhat_n)^2
    dE/dalpha_ij = sum_n 2 (yhat_n - y_n) sum_{r: j_i(r) = j} (f_rn - yhat_n) / S_n
                   * prod_{k != i} mu_{k, j_k(r)}(x_n) * dmu_ij(x_n)/dalpha_ij,   S_n = sum_r w_rn

    The product over the other inputs is formed directly (never w_r / mu_ij), so it is exact where
    a triangle grade is 0. Vectorised over samples and rules; the loop runs over inputs only.

    Parameters
    ----------
    x : (N, n) array
        Inputs (clipped into the universe), input units.
    y : (N,) array
        Targets.
    mf_params : (n, m, 3) array
        Membership parameters.
    mf : {'triangle', 'gbell'}
        Membership-function type.
    consequents : (R, n + 1) array
        Consequents, row r = (p_r1, ..., p_rn, r_r).

    Returns
    -------
    grad : (n, m, 3) array, dE/d(a, b, c).
    yhat : (N,) array, the network output used (after the consequents, before the step).

    """
    n_samples, n_inputs = x.shape
    n_mfs = mf_params.shape[1]
    mu = membership_grades(x, mf_params, mf)
    wbar, total = normalised_firing_strengths(firing_strengths(mu))
    f = rule_outputs(x, consequents)
    yhat = anfis_output(wbar, f)
    d_e_d_y = 2.0 * (yhat - y)
    g = (d_e_d_y / total)[:, None] * (f - yhat[:, None])        # dE/dw_r, (N, R)
    d_e_d_mu = np.empty((n_samples, n_inputs, n_mfs))
    for i in range(n_inputs):
        d_e_d_mu[:, i, :] = _sum_over_other_inputs(g, mu, i)
    derivative = (triangle_membership_derivatives if mf == 'triangle'
                  else gbell_membership_derivatives)
    d_mu = derivative(x[:, :, None], mf_params[:, :, 0], mf_params[:, :, 1], mf_params[:, :, 2])
    return np.einsum('nij,nijp->ijp', d_e_d_mu, d_mu), yhat


def gradient_step(mf_params: np.ndarray, grad: np.ndarray, step_size: float) -> np.ndarray:
    """
    Hybrid learning: one normalised steepest-descent step on the premise parameters (Jang).

    alpha <- alpha - eta dE/dalpha,   eta = k / sqrt(sum_alpha (dE/dalpha)^2)

    so the whole parameter vector moves by exactly k (input units). A zero gradient moves nothing.

    Parameters
    ----------
    mf_params : (n, m, 3) array
        Membership parameters (a, b, c).
    grad : (n, m, 3) array
        From :func:`premise_gradient`.
    step_size : float
        Step size k, input units.

    Returns
    -------
    (n, m, 3) array, new parameters (not yet projected, see :func:`project_mf_params`).

    """
    norm = float(np.sqrt(np.sum(grad * grad)))
    if not norm > 0.0 or not math.isfinite(norm):
        return mf_params.copy()
    return mf_params - (step_size / norm) * grad


def update_step_size(step_size: float, errors, last_increase: int, last_decrease: int,
                     increase_rate: float = 1.1, decrease_rate: float = 0.9) -> tuple:
    """
    Jang's heuristic step-size rules, applied after epoch e = len(errors) - 1.

    decrease: k <- decrease_rate * k  if E_e < E_e-1 > E_e-2 < E_e-3 > E_e-4 (two up-down
              oscillations: up, down, up, down) and e - last_decrease >= 4;
    otherwise increase: k <- increase_rate * k  if E_e < E_e-1 < E_e-2 < E_e-3 < E_e-4 (four
              consecutive reductions) and e - last_increase >= 4.
    Each rule looks only at epochs since it last fired (as MATLAB's anfis does), so a steady
    decrease raises k every fourth epoch, not every epoch.

    Parameters
    ----------
    step_size : float
        Current k.
    errors : sequence of float
        Training error of every epoch so far (epoch 0 first).
    last_increase, last_decrease : int
        Epoch at which each rule last fired (0 at the start).
    increase_rate, decrease_rate : float
        Factors (MATLAB defaults 1.1 and 0.9).

    Returns
    -------
    (step_size, last_increase, last_decrease) after the update.

    """
    epoch = len(errors) - 1
    if epoch < 4:
        return step_size, last_increase, last_decrease
    e = [float(v) for v in errors[-5:]]   # e[4] = E_epoch, ..., e[0] = E_epoch-4
    if epoch - last_decrease >= 4 and e[4] < e[3] > e[2] < e[1] > e[0]:
        return step_size * decrease_rate, last_increase, epoch
    if epoch - last_increase >= 4 and e[4] < e[3] < e[2] < e[1] < e[0]:
        return step_size * increase_rate, epoch, last_decrease
    return step_size, last_increase, last_decrease


def grid_partition(input_range: np.ndarray, n_mfs: int, mf: str) -> np.ndarray:
    """
    Make the initial membership functions: grid partition of each input range (MATLAB genfis).

    centres c_j = lo + j (hi - lo) / (m - 1),  j = 0 .. m - 1,  spacing d = (hi - lo) / (m - 1)
    triangle: (a, b, c) = (c_j - d, c_j, c_j + d), each reaching its neighbours' peaks
    gbell:    (a, b, c) = (d / 2, 2, c_j)   (genfis: a = range / (2 (m - 1)), b = 2)

    Parameters
    ----------
    input_range : (n, 2) array
        (lo, hi) per input, lo < hi, input units.
    n_mfs : int >= 2
        Membership functions per input.
    mf : {'triangle', 'gbell'}
        Membership-function type.

    Returns
    -------
    (n, n_mfs, 3) array of (a, b, c).

    """
    lo, hi = input_range[:, 0:1], input_range[:, 1:2]
    spacing = (hi - lo) / (n_mfs - 1)
    centres = lo + spacing * np.arange(n_mfs)
    if mf == 'triangle':
        return np.stack((centres - spacing, centres, centres + spacing), axis=-1)
    return np.stack((np.broadcast_to(spacing / 2.0, centres.shape),
                     np.full(centres.shape, 2.0), centres), axis=-1)


def project_mf_params(mf_params: np.ndarray, mf: str, input_range: np.ndarray) -> np.ndarray:
    """
    Keep membership functions valid and covering the universe after a gradient step.

    triangle (per input, MFs taken in order of their peaks b_(0) <= ... <= b_(m-1)),
        a <= b - w,  c >= b + w                      (non-zero width, w = 1e-3 (hi - lo))
        a_(s) <= b_(s-1),  c_(s) >= b_(s+1)          (each triangle reaches its neighbours' peaks)
        a_(0) <= min(lo, b_(0)) - w,  c_(m-1) >= max(hi, b_(m-1)) + w   (outer ones pass the edges)
    gbell: a >= w, b >= 1/2.
    The projection only widens, so every point of [lo, hi] keeps a positive grade on each input
    and, the rule base being a grid, some rule always fires there.

    Parameters
    ----------
    mf_params : (n, m, 3) array
        Membership parameters (a, b, c).
    mf : {'triangle', 'gbell'}
        Membership-function type.
    input_range : (n, 2) array
        Universe (lo, hi) per input.

    Returns
    -------
    (n, m, 3) array, projected copy.

    """
    out = np.array(mf_params, dtype=float)
    lo, hi = input_range[:, 0], input_range[:, 1]
    min_width = MIN_WIDTH_FRACTION * (hi - lo)
    if mf == 'gbell':
        out[:, :, 0] = np.maximum(out[:, :, 0], min_width[:, None])
        out[:, :, 1] = np.maximum(out[:, :, 1], MIN_GBELL_SLOPE)
        return out
    a, b, c = out[:, :, 0], out[:, :, 1], out[:, :, 2]
    order = np.argsort(b, axis=1, kind='stable')
    peaks = np.take_along_axis(b, order, axis=1)
    left_peak = np.concatenate(((np.minimum(lo, peaks[:, 0]) - min_width)[:, None],
                                peaks[:, :-1]), axis=1)
    right_peak = np.concatenate((peaks[:, 1:],
                                 (np.maximum(hi, peaks[:, -1]) + min_width)[:, None]), axis=1)
    left_limit = np.empty_like(b)
    right_limit = np.empty_like(b)
    np.put_along_axis(left_limit, order, left_peak, axis=1)
    np.put_along_axis(right_limit, order, right_peak, axis=1)
    out[:, :, 0] = np.minimum(np.minimum(a, left_limit), b - min_width[:, None])
    out[:, :, 2] = np.maximum(np.maximum(c, right_limit), b + min_width[:, None])
    return out


def _rmse(residual: np.ndarray) -> float:
    return float(np.sqrt(np.mean(residual * residual)))


# --------------------------------------------------------------------------------- validation

def _check_count(name: str, value, minimum: int) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f'{name} must be an int >= {minimum}, got {value!r}')
    if value < minimum:
        raise ValueError(f'{name} must be an int >= {minimum}, got {value}')
    return int(value)


def _check_inputs(name: str, x, n_inputs: int) -> np.ndarray:
    try:
        x = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as err:
        raise ValueError(f'{name} must be a numeric (N, {n_inputs}) array: {err}') from None
    if x.ndim != 2 or x.shape[1] != n_inputs:
        raise ValueError(f'{name} must have shape (N, {n_inputs}) (one row per sample), '
                         f'got {x.shape}; reshape a single sample with x[None, :]')
    if not np.isfinite(x).all():
        bad = np.argwhere(~np.isfinite(x))[0]
        raise ValueError(f'{name} holds non-finite values (first at row {bad[0]}, column '
                         f'{bad[1]}); drop or repair those samples first')
    return x


def _check_targets(name: str, y, n_samples: int) -> np.ndarray:
    try:
        y = np.asarray(y, dtype=float)
    except (TypeError, ValueError) as err:
        raise ValueError(f'{name} must be a numeric (N,) array: {err}') from None
    if y.shape != (n_samples,):
        raise ValueError(f'{name} must have shape ({n_samples},) to match the inputs, '
                         f'got {y.shape}')
    if not np.all(np.isfinite(y)):
        raise ValueError(f'{name} holds non-finite values (first at index '
                         f'{int(np.argmax(~np.isfinite(y)))}); drop or repair those samples first')
    return y


def _uncovered_point(mf_params_1d: np.ndarray, lo: float, hi: float) -> Optional[float]:
    """First point of [lo, hi] where every triangle (a, c) support misses, or None if covered."""
    position = lo
    while True:
        reach = [c for a, _, c in mf_params_1d if a < position < c]
        if not reach:
            return position
        position = max(reach)
        if position > hi:
            return None


def _validate_params(mf_params: np.ndarray, consequents: np.ndarray, input_range: np.ndarray,
                     mf: str):
    n_inputs, n_mfs = mf_params.shape[:2]
    if mf_params.shape != (n_inputs, n_mfs, 3):
        raise ValueError(f'mf_params must have shape (n_inputs, n_mfs, 3), got {mf_params.shape}')
    expected = (n_mfs ** n_inputs, n_inputs + 1)
    if consequents.shape != expected:
        raise ValueError(f'consequents must have shape {expected} (n_mfs ** n_inputs rules, '
                         f'n_inputs + 1 coefficients), got {consequents.shape}')
    if input_range.shape != (n_inputs, 2):
        raise ValueError(f'input_range must have shape ({n_inputs}, 2), got {input_range.shape}')
    for name, array in (('mf_params', mf_params), ('consequents', consequents),
                        ('input_range', input_range)):
        if not np.all(np.isfinite(array)):
            raise ValueError(f'{name} holds non-finite numbers')
    if not np.all(input_range[:, 0] < input_range[:, 1]):
        i = int(np.argmin(input_range[:, 0] < input_range[:, 1]))
        raise ValueError(f'input_range of input {i} must have lo < hi, got {input_range[i]}')
    a, b, c = mf_params[:, :, 0], mf_params[:, :, 1], mf_params[:, :, 2]
    if mf == 'triangle':
        if not np.all((a < b) & (b < c)):
            i, j = np.argwhere(~((a < b) & (b < c)))[0]
            raise ValueError(f'triangle {j} of input {i} must have a < b < c, '
                             f'got {mf_params[i, j]}')
        for i in range(n_inputs):
            point = _uncovered_point(mf_params[i], input_range[i, 0], input_range[i, 1])
            if point is not None:
                raise ValueError(f'the triangles of input {i} leave {point!r} of its universe '
                                 f'{input_range[i]} uncovered (no rule would fire there)')
    elif not np.all((a > 0) & (b > 0)):
        i, j = np.argwhere(~((a > 0) & (b > 0)))[0]
        raise ValueError(f'bell {j} of input {i} must have width a > 0 and slope b > 0, '
                         f'got {mf_params[i, j]}')


# --------------------------------------------------------------------------------- model

@dataclass(frozen=True)
class EpochReport:
    """
    Progress of one training epoch, passed to the ``callback`` of :meth:`Anfis.fit`.

    Attributes
    ----------
    epoch : int, 0-based epoch index.
    epochs : int, number of epochs requested.
    train_rmse : float, training RMSE after this epoch's least-squares step, output units.
    check_rmse : float or None, checking RMSE of the same parameters (None without checking data).
    step_size : float, step size k of this epoch's gradient step, input units.

    """

    epoch: int
    epochs: int
    train_rmse: float
    check_rmse: Optional[float]
    step_size: float


class Anfis:
    """
    First-order Takagi-Sugeno ANFIS on a grid rule base, trained by Jang's hybrid rule [1].

    Parameters
    ----------
    n_inputs : int >= 1
        Number of inputs n.
    n_mfs : int >= 2
        Membership functions per input m (with 3 they are the S, Z, B sets); the rule base has
        m ** n rules (243 for 5 inputs x 3), each with n + 1 consequents.
    mf : {'triangle', 'gbell'}
        Membership-function type.

    Attributes
    ----------
    rule_mf_index : (m ** n, n) int array, membership function of each input used by each rule.
    mf_params_ : (n, m, 3) array or None, (a, b, c) per membership function, see :data:`MF_TYPES`.
    consequents_ : (m ** n, n + 1) array or None, row r = (p_r1, ..., p_rn, r_r).
    input_range_ : (n, 2) array or None, universe (lo, hi) per input; inputs are clipped into it.
    train_rmse_ : (epochs,) array or None, training RMSE per epoch (after its least-squares step).
    check_rmse_ : (epochs,) array or None, checking RMSE per epoch (None without checking data).
    step_size_ : (epochs,) array or None, step size k used by each epoch's gradient step.
    best_epoch_ : int or None, epoch whose parameters were kept: lowest checking RMSE if checking
        data were given, else lowest training RMSE.
    metadata_ : dict, free-form JSON information saved with the model (e.g. how it was trained).

    Examples
    --------
    >>> model = Anfis(n_inputs=5, n_mfs=3).fit(x_train, y_train, epochs=20,
    ...                                         X_check=x_check, y_check=y_check)
    >>> model.save('anfis.json'); y = Anfis.load('anfis.json').predict(x)

    """

    def __init__(self, n_inputs: int, n_mfs: int = 3, mf: str = 'triangle'):
        self.n_inputs = _check_count('n_inputs', n_inputs, 1)
        self.n_mfs = _check_count('n_mfs', n_mfs, 2)
        if mf not in MF_TYPES:
            raise ValueError(f'mf must be one of {MF_TYPES}, got {mf!r}')
        self.mf = mf
        n_params = self.n_mfs ** self.n_inputs * (self.n_inputs + 1)
        if n_params > MAX_CONSEQUENT_PARAMS:
            raise ValueError(
                f'{self.n_inputs} inputs x {self.n_mfs} MFs give {self.n_mfs ** self.n_inputs} '
                f'rules and {n_params} consequents, more than {MAX_CONSEQUENT_PARAMS} (the '
                'least-squares step would need a normal matrix of that size squared); use fewer '
                'inputs or membership functions')
        self.rule_mf_index = grid_rule_indices(self.n_inputs, self.n_mfs)
        self.mf_params_ = None
        self.consequents_ = None
        self.input_range_ = None
        self.train_rmse_ = None
        self.check_rmse_ = None
        self.step_size_ = None
        self.best_epoch_ = None
        self.metadata_ = {}

    def __repr__(self):
        state = 'fitted' if self.is_fitted else 'not fitted'
        return f'Anfis(n_inputs={self.n_inputs}, n_mfs={self.n_mfs}, mf={self.mf!r}) [{state}]'

    @property
    def n_rules(self) -> int:
        """Return the number of rules, n_mfs ** n_inputs."""
        return self.n_mfs ** self.n_inputs

    @property
    def is_fitted(self) -> bool:
        """Tell whether the model has parameters (after :meth:`fit`, :meth:`load`, ...)."""
        return self.consequents_ is not None

    # ----------------------------------------------------------------------------- training

    def fit(self, X, y, epochs: int = 10, X_check=None, y_check=None, *,
            step_size: float = 0.01, step_increase: float = 1.1, step_decrease: float = 0.9,
            ridge: float = DEFAULT_RIDGE, input_range=None,
            callback: Optional[Callable[[EpochReport], Optional[bool]]] = None) -> 'Anfis':
        """
        Train by Jang's hybrid rule from a grid-partition start; returns self.

        Each epoch: membership grades -> least-squares consequents -> training (and checking)
        RMSE -> step-size rules -> gradient step on the membership parameters -> projection. The
        last epoch stops after its least-squares step. The parameters of the best epoch are kept
        (lowest checking RMSE with checking data, else lowest training RMSE).

        Parameters
        ----------
        X : (N, n_inputs) array
            Training inputs, finite, N >= 2.
        y : (N,) array
            Training targets, finite.
        epochs : int >= 1
            Number of epochs.
        X_check, y_check : (M, n_inputs) and (M,) arrays or None
            Checking data (both or neither).
        step_size : float > 0
            Initial step size k, input units (MATLAB default 0.01).
        step_increase, step_decrease : float > 0
            Factors of Jang's step-size rules.
        ridge : float >= 0
            Least-squares regularisation relative to mean(diag(A^T A)), see
            :func:`least_squares_consequents` and :data:`DEFAULT_RIDGE`.
        input_range : (n_inputs, 2) array or None
            Universe (lo, hi) per input; default the training range. Inputs outside it are
            clipped into it.
        callback : callable or None
            Called with an :class:`EpochReport` after every epoch; a return value of True stops
            training after that epoch.

        Raises
        ------
        ValueError : bad shapes, non-finite values, a constant input column, bad options.

        """
        x = _check_inputs('X', X, self.n_inputs)
        if x.shape[0] < 2:
            raise ValueError(f'X needs at least 2 samples, got {x.shape[0]}')
        y = _check_targets('y', y, x.shape[0])
        if (X_check is None) != (y_check is None):
            raise ValueError('give both X_check and y_check, or neither')
        if X_check is not None:
            x_check = _check_inputs('X_check', X_check, self.n_inputs)
            y_check = _check_targets('y_check', y_check, x_check.shape[0])
        epochs = _check_count('epochs', epochs, 1)
        check_positive('step_size', step_size)
        check_positive('step_increase', step_increase)
        check_positive('step_decrease', step_decrease)
        step_size, step_increase, step_decrease = (
            float(step_size), float(step_increase), float(step_decrease))
        check_finite('ridge', ridge)
        check_range('ridge', ridge, 0.0, math.inf)
        universe = self._check_range(x, input_range)

        x = np.clip(x, universe[:, 0], universe[:, 1])
        mf_params = grid_partition(universe, self.n_mfs, self.mf)
        train_rmse, check_rmse, step_sizes = [], [], []
        last_increase = last_decrease = 0
        best = (math.inf, -1, None, None)
        for epoch in range(epochs):
            mu = membership_grades(x, mf_params, self.mf)
            wbar, _ = normalised_firing_strengths(firing_strengths(mu))
            consequents = least_squares_consequents(wbar, x, y, float(ridge))
            train_rmse.append(_rmse(anfis_output(wbar, rule_outputs(x, consequents)) - y))
            score = train_rmse[-1]
            if X_check is not None:
                check_rmse.append(_rmse(
                    self._evaluate(x_check, mf_params, consequents, universe) - y_check))
                score = check_rmse[-1]
            if score < best[0]:
                best = (score, epoch, mf_params.copy(), consequents)
            step_size, last_increase, last_decrease = update_step_size(
                step_size, train_rmse, last_increase, last_decrease, step_increase, step_decrease)
            step_sizes.append(step_size)
            stop = callback is not None and callback(EpochReport(
                epoch, epochs, train_rmse[-1], check_rmse[-1] if check_rmse else None,
                step_size)) is True
            if stop or epoch == epochs - 1:
                break
            grad, _ = premise_gradient(x, y, mf_params, self.mf, consequents)
            mf_params = project_mf_params(gradient_step(mf_params, grad, step_size), self.mf,
                                          universe)
        if best[2] is None:
            raise ValueError('training produced no finite error (check the scale of X and y)')
        _, self.best_epoch_, self.mf_params_, self.consequents_ = best
        self.input_range_ = universe
        self.train_rmse_ = np.array(train_rmse)
        self.check_rmse_ = np.array(check_rmse) if X_check is not None else None
        self.step_size_ = np.array(step_sizes)
        return self

    def _check_range(self, x: np.ndarray, input_range) -> np.ndarray:
        if input_range is None:
            universe = np.stack((x.min(axis=0), x.max(axis=0)), axis=1)
            constant = np.flatnonzero(~(universe[:, 0] < universe[:, 1]))
            if constant.size:
                raise ValueError(f'input column(s) {constant.tolist()} of X are constant; ANFIS '
                                 'cannot partition them: drop them or pass input_range')
            return universe
        universe = _check_inputs('input_range', input_range, 2)
        if universe.shape != (self.n_inputs, 2) or not np.all(universe[:, 0] < universe[:, 1]):
            raise ValueError(f'input_range must be ({self.n_inputs}, 2) rows (lo, hi) with '
                             f'lo < hi, got {universe.tolist()}')
        return universe.copy()

    # ----------------------------------------------------------------------------- inference

    def _require_fitted(self):
        if not self.is_fitted:
            raise RuntimeError('the Anfis model has no parameters yet: call fit() or use '
                               'Anfis.load(path)')

    def _evaluate(self, x, mf_params, consequents, universe) -> np.ndarray:
        x = np.minimum(np.maximum(x, universe[:, 0]), universe[:, 1])    # clip into universe
        mu = membership_grades(x, mf_params, self.mf)
        wbar, _ = normalised_firing_strengths(firing_strengths(mu))
        return anfis_output(wbar, rule_outputs(x, consequents))

    def predict(self, X) -> np.ndarray:
        """
        Network output for every row of X (layers 1-5, inputs clipped into the universe).

        Parameters
        ----------
        X : (N, n_inputs) array
            Finite, input units; one sample as x[None, :].

        Returns
        -------
        (N,) array, output units.

        """
        self._require_fitted()
        x = _check_inputs('X', X, self.n_inputs)
        return self._evaluate(x, self.mf_params_, self.consequents_, self.input_range_)

    def memberships(self, X) -> np.ndarray:
        """Layer 1 grades mu_ij(x_i) of the clipped inputs, shape (N, n_inputs, n_mfs)."""
        self._require_fitted()
        x = _check_inputs('X', X, self.n_inputs)
        x = np.clip(x, self.input_range_[:, 0], self.input_range_[:, 1])
        return membership_grades(x, self.mf_params_, self.mf)

    def firing_strengths(self, X, normalised: bool = True) -> np.ndarray:
        """
        Compute the firing strength of every rule for every row of X, shape (N, n_rules).

        w_r = prod_i mu_{i, j_i(r)}(clip(x_i))          (layer 2, normalised=False)
        wbar_r = w_r / max(sum_s w_s, tiny)             (layer 3, normalised=True; sums to 1)

        Rule r uses membership functions ``rule_mf_index[r]``.
        """
        w = firing_strengths(self.memberships(X))
        return normalised_firing_strengths(w)[0] if normalised else w

    # ----------------------------------------------------------------------------- files

    @classmethod
    def from_params(cls, mf_params, consequents, input_range, mf: str = 'triangle',
                    metadata: Optional[dict] = None) -> 'Anfis':
        """
        Build a fitted model from explicit parameters (validated, copied).

        Parameters
        ----------
        mf_params : (n, m, 3) array
            (a, b, c) per membership function; triangles need
            a < b < c and must cover the universe, bells a > 0 and b > 0.
        consequents : (m ** n, n + 1) array
            Row r = (p_r1, ..., p_rn, r_r).
        input_range : (n, 2) array
            Universe (lo, hi) per input, lo < hi.
        mf : {'triangle', 'gbell'}
            Membership-function type.
        metadata : dict or None
            Free-form JSON information kept in ``metadata_``.

        Raises
        ------
        ValueError : shapes, non-finite numbers or invalid membership functions.

        """
        arrays = []
        for name, value in (('mf_params', mf_params), ('consequents', consequents),
                            ('input_range', input_range)):
            try:
                arrays.append(np.array(value, dtype=float))
            except (TypeError, ValueError) as err:
                raise ValueError(f'{name} must be a numeric array: {err}') from None
        mf_params, consequents, input_range = arrays
        if mf_params.ndim != 3:
            raise ValueError('mf_params must have shape (n_inputs, n_mfs, 3), '
                             f'got {mf_params.shape}')
        model = cls(mf_params.shape[0], mf_params.shape[1], mf)
        _validate_params(mf_params, consequents, input_range, mf)
        model.mf_params_ = mf_params
        model.consequents_ = consequents
        model.input_range_ = input_range
        model.metadata_ = dict(metadata or {})
        return model

    def to_dict(self) -> dict:
        """JSON-ready description of the fitted model (what :meth:`save` writes)."""
        self._require_fitted()
        return {
            'format': FORMAT_NAME,
            'version': FORMAT_VERSION,
            'mf': self.mf,
            'n_inputs': self.n_inputs,
            'n_mfs': self.n_mfs,
            'rule_base': 'grid',
            'input_range': self.input_range_.tolist(),
            'mf_params': self.mf_params_.tolist(),
            'consequents': self.consequents_.tolist(),
            'metadata': self.metadata_,
        }

    def save(self, path, metadata: Optional[dict] = None):
        """
        Write the model as JSON (format ``anfis_elevation_ros.anfis`` version 1), atomically.

        Floats are written with Python's shortest round-trip repr, so :meth:`load` restores them
        to the bit. Arrays are written one row per line, so model diffs stay readable.

        Parameters
        ----------
        path : str or os.PathLike
            Destination file (replaced atomically).
        metadata : dict or None
            JSON-serialisable information to store (merged into
            ``metadata_``), e.g. the training command and data set.

        """
        if metadata:
            self.metadata_ = {**self.metadata_, **metadata}
        doc = self.to_dict()
        lines = []
        for key, value in doc.items():
            if key in ('input_range', 'consequents', 'mf_params'):
                rows = ',\n    '.join(json.dumps(row, allow_nan=False) for row in value)
                text = f'[\n    {rows}\n  ]'
            else:
                text = json.dumps(value, allow_nan=False, sort_keys=True)
            lines.append(f'  {json.dumps(key)}: {text}')
        write_text_atomically(path, '{\n' + ',\n'.join(lines) + '\n}\n')

    @classmethod
    def load(cls, path) -> 'Anfis':
        """
        Read a model written by :meth:`save`, validating everything.

        Raises
        ------
        InputError : missing or unreadable file, invalid JSON, wrong format or version, missing or
            unknown keys, wrong shapes or types, non-finite numbers, invalid membership functions.

        """
        path = os.fspath(path)
        hint = 'train a model (anfis_elevation_ros train) or pass the path of a saved one'
        doc = read_json_file(path, MAX_MODEL_BYTES, 'ANFIS model', hint)
        return cls._from_document(doc, path)

    @classmethod
    def _from_document(cls, doc, path: str) -> 'Anfis':
        def fail(message):
            raise InputError(f'{path}: {message}')

        if not isinstance(doc, dict):
            fail(f'expected a JSON object with "format": "{FORMAT_NAME}", '
                 f'got {type(doc).__name__}')
        if doc.get('format') != FORMAT_NAME:
            fail(f'format is {doc.get("format")!r}, expected {FORMAT_NAME!r}: not an ANFIS model '
                 'file of this package')
        if type(doc.get('version')) is not int or doc['version'] != FORMAT_VERSION:
            fail(f'version {doc.get("version")!r} is not supported (this reader reads version '
                 f'{FORMAT_VERSION}); re-save the model with this version of the package')
        required = ('format', 'version', 'mf', 'n_inputs', 'n_mfs', 'rule_base', 'input_range',
                    'mf_params', 'consequents')
        missing = [key for key in required if key not in doc]
        unknown = sorted(set(doc) - set(required) - {'metadata'})
        if missing or unknown:
            fail(f'missing keys {missing} / unknown keys {unknown}; expected {list(required)} '
                 'and optionally "metadata"')
        if doc['mf'] not in MF_TYPES:
            fail(f'mf is {doc["mf"]!r}, expected one of {list(MF_TYPES)}')
        if doc['rule_base'] != 'grid':
            fail(f'rule_base is {doc["rule_base"]!r}, only "grid" is supported')
        counts = {}
        for key, minimum in (('n_inputs', 1), ('n_mfs', 2)):
            if type(doc[key]) is not int or doc[key] < minimum:
                fail(f'{key} must be an integer >= {minimum}, got {doc[key]!r}')
            counts[key] = doc[key]
        if not isinstance(doc.get('metadata', {}), dict):
            fail('metadata must be a JSON object')
        n_inputs, n_mfs = counts['n_inputs'], counts['n_mfs']
        # Each count alone first: n_mfs ** n_inputs of a huge n_inputs would never finish.
        if max(n_inputs, n_mfs) > MAX_CONSEQUENT_PARAMS \
                or n_mfs ** n_inputs * (n_inputs + 1) > MAX_CONSEQUENT_PARAMS:
            fail(f'{n_inputs} inputs x {n_mfs} MFs exceed {MAX_CONSEQUENT_PARAMS} consequents')
        shapes = {'input_range': (n_inputs, 2), 'mf_params': (n_inputs, n_mfs, 3),
                  'consequents': (n_mfs ** n_inputs, n_inputs + 1)}
        arrays = {}
        for key, shape in shapes.items():
            array = None
            if _only_numbers(doc[key], len(shape)):
                try:
                    array = np.array(doc[key], dtype=float)
                except (TypeError, ValueError, OverflowError):
                    array = None
            if array is None or array.shape != shape:
                fail(f'{key} must be a {shape} array of numbers (n_inputs = {n_inputs}, n_mfs = '
                     f'{n_mfs}), got {_describe(doc[key], array)}')
            if not np.all(np.isfinite(array)):
                fail(f'{key} holds non-finite numbers')
            arrays[key] = array
        try:
            return cls.from_params(arrays['mf_params'], arrays['consequents'],
                                   arrays['input_range'], doc['mf'], doc.get('metadata'))
        except ValueError as err:
            raise InputError(f'{path}: {err}') from None


def _only_numbers(value, depth: int) -> bool:
    """
    Return True if value is a number or lists of numbers nested at most ``depth`` deep.

    JSON true/false are not numbers; the depth bound keeps a deeply nested document from
    exhausting the recursion limit.
    """
    if isinstance(value, list):
        return depth > 0 and all(_only_numbers(item, depth - 1) for item in value)
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _describe(value, array) -> str:
    if array is None:
        return f'a {type(value).__name__} that is not a rectangular array of numbers'
    return f'shape {array.shape}'
