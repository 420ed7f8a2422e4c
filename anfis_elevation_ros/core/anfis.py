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

The network has Jang's five layers [1], each one function of ``core/anfis_layers.py`` with its
equation in the docstring: membership grades (:func:`membership_grades`, triangles or
generalised bells), rule firing strengths over the grid rule base (:func:`firing_strengths`),
their normalisation (:func:`normalised_firing_strengths`), first-order rule outputs
(:func:`rule_outputs`) and their weighted sum (:func:`anfis_output`).

Hybrid learning (``core/anfis_learning.py``), one epoch [1]: with the premise (membership)
parameters fixed, the output is linear in the consequents, which
:func:`least_squares_consequents` solves in one ridge-regularised least-squares step; then
:func:`premise_gradient` back-propagates the squared error to the membership parameters and
:func:`gradient_step` moves them by a step of length k along the negative gradient, k adapted by
Jang's heuristic rules (:func:`update_step_size`). :func:`project_mf_params` keeps the membership
functions valid, and with checking data the parameters of the epoch with the lowest checking
error are kept, as MATLAB's ``anfis`` does [2]. Initial membership functions are a grid
partition of each input's training range as MATLAB ``genfis`` makes it (:func:`grid_partition`)
[2].

Inputs outside the universe. Every input is clipped into its universe (the training range, stored
with the model) before any layer is evaluated, so ``predict(x) == predict(clip(x, lo, hi))``: the
model saturates at the edge of the data it has seen instead of extrapolating its linear
consequents. The universe is always covered: the projection keeps each triangle reaching its
neighbours' peaks and the outer triangles reaching past the universe edges, and bells are positive
everywhere, so some rule always fires there. As a last guard the normalisation divides by
max(sum w, tiny); should no rule fire at all (only possible for a hand-made model, and
:meth:`Anfis.from_params` refuses uncovered triangles) all normalised strengths are 0 and the
output is 0.

Modules: the layers in ``core/anfis_layers.py``, the learning in ``core/anfis_learning.py``,
the model file in ``core/anfis_file.py``; this one holds the model object.

Public API: :class:`Anfis` (``fit``, ``predict``, ``memberships``, ``firing_strengths``, ``save``,
``load``, ``from_params``), :class:`EpochReport`, and (re-exported) the layer and learning
functions above and the constants of the three modules.

References
----------
[1] J.-S. R. Jang, "ANFIS: adaptive-network-based fuzzy inference system", IEEE Transactions on
    Systems, Man, and Cybernetics 23(3), 665-685, 1993.
[2] The MathWorks, Fuzzy Logic Toolbox: ``genfis`` (grid partition defaults) and ``anfis``
    (step-size rules, initial step 0.01, rates 0.9 / 1.1; best-checking-error parameters).

"""

from dataclasses import dataclass
import math
import os
from typing import Callable, Optional

import numpy as np

from .anfis_file import FORMAT_NAME, FORMAT_VERSION, MAX_MODEL_BYTES, model_arrays
from .anfis_file import model_file_text, validate_params
from .anfis_layers import anfis_output, firing_strengths, gbell_membership
from .anfis_layers import gbell_membership_derivatives, grid_rule_indices, membership_grades
from .anfis_layers import MF_TYPES, normalised_firing_strengths, rule_outputs
from .anfis_layers import triangle_membership, triangle_membership_derivatives
from .anfis_learning import DEFAULT_RIDGE, gradient_step, grid_partition
from .anfis_learning import least_squares_consequents, MAX_CONSEQUENT_PARAMS, MIN_GBELL_SLOPE
from .anfis_learning import MIN_WIDTH_FRACTION, premise_gradient, project_mf_params
from .anfis_learning import update_step_size
from .errors import InputError
from .json_file import read_json_file, write_text_atomically
from .validation import check_finite, check_positive, check_range

__all__ = [
    'Anfis', 'EpochReport',
    'FORMAT_NAME', 'FORMAT_VERSION', 'MAX_MODEL_BYTES',
    'anfis_output', 'firing_strengths', 'gbell_membership', 'gbell_membership_derivatives',
    'grid_rule_indices', 'membership_grades', 'MF_TYPES', 'normalised_firing_strengths',
    'rule_outputs', 'triangle_membership', 'triangle_membership_derivatives',
    'DEFAULT_RIDGE', 'gradient_step', 'grid_partition', 'least_squares_consequents',
    'MAX_CONSEQUENT_PARAMS', 'MIN_GBELL_SLOPE', 'MIN_WIDTH_FRACTION', 'premise_gradient',
    'project_mf_params', 'update_step_size']


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
        validate_params(mf_params, consequents, input_range, mf)
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
        write_text_atomically(path, model_file_text(self.to_dict()))

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
        mf_params, consequents, input_range, mf, metadata = model_arrays(doc, path)
        try:
            return cls.from_params(mf_params, consequents, input_range, mf, metadata)
        except ValueError as err:
            raise InputError(f'{path}: {err}') from None
