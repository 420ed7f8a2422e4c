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
The ANFIS model file: JSON, format ``anfis_elevation_ros.anfis`` version 1.

A model file is data, validated on load as a whole: format and version, keys, shapes, numbers,
membership functions that cover their universe (:func:`validate_params`). Floats are written
with Python's shortest round-trip repr, so a saved model loads to the bit; arrays one row per
line, so model diffs stay readable.

Public API: ``FORMAT_NAME``, ``FORMAT_VERSION``, ``MAX_MODEL_BYTES``, :func:`model_file_text`,
:func:`model_arrays`, :func:`validate_params`.
"""

import json
from typing import Optional

import numpy as np

from .anfis_layers import MF_TYPES
from .anfis_learning import MAX_CONSEQUENT_PARAMS
from .errors import InputError

FORMAT_NAME = 'anfis_elevation_ros.anfis'
"""Value of the ``format`` key of a saved model."""
FORMAT_VERSION = 1
"""Value of the ``version`` key of a saved model; :meth:`Anfis.load` reads only this version."""
MAX_MODEL_BYTES = 10_000_000
"""Largest model file :meth:`Anfis.load` reads; the largest rule base takes about 0.2 MB."""


def model_file_text(doc: dict) -> str:
    """
    Return the text of a model file: one key a line, arrays one row a line.

    Floats are written with Python's shortest round-trip repr (``json.dumps``), so they load to
    the bit.
    """
    lines = []
    for key, value in doc.items():
        if key in ('input_range', 'consequents', 'mf_params'):
            rows = ',\n    '.join(json.dumps(row, allow_nan=False) for row in value)
            text = f'[\n    {rows}\n  ]'
        else:
            text = json.dumps(value, allow_nan=False, sort_keys=True)
        lines.append(f'  {json.dumps(key)}: {text}')
    return '{\n' + ',\n'.join(lines) + '\n}\n'


def model_arrays(doc, path: str) -> tuple:
    """
    Check a model document read from ``path``; return its parameters.

    Returns
    -------
    (mf_params, consequents, input_range, mf, metadata), for ``Anfis.from_params``, which checks
    the membership functions themselves (:func:`validate_params`).

    Raises
    ------
    InputError : naming the file: not a JSON object, wrong format or version, missing or unknown
        keys, wrong shapes or types, non-finite numbers.

    """
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
    return (arrays['mf_params'], arrays['consequents'], arrays['input_range'], doc['mf'],
            doc.get('metadata'))


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


def validate_params(mf_params: np.ndarray, consequents: np.ndarray, input_range: np.ndarray,
                    mf: str):
    """
    Refuse model parameters of wrong shapes, non-finite ones, or invalid membership functions.

    Triangles need a < b < c and must cover the universe (some rule fires everywhere); bells
    need a > 0 and b > 0.

    Raises
    ------
    ValueError : naming the array, the membership function and the input.

    """
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
