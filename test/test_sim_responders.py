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

"""The command-centre demo's incident: three responders on their floors, the tower's file."""

from anfis_elevation_ros.core.building import load_building, save_building
from anfis_elevation_ros.core.height import floor_index
from anfis_elevation_ros.core.params import elevation_params_from_dict
from anfis_elevation_ros.sim import DEFAULT_TREAD_M, GaitParams
from anfis_elevation_ros.sim.responders import LEVEL_STRIDES, OUTLINE_MARGIN_M, RESPONDERS
from anfis_elevation_ros.sim.responders import simulate_responder, STOREY_STEPS, tower_building
import numpy as np

LANDING_STRIDE_M = 0.7          # tower_walk's two strides round a landing (and between storeys)


def planned_reach_m(plan) -> float:
    """
    Farthest the plan lets a responder get from its start (m), from the tower's dimensions.

    A corridor walked out and back leaves at most LEVEL_STRIDES times the spread of the level
    stride lengths; each storey adds one level stride into the stairwell, its two flights cancel
    (as many treads up and back, a 180 deg landing between them) and each landing moves the
    foot by at most its two strides; the piece being walked adds the longer of a corridor and
    a flight, and the IMU sits up to a toe or heel away from the foot's planned position.
    """
    gait = GaitParams()
    shortest, longest = gait.level_stride_length_m
    legs = [abs(b - a) for a, b in zip(plan.route, plan.route[1:])]
    landings = sum(2 * storeys - 1 for storeys in legs)
    landing_m = 2 * LANDING_STRIDE_M * (1.0 + 3.0 * gait.stride_length_jitter)
    flight_m = max(steps - steps // 2 for steps in STOREY_STEPS) * DEFAULT_TREAD_M
    return ((len(plan.route) - 1) * LEVEL_STRIDES * (longest - shortest) + sum(legs) * longest
            + landings * landing_m + max(flight_m, LEVEL_STRIDES * longest)
            + max(gait.toe_from_imu_m, gait.heel_from_imu_m))


def test_responders_end_on_their_floors_inside_the_building(tmp_path):
    """
    Each responder ends on its floor, never farther from its start than its plan allows.

    The outline (the walks' box plus OUTLINE_MARGIN_M) is then a tower of one stairwell and
    short corridors, no wider than the plans' reach, and the saved file keeps it round them.
    """
    walks = [simulate_responder(plan) for plan in RESPONDERS]
    storey_m = elevation_params_from_dict({}).floor_height_m      # what the nodes use
    for plan, walk in zip(RESPONDERS, walks):
        assert floor_index(walk.strides.height_m[-1], storey_m) == plan.final_floor
        assert walk.duration_s < 70.0, plan.namespace           # the demo stays short
    building = tower_building(walks)
    save_building(tmp_path / 'tower.yaml', building)
    loaded = load_building(tmp_path / 'tower.yaml')
    assert [f.index for f in loaded.floors] == [0, 1, 2]
    for plan, walk in zip(RESPONDERS, walks):
        z = walk.strides.height_m[-1]
        assert loaded.nearest_floor(z)[0] == plan.final_floor
        (x0, y0), _, (x1, y1), _ = loaded.floors[0].outline
        xy = walk.pos_n[:, :2] - walk.pos_n[0, :2]
        assert np.hypot(*xy.T).max() <= planned_reach_m(plan), plan.namespace
        assert (xy.min(axis=0) > (x0, y0)).all() and (xy.max(axis=0) < (x1, y1)).all()
    # Every walk lies in a disc of the largest reach round the start (outline rounded to 0.1 m).
    widest_m = 2.0 * (max(planned_reach_m(plan) for plan in RESPONDERS) + OUTLINE_MARGIN_M) + 0.1
    assert x1 - x0 <= widest_m and y1 - y0 <= widest_m
