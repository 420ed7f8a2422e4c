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
Range checks of parameter values, one message form for every parameter dataclass.

A refused value raises ``InputError`` (a ValueError) naming the parameter, the value and what
is allowed: ``zupt.window_s = 0.6 is outside [0.005, 0.5]``.

Public API: ``check_range``, ``check_positive``, ``check_finite``.
"""

import math
import numbers

from .errors import InputError


def check_range(name: str, value, low, high, *, open_low: bool = False, open_high: bool = False,
                note: str = ''):
    """
    Refuse a value that is not a real number (bools are not) in [low, high].

    ``open_low`` / ``open_high`` exclude the bound; ``note`` is appended in brackets (what
    else is allowed, or why). An infinite value passes only an infinite bound; NaN never.
    """
    interval = f'{"(" if open_low else "["}{low:g}, {high:g}{")" if open_high else "]"}'
    if not _is_real(value):
        problem = f'is not a number in {interval}'
    elif (low < value if open_low else low <= value) and (
            value < high if open_high else value <= high):
        return
    else:
        problem = f'is outside {interval}'
    raise InputError(f'{name} = {_shown(value)} {problem}' + (f' ({note})' if note else ''))


def check_positive(name: str, value):
    """Refuse a value that is not a finite real number > 0."""
    if not (_is_real(value) and math.isfinite(value) and value > 0):
        raise InputError(f'{name} = {_shown(value)} is not a finite number > 0')


def check_finite(name: str, value):
    """Refuse a value that is not a finite real number."""
    if not (_is_real(value) and math.isfinite(value)):
        raise InputError(f'{name} = {_shown(value)} is not a finite number')


def _is_real(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _shown(value) -> str:
    """Show the value as the user wrote it (numpy scalars as plain numbers)."""
    if _is_real(value):
        return str(int(value)) if isinstance(value, numbers.Integral) else repr(float(value))
    return repr(value)
