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
``play`` waits for the IMU node to be ready, not only for it to subscribe.

The IMU node subscribes before it loads its numba code and publishes its first diagnostics
after (on a new machine compiling takes 30-60 s: a walk played meanwhile lost its first 39 s,
the b451fbb demo bug). A stand-in node here subscribes at once and publishes an "IMU input"
status naming its topic (``imu_topic``) only ``READY_AFTER_S`` later: no message may reach it
before that, and every message must reach it after. A status naming another topic is not
readiness: with only that, ``play`` gives up after ``--ready-s`` with a clear message.
"""

import subprocess
import threading
import time

from anfis_elevation_ros.tools.bags import read_imu_bag
from live_support import cli, cli_env, PACKAGE_ROOT, SAMPLE_BAG, wait_for
import pytest

TOPIC = '/ready_test/imu/data'
READY_AFTER_S = 6.0      # after the stand-in starts; play's own start-up takes 1-3 s


@pytest.fixture()
def stand_in():
    """Start the stand-in IMU node (factory: the topic its diagnostics name), spun in a thread."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    rclpy.init()
    executor = SingleThreadedExecutor()
    nodes = []

    def start(reported_topic):
        node = _StandIn(reported_topic)
        nodes.append(node)
        executor.add_node(node)
        threading.Thread(target=executor.spin, daemon=True).start()
        return node

    try:
        yield start
    finally:
        executor.shutdown()
        for node in nodes:
            node.destroy_node()
        rclpy.try_shutdown()


def _StandIn(reported_topic):
    """Build the stand-in node: Imu subscriber now, diagnostics naming a topic later."""
    from diagnostic_msgs.msg import DiagnosticArray
    from rclpy.node import Node
    from sensor_msgs.msg import Imu

    from anfis_elevation_ros.nodes.diagnostics import diagnostic_status
    from anfis_elevation_ros.nodes.qos import DIAGNOSTICS_QOS, imu_qos

    class StandIn(Node):
        def __init__(self):
            super().__init__('imu_node', namespace='/ready_test')
            self.received_ns = []
            self.ready_ns = None
            self.started = time.monotonic()
            self.create_subscription(Imu, 'imu/data', self._imu, imu_qos(20000))
            self.publisher = self.create_publisher(DiagnosticArray, '/diagnostics',
                                                   DIAGNOSTICS_QOS)
            self.create_timer(0.25, self._diagnostics)

        def _imu(self, msg):
            self.received_ns.append(time.time_ns())

        def _diagnostics(self):
            if time.monotonic() - self.started < READY_AFTER_S:
                return
            if self.ready_ns is None:
                self.ready_ns = time.time_ns()
            status = diagnostic_status('/ready_test/imu_node: IMU input', b'\x00', 'ok', 'imu',
                                       {'imu_topic': reported_topic})
            self.publisher.publish(DiagnosticArray(status=[status]))

    return StandIn()


def play(*extra):
    return subprocess.run(cli('play', SAMPLE_BAG, '--topic', TOPIC, '--rate', 0,
                              '--max-rate-hz', 1000, '--wait-s', 30, '--linger-s', 0.5, *extra),
                          env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True,
                          timeout=120)


def test_play_starts_when_the_imu_node_is_ready(stand_in):
    node = stand_in(TOPIC)
    messages = len(read_imu_bag(SAMPLE_BAG))
    result = play()
    assert result.returncode == 0, result.stderr
    assert wait_for(lambda: len(node.received_ns) >= messages, 10.0), \
        f'{len(node.received_ns)} of {messages} messages received'
    assert node.ready_ns is not None
    early = sum(t < node.ready_ns for t in node.received_ns)
    assert early == 0, f'{early} messages reached the node before it was ready'
    assert 'waiting for the IMU node to be ready' in result.stderr


def test_play_refuses_when_no_imu_node_on_its_topic_is_ready(stand_in):
    node = stand_in('/another/imu/data')
    result = play('--ready-s', READY_AFTER_S + 4.0)
    assert result.returncode == 1, result.stderr
    assert f'no IMU node reading {TOPIC} reported ready' in result.stderr
    assert '--ready-s 0' in result.stderr
    assert node.ready_ns is not None, 'the other status was published'
    assert node.received_ns == []
