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
The classifier node: gait cycles in, stair mode, quantised height and floor out.

Each valid gait cycle from the IMU node goes through ``ElevationTracker.update`` (ANFIS ->
stair mode, eq. 13 -> quantised height, eq. 14 -> floor). Invalid cycles (a gap or an
overlong swing) and malformed messages are counted, not classified: the height stays as it
was. The model is loaded once at start from ``model_path`` ('' = the packaged
``config/anfis_default.json``); a missing or corrupt model stops the node at start with an
error and exit code 1, so it never runs with garbage.

Topics
------
Subscribes:
    ``gait_cycle``, sensor_msgs/PointCloud2 (layout in ``nodes/common.py``), reliable.
Publishes (reliable, transient local, depth 1: a late subscriber gets the latest at once):
    ``elevation``, geometry_msgs/PointStamped: frame ``map_frame_id`` (``map``), stamp = the
    IMU stamp of the sample that closed the cycle, x, y = INS position, z = quantised height.
    ``stair_mode``, std_msgs/Int8: +1 up, 0 level, -1 down, per classified cycle.
    ``floor``, std_msgs/Int32: the floor index per classified cycle, and ``elevation.start_floor``
    once at start.
    ``/diagnostics``, diagnostic_msgs/DiagnosticArray at 1 Hz: "classifier_node: elevation"
    (cycles classified, invalid, malformed, height, floor, mode).

Parameters: ``elevation.*`` (step height, mode threshold, storey height and start floor may
change live; the height is kept), ``model_path``, ``map_frame_id``; see ``core/params.py``.
"""

import sys

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PointStamped
from rclpy.node import Node
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Int32, Int8

from .common import cycle_from_msg, CYCLE_QOS, declare_node_parameters, DIAGNOSTICS_QOS
from .common import diagnostic_status, LATEST_QOS, LiveParameters, ns_to_stamp, spin_node
from ..core.errors import InputError
from ..core.height import ElevationTracker
from ..core.params import CLASSIFIER_NODE, elevation_params_from_dict, load_model, model_file

LOG_PERIOD_S = 5.0
DIAGNOSTICS_PERIOD_S = 1.0


class ClassifierNode(Node):
    """
    Gait-cycle features to stair mode, height and floor.

    Parameters
    ----------
    kwargs
        Passed to rclpy's Node (e.g. ``context``, ``parameter_overrides``).

    Raises
    ------
    InputError : bad parameters, or a missing or corrupt model file.

    """

    def __init__(self, **kwargs):
        super().__init__(CLASSIFIER_NODE, **kwargs)
        values = declare_node_parameters(self, CLASSIFIER_NODE)
        self._model = load_model(values['model_path'])
        self.get_logger().info(f"ANFIS model loaded from {model_file(values['model_path'])}")
        self._tracker = ElevationTracker(self._model, elevation_params_from_dict(values))
        self._live_parameters = LiveParameters(
            self, CLASSIFIER_NODE, values, elevation_params_from_dict, self._apply_parameters)
        self._map_frame_id = values['map_frame_id']
        self._classified = 0
        self._invalid = 0
        self._malformed = 0
        self._last_mode = 0
        self._floor = self._tracker.floor

        self._elevation_pub = self.create_publisher(PointStamped, 'elevation', LATEST_QOS)
        self._mode_pub = self.create_publisher(Int8, 'stair_mode', LATEST_QOS)
        self._floor_pub = self.create_publisher(Int32, 'floor', LATEST_QOS)
        self._diag_pub = self.create_publisher(DiagnosticArray, '/diagnostics', DIAGNOSTICS_QOS)
        self.create_subscription(PointCloud2, 'gait_cycle', self._on_cycle, CYCLE_QOS)
        self.create_timer(DIAGNOSTICS_PERIOD_S, self._publish_diagnostics)
        self._floor_pub.publish(Int32(data=self._floor))
        self.get_logger().info(f'start floor {self._floor}')

    def _apply_parameters(self, values, changed):
        # Keep the height; the new step height counts from here, the floor follows the
        # new storey height and start floor.
        self._tracker = ElevationTracker(self._model, elevation_params_from_dict(values),
                                         height_m=self._tracker.height_m)
        self.get_logger().info(f'parameters changed: {", ".join(changed)}')
        self._publish_floor_if_changed()

    def _on_cycle(self, msg: PointCloud2):
        try:
            cycle = cycle_from_msg(msg)
        except InputError as err:
            self._malformed += 1
            self.get_logger().warning(f'gait_cycle message skipped: {err}',
                                      throttle_duration_sec=LOG_PERIOD_S)
            return
        if not cycle.valid:
            self._invalid += 1
            return
        try:
            estimate = self._tracker.update(cycle.stamp_ns, cycle.features, cycle.x_m,
                                            cycle.y_m)
        except InputError as err:
            self._malformed += 1
            self.get_logger().warning(f'gait cycle skipped: {err}',
                                      throttle_duration_sec=LOG_PERIOD_S)
            return
        self._classified += 1
        self._last_mode = estimate.mode
        point = PointStamped()
        point.header.stamp = ns_to_stamp(estimate.stamp_ns)
        point.header.frame_id = self._map_frame_id
        point.point.x, point.point.y, point.point.z = estimate.x_m, estimate.y_m, \
            float(estimate.height_m)
        self._elevation_pub.publish(point)
        self._mode_pub.publish(Int8(data=int(estimate.mode)))
        self._floor_pub.publish(Int32(data=int(estimate.floor)))
        if estimate.floor != self._floor:
            self.get_logger().info(f'floor {self._floor} -> {estimate.floor} (height '
                                   f'{estimate.height_m:.2f} m)')
            self._floor = estimate.floor

    def _publish_floor_if_changed(self):
        floor = self._tracker.floor
        if floor != self._floor:
            self.get_logger().info(f'floor {self._floor} -> {floor} (parameters changed)')
            self._floor = floor
            self._floor_pub.publish(Int32(data=int(floor)))

    def diagnostics(self, now_ns: int) -> DiagnosticArray:
        """Build the classifier's diagnostics."""
        if self._malformed:
            level, message = DiagnosticStatus.WARN, f'{self._malformed} malformed cycles'
        else:
            level, message = DiagnosticStatus.OK, 'ok'
        values = {'classified': self._classified, 'invalid_cycles': self._invalid,
                  'malformed': self._malformed, 'height_m': self._tracker.height_m,
                  'floor': self._floor, 'last_mode': self._last_mode}
        msg = DiagnosticArray(status=[diagnostic_status(
            'classifier_node: elevation', level, message, self._map_frame_id, values)])
        msg.header.stamp = ns_to_stamp(now_ns)
        return msg

    def _publish_diagnostics(self):
        self._diag_pub.publish(self.diagnostics(self.get_clock().now().nanoseconds))

    @property
    def tracker(self) -> ElevationTracker:
        """Give access to the elevation tracker, its height and floor."""
        return self._tracker


def main(args=None) -> int:
    """Run the classifier node until Ctrl-C or shutdown; return the exit code."""
    return spin_node(ClassifierNode, CLASSIFIER_NODE, args)


if __name__ == '__main__':
    sys.exit(main())
