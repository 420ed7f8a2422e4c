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
The IMU node: foot IMU in, gait cycles, foot track and diagnostics out.

Each ``sensor_msgs/msg/Imu`` message goes through the input gate (``core/input_gate.py``:
non-finite values, wrong frame, out-of-order or duplicate stamps, wrong units are refused,
saturation and gaps are counted) and then ``FootNavigator.step``. Nothing that was refused
reaches the navigator, and a navigator error (IMU data that are not SI at start-up) is
counted as ``wrong_units``: bad input never stops the node.

Topics
------
Subscribes:
    ``imu_topic`` (parameter, default ``imu/data``: ``/ff1/imu/data`` under ``/ff1``),
    sensor_msgs/Imu, sensor-data QoS with
    depth ``imu_qos_depth`` (2000: 5 s at 400 Hz; with 200 a loaded two-core machine dropped
    messages when the imu node fell behind for a moment). A thread of the node takes the
    messages in batches every ``imu_batch_period_s`` (8 ms; ``PolledSubscription``, its helper
    node is ``<node name>_input``): at 400 Hz about a fifth less CPU than one executor
    callback per message. Once the foot is still in a swing, the sample that will close the
    gait cycle is due after the few samples the stance still needs: the thread wakes then, so
    the batching does not delay the cycles. 0 gives one callback per message.
Publishes:
    ``gait_cycle``, sensor_msgs/PointCloud2, reliable, transient local, depth
    ``cycle_history`` (3600): one message per gait cycle (invalid ones too, flagged), one
    point, fields x, y, z (raw INS height), valid, the five features and the cycle index;
    layout in ``nodes/gait_cycle_msg.py``. A classifier that starts late gets the cycles it missed.
    ``foot_odom``, nav_msgs/Odometry, reliable, transient local, depth 1, at
    ``track_rate_hz`` (10 Hz): the latest EKF pose of the IMU, frame ``odom_frame_id``
    (REP 105 ``odom``), child frame the IMU frame; position covariance from the filter
    (isotropic, sigma^2 / 3 per axis), the rest unknown (0); twist not estimated (0).
    ``foot_odom_throttle``, the same, at ``centre_track_rate_hz`` (2 Hz), for the command
    centre: 50 responders' 10 Hz tracks cost it more CPU than it has, and a radio network
    358 kB/s (``topic_tools throttle``'s name; those tools are not in the wheels).
    With a building file that has a ``start``, ``foot_odom`` and ``gait_cycle`` are in the
    building's frame, ``map_frame_id`` (REP 105 ``map``: the track starts at the entrance,
    turned so that its first strides point along ``start.heading_deg``, ``core/map_frame.py``;
    stair-entry corrections make it jump, as a map-frame pose may).
    ``/diagnostics``, diagnostic_msgs/DiagnosticArray, at ``diagnostics_rate_hz`` (1 Hz):
    "/imu_node: IMU input" (its topic, ``imu_topic``; rate, refusals by reason, saturated
    samples, gaps, samples lost in transit estimated from the stamps: WARN above 1 % per
    period; the first is published once the navigator is compiled: ready) and
    "/imu_node: foot navigator" (initialised, stance fraction, cycles, NIS, position sigma,
    resumed or not, state file and failed writes; with stairs: stair-entry corrections
    received, applied, pending, late, duplicate, stale, malformed, last NIS). The names start
    with the node's full name: "/ff1/imu_node: IMU input" under the namespace /ff1.
Subscribes too, with a building that has ``stairs`` and a ``start``:
    ``stair_fix``, sensor_msgs/PointCloud2 (``nodes/stair_fix_msg.py``), reliable, transient
    local, depth 100: the classifier's stair-entry correction requests. Each is applied once,
    as a horizontal position measurement in the EKF, at the first stance sample at least
    ``building_aid.stair_fix_delay_s`` (0.5 s) of sensor time after its gait cycle
    (``core/position_fix.py``): the sample ``replay`` applies it at, so live equals replay.
    One that arrives after that sample was handled (the classifier stalled) is applied at the
    next stance and counted as late (WARN: the track then differs from a replay).

Parameters: every navigator and input-gate parameter of ``core/params.py`` (read once at start;
the ``gate.*`` ones may change live) and the node-level ones listed there.

