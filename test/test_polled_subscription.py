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

"""PolledSubscription over DDS: every message once, in order, in batches, under the lock."""

import threading
import time

from anfis_elevation_ros.nodes.imu_msg import imu_sample_from_cdr
from anfis_elevation_ros.nodes.polled_subscription import PolledSubscription
from anfis_elevation_ros.nodes.qos import imu_qos
from anfis_elevation_ros.tools.ros_io import PLAYER_QOS
import pytest
import rclpy
from sensor_msgs.msg import Imu

TOPIC = '/polled_test/imu'
PERIOD_S = 0.05


@pytest.fixture
def ros():
    rclpy.init()
    yield
    rclpy.try_shutdown()


@pytest.fixture
def endpoints(ros):
    """(owner node, publisher on TOPIC from another node); both destroyed after the test."""
    owner = rclpy.create_node('polled_owner')
    source = rclpy.create_node('polled_source')
    yield owner, source.create_publisher(Imu, TOPIC, PLAYER_QOS)
    source.destroy_node()
    owner.destroy_node()


def wait_for(condition, timeout_s=10.0):
    deadline = time.monotonic() + timeout_s
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.005)
    return condition()


def test_messages_are_taken_once_in_order_in_batches_under_the_lock(endpoints):
    owner, publisher = endpoints
    lock = threading.Lock()
    handled, batches, held = [], [], []

    def handler(data):
        held.append(lock.locked())
        stamp_ns = imu_sample_from_cdr(data)[0]
        if not handled or time.monotonic() - batches[-1][1] > PERIOD_S / 2:
            batches.append([0, time.monotonic()])
        batches[-1][0] += 1
        handled.append(stamp_ns)

    polled = PolledSubscription(owner, Imu, TOPIC, imu_qos(100), handler, PERIOD_S, lock)
    assert wait_for(lambda: publisher.get_subscription_count() == 1)
    assert [i.node_name for i in owner.get_subscriptions_info_by_topic(TOPIC)] == \
        ['polled_owner_input']
    n = 60
    for k in range(n):
        msg = Imu()
        msg.header.stamp.sec, msg.header.frame_id = k + 1, 'imu_link'
        publisher.publish(msg)
        time.sleep(0.002)                # 60 messages over about 0.15 s
    assert wait_for(lambda: len(handled) == n)
    assert handled == [(k + 1) * 1_000_000_000 for k in range(n)]
    assert all(held)
    assert max(count for count, _ in batches) > 1, 'the messages should come in batches'
    assert len(batches) < n / 2
    polled.close()


def test_close_handles_the_messages_already_received(endpoints):
    owner, publisher = endpoints
    handled = []
    polled = PolledSubscription(owner, Imu, TOPIC, imu_qos(100), handled.append, 60.0,
                                threading.Lock())
    assert wait_for(lambda: publisher.get_subscription_count() == 1)
    for _ in range(5):
        publisher.publish(Imu())
    time.sleep(0.5)                      # delivered; the first batch is a minute away
    assert handled == []
    polled.close()
    assert len(handled) == 5


def test_a_foreseen_message_is_taken_when_due_not_a_period_later(endpoints):
    owner, publisher = endpoints
    handled, foreseen = [], [0.01]
    polled = PolledSubscription(owner, Imu, TOPIC, imu_qos(100), handled.append, 1.0,
                                threading.Lock(), due_s=lambda: foreseen[0])
    assert wait_for(lambda: publisher.get_subscription_count() == 1)
    time.sleep(1.2)                      # past the first period: now polled every 11 ms
    sent = time.monotonic()
    publisher.publish(Imu())
    assert wait_for(lambda: len(handled) == 1, 0.5)
    assert time.monotonic() - sent < 0.2
    foreseen[0] = None                   # nothing foreseen: back to the 1 s period
    time.sleep(0.05)
    publisher.publish(Imu())
    time.sleep(0.3)
    assert len(handled) == 1
    assert wait_for(lambda: len(handled) == 2, 2.0)
    polled.close()
