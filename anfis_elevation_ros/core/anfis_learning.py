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
Jang's hybrid learning of an ANFIS [1]: least squares and gradient descent.

Least squares fits the consequents, gradient descent the membership functions.

One epoch: with the premise (membership) parameters fixed, the output is linear in the
consequents, which :func:`least_squares_consequents` solves in one ridge-regularised
least-squares step; then :func:`premise_gradient` back-propagates the squared error to the
membership parameters and :func:`gradient_step` moves them by a step of length k along the
negative gradient, k adapted by Jang's heuristic rules (:func:`update_step_size`).
:func:`project_mf_params` keeps the membership functions valid. Initial membership functions are
a grid partition of each input's training range as MATLAB ``genfis`` makes it
(:func:`grid_partition`) [2].

References
----------
[1] J.-S. R. Jang, "ANFIS: adaptive-network-based fuzzy inference system", IEEE Transactions on
    Systems, Man, and Cybernetics 23(3), 665-685, 1993.
[2] The MathWorks, Fuzzy Logic Toolbox: ``genfis`` (grid partition defaults) and ``anfis``
    (step-size rules, initial step 0.01, rates 0.9 / 1.1).

"""

import math

import numpy as np

from .anfis_layers import anfis_output, firing_strengths, gbell_membership_derivatives
from .anfis_layers import membership_grades, normalised_firing_strengths, rule_outputs
from .anfis_layers import triangle_membership_derivatives

MAX_CONSEQUENT_PARAMS = 5000
"""Largest n_rules * (n_inputs + 1): the normal matrix of the least-squares step is its square."""
DEFAULT_RIDGE = 0.0
"""
Default ridge factor of :func:`least_squares_consequents`, relative to mean(diag(A^T A)).

0 is Jang's plain least squares, so the defaults reproduce his Mackey-Glass result (4 inputs x 2
bells, 500 epochs on his own files: checking RMSE 0.00138, against 0.0040 with 1e-4; Jang reports
0.0016). A rule base with many more unknowns than samples needs regularisation: the stair training
tool passes its own (``tools/cross_validation.py``, ``DEFAULT_TRAIN_RIDGE``).
"""
MIN_WIDTH_FRACTION = 1e-3
"""Smallest triangle half-width and bell width a, as a fraction of the input's universe width."""
MIN_GBELL_SLOPE = 0.5
"""Smallest bell slope b: 2b >= 1 keeps the bell differentiable in its centre c."""

_LSQ_CHUNK_ROWS = 2048


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