Persisted state (``persist_state``, ``state_dir``, ``state_max_age_s``, ``resume_max_gap_s``):
after every gait cycle the node writes a ``NavigationState`` (position, heading, filter status,
IMU identity = Imu topic and frame_id, cycle count, walk identity) atomically with permissions
0600 to ``<state_dir>/<node name>.state.json``. At the first accepted IMU message it decides: a
state that is fresh, from the same IMU, written while the filter was healthy, and continued by
the sensor's own stamps (the first stamp after the saved one by at most ``resume_max_gap_s``:
``core/state.py``, ``walk_continues``) is resumed (the INS starts at the saved position and
heading at its first stance, cycle indices and the walk identity carry on); otherwise it
starts fresh, with a new walk identity. The log and the diagnostics (``resume``: the decision
and why; ``resume_refusals``: saved states not resumed) say which. The motion while the node
was down is unknown: at its first stance the resumed node publishes one invalid cycle per
stride period (recent median) that passed since the saved cycle (``core/outage.py``,
``outage_cycle_count``), flagged ``outage``: the classifier bridges them when the stair mode on
both sides agrees and otherwise says the floor is uncertain.
The state also says whether the position is in the building's map frame (a state is resumed
only into the same kind of frame) and which stair-entry corrections it already contains: those
are never applied again, and a request the restarted node gets again from the topic's history
that the saved position does not contain yet is applied once, late.
"""

from collections import deque
import sys
import threading
import time

from diagnostic_msgs.msg import DiagnosticArray
from nav_msgs.msg import Odometry
import numpy as np
from rclpy.node import Node
from sensor_msgs.msg import Imu, PointCloud2

from .gait_cycle_msg import cycle_to_msg
from .imu_diagnostics import input_status, InputPeriod, navigator_status
from .imu_msg import imu_sample_from_cdr
from .node_params import declare_node_parameters, LiveParameters
from .polled_subscription import PolledSubscription
from .qos import cycle_history_qos, DIAGNOSTICS_QOS, imu_qos, LATEST_QOS, STAIR_FIX_QOS
from .spin import spin_node
from .stair_fix_msg import request_from_msg
from .stamps import ns_to_stamp
from .state_writer import PersistsState
from ..core.building import load_building_file
from ..core.errors import InputError
from ..core.gait import GaitCycle, N_FEATURES
from ..core.heading_aids import hde_directions_deg
from ..core.input_gate import InputGate, WRONG_UNITS
from ..core.map_frame import map_alignment_for
from ..core.navigator import compile_navigator, FootNavigator
from ..core.outage import outage_cycle_count
from ..core.params import building_aid_params_from_dict, gate_params_from_dict, IMU_NODE
from ..core.params import navigator_params_from_dict
from ..core.position_fix import PositionFixQueue
from ..core.state import NavigationState, new_walk_id, resumable_state, state_file
from ..core.state import walk_continues

REJECT_LOG_PERIOD_S = 5.0
STRIDE_PERIODS = 5          # recent cycle periods whose median is the stride period
MIN_STRIDE_PERIOD_S = 0.1   # periods outside these limits are not strides: the clock went
MAX_STRIDE_PERIOD_S = 3.0   # back, or the firefighter stopped


class ImuNode(PersistsState, Node):
    """
    Foot IMU to gait cycles: input gate, FootNavigator, publishers, diagnostics.

    Parameters
    ----------
    kwargs
        Passed to rclpy's Node (e.g. ``context``, ``parameter_overrides``).

    Raises
    ------
    InputError : bad parameters (type, range, inconsistent values).

    """

    def __init__(self, **kwargs):
        super().__init__(IMU_NODE, **kwargs)
        values = declare_node_parameters(self, IMU_NODE)
        self._navigator_params = navigator_params_from_dict(values)
        self._gate = InputGate(gate_params_from_dict(values))
        self._building = load_building_file(values['building_file'])
        if self._building is not None:
            self.get_logger().info(f'building {self._building.name or ""} loaded from '
                                   f'{self._building.source}')
        aid = building_aid_params_from_dict(values)
        self._in_map_frame = self._building is not None and self._building.start is not None
        self._hde_directions_deg = hde_directions_deg(self._building, self._in_map_frame)
        self._navigator = FootNavigator(
            self._navigator_params, map_alignment=map_alignment_for(self._building,
                                                                    aid.align_strides),
            dominant_directions_deg=self._hde_directions_deg)
        self._fixes = PositionFixQueue(aid.stair_fix_delay_s, aid.stair_fix_sigma_m)
        self._take_fixes = self._in_map_frame and bool(self._building.stairs)
        self._malformed_fixes = 0
        self._live_parameters = LiveParameters(
            self, IMU_NODE, values, self._check_parameters, self._apply_parameters)
        self._track_frame_id = values['map_frame_id' if self._in_map_frame else 'odom_frame_id']
        self._imu_frame_id = values['gate.frame_id']
        self._received = 0
        self._internal_errors = 0
        self._malformed = 0
        self._last_point = None
        self._published_points = {}     # publisher -> the point it published last
        self._input_period = InputPeriod(self._gate, self.get_clock().now().nanoseconds)
        self._imu_topic = self.resolve_topic_name(values['imu_topic'])
        self._full_name = self.get_fully_qualified_name()
        self._persist = values['persist_state']
        self._state_path = state_file(values['state_dir'], self.get_fully_qualified_name())
        self._start_state_writer(self._state_path, self._persist)
        self._state_max_age_s = values['state_max_age_s']
        self._resume_max_gap_s = values['resume_max_gap_s']
        self._walk_id = new_walk_id()
        self._resume_decision = 'waiting for the first IMU message'
        self._resume_refusals = 0
        self._source_id = None        # set by the first accepted IMU message
        self._resumed = False
        self._cycle_index = 0
        self._last_cycle_stamp_ns = None
        self._periods_s = deque(maxlen=STRIDE_PERIODS)
        self._resumed_from = None     # the resumed state until the first stance
        self._outage_cycles = 0

        self._cycle_pub = self.create_publisher(PointCloud2, 'gait_cycle',
                                                cycle_history_qos(values['cycle_history']))
        self._odom_pub = self.create_publisher(Odometry, 'foot_odom', LATEST_QOS)
        self._throttled_pub = self.create_publisher(Odometry, 'foot_odom_throttle', LATEST_QOS)
        self._diag_pub = self.create_publisher(DiagnosticArray, '/diagnostics', DIAGNOSTICS_QOS)
        # Raw messages: _on_imu decodes the CDR bytes itself (imu_sample_from_cdr), which
        # halves the cost of a message compared with building the Python Imu object.
        self._lock = threading.Lock()    # the input thread's batches against the callbacks
        self._input = None
        qos = imu_qos(values['imu_qos_depth'])
        if values['imu_batch_period_s'] > 0.0:
            self._input = PolledSubscription(self, Imu, self._imu_topic, qos, self._on_imu,
                                             values['imu_batch_period_s'], self._lock,
                                             due_s=self._closing_sample_due_s)
        else:
            self.create_subscription(Imu, values['imu_topic'], self._on_imu, qos, raw=True)
        if self._take_fixes:
            self.create_subscription(PointCloud2, 'stair_fix', self._on_stair_fix, STAIR_FIX_QOS)
        # Subscribed first, compiled (or loaded from numba's cache) after: the samples that
        # arrive meanwhile wait in the queue (imu_qos_depth) instead of being lost, which
        # shortens the outage of a restart by the load time (test/benchmarks/bench_startup.py).
        with self._lock:
            compile_s = compile_navigator()
        if compile_s > 1.0:
            self.get_logger().info(f'navigator compiled in {compile_s:.0f} s (cached from now on)')
        if values['track_rate_hz'] > 0.0:
            self.create_timer(1.0 / values['track_rate_hz'],
                              lambda: self._publish_track(self._odom_pub))
        if values['centre_track_rate_hz'] > 0.0:
            self.create_timer(1.0 / values['centre_track_rate_hz'],
                              lambda: self._publish_track(self._throttled_pub))
        self.create_timer(1.0 / values['diagnostics_rate_hz'], self._publish_diagnostics)
        self.get_logger().info(f'listening on {self._imu_topic}; waiting for the first stance '
                               f'to start navigating; track in frame {self._track_frame_id!r}')

    # -- parameters ----------------------------------------------------------------------------

    @staticmethod
    def _check_parameters(values):
        navigator_params_from_dict(values)
        gate_params_from_dict(values)

    def _apply_parameters(self, values, changed):
        with self._lock:
            self._gate.set_params(gate_params_from_dict(values))
            self._imu_frame_id = values['gate.frame_id']
        self.get_logger().info(f'parameters changed: {", ".join(changed)}')

    # -- input ---------------------------------------------------------------------------------

    def _on_imu(self, data: bytes):
        self._received += 1
        try:
            self._handle_imu(data)
        except Exception as err:   # noqa: B902 a bug must not stop a firefighter's tracking
            self._internal_errors += 1
            self.get_logger().error(f'internal error on an IMU sample ({type(err).__name__}: '
                                    f'{err}); sample skipped',
                                    throttle_duration_sec=REJECT_LOG_PERIOD_S)

    def _on_stair_fix(self, msg: PointCloud2):
        try:
            self._handle_stair_fix(msg)
        except Exception as err:   # noqa: B902 a bug must not stop a firefighter's tracking
            self._internal_errors += 1
            self.get_logger().error(f'internal error on a stair_fix request '
                                    f'({type(err).__name__}: {err}); request skipped')

    def _handle_stair_fix(self, msg: PointCloud2):
        try:
            request = request_from_msg(msg)
            if msg.header.frame_id != self._track_frame_id:
                raise InputError(f'its frame is {msg.header.frame_id!r}, not '
                                 f'{self._track_frame_id!r}')
        except InputError as err:
            self._malformed_fixes += 1
            self.get_logger().warning(f'stair_fix request refused: {err}')
            return
        with self._lock:
            verdict = self._fixes.submit(request)
        text = (f'stair-entry correction of cycle {request.cycle_index} {verdict} (entry '
                f'({request.entry_x_m:.2f}, {request.entry_y_m:.2f}) m)')
        if verdict == 'late':
            self.get_logger().warning(f'{text}: its sample has passed, applied at the next '
                                      'stance; the track now differs from a replay')
        else:
            self.get_logger().info(text)

    def _closing_sample_due_s(self):
        """Seconds until the sample that will close a gait cycle, if one is foreseen."""
        samples = self._navigator.samples_to_stance
        return None if samples is None else samples / self._navigator.status.rate_hz

    def _handle_imu(self, data: bytes):
        try:
            stamp_ns, acc_b, gyr_b, frame_id = imu_sample_from_cdr(data)
        except InputError as err:
            self._malformed += 1
            self.get_logger().warning(f'IMU message refused: {err}',
                                      throttle_duration_sec=REJECT_LOG_PERIOD_S)
            return
        latched = self._gate.units_latched
        reason = self._gate.check(stamp_ns, acc_b, gyr_b, frame_id)
        if reason is not None:
            if self._gate.units_latched and not latched:
                self.get_logger().error('IMU data are in the wrong units (gyro beyond 40 rad/s '
                                        'again and again: deg/s?); every message is refused '
                                        'until the units are fixed and the node restarted')
            self.get_logger().warning(f'IMU message refused: {reason} (counts in /diagnostics)',
                                      throttle_duration_sec=REJECT_LOG_PERIOD_S)
            return
        if self._source_id is None:
            self._resume_or_start_fresh(frame_id, stamp_ns)
            if not self._resumed:
                self._fixes.refuse_before(stamp_ns)   # requests of an earlier walk
        was_initialised = self._navigator.initialised
        try:
            outputs = self._navigator.step(stamp_ns, np.array(acc_b), np.array(gyr_b))
        except InputError as err:
            self._gate.refuse_accepted(WRONG_UNITS)
            self.get_logger().error(f'IMU data refused by the navigator: {err}',
                                    throttle_duration_sec=REJECT_LOG_PERIOD_S)
            return
        for point, cycle in outputs:     # several after clipped gyro samples were held
            self._navigated(point, cycle, frame_id, was_initialised)
            was_initialised = True

    def _navigated(self, point, cycle, frame_id, was_initialised):
        """Take one navigated sample: stair-entry corrections due, its cycle published."""
        if not was_initialised:
            status = self._navigator.status
            self.get_logger().info(f'navigation started ({status.rate_hz:.1f} Hz IMU, frame '
                                   f'{frame_id!r})')
            if self._resumed_from is not None:
                self._publish_outage(point)
        for request in self._fixes.after_step(self._navigator, point):
            dx, dy = request.innovation_xy
            self.get_logger().info(f'stair-entry correction of cycle {request.cycle_index} '
                                   f'applied: ({dx:+.2f}, {dy:+.2f}) m, NIS '
                                   f'{self._fixes.last_nis:.1f}')
        if not self._imu_frame_id:
            self._imu_frame_id = frame_id
        self._last_point = point
        if cycle is not None:
            self._publish_cycle(cycle)
            if self._persist:
                self._save_state(cycle)

    def _publish_cycle(self, cycle, outage: bool = False):
        self._cycle_index += 1
        self._cycle_pub.publish(cycle_to_msg(cycle, self._track_frame_id, self._cycle_index,
                                             self._walk_id, outage))
        if self._last_cycle_stamp_ns is not None:
            period_s = (cycle.stamp_ns - self._last_cycle_stamp_ns) * 1e-9
            if MIN_STRIDE_PERIOD_S <= period_s <= MAX_STRIDE_PERIOD_S:
                self._periods_s.append(period_s)
        self._last_cycle_stamp_ns = cycle.stamp_ns

    def _stride_period_s(self) -> float:
        return float(np.median(self._periods_s)) if self._periods_s else 1.0

    def _publish_outage(self, point):
        """Publish the cycles lost while the node was down as invalid ones (see above)."""
        state, self._resumed_from = self._resumed_from, None
        outage_s = (point.stamp_ns - state.stamp_ns) * 1e-9     # > 0: walk_continues
        lost = outage_cycle_count(outage_s, state.stride_period_s)
        for k in range(1, lost + 1):
            stamp_ns = state.stamp_ns + (point.stamp_ns - state.stamp_ns) * k // (lost + 1)
            self._publish_cycle(GaitCycle(stamp_ns, stamp_ns, point.pos_n,
                                          np.zeros(N_FEATURES), valid=False), outage=True)
        self._outage_cycles += lost
        self.get_logger().info(f'{outage_s:.1f} s since the saved cycle: {lost} cycles lost '
                               'in the outage, published as invalid')

    # -- persisted state -----------------------------------------------------------------------

    def _resume_or_start_fresh(self, frame_id: str, stamp_ns: int):
        self._source_id = f'{self._imu_topic}:{frame_id}'
        if not self._persist:
            self._resume_decision = 'starting fresh (persist_state is false)'
            self.get_logger().info(self._resume_decision)
            return
        state, reason = resumable_state(self._state_path, NavigationState, self._source_id,
                                        self._state_max_age_s)
        if state is not None and not state.filter_ok:
            state, reason = None, 'starting fresh: the saved state had an unhealthy filter'
        if state is not None and state.map_frame != self._in_map_frame:
            frames = ['map' if in_map else 'start'
                      for in_map in (state.map_frame, self._in_map_frame)]
            state, reason = None, (f'starting fresh: the saved position is in the {frames[0]} '
                                   f'frame, the track now in the {frames[1]} frame')
        if state is not None:
            continues, why = walk_continues(state.stamp_ns, stamp_ns, self._resume_max_gap_s)
            state, reason = (state, f'{reason}; {why}') if continues else \
                (None, f'starting fresh: {why}')
        self._resume_decision = reason
        if state is None:
            if self._state_path.exists():
                self._resume_refusals += 1
            self.get_logger().info(reason)
            return
        self._walk_id = state.walk_id
        self._navigator = FootNavigator(self._navigator_params,
                                        start_pos_n=(state.x_m, state.y_m, state.z_m),
                                        start_heading_rad=state.heading_rad,
                                        start_sigmas=(state.pos_sigma_m, state.yaw_sigma_rad),
                                        dominant_directions_deg=self._hde_directions_deg)
        self._fixes.restore(state.stair_fixes)
        self._cycle_index = state.cycles
        self._last_cycle_stamp_ns = state.stamp_ns
        self._periods_s.append(state.stride_period_s)
        self._resumed = True
        self._resumed_from = state
        self.get_logger().info(
            f'{reason}: position ({state.x_m:.2f}, {state.y_m:.2f}, {state.z_m:.2f}) m, heading '
            f'{np.degrees(state.heading_rad):.0f} deg, {state.cycles} cycles; navigation '
            'resumes at the first stance')

    def _save_state(self, cycle):
        pos_n, status = cycle.pos_n, self._navigator.status
        filter_ok = bool(np.all(np.isfinite(pos_n))) and not self._internal_errors \
            and 0.0 <= status.pos_sigma_m <= 1e4 and 0.0 <= status.yaw_sigma_rad <= 10.0
        self._state_writer.submit(NavigationState(
            stamp_ns=cycle.stamp_ns, wall_time_s=time.time(), source_id=self._source_id,
            x_m=float(pos_n[0]) if filter_ok else 0.0,
            y_m=float(pos_n[1]) if filter_ok else 0.0,
            z_m=float(pos_n[2]) if filter_ok else 0.0,
            heading_rad=self._navigator.heading_rad if filter_ok else 0.0,
            filter_ok=filter_ok, cycles=self._cycle_index,
            stride_period_s=self._stride_period_s(), walk_id=self._walk_id,
            map_frame=self._in_map_frame, stair_fixes=self._fixes.applied_before(cycle.stamp_ns),
            pos_sigma_m=status.pos_sigma_m if filter_ok else 0.0,
            yaw_sigma_rad=status.yaw_sigma_rad if filter_ok else 0.0))

    # -- outputs -------------------------------------------------------------------------------

    def _publish_track(self, publisher):
        """Publish the latest point on foot_odom or foot_odom_throttle, unless it already was."""
        with self._lock:
            point = self._last_point
            if point is not self._published_points.get(publisher):
                self._published_points[publisher] = point
                self._publish_point(point, publisher)

    def _publish_point(self, point, publisher):
        if point is None or not (np.all(np.isfinite(point.pos_n))
                                 and np.all(np.isfinite(point.quat_nb))):
            return
        msg = Odometry()
        msg.header.stamp = ns_to_stamp(point.stamp_ns)
        msg.header.frame_id = self._track_frame_id
        msg.child_frame_id = self._imu_frame_id
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        p.x, p.y, p.z = (float(v) for v in point.pos_n)
        q.w, q.x, q.y, q.z = (float(v) for v in point.quat_nb)
        variance = self._navigator.status.pos_sigma_m ** 2 / 3.0
        covariance = [0.0] * 36
        covariance[0] = covariance[7] = covariance[14] = variance
        msg.pose.covariance = covariance
        publisher.publish(msg)

    def diagnostics(self, now_ns: int) -> DiagnosticArray:
        """Build the diagnostics since the last call (rates over that period)."""
        status, hardware_id = self._navigator.status, self._imu_frame_id or 'imu'
        period = self._input_period.close(now_ns, self._received, self._gate, status)
        node_values = {
            'resumed': self._resumed, 'resume': self._resume_decision,
            'resume_refusals': self._resume_refusals, 'outage_cycles': self._outage_cycles,
            'state_file': str(self._state_path) if self._persist else '',
            'state_write_errors': self._state_write_errors(), 'frame_id': self._track_frame_id}
        if self._take_fixes:
            node_values.update(self._fixes.counters)
            node_values['stair_fix_malformed'] = self._malformed_fixes
        msg = DiagnosticArray(status=[
            input_status(self._full_name, hardware_id, self._imu_topic, period, self._gate,
                         status, self._received, self._malformed, self._internal_errors),
            navigator_status(self._full_name, hardware_id, period, status,
                             self._internal_errors, self._state_write_errors(),
                             self._fixes.late, self._malformed_fixes, node_values)])
        msg.header.stamp = ns_to_stamp(now_ns)
        return msg

    def _publish_diagnostics(self):
        with self._lock:
            msg = self.diagnostics(self.get_clock().now().nanoseconds)
        self._diag_pub.publish(msg)

    def destroy_node(self):
        """Handle the Imu messages already received, then write the state and destroy."""
        if self._input is not None:
            self._input.close()
            self._input = None
        super().destroy_node()

    @property
    def gate(self) -> InputGate:
        """Give access to the input gate and its counters."""
        return self._gate

    @property
    def navigator(self) -> FootNavigator:
        """Give access to the navigator and its status."""
        return self._navigator


def main(args=None) -> int:
    """Run the IMU node until Ctrl-C or shutdown; return the exit code."""
    return spin_node(ImuNode, IMU_NODE, args)


if __name__ == '__main__':
    sys.exit(main())
