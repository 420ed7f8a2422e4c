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
The rclpy side of the tools: an IMU player, an output recorder, a cycle listener.

Kept apart from the subcommand modules, which the CLI imports up front, so that the tools that
need no ROS (replay, train, simulate, plot) start without rclpy; ``play``, ``record``, ``run``
and ``demo`` import this module when they run.

Public API: ``ImuPlayer``, ``PlayResult``, ``OutputRecorder``, ``OUTPUT_TOPICS``,
``CycleListener``.
"""

from dataclasses import dataclass
from pathlib import Path
import time

import numpy as np
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Imu

from .bags import BagWriter
from ..core.errors import InputError
from ..nodes.gait_cycle_msg import cycle_from_msg
from ..nodes.qos import CYCLE_QOS, LATEST_QOS

OUTPUT_TOPICS = (
    ('/elevation', 'geometry_msgs/msg/PointStamped', LATEST_QOS),
    ('/stair_mode', 'std_msgs/msg/Int8', LATEST_QOS),
    ('/floor', 'std_msgs/msg/Int32', LATEST_QOS),
    ('/gait_cycle', 'sensor_msgs/msg/PointCloud2', CYCLE_QOS),
)
"""(topic, type, QoS) of every output the recorder records."""

PLAYER_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                        reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.VOLATILE)
"""Reliable, so that both best-effort (the IMU node) and reliable subscribers match."""


def message_class(type_name: str):
    """Return the rclpy message class of a type name such as 'std_msgs/msg/Int8'."""
    package, _, name = type_name.split('/')
    module = __import__(f'{package}.msg', fromlist=[name])
    return getattr(module, name)


@dataclass
class PlayResult:
    """
    What ``ImuPlayer.play`` did.

    Attributes
    ----------
    published : int
        Messages published.
    wall_s : float
        Duration of the publishing, s.
    publish_time_ns : (published,) int64 array
        Wall-clock time (``time.time_ns``, comparable across processes) right after each
        message was handed to the middleware.

    """

    published: int
    wall_s: float
    publish_time_ns: np.ndarray


class ImuPlayer(Node):
    """
    Publishes an ImuRecording as sensor_msgs/Imu at its recorded pace (or scaled).

    Parameters
    ----------
    recording : ImuRecording
        The samples; header.stamp and frame_id as recorded, orientation unknown
        (orientation_covariance[0] = -1, REP 145), covariances 0 (unknown).
    topic : str
        Topic to publish on.
    node_kwargs
        Passed to rclpy's Node.

    """

    def __init__(self, recording, topic: str = '/imu/data', **node_kwargs):
        super().__init__('imu_player', **node_kwargs)
        self.recording = recording
        self.publisher = self.create_publisher(Imu, topic, PLAYER_QOS)

    def wait_for_subscribers(self, count: int = 1, timeout_s: float = 10.0,
                             settle_s: float = 0.5) -> bool:
        """
        Wait until ``count`` subscriptions match, then ``settle_s`` more; False on timeout.

        The publisher sees a match a moment before the subscriber may; ``settle_s`` lets the
        subscriber's side of discovery finish so that the first messages are not lost.
        """
        deadline = time.monotonic() + timeout_s
        while self.publisher.get_subscription_count() < count:
            if time.monotonic() > deadline:
                return False
            time.sleep(0.02)
        time.sleep(settle_s)
        return True

    def wait_until_ready(self, timeout_s: float = 180.0, stop=None) -> bool:
        """
        Wait until an IMU node that reads this topic publishes diagnostics; False on timeout.

        The IMU node subscribes before it loads its numba code and publishes diagnostics (whose
        "IMU input" status names its topic, ``imu_topic``) only after. Loading takes about 2 s;
        on a new machine, with numba's cache empty, compiling takes 30-60 s, and a walk
        played meanwhile loses all but its newest samples (``imu_qos_depth``).

        Parameters
        ----------
        timeout_s : float
            Longest wait, s.
        stop : callable or None
            Polled while waiting; True gives up (returns False).

        """
        from diagnostic_msgs.msg import DiagnosticArray
        import rclpy

        from ..nodes.qos import DIAGNOSTICS_QOS

        topic = self.publisher.topic_name
        ready = []

        def on_diagnostics(msg):
            ready.extend(status.name for status in msg.status
                         if any(kv.key == 'imu_topic' and kv.value == topic
                                for kv in status.values))

        subscription = self.create_subscription(DiagnosticArray, '/diagnostics', on_diagnostics,
                                                DIAGNOSTICS_QOS)
        try:
            deadline = time.monotonic() + timeout_s
            while not ready:
                if time.monotonic() > deadline or (stop is not None and stop()):
                    return False
                rclpy.spin_once(self, timeout_sec=0.2)
            return True
        finally:
            self.destroy_subscription(subscription)

    def play(self, rate: float = 1.0, max_rate_hz: float = 2000.0, stop=None) -> PlayResult:
        """
        Publish every sample once, paced by its stamps.

        Sample k goes out at wall time t_0 + (stamp_k - stamp_0) / rate; rate 0 publishes as
        fast as the receiver can be expected to follow: at ``max_rate_hz`` messages per
        second (a Python node handles about 2000 Imu messages/s).

        Parameters
        ----------
        rate : float
            Speed factor (1 = as recorded); 0 for the ``max_rate_hz`` ceiling only.
        max_rate_hz : float
            Most messages per second, whatever the rate.
        stop : callable or None
            Polled between messages; True stops early.

        """
        if rate < 0 or not max_rate_hz > 0:
            raise InputError(f'rate = {rate} must be >= 0 and max_rate_hz = {max_rate_hz} > 0')
        rec = self.recording
        stamps = np.asarray(rec.stamp_ns, dtype=np.int64)
        # Pace on the largest stamp so far, so that an out-of-order stamp cannot stall playback.
        pace_ns = np.maximum.accumulate(stamps - stamps[0]) if len(stamps) else stamps
        min_step_s = 1.0 / max_rate_hz
        publish_time_ns = np.zeros(len(stamps), dtype=np.int64)
        msg = Imu()
        msg.header.frame_id = rec.frame_id
        msg.orientation_covariance[0] = -1.0
        acc, gyr = rec.acc_b.tolist(), rec.gyr_b.tolist()
        sec, nanosec = np.divmod(stamps, 1_000_000_000)
        sec, nanosec = sec.tolist(), nanosec.tolist()
        start = time.perf_counter()
        published = 0
        for k in range(len(stamps)):
            # An absolute schedule: a late message goes out at once, and the ones after it
            # catch up at the pace of the recording, never faster than max_rate_hz on average.
            target = start + k * min_step_s
            if rate > 0:
                target = max(target, start + pace_ns[k] * 1e-9 / rate)
            delay = target - time.perf_counter()
            if delay > 0:
                time.sleep(delay)
            if stop is not None and stop():
                break
            msg.header.stamp.sec, msg.header.stamp.nanosec = sec[k], nanosec[k]
            a, w = msg.linear_acceleration, msg.angular_velocity
            a.x, a.y, a.z = acc[k]
            w.x, w.y, w.z = gyr[k]
            self.publisher.publish(msg)
            publish_time_ns[k] = time.time_ns()
            published += 1
        return PlayResult(published, time.perf_counter() - start, publish_time_ns[:published])


class OutputRecorder(Node):
    """
    Writes every message of the output topics to a new bag, serialised as received.

    Parameters
    ----------
    path : str or Path
        New bag directory (must not exist).
    storage : str
        'mcap' or 'sqlite3'.
    topics : sequence of (topic, type name, QoSProfile)
        What to record (default ``OUTPUT_TOPICS``).
    node_kwargs
        Passed to rclpy's Node.

    """

    def __init__(self, path, storage: str = 'mcap', topics=OUTPUT_TOPICS, **node_kwargs):
        super().__init__('output_recorder', **node_kwargs)
        self.path = Path(path)
        self.counts = {topic: 0 for topic, _, _ in topics}
        bag = BagWriter(self.path, storage=storage)
        self._bag = bag.__enter__()
        for topic, type_name, qos in topics:
            self.create_subscription(message_class(type_name), topic,
                                     self._writer(topic, type_name), qos, raw=True)

    def _writer(self, topic: str, type_name: str):
        def write(data: bytes):
            if self._bag is not None:
                self._bag.write_raw(topic, type_name, data, self.get_clock().now().nanoseconds)
                self.counts[topic] += 1
        return write

    def close(self):
        """Finish the bag (safe to call twice)."""
        if self._bag is not None:
            bag, self._bag = self._bag, None
            bag.__exit__(None, None, None)


LISTENER_DEPTH = 1000   # outputs a CycleListener queues per topic while busy


class CycleListener(Node):
    """
    Collects the classifier's outputs: elevation points, modes, floors, as they arrive.

    Attributes
    ----------
    elevations : list of (stamp_ns, x_m, y_m, height_m, receive_time_ns)
    modes, floors, floor_certain : list of (value, receive_time_ns)
    floor_ranges : list of (list of int, receive_time_ns), from ``floor_range``
    cycles : list of (CycleMessage, receive_time_ns), from ``gait_cycle``
    diagnostics : dict
        {status name: (level, message, {key: value})}, the latest of each.

    """

    def __init__(self, on_elevation=None, **node_kwargs):
        from diagnostic_msgs.msg import DiagnosticArray
        from geometry_msgs.msg import PointStamped
        from sensor_msgs.msg import PointCloud2
        from std_msgs.msg import Bool, Int32, Int32MultiArray, Int8

        from ..nodes.qos import DIAGNOSTICS_QOS

        super().__init__('cycle_listener', **node_kwargs)
        self.elevations, self.modes, self.floors, self.cycles = [], [], [], []
        self.floor_certain, self.floor_ranges = [], []
        self.diagnostics = {}
        self._on_elevation = on_elevation
        self.create_subscription(DiagnosticArray, '/diagnostics', self._diagnostics,
                                 DIAGNOSTICS_QOS)
        # Relative: a listener made with namespace='/ff1' hears the responder run there. A
        # deep reader queue (compatible with the depth-1 publishers) keeps a burst of outputs
        # (a late classifier going through the cycle history) when this listener is slow.
        latest = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=LISTENER_DEPTH,
                            reliability=LATEST_QOS.reliability, durability=LATEST_QOS.durability)
        self.create_subscription(PointStamped, 'elevation', self._elevation, latest)
        self.create_subscription(Int8, 'stair_mode', self._mode, latest)
        self.create_subscription(Int32, 'floor', self._floor, latest)
        self.create_subscription(Bool, 'floor_certain', self._floor_certain, latest)
        self.create_subscription(Int32MultiArray, 'floor_range', self._floor_range, latest)
        self.create_subscription(PointCloud2, 'gait_cycle', self._cycle, CYCLE_QOS)

    def _elevation(self, msg):
        now = time.time_ns()
        stamp = msg.header.stamp
        item = (stamp.sec * 1_000_000_000 + stamp.nanosec, msg.point.x, msg.point.y,
                msg.point.z, now)
        self.elevations.append(item)
        if self._on_elevation is not None:
            self._on_elevation(item)

    def _mode(self, msg):
        self.modes.append((msg.data, time.time_ns()))

    def _floor(self, msg):
        self.floors.append((msg.data, time.time_ns()))

    def _floor_certain(self, msg):
        self.floor_certain.append((msg.data, time.time_ns()))

    def _floor_range(self, msg):
        self.floor_ranges.append((list(msg.data), time.time_ns()))

    def _cycle(self, msg):
        self.cycles.append((cycle_from_msg(msg), time.time_ns()))

    def _diagnostics(self, msg):
        for status in msg.status:
            self.diagnostics[status.name] = (
                status.level, status.message, {kv.key: kv.value for kv in status.values})

    def diagnostic_value(self, name: str, key: str, default=None):
        """Return a value of the latest status ``name`` (a string), or default."""
        status = self.diagnostics.get(name)
        return status[2].get(key, default) if status else default
