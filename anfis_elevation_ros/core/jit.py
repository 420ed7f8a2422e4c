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
of the maths, still callable from Python with numpy arrays. Compiled code is cached next to
the module (or in numba's user cache when that folder is read-only), so only the first run on
a machine pays the compilation (about 20 s); ``NUMBA_DISABLE_JIT=1`` runs everything as plain
Python, for debugging.
"""

import numba


def jit(function):
    """Compile a numeric function of floats and numpy arrays (numba nopython mode, cached)."""
    return numba.njit(cache=True, nogil=True)(function)


__all__ = ['jit']
