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
The five layers of a first-order Takagi-Sugeno ANFIS [1] (the forward pass), numpy only.

Layer 1  :func:`membership_grades`  mu_ij = mu(x_i; a_ij, b_ij, c_ij), triangular
         (:func:`triangle_membership`) or generalised bell (:func:`gbell_membership`).
Layer 2  :func:`firing_strengths`  w_r = prod_i mu_{i, j_i(r)} (product t-norm) over the grid rule
         base, rule r <-> (j_1, ..., j_n), first input varying slowest (:func:`grid_rule_indices`).
Layer 3  :func:`normalised_firing_strengths`  wbar_r = w_r / sum_s w_s.
Layer 4  :func:`rule_outputs`  f_r = p_r . x + r_r (first-order consequents).
Layer 5  :func:`anfis_output`  y = sum_r wbar_r f_r.

The derivatives of the membership functions, used by the learning's backward pass
(``core/anfis_learning.py``), sit beside them.

References
----------
[1] J.-S. R. Jang, "ANFIS: adaptive-network-based fuzzy inference system", IEEE Transactions on
    Systems, Man, and Cybernetics 23(3), 665-685, 1993.

"""

import numpy as np

MF_TYPES = ('triangle', 'gbell')
"""Membership-function types; parameters (a, b, c) are feet-peak-foot or width-slope-centre."""

_TINY = np.finfo(float).tiny


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
