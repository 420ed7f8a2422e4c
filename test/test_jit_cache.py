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
The compiled-code cache follows every source of ``core/``, not only the function's own file.

numba keys a function's cache on its own file: the compiled ``navigation_step`` kept the code
of the ``ekf``/``zupt``/``stride_gate`` functions it calls after an edit of those files alone
(the stride-gate benchmarks ran stale code until the cache was deleted). ``core/jit.py`` names
the cache folder by a digest of every ``core/`` file with compiled functions.
"""

import os
from pathlib import Path

from anfis_elevation_ros.core import jit
from anfis_elevation_ros.core.navigator import navigation_step
import numba


def test_an_edit_of_any_compiled_source_changes_the_cache_folder(tmp_path):
    (tmp_path / 'navigator.py').write_text('@jit\ndef step(): return ekf.update()\n')
    (tmp_path / 'ekf.py').write_text('@jit\ndef update(): return 1\n')
    (tmp_path / 'height.py').write_text('def not_compiled(): return 1\n')
    before = jit.sources_digest(tmp_path)
    (tmp_path / 'height.py').write_text('def not_compiled(): return 2\n')
    assert jit.sources_digest(tmp_path) == before, 'an edit of uncompiled code costs nothing'
    (tmp_path / 'ekf.py').write_text('@jit\ndef update(): return 2\n')
    after = jit.sources_digest(tmp_path)
    assert before != after
    user = str(tmp_path / 'user')
    assert jit.cache_dir(before, user) != jit.cache_dir(after, user)


def test_the_user_cache_dir_is_kept_and_named_by_the_digest(tmp_path):
    folder = jit.cache_dir('0123456789abcdef', str(tmp_path))
    assert Path(folder) == tmp_path / 'anfis_elevation_ros-0123456789abcdef'


def test_in_tree_only_the_current_digest_stays(tmp_path):
    pycache = tmp_path / '__pycache__'
    (pycache / 'numba-old').mkdir(parents=True)
    (pycache / 'navigator.navigation_step-173.py311.nbi').write_bytes(b'stale')
    (pycache / 'navigator.cpython-311.pyc').write_bytes(b'python')
    folder = jit.cache_dir('new', None, core_dir=tmp_path)
    assert Path(folder) == pycache / 'numba-new'
    assert sorted(p.name for p in pycache.iterdir()) == ['navigator.cpython-311.pyc']


def test_the_navigator_caches_in_the_folder_of_these_sources():
    expected = jit.cache_dir(jit.sources_digest(), os.environ.get('NUMBA_CACHE_DIR'))
    assert numba.config.CACHE_DIR == expected
    # numba's own record of where navigation_step's compiled code goes (an internal attribute)
    assert navigation_step._cache.cache_path.startswith(expected)
