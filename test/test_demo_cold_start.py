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
The README's first command on a new machine: the demo with numba's cache empty.

The IMU node subscribes before it compiles its numba code (30-60 s without a cache); a demo
that played as soon as the subscription appeared lost the first 39 s of the 67 s walk, and with
it the flight up (19 of 47 cycles classified, height -1.41 m at the end, truth 0).
"""

import os
import subprocess
import sys


def test_demo_with_an_empty_numba_cache_classifies_the_whole_walk(tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / 'numba_cache'))
    done = subprocess.run([sys.executable, '-m', 'anfis_elevation_ros', 'demo',
                           '--out', str(tmp_path / 'demo')], env=env, capture_output=True,
                          text=True, timeout=400)
    assert done.returncode == 0, done.stderr[-3000:]
    assert 'floor 0 -> 1' in done.stderr + done.stdout, done.stderr[-3000:]
    summary = [line for line in done.stderr.splitlines() if 'gait cycles classified' in line]
    assert summary, done.stderr[-3000:]
    assert int(summary[-1].split('] ')[1].split()[0]) >= 45, summary
