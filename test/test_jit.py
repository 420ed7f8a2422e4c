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

"""The compiled navigator step is the same maths as its source run as plain Python."""

import json
import os
from pathlib import Path
import subprocess
import sys

from anfis_elevation_ros.core.navigator import compile_navigator
import numpy as np

PACKAGE_ROOT = Path(__file__).resolve().parents[1]

# 10 s of the sample walk at 100 Hz: start-up, stance and swing, a few cycles; plain Python
# takes about a millisecond per sample, so keep it short.
TRACK_SCRIPT = """
import json, sys
import numpy as np
from anfis_elevation_ros.core.navigator import FootNavigator
from anfis_elevation_ros.sim import sample_walk, simulate_walk
walk = simulate_walk(sample_walk(), rng=np.random.default_rng(5), rate_hz=100.0, imu='consumer')
n = 1000
track, cycles = FootNavigator().run(walk.stamp_ns[:n], walk.acc_b[:n], walk.gyr_b[:n])
json.dump({'pos': [p.pos_n.tolist() for p in track], 'quat': [p.quat_nb.tolist() for p in track],
           'stance': [bool(p.stance) for p in track],
           'features': [c.features.tolist() for c in cycles]}, sys.stdout)
"""


def navigate(disable_jit: bool) -> dict:
    env = dict(os.environ, NUMBA_DISABLE_JIT='1' if disable_jit else '0')
    result = subprocess.run([sys.executable, '-c', TRACK_SCRIPT], env=env, cwd=PACKAGE_ROOT,
                            capture_output=True, text=True, timeout=300, check=True)
    return json.loads(result.stdout)


def test_compiled_step_equals_the_plain_python_source():
    compiled, plain = navigate(False), navigate(True)
    assert len(compiled['pos']) == len(plain['pos']) > 800
    assert compiled['stance'] == plain['stance']
    assert len(compiled['features']) == len(plain['features']) >= 2
    # Same operations in the same order; only libm and fused multiply-adds may differ.
    for key in ('pos', 'quat', 'features'):
        assert np.allclose(compiled[key], plain[key], rtol=0.0, atol=1e-9), key


def test_compile_navigator_leaves_it_ready():
    assert compile_navigator() < 5.0     # loaded from the cache the tests above filled
