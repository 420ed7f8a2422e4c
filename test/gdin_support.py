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

"""The gdin_hallway walks for tests: skipped, not failed, where the shared data lacks them."""

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.tools import datasets
from anfis_elevation_ros.tools.gdin_hallway import load_gdin_walk
import pytest


def gdin_files():
    """Return the walks' CSV files, or skip the test when the folder is absent."""
    try:
        return datasets.dataset_files('gdin_hallway')
    except InputError as err:
        pytest.skip(f'gdin_hallway not in the shared data: {err}')


def gdin_walk(number):
    """Return one gdin_hallway walk, or skip when the shared data lacks it."""
    paths = [p for p in gdin_files() if p.stem.endswith(f'_{number}')]
    if not paths:
        pytest.skip(f'gdin_hallway walk {number} not in the shared data')
    return load_gdin_walk(paths[0])
