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
One responder under a namespace: ``run --namespace /ff1`` and ``play --topic /ff1/imu/data``.

The parameter file keys its nodes ``/**/imu_node`` (as config/params.yaml does): it must apply
under the namespace (the test's state directory and model are used). Every output and the Imu
input live under ``/ff1``, nothing reaches the root namespace's ``elevation``, the
diagnostics status names carry the node's full name, and the track comes twice: ``foot_odom``
at 10 Hz and, for the command centre, ``foot_odom_throttle`` at 2 Hz.
"""

import subprocess
import time

from anfis_elevation_ros.tools.bags import read_imu_bag
from live_support import cli, cli_env, NodesProcess, PACKAGE_ROOT, SAMPLE_BAG, truth_floors
from live_support import wait_for, write_linear_model, write_params
import numpy as np
import pytest
import yaml

NAMESPACE = '/ff1'


def namespaced_params(path, model):
    """Write the test's parameter file with its node keys written ``/**/<node>``."""
    plain = yaml.safe_load(write_params(path, model).read_text())
    path.write_text(yaml.safe_dump({f'/**/{node}': value for node, value in plain.items()}))
    return path


@pytest.fixture()
def listeners():
    """Listen in /ff1 and in the root namespace, spun in a background thread."""
    import threading

    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    from anfis_elevation_ros.tools.ros_io import CycleListener

    rclpy.init()
    executor = SingleThreadedExecutor()
    inside, root = CycleListener(namespace=NAMESPACE), CycleListener()
    executor.add_node(inside)
    executor.add_node(root)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        yield inside, root
    finally:
        executor.shutdown()
        inside.destroy_node()
        root.destroy_node()
        rclpy.try_shutdown()
        thread.join(timeout=5.0)


def listen_to_tracks(node) -> dict:
    """Subscribe the node to foot_odom and foot_odom_throttle; return their receive times."""
    from nav_msgs.msg import Odometry

    from anfis_elevation_ros.nodes.qos import LATEST_QOS

    times = {'foot_odom': [], 'foot_odom_throttle': []}
    for topic, received in times.items():
        node.create_subscription(Odometry, topic, lambda _, r=received: r.append(time.monotonic()),
                                 LATEST_QOS)
    return times


def test_run_under_a_namespace(tmp_path, listeners):
    inside, root = listeners
    tracks = listen_to_tracks(inside)
    model = write_linear_model(tmp_path / 'model.json')
    params = namespaced_params(tmp_path / 'params.yaml', model)
    messages = len(read_imu_bag(SAMPLE_BAG))
    with NodesProcess(params, tmp_path / 'run.log', ['--namespace', NAMESPACE]) as nodes:
        play = subprocess.run(cli('play', SAMPLE_BAG, '--topic', f'{NAMESPACE}/imu/data',
                                  '--rate', 0, '--max-rate-hz', 1000, '--wait-s', 60,
                                  '--linger-s', 1.0),
                              env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True,
                              timeout=180)
        assert play.returncode == 0, play.stderr
        status = f'{NAMESPACE}/imu_node: IMU input'
        assert wait_for(lambda: inside.diagnostic_value(status, 'received') == str(messages),
                        timeout_s=30), (inside.diagnostics.keys(), nodes.log())
        assert f'{NAMESPACE}/classifier_node: elevation' in inside.diagnostics
        final_floor, _ = truth_floors()
        assert wait_for(lambda: inside.floors and inside.floors[-1][0] == final_floor, 30)
        assert len(inside.elevations) > 10
        assert root.elevations == []
        # The command centre's track (centre_track_rate_hz, 2 Hz) beside the 10 Hz one.
        full, thinned = (np.diff(tracks[t]) for t in ('foot_odom', 'foot_odom_throttle'))
        assert len(thinned) >= 5 and len(full) >= 3 * len(thinned), (len(full), len(thinned))
        assert 0.4 < np.median(thinned) < 0.6 and np.median(full) < 0.15
        assert nodes.stop() == 0, nodes.log()
    # The /**/ keys applied: the state files went to the test's directory, named by namespace.
    assert sorted(p.name for p in (tmp_path / 'state').iterdir()) == [
        'ff1.classifier_node.state.json', 'ff1.imu_node.state.json']
    assert f'{NAMESPACE}/imu_node and {NAMESPACE}/classifier_node running' in nodes.log()
