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

"""The shared range checks of parameter values (core/validation.py)."""

import math

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.validation import check_finite, check_positive, check_range
import numpy as np
import pytest


def test_check_range_accepts_the_closed_interval_and_numpy_scalars():
    for value in (0.005, 0.5, 0.1, np.float64(0.2), np.int64(0)):
        check_range('zupt.window_s', value, 0.0 if value == 0 else 0.005, 0.5)
    check_range('gyr_range_rps', math.inf, 1e-3, math.inf)       # an infinite bound admits inf


@pytest.mark.parametrize(('value', 'kwargs', 'message'), [
    (0.6, {}, 'zupt.window_s = 0.6 is outside [0.005, 0.5]'),
    (0.004, {}, 'zupt.window_s = 0.004 is outside [0.005, 0.5]'),
    (0.005, {'open_low': True}, 'zupt.window_s = 0.005 is outside (0.005, 0.5]'),
    (0.5, {'open_high': True}, 'zupt.window_s = 0.5 is outside [0.005, 0.5)'),
    (math.nan, {}, 'zupt.window_s = nan is outside [0.005, 0.5]'),
    (math.inf, {}, 'zupt.window_s = inf is outside [0.005, 0.5]'),
    (np.float64(0.7), {}, 'zupt.window_s = 0.7 is outside [0.005, 0.5]'),
    (True, {}, 'zupt.window_s = True is not a number in [0.005, 0.5]'),
    ('0.1', {}, "zupt.window_s = '0.1' is not a number in [0.005, 0.5]"),
    (0.6, {'note': 'or 0: automatic'},
     'zupt.window_s = 0.6 is outside [0.005, 0.5] (or 0: automatic)'),
])
def test_check_range_names_parameter_value_and_interval(value, kwargs, message):
    with pytest.raises(InputError) as raised:
        check_range('zupt.window_s', value, 0.005, 0.5, **kwargs)
    assert str(raised.value) == message


@pytest.mark.parametrize('value', [0.0, -1.0, math.nan, math.inf, False, None, '1'])
def test_check_positive_refuses_all_but_finite_positive_numbers(value):
    with pytest.raises(InputError, match='step_size = .* is not a finite number > 0'):
        check_positive('step_size', value)
    check_positive('step_size', 1e-9)


@pytest.mark.parametrize('value', [math.nan, -math.inf, math.inf, True, 'x'])
def test_check_finite_refuses_all_but_finite_numbers(value):
    with pytest.raises(InputError, match='is not a finite number'):
        check_finite('start_height_m', value)
    check_finite('start_height_m', -3)
