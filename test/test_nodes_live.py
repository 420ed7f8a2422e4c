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
The live nodes over DDS equal offline replay, cycle for cycle, for sqlite3 and mcap bags.

And for a bag whose gyro clips, with its samples held and rebuilt (``rail.enabled``).

Three processes per bag: ``run`` (both nodes), ``play`` (the bag, at most 1000 messages/s,
which a Python node follows on a loaded machine), and this test, which subscribes to the
outputs. The same bag through ``replay`` (the same core objects, no ROS) gives cycles.csv;
the /elevation stream must hold exactly its valid cycles: same stamps, same quantised heights,
same x, y (bit for bit: one pipeline, no message is lost or reordered). The imu node's
diagnostics must count every message as received and accepted (zero lost), the last /floor
must be the true final floor of the walk and the highest the true highest floor, and the
nodes must stop cleanly on SIGINT.
"""

import csv
from dataclasses import replace
import subprocess

from anfis_elevation_ros.tools.bags import read_imu_bag, write_imu_bag
from live_support import cli, cli_env, NodesProcess, PACKAGE_ROOT, SAMPLE_BAG, truth_floors
from live_support import listening, wait_for, write_linear_model, write_params
import numpy as np
import pytest

PLAY_MAX_RATE_HZ = 1000.0
IMU_INPUT = '/imu_node: IMU input'
# The sample walk with its gyro clipped at 0.99 x 7 rad/s (82 samples): held and rebuilt.
CLIPPED_RANGE_RPS = 7.0
REBUILT_RAIL = {'gyro_range_rps': CLIPPED_RANGE_RPS, 'rail.enabled': True}


@pytest.fixture(scope='module')
def workspace(tmp_path_factory):
    """Write a known model and the sample walk: mcap, sqlite3, and with a clipped gyro."""
    root = tmp_path_factory.mktemp('live')
    model = write_linear_model(root / 'model.json')
    recording = read_imu_bag(SAMPLE_BAG)
    rail_rps = 0.99 * CLIPPED_RANGE_RPS
    clipped = replace(recording, gyr_b=np.clip(recording.gyr_b, -rail_rps, rail_rps))
    bags = {'mcap': SAMPLE_BAG,
            'sqlite3': write_imu_bag(root / 'imu_sqlite3', recording, storage='sqlite3'),
            'clipped': write_imu_bag(root / 'imu_clipped', clipped)}
    return {'root': root, 'model': model, 'bags': bags, 'messages': len(recording)}


@pytest.fixture(scope='module')
def listener():
    """Listen to the outputs with rclpy, spun in a background thread."""
    with listening() as node:
        yield node


def offline_cycles(bag, params, out_dir):
    """Run ``replay`` and return the valid rows of its cycles.csv."""
    result = subprocess.run(cli('replay', bag, '--out', out_dir, '--params', params),
                            env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    with open(out_dir / 'cycles.csv', newline='') as stream:
        return [row for row in csv.DictReader(stream) if row['valid'] == '1']


def reset(listener):
    """Forget what the listener collected."""
    for items in (listener.elevations, listener.modes, listener.floors, listener.cycles,
                  listener.floor_ranges):
        items.clear()
    listener.diagnostics.clear()


@pytest.mark.parametrize('storage, imu', [('sqlite3', None), ('mcap', None),
                                          ('clipped', REBUILT_RAIL)],
                         ids=['sqlite3', 'mcap', 'clipped-rebuilt'])
def test_live_nodes_equal_offline_replay(storage, imu, workspace, listener, tmp_path):
    """Every valid cycle, in order, with the stamp, height and x, y of offline replay."""
    # Parameters of this test alone: a state of its own (a run of the same bag would resume).
    bag, params = workspace['bags'][storage], write_params(tmp_path / 'params.yaml',
                                                           workspace['model'], imu=imu)
    expected = offline_cycles(bag, params, tmp_path / 'replay')
    assert len(expected) > 30, 'the sample walk should give dozens of gait cycles'
    reset(listener)
    n_messages = workspace['messages']
    with NodesProcess(params, tmp_path / 'run.log') as nodes:
        assert wait_for(lambda: listener.count_publishers('/elevation') >= 1, 30.0), nodes.log()
        play = subprocess.run(
            cli('play', bag, '--rate', 0, '--max-rate-hz', PLAY_MAX_RATE_HZ, '--wait-s', 30,
                '--linger-s', 0.5),
            env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True, timeout=120)
        assert play.returncode == 0, play.stderr + nodes.log()
        # First every IMU message handled (a loaded machine may leave a backlog), then the
        # cycles of the last ones classified and received.
        assert wait_for(lambda: listener.diagnostic_value(IMU_INPUT, 'received')
                        == str(n_messages), 60.0), (listener.diagnostics, nodes.log())
        wait_for(lambda: len(listener.elevations) >= len(expected), 20.0)
        code = nodes.stop()
    assert code == 0, f'the nodes did not stop cleanly on SIGINT:\n{nodes.log()}'

    inputs = listener.diagnostics[IMU_INPUT][2]
    assert inputs['accepted'] == str(n_messages), inputs      # zero lost, zero refused
    assert inputs['rejected'] == '0', inputs
    live = [(stamp, x, y, height) for stamp, x, y, height, _ in listener.elevations]
    offline = [(int(r['stamp_ns']), float(r['x_m']), float(r['y_m']), float(r['height_m']))
               for r in expected]
    assert len(live) == len(offline)
    assert live == offline
    assert [m for m, _ in listener.modes] == [int(r['mode']) for r in expected]

    floors = [f for f, _ in listener.floors]
    final_floor, _ = truth_floors()
    assert floors[-1] == final_floor == int(expected[-1]['floor'])
    assert max(floors) == max(int(r['floor']) for r in expected)
    # With every floor, the floors the height can be on: the start floor alone at the end.
    assert len(listener.floor_ranges) == len(listener.floors)
    assert listener.floor_ranges[-1][0] == [final_floor, final_floor]
