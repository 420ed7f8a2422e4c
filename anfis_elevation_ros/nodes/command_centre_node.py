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
The command centre's ROS side: finds every responder on the DDS domain and feeds the Incident.

A responder is a namespace that publishes ``elevation`` (geometry_msgs/PointStamped), as
``run --namespace /ff1`` does; the namespace is the responder's id. Every
``discovery_period_s`` the node reads the ROS graph (``get_topic_names_and_types``) and
subscribes each new responder's topics:

======================  ===============  ============================  ====================
topic                   type             QoS                           Incident
======================  ===============  ============================  ====================
``elevation``           PointStamped     reliable, transient local, 1  update_elevation
``floor``               Int32            reliable, transient local, 1  update_floor
``floor_certain``       Bool             reliable, transient local, 1  update_floor_certain
``floor_range``         Int32MultiArray  reliable, transient local, 1  update_floor_range
``stair_mode``          Int8             reliable, transient local, 1  update_mode
``foot_odom_throttle``  Odometry (raw)   reliable, transient local, 1  update_pose
``/diagnostics``        DiagnosticArray  reliable, volatile, 10        update_diagnostics
======================  ===============  ============================  ====================

``foot_odom_throttle`` is the IMU node's track at ``centre_track_rate_hz`` (2 Hz), not its
10 Hz ``foot_odom``: 50 responders' 10 Hz tracks took 11-14 % of a core here, 2 Hz 7.5 %
(``test/benchmarks/bench_command_centre_dds.py``). It is still most of the messages: taken
raw and decoded by rosbags (``odometry_msg.py``), a fifth of the cost of rclpy's Python
message.

Transient local as the responders publish them: a command centre started late gets every
responder's last state at once. A diagnostics status belongs to the responder whose node's
full name starts it (``/ff1/imu_node: IMU input``); statuses of other nodes are ignored.

The heading shown is the direction of travel (the last ``HEADING_BASE_M`` of track), not the
IMU's yaw: it does not depend on how the IMU is mounted on the boot.

Bad input never stops the node: the Incident refuses and counts non-finite values; a topic
with a responder's name but another type is not subscribed (logged once); a message the
conversion cannot read is counted (``rejected``) and logged, at most once per
``LOG_PERIOD_S``.
"""

import math
import time

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PointStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node
from std_msgs.msg import Bool, Int32, Int32MultiArray, Int8

from .node_params import declare_node_parameters
from .odometry_msg import odometry_from_cdr
from .qos import DIAGNOSTICS_QOS, LATEST_QOS
from .stamps import stamp_to_ns
from ..core.building import load_building_file
from ..core.errors import InputError
from ..core.params import ALARM_PREFIX, check_command_centre_params, COMMAND_CENTRE_NODE

ELEVATION = 'elevation'
ELEVATION_TYPE = 'geometry_msgs/msg/PointStamped'
HEADING_BASE_M = 0.5
LOG_PERIOD_S = 10.0


def responder_of_topic(topic: str, types) -> str:
    """
    Return the namespace of a responder's ``elevation`` topic, or None for any other topic.

    ``/ff1/elevation`` of type PointStamped is responder ``/ff1``; ``/elevation`` (the root
    namespace) is not a responder the Incident can name, and is None too.
    """
    head, _, leaf = topic.rpartition('/')
    if leaf != ELEVATION or not head or ELEVATION_TYPE not in types:
        return None
    return head


def responder_of_status(name: str, responders) -> str:
    """Return the responder (namespace) whose node's full name starts a status name, or None."""
    node, sep, _ = name.partition(':')
    if not sep:
        return None
    namespace = node.strip().rpartition('/')[0]
    return namespace if namespace in responders else None


def yaw_deg(qw: float, qx: float, qy: float, qz: float) -> float:
    """
    Yaw of a body-to-ENU quaternion, degrees counter-clockwise from +x (east), REP 103.

    psi = atan2(2 (w z + x y), 1 - 2 (y^2 + z^2))
    """
    return math.degrees(math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz)))


class TravelHeading:
    """
    Direction of travel of one responder: the bearing of the last ``base_m`` of track.

    Before the responder has moved that far, the IMU's yaw stands in.
    """

    def __init__(self, base_m: float = HEADING_BASE_M):
        self.base_m = base_m
        self._anchor = None
        self.heading_deg = None

    def update(self, x_m: float, y_m: float, imu_yaw_deg: float) -> float:
        """Take a position; return the heading, degrees counter-clockwise from +x."""
        if not (math.isfinite(x_m) and math.isfinite(y_m)):
            return imu_yaw_deg         # the Incident refuses the position; keep the anchor
        if self._anchor is None:
            self._anchor = (x_m, y_m)
        dx, dy = x_m - self._anchor[0], y_m - self._anchor[1]
        if math.hypot(dx, dy) >= self.base_m:
            self.heading_deg = math.degrees(math.atan2(dy, dx))
            self._anchor = (x_m, y_m)
        return imu_yaw_deg if self.heading_deg is None else self.heading_deg


