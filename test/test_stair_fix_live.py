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
Live over DDS equals ``replay`` with a building file: the stair-entry corrections included.

The short stair walk of ``stair_support.py`` (about 50 s, tactical IMU, 100 Hz; a building
file whose two stair entries are 0.5 m off the truth, so that each correction moves the track)
is played at twice its recorded pace into ``run --building``; the same bag goes through
``replay --building``. Heuristic drift elimination is on, along the building's corridor
directions (``dominant_directions_deg``), so that the heading aid's input is checked too.
Every valid cycle's /elevation must hold the stamp, the quantised height and the x, y of
replay, bit for bit: the classifier's correction requests reach the IMU node
over ``stair_fix`` within milliseconds, and the node applies each at the first stance sample
0.5 s of sensor time after its cycle, the sample replay applies it at (0.25 s of wall time at
twice the pace: a margin of about 50 over the hand-over's latency). The diagnostics must count
two corrections requested and applied, none late, and the track in the ``map`` frame.
"""

import csv
import subprocess

from anfis_elevation_ros.core.building import save_building
from anfis_elevation_ros.tools.bags import write_imu_bag
from live_support import cli, cli_env, listening, NodesProcess, PACKAGE_ROOT, wait_for
from live_support import write_linear_model, write_params
import pytest
from stair_support import simulate_stair_walk, stair_walk_building, STEP_HEIGHT_M

PLAY_RATE = 2.0
NAVIGATOR = '/imu_node: foot navigator'
ELEVATION = '/classifier_node: elevation'
IMU_INPUT = '/imu_node: IMU input'


@pytest.fixture(scope='module')
def stair_walk(tmp_path_factory):
    """Write the walk's bag, its building file, a known model and the parameters."""
    root = tmp_path_factory.mktemp('stair_live')
    walk, entries = simulate_stair_walk()
    recording = walk.to_recording()
    bag = write_imu_bag(root / 'imu', recording)
    building = root / 'building.yaml'
    save_building(building, stair_walk_building(walk, entries, directions_deg=(0.0,)))
    model = write_linear_model(root / 'model.json', STEP_HEIGHT_M)
    # th_st = 20 % of the distance walked: the walk is short (7 m to the first entry).
    params = write_params(root / 'params.yaml', model, imu={'heading.hde_enabled': True},
                          classifier={'building_aid.stair_fix_ratio': 0.2})
    return {'root': root, 'bag': bag, 'building': building, 'params': params,
            'messages': len(recording)}


def test_live_with_a_building_equals_replay(stair_walk):
    root = stair_walk['root']
    replay = subprocess.run(cli('replay', stair_walk['bag'], '--out', root / 'replay', '--params',
                                stair_walk['params'], '--building', stair_walk['building']),
                            env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True,
                            timeout=120)
    assert replay.returncode == 0, replay.stderr
    assert '2 corrections applied' in replay.stderr, replay.stderr
    with open(root / 'replay' / 'cycles.csv', newline='') as stream:
        expected = [row for row in csv.DictReader(stream) if row['valid'] == '1']
    assert len(expected) > 30

    with listening() as listener, NodesProcess(stair_walk['params'], root / 'run.log',
                                               ('--building', stair_walk['building'])) as nodes:
        assert wait_for(lambda: listener.count_publishers('/elevation') >= 1, 30.0), nodes.log()
        play = subprocess.run(cli('play', stair_walk['bag'], '--rate', PLAY_RATE, '--wait-s', 30,
                                  '--linger-s', 0.5),
                              env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True,
                              timeout=180)
        assert play.returncode == 0, play.stderr + nodes.log()
        received = str(stair_walk['messages'])
        assert wait_for(lambda: listener.diagnostic_value(IMU_INPUT, 'received') == received,
                        60.0), (listener.diagnostics, nodes.log())
        wait_for(lambda: len(listener.elevations) >= len(expected), 20.0)
        # Diagnostics come once a second: wait for those after the last correction.
        wait_for(lambda: listener.diagnostic_value(NAVIGATOR, 'stair_fix_applied') == '2'
                 and listener.diagnostic_value(ELEVATION, 'stair_fix_accepted') == '2', 5.0)
        navigator = dict(listener.diagnostics[NAVIGATOR][2])
        classifier = dict(listener.diagnostics[ELEVATION][2])
        live = [(stamp, x, y, height) for stamp, x, y, height, _ in listener.elevations]
        assert nodes.stop() == 0, nodes.log()

    offline = [(int(r['stamp_ns']), float(r['x_m']), float(r['y_m']), float(r['height_m']))
               for r in expected]
    assert live == offline, nodes.log()
    assert navigator['frame_id'] == 'map'
    assert classifier['stair_fix_accepted'] == '2', classifier
    assert navigator['stair_fix_requests'] == '2' and navigator['stair_fix_applied'] == '2', \
        navigator
    assert navigator['stair_fix_late'] == '0' and navigator['stair_fix_duplicates'] == '0'
    assert 'stair-entry correction of cycle' in nodes.log()
