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
Compilation of the per-sample maths with numba.

The navigator runs a dozen small vector and 15 x 15 matrix operations per IMU sample; as numpy
calls each costs about a microsecond of interpreter overhead, which capped the pipeline at
18,000 samples per second and kept the live node above 10 % of a core at 400 Hz. ``jit``
compiles such a function to machine code (numba ``njit``) instead: the same source, one copy
of the maths, still callable from Python with numpy arrays. ``NUMBA_DISABLE_JIT=1`` runs
everything as plain Python, for debugging.

Compiled code is cached, so only the first run on a machine pays the compilation (about 20 s),
in a folder named by a digest of the compiled sources of ``core/`` (``sources_digest``,
``cache_dir``). numba keys a
function's cache on its own file only: the compiled ``navigation_step`` holds the code of the
``ekf`` and ``zupt`` functions it calls, and outlived an edit of ``ekf.py`` or a ``git pull``
that changed only that file (found running the stride-gate benchmarks: the edit was ignored
until the cache was deleted). The folder is ``$NUMBA_CACHE_DIR/anfis_elevation_ros-DIGEST``
when that variable is set, else ``core/__pycache__/numba-DIGEST`` (the other digests' folders
there, and numba's own files of the time before them, are removed: one checkout runs one set
of sources), else, when that is read-only, numba's user-wide cache.
"""

import hashlib
import os
from pathlib import Path
import shutil

import numba
from numba.misc.appdirs import AppDirs

CORE_DIR = Path(__file__).resolve().parent


def sources_digest(folder: Path = CORE_DIR) -> str:
    """
    Return a digest (16 hex digits) of the folder's compiled sources: names and contents.

    Those are this file and every .py file with an ``@jit`` function (compiled code calls only
    compiled code), so an edit elsewhere does not cost a compilation.
    """
    digest = hashlib.sha256()
    for path in sorted(folder.glob('*.py')):
        text = path.read_bytes()
        if b'@jit' in text or path.name == Path(__file__).name:
            digest.update(path.name.encode() + b'\0' + text + b'\0')
    return digest.hexdigest()[:16]


def cache_dir(digest: str, user_dir: str = None, core_dir: Path = CORE_DIR) -> str:
    """
    Return the folder for the compiled code of sources with this digest (see the module doc).

    Parameters
    ----------
    digest : str
        ``sources_digest()``.
    user_dir : str or None
        ``$NUMBA_CACHE_DIR``; None or '' when not set.
    core_dir : Path
        The folder of the sources (its ``__pycache__`` holds the cache when writable).

    """
    if user_dir:
        return os.path.join(user_dir, f'anfis_elevation_ros-{digest}')
    in_tree = core_dir / '__pycache__'
    try:
        in_tree.mkdir(exist_ok=True)
        for old in in_tree.glob('numba-*'):
            if old.name != f'numba-{digest}':
                shutil.rmtree(old, ignore_errors=True)
        for old in (*in_tree.glob('*.nbi'), *in_tree.glob('*.nbc')):   # before the digests
            old.unlink(missing_ok=True)
        if os.access(in_tree, os.W_OK):
            return str(in_tree / f'numba-{digest}')
    except OSError:
        pass
    return os.path.join(AppDirs('numba').user_cache_dir,
                        f'anfis_elevation_ros-{digest}')


# Read by numba when a function is decorated: set before any module of core defines one.
numba.config.CACHE_DIR = cache_dir(sources_digest(), os.environ.get('NUMBA_CACHE_DIR'))


def jit(function):
    """Compile a numeric function of floats and numpy arrays (numba nopython mode, cached)."""
    return numba.njit(cache=True, nogil=True)(function)


__all__ = ['cache_dir', 'jit', 'sources_digest']
