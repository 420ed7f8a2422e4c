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
Lost IMU messages: the simulated building walk still ends on the right floor.

The issue's building walk (start upstairs, down two flights of 18 steps of 0.15 m with a
landing turn, about 500 s of level walking, back up; 640 s, tactical IMU at 100 Hz) goes
through the pipeline the nodes run (input gate, navigator, ANFIS with the packaged model,
eq. 13-14) with IMU messages lost in transit:

- 10 % of the messages dropped at random (single samples: no gaps, nothing invalid);
- 200 ms bursts lost every 2-4 s (about 140 of 490 gait cycles invalid: bridged inside
  flights, not counted elsewhere; the attitude is re-levelled at the stance after each gap).

The floor must be right at the end, and on every level stretch away from the stairs it is right
or said uncertain (with single samples lost: right); the quantised height must stay within
1.2 m of the truth (the floor is right while the error is below half a storey, 1.5 m). The
navigator's count of missing samples reports the loss (the IMU node puts it in /diagnostics;
test_bad_input_live.py checks that part).
"""

from dataclasses import replace

from anfis_elevation_ros import sim
from anfis_elevation_ros.core.height import floor_index
from anfis_elevation_ros.core.imu_data import ImuRecording
from anfis_elevation_ros.core.params import load_model, load_pipeline_params
from anfis_elevation_ros.tools.replay import CYCLE_COLUMNS, replay_recording
import numpy as np
import pytest

STEP_M = 0.15
FLOOR_M = 3.0


@pytest.fixture(scope='module')
def building():
    """Simulate the walk; return it, its recording, the pipeline and the packaged model."""
    walk = sim.simulate_walk(sim.building_walk(step_height_m=STEP_M),
                             rng=np.random.default_rng(3), rate_hz=100.0, imu='tactical',
                             step_height_m=STEP_M)
    pipeline = load_pipeline_params()
    pipeline = replace(pipeline, elevation=replace(pipeline.elevation, step_height_m=STEP_M))
    return walk, walk.to_recording(), pipeline, load_model('')


def random_drop(stamp_ns, rng):
    return rng.random(len(stamp_ns)) >= 0.10


def burst_drop(stamp_ns, rng):
    t = (stamp_ns - stamp_ns[0]) * 1e-9
    keep = np.ones(len(t), bool)
    start = rng.uniform(0.0, 3.0)
    while start < t[-1]:
        keep &= ~((t >= start) & (t < start + 0.2))
        start += rng.uniform(2.0, 4.0)
    return keep


@pytest.mark.parametrize('drop', [random_drop, burst_drop])
def test_building_walk_ends_on_the_right_floor(building, drop):
    walk, rec, pipeline, model = building
    keep = drop(rec.stamp_ns, np.random.default_rng(11))
    lossy = ImuRecording(rec.stamp_ns[keep], rec.acc_b[keep], rec.gyr_b[keep], rec.frame_id)
    result = replay_recording(lossy, pipeline, model)

    stamp = np.array([row[0] for row in result.cycles])
    height = np.array([row[2] for row in result.cycles])
    floor = np.array([row[5] for row in result.cycles])
    valid = np.array([row[7] for row in result.cycles], bool)
    strides = walk.strides
    k = np.searchsorted(strides.stamp_ns, stamp + 200_000_000, side='right') - 1
    truth_height = strides.height_m[k]
    truth_floor = floor_index(truth_height, FLOOR_M)
    stairs = np.flatnonzero(strides.mode != 0)
    away = np.min(np.abs(k[:, None] - stairs[None, :]), axis=1) >= 3

    assert floor[-1] == floor_index(strides.height_m[-1], FLOOR_M) == 0
    assert truth_floor.min() == -2
    assert np.max(np.abs(height - truth_height)) <= 1.2
    certain = np.array([row[CYCLE_COLUMNS.index('floor_certain')] for row in result.cycles],
                       bool)
    # Away from the stairs a floor is never claimed wrong: right, or said uncertain.
    assert np.all((floor[away] == truth_floor[away]) | ~certain[away])
    if drop is burst_drop:
        # Three stair strides of two risers fall in a burst next to a landing or the floor
        # (level on one side: not bridged), so the bottom, 5.40 m down, reads 4.49 m: half a
        # storey short, between floors -1 and -2, and said uncertain there (it read 4.500 m,
        # floor -2, only while K was a grid point; doc/riser_height_notebook.md).
        assert floor.min() in (-1, -2)
    else:
        assert floor.min() == -2
        assert np.all(floor[away] == truth_floor[away])
    lost = int(np.count_nonzero(~keep))
    assert 0.95 * lost <= result.navigator.status.missing_samples <= lost
    if drop is burst_drop:
        assert 100 <= np.count_nonzero(~valid) <= 200
        assert result.navigator.status.gaps >= 150
    else:
        assert valid.all() and result.navigator.status.gaps <= 2