def level_of(level) -> int:
    """DiagnosticStatus.level (a byte in rclpy) as an int."""
    return level[0] if isinstance(level, (bytes, bytearray)) and len(level) == 1 else level


class CommandCentreNode(Node):
    """
    Discovers responders and feeds their topics to an Incident; ticks its timers.

    Parameters (core/params.py, node ``command_centre``): ``building_file``,
    ``discovery_period_s``, ``tick_rate_hz``, ``alarm.*`` (the Incident's AlarmParams), and the
    web server's ``host``, ``port``, ``insecure``, ``tls_cert_file``, ``tls_key_file`` (read by
    ``tools/command_centre.py`` from ``values``).

    Attributes
    ----------
    incident : command_centre.Incident
        The model the web page shows.
    values : dict
        The node's parameter values.
    responders : set of str
        Namespaces subscribed so far.
    rejected : int
        Messages that could not be read.

    """

    def __init__(self, **node_kwargs):
        from ..command_centre.alarms import AlarmParams
        from ..command_centre.incident import Incident

        super().__init__(COMMAND_CENTRE_NODE, **node_kwargs)
        self.values = declare_node_parameters(self, COMMAND_CENTRE_NODE)
        check_command_centre_params(self.values)
        building = load_building_file(self.values['building_file'])
        alarm = {name[len(ALARM_PREFIX):]: value for name, value in self.values.items()
                 if name.startswith(ALARM_PREFIX)}
        try:
            params = AlarmParams(**alarm)
        except ValueError as err:
            raise InputError(str(err)) from None
        self.incident = Incident(building, params)
        self.responders = set()
        self.rejected = 0
        self._refused_topics = set()
        self._headings = {}
        self._last_log = -math.inf
        self.create_subscription(DiagnosticArray, '/diagnostics', self._guarded(
            self._on_diagnostics), DIAGNOSTICS_QOS)
        self.create_timer(self.values['discovery_period_s'], self.discover)
        self.create_timer(1.0 / self.values['tick_rate_hz'], self.incident.tick)
        self.discover()

    def discover(self):
        """Subscribe the topics of every responder that appeared in the ROS graph."""
        for topic, types in self.get_topic_names_and_types():
            responder = responder_of_topic(topic, types)
            if responder is None:
                if topic.rpartition('/')[2] == ELEVATION and topic not in self._refused_topics:
                    self._refused_topics.add(topic)
                    self.get_logger().warning(
                        f'{topic} ({", ".join(types)}) is not a responder: responders publish '
                        f'{ELEVATION_TYPE} under a namespace (run --namespace /ff1)')
                continue
            if responder not in self.responders:
                self._subscribe(responder)

    def _subscribe(self, ns: str):
        incident = self.incident
        self.responders.add(ns)
        self._headings[ns] = TravelHeading()
        feeds = (
            (PointStamped, ELEVATION, lambda m: incident.update_elevation(
                ns, stamp_to_ns(m.header.stamp), m.point.x, m.point.y, m.point.z)),
            (Int32, 'floor', lambda m: incident.update_floor(ns, m.data)),
            (Bool, 'floor_certain', lambda m: incident.update_floor_certain(ns, m.data)),
            (Int32MultiArray, 'floor_range',
             lambda m: incident.update_floor_range(ns, [int(f) for f in m.data])),
            (Int8, 'stair_mode', lambda m: incident.update_mode(ns, m.data)),
        )
        for msg_type, name, feed in feeds:
            self.create_subscription(msg_type, f'{ns}/{name}', self._guarded(feed), LATEST_QOS)
        # Most of the messages: decoded from the raw bytes by rosbags (odometry_msg.py).
        self.create_subscription(Odometry, f'{ns}/foot_odom_throttle', self._guarded(
            lambda data: self._on_odom(ns, odometry_from_cdr(data))), LATEST_QOS, raw=True)
        self.get_logger().info(f'responder {ns} found; subscribed to its topics')

    def _on_odom(self, ns: str, msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        covariance = msg.pose.covariance
        horizontal_variance = covariance[0] + covariance[7]
        sigma_xy_m = math.sqrt(horizontal_variance) if horizontal_variance > 0 else None
        heading_deg = self._headings[ns].update(p.x, p.y, yaw_deg(q.w, q.x, q.y, q.z))
        self.incident.update_pose(ns, stamp_to_ns(msg.header.stamp), p.x, p.y, p.z,
                                  heading_deg, sigma_xy_m)

    def _on_diagnostics(self, msg):
        for status in msg.status:
            responder = responder_of_status(status.name, self.responders)
            if responder is not None:
                self.incident.update_diagnostics(responder, level_of(status.level),
                                                 status.name, status.message)

    def _guarded(self, feed):
        """Wrap a callback: a message it cannot read is counted and logged, never raised."""
        def callback(msg):
            try:
                feed(msg)
            except (ArithmeticError, TypeError, ValueError, IndexError) as err:
                self.rejected += 1
                now = time.monotonic()
                if now - self._last_log >= LOG_PERIOD_S:
                    self._last_log = now
                    self.get_logger().warning(
                        f'message refused ({self.rejected} so far): {type(err).__name__}: {err}')
        return callback
