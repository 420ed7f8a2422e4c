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
from anfis_elevation_ros.sim.responders import RESPONDERS, simulate_responder, tower_building


def test_responders_end_on_their_floors_inside_the_building(tmp_path):
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
        assert (xy.min(axis=0) > (x0, y0)).all() and (xy.max(axis=0) < (x1, y1)).all()
