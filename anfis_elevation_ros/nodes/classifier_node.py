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
overlong swing) are counted, not classified: the height stays as it was until the next valid
cycle, which bridges them when the cycles around agree on a stair mode (``core/height.py``).
Malformed messages are counted and skipped. The model is loaded once at start from
``model_path`` ('' = the packaged ``config/forest_default.json``; ANFIS or forest by the
file's format, ``core/classifier.py``); a missing or corrupt model stops the node at start
with an error and exit code 1, so it never runs with garbage.

Topics
------
Subscribes:
    ``gait_cycle``, sensor_msgs/PointCloud2 (layout in ``nodes/gait_cycle_msg.py``), reliable,
    transient local, depth ``cycle_history``: started late or restarted, the node receives
    the cycles the IMU node still holds and counts those newer than the last one it counted.
Publishes (reliable, transient local, depth 1: a late subscriber gets the latest at once):
    ``elevation``, geometry_msgs/PointStamped: frame ``map_frame_id`` (``map``), stamp = the
    IMU stamp of the sample that closed the cycle, x, y = INS position, z = quantised height.
    ``stair_mode``, std_msgs/Int8: +1 up, 0 level, -1 down, per classified cycle.
    ``floor``, std_msgs/Int32: the floor index per classified cycle, and ``elevation.start_floor``
    once at start.
    ``floor_certain``, std_msgs/Bool, with every ``floor``: whether the height has settled on
    the floor (False on stairs, on a landing between floors, level but off every floor; a map
    shows 'Floor ?'). Floors come from the building file's elevations when ``building_file``
    is given, else from ``elevation.floor_height_m`` and ``elevation.start_floor``, certain
    only where every plausible storey height agrees (``core/floors.py``).
    ``floor_range``, std_msgs/Int32MultiArray, with every ``floor``: [lowest, highest], the
    floors the height can be on ([f, f] while certain; on a level stretch without a building
    file, the floors storeys of ``floor_height_min_m``-``floor_height_max_m`` allow), or []
    when not known (on the stairs, off every floor, after an outage).
    ``stair_fix``, sensor_msgs/PointCloud2 (layout in ``nodes/stair_fix_msg.py``), reliable,
    transient local, depth 100, only with a building file that has ``stairs`` and a ``start``:
    one correction request per stair entry associated with the stair-position database
    (``core/stair_database.py``: the first stair cycle after level walking, the nearest entry
    of that direction on the floor walked, closer than th_st = ``building_aid.stair_fix_ratio``
    x the distance walked since the last correction). The IMU node applies each once.
    ``/diagnostics``, diagnostic_msgs/DiagnosticArray at 1 Hz: "/classifier_node: elevation"
    (cycles classified, invalid, bridged, unbridged, missed (index gaps), malformed, height,
    floor, floor_certain, step_height_m (the riser height K in use: online estimate or the
    building file's), riser_strides, stairwells, mode, resumed or not, failed state writes;
    with stairs: stair entries seen, associations accepted, refused as too far or for want of
    an entry, cycles not in the map frame, distance since the last correction).

Parameters: ``elevation.*`` (step height, mode threshold, storey height and start floor may
change live; the height is kept), ``model_path``, ``map_frame_id``, persistence; see
``core/params.py``.

Persisted state (``persist_state``, ``state_dir``, ``state_max_age_s``, ``resume_max_gap_s``):
after every gait cycle the node writes an ``ElevationState`` (quantised height, floor, stamp and
index of the last cycle counted, the walk identity, the riser height estimate and its strides;
source = the resolved gait_cycle topic)
atomically with permissions 0600. On start a fresh state from the same topic is a candidate:
its floor is published with ``floor_certain`` false, and the first gait cycle decides. The
state is resumed when that cycle belongs to the saved walk (``walk_id``: the IMU node resumed
it too, or never stopped) and either is one already counted (the IMU node's history) or
follows the saved stamp by at most ``resume_max_gap_s`` (``core/state.py``,
``walk_continues``): the height carries on, and cycles up to the saved index and stamp are not
counted twice, and the riser estimate carries on. Otherwise (a second play of a bag, an IMU
node that started a new walk) the node
starts fresh. The log and the diagnostics (``resume``: the decision and why;
``resume_refusals``: saved states not resumed) say which. A new walk while the node runs (the
IMU node restarted and could not resume) carries the height on: the wearer did not move.
The stair-entry monitor is not saved: a restarted node measures the distance walked for eq. (18)
from its restart (a stricter threshold for the first entry), and a request it repeats is
refused by the IMU node as a duplicate.
"""

from dataclasses import replace
import sys
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PointStamped
from rclpy.node import Node
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Bool, Int32, Int32MultiArray, Int8

from .diagnostics import diagnostic_status
from .gait_cycle_msg import cycle_from_msg
from .node_params import declare_node_parameters, LiveParameters
from .qos import cycle_history_qos, DIAGNOSTICS_QOS, LATEST_QOS, STAIR_FIX_QOS
from .spin import spin_node
from .stair_fix_msg import request_to_msg
from .stamps import ns_to_stamp
from .state_writer import PersistsState
from ..core.building import load_building_file
from ..core.classifier import backend_name, warm_up
from ..core.errors import InputError
from ..core.height import ElevationTracker
from ..core.outage import FloorDoubt, LEVEL_STRETCH_CYCLES, MAX_OUTAGE_CYCLES
from ..core.outage import max_unobserved_climb, outage_leaves_doubt, snapped_floor_height
from ..core.outage import UNKNOWN_CLIMB_M
from ..core.params import building_aid_params_from_dict, CLASSIFIER_NODE
from ..core.params import elevation_params_from_dict, load_model, model_file
from ..core.stair_database import stair_monitor_for
from ..core.state import ElevationState, resumable_state, state_file, walk_continues

LOG_PERIOD_S = 5.0
DIAGNOSTICS_PERIOD_S = 1.0


class ClassifierNode(PersistsState, Node):
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
        compile_s = warm_up(self._model)
        if compile_s > 1.0:
            self.get_logger().info(f'stair classifier compiled in {compile_s:.0f} s (cached from '
                                   'now on)')
        self._building = load_building_file(values['building_file'])
        if self._building is not None:
            self.get_logger().info(f'building {self._building.name or ""} loaded from '
                                   f'{self._building.source}')
        self._source_id = self.resolve_topic_name('gait_cycle')
        self._persist = values['persist_state']
        self._state_path = state_file(values['state_dir'], self.get_fully_qualified_name())
        self._start_state_writer(self._state_path, self._persist)
        state, reason = None, 'starting fresh (persist_state is false)'
        if self._persist:
            state, reason = resumable_state(self._state_path, ElevationState, self._source_id,
                                            values['state_max_age_s'])
        elevation = elevation_params_from_dict(values)
        self._tracker = ElevationTracker(self._model, elevation, building=self._building)
        self._resume_max_gap_s = values['resume_max_gap_s']
        self._candidate = state          # resumed or not at the first gait cycle
        self._walk_id = None             # the walk of the cycles counted
        self._doubt = FloorDoubt()
        self._pending_lost = 0           # cycles lost (outage, never received) not yet weighed
        self._resume_refusals = int(state is None and self._state_path.exists())
        self._resume_decision = reason if state is None else \
            'saved state found; the first gait cycle decides'
        threshold_from = 'the model' if elevation.mode_threshold < 0.0 else \
            'elevation.mode_threshold'
        self.get_logger().info(
            f"{backend_name(self._model)} model loaded from {model_file(values['model_path'])}; "
            f'sigma_th {self._tracker.mode_threshold:g} ({threshold_from})')
        self._resumed = False
        self._last_stamp_ns = -1
        self._last_index = 0
        self._already_counted = 0
        self._missed = 0
        self.get_logger().info(reason if state is None else
                               f'{reason}: height {state.height_m:.2f} m, floor {state.floor}, '
                               f'last cycle {state.cycle_index}; resumed if the first gait '
                               'cycle continues it')
        self._live_parameters = LiveParameters(
            self, CLASSIFIER_NODE, values, elevation_params_from_dict, self._apply_parameters)
        self._map_frame_id = values['map_frame_id']
        self._classified = 0
        self._invalid = 0
        self._malformed = 0
        self._internal_errors = 0
        self._last_mode = 0
        self._floor = self._tracker.floor
        self._stair_monitor = stair_monitor_for(
            self._building, building_aid_params_from_dict(values).stair_fix_ratio)
        self._not_in_map_frame = 0

        self._elevation_pub = self.create_publisher(PointStamped, 'elevation', LATEST_QOS)
        self._mode_pub = self.create_publisher(Int8, 'stair_mode', LATEST_QOS)
        self._floor_pub = self.create_publisher(Int32, 'floor', LATEST_QOS)
        self._floor_certain_pub = self.create_publisher(Bool, 'floor_certain', LATEST_QOS)
        self._floor_range_pub = self.create_publisher(Int32MultiArray, 'floor_range', LATEST_QOS)
        self._diag_pub = self.create_publisher(DiagnosticArray, '/diagnostics', DIAGNOSTICS_QOS)
        self._fix_pub = None
        if self._stair_monitor is not None:
            self._fix_pub = self.create_publisher(PointCloud2, 'stair_fix', STAIR_FIX_QOS)
            self.get_logger().info(f'stair-position database: {len(self._building.stairs)} '
                                   'entries; corrections requested on stair_fix')
        self.create_subscription(PointCloud2, 'gait_cycle', self._on_cycle,
                                 cycle_history_qos(values['cycle_history']))
        self.create_timer(DIAGNOSTICS_PERIOD_S, self._publish_diagnostics)
        if state is None:
            self._publish_floor(self._floor, self._tracker.floor_certain)
            self.get_logger().info(f'start floor {self._floor}')
        else:
            self._publish_floor(state.floor, certain=False, tracked=False)

    def _apply_parameters(self, values, changed):
        self._tracker.set_params(elevation_params_from_dict(values))
        self.get_logger().info(f'parameters changed: {", ".join(changed)}')
        self._publish_floor_if_changed()

    def _on_cycle(self, msg: PointCloud2):
        try:
            self._handle_cycle(msg)
        except Exception as err:   # noqa: B902 a bug must not stop a firefighter's tracking
            self._internal_errors += 1
            self.get_logger().error(f'internal error on a gait cycle ({type(err).__name__}: '
                                    f'{err}); cycle skipped', throttle_duration_sec=LOG_PERIOD_S)

    def _handle_cycle(self, msg: PointCloud2):
        try:
            cycle = cycle_from_msg(msg)
        except InputError as err:
            self._malformed += 1
            self.get_logger().warning(f'gait_cycle message skipped: {err}',
                                      throttle_duration_sec=LOG_PERIOD_S)
            return
        if self._walk_id is None:
            self._decide_resume(cycle)
        elif cycle.walk_id != self._walk_id:
            self._walk_id = cycle.walk_id
            self._last_index, self._last_stamp_ns = 0, -1
            self._doubt.doubt('the IMU node started a new walk', UNKNOWN_CLIMB_M)
            self.get_logger().warning('the IMU node started a new walk (it could not resume its '
                                      f'own): carrying on from height '
                                      f'{self._tracker.height_m:.2f} m, floor uncertain')
        if cycle.index <= self._last_index and cycle.stamp_ns <= self._last_stamp_ns:
            # History sent to a restarted node. (A resumed IMU node carries its index on, so a
            # sensor clock that restarted does not make new cycles look old.)
            self._already_counted += 1
            return
        self._note_cycle_index(cycle)
        self._pending_lost += cycle.outage
        mode_before = self._tracker.last_mode
        risers_before = round(self._tracker.last_abs_dh_m / self._tracker.step_height_m)
        try:
            estimate = self._tracker.update(cycle.stamp_ns, cycle.features, cycle.x_m,
                                            cycle.y_m, cycle.valid)
        except InputError as err:
            self._malformed += 1
            self.get_logger().warning(f'gait cycle skipped: {err}',
                                      throttle_duration_sec=LOG_PERIOD_S)
            return
        self._last_stamp_ns, self._last_index = cycle.stamp_ns, cycle.index
        if self._persist:
            self._save_state()
        if self._stair_monitor is not None:
            self._watch_stair_entry(cycle, estimate, msg.header.frame_id)
        if not cycle.valid:
            self._invalid += 1
            return
        if estimate.bridged_steps:
            self.get_logger().info(f'{estimate.bridged_steps:+d} steps credited to invalid '
                                   'cycles inside a stair flight')
        estimate = self._weigh_doubt(mode_before, risers_before, estimate)
        self._classified += 1
        self._last_mode = estimate.mode
        point = PointStamped()
        point.header.stamp = ns_to_stamp(estimate.stamp_ns)
        point.header.frame_id = self._map_frame_id
        point.point.x, point.point.y, point.point.z = estimate.x_m, estimate.y_m, \
            float(estimate.height_m)
        self._elevation_pub.publish(point)
        self._mode_pub.publish(Int8(data=int(estimate.mode)))
        self._publish_floor(estimate.floor, estimate.floor_certain)
        if estimate.floor != self._floor:
            self.get_logger().info(f'floor {self._floor} -> {estimate.floor} (height '
                                   f'{estimate.height_m:.2f} m)')
            self._floor = estimate.floor

    def _watch_stair_entry(self, cycle, estimate, frame_id: str):
        """Give the cycle to the stair-entry monitor; publish the request it makes, if any."""
        if frame_id != self._map_frame_id:
            # The IMU node has no building start: its x/y are not building coordinates.
            self._not_in_map_frame += 1
            self.get_logger().warning(
                f'gait cycles in frame {frame_id!r}, not {self._map_frame_id!r}: no stair-entry '
                'correction (give the IMU node the same building file)',
                throttle_duration_sec=LOG_PERIOD_S)
            return
        monitor = self._stair_monitor
        request = monitor.update(cycle.index, cycle.stamp_ns, cycle.x_m, cycle.y_m, cycle.valid,
                                 estimate.mode, estimate.floor)
        if monitor.entries and monitor.last_stamp_ns == cycle.stamp_ns:
            where = (f'{monitor.last_distance_m:.2f} m from the nearest entry, threshold '
                     f'{monitor.last_threshold_m:.2f} m')
            if request is None:
                self.get_logger().info(f'stair entry at cycle {cycle.index} not associated: '
                                       f'{where}')
            else:
                self._fix_pub.publish(request_to_msg(request, self._map_frame_id))
                self.get_logger().info(
                    f'stair entry at cycle {cycle.index}: stairwell {request.stairwell} (floor '
                    f'{request.floor}, {"up" if request.direction > 0 else "down"}), {where}; '
                    'correction requested')

    def _weigh_doubt(self, mode_before: int, risers_before: int, estimate):
        """Doubt the floor after unobserved cycles; clear the doubt at a floor of the building."""
        if self._pending_lost:
            lost, self._pending_lost = self._pending_lost, 0
            if outage_leaves_doubt(lost, mode_before, estimate.mode):
                self._doubt.doubt(f'{lost} gait cycles unobserved (stair mode {mode_before:+d} '
                                  f'before, {estimate.mode:+d} after)', max_unobserved_climb(
                                      lost, risers_before, self._tracker.step_height_m))
                self.get_logger().warning(f'floor uncertain: {self._doubt.reason}')
        if self._doubt.certain or estimate.mode != 0 \
                or self._tracker.floors.level_cycles < LEVEL_STRETCH_CYCLES:
            return estimate
        height_m = snapped_floor_height(
            estimate.height_m, self._tracker.floors.floor_map.elevations_m,
            self._doubt.reach_m + self._tracker.step_height_m)
        if height_m is None:
            return estimate
        self._tracker.correct_height(height_m)
        self._doubt.clear()
        self.get_logger().info(f'floor certain again: a level stretch at height '
                               f'{estimate.height_m:.2f} m is floor {self._tracker.floor} of the '
                               f'building ({height_m:.2f} m)')
        return replace(estimate, height_m=self._tracker.height_m, floor=self._tracker.floor,
                       floor_certain=self._tracker.floor_certain,
                       floor_range=self._tracker.floor_range)

    def _decide_resume(self, cycle):
        """Resume the saved state if this first cycle continues its walk, else start fresh."""
        state, self._candidate = self._candidate, None
        self._walk_id = cycle.walk_id
        if state is None:
            return
        if state.walk_id != cycle.walk_id:
            continues, why = False, ('the gait cycles belong to another walk (the IMU node '
                                     'started it fresh)')
        elif cycle.index <= state.cycle_index and cycle.stamp_ns <= state.stamp_ns:
            continues, why = True, "the IMU node still holds the saved walk's cycles"
        else:
            continues, why = walk_continues(state.stamp_ns, cycle.stamp_ns,
                                            self._resume_max_gap_s)
        if not continues:
            self._resume_refusals += 1
            self._resume_decision = f'starting fresh: {why}'
            self.get_logger().warning(self._resume_decision)
            self.get_logger().info(f'start floor {self._floor}')
            self._publish_floor(self._floor, self._tracker.floor_certain)
            return
        self._tracker.reset(state.height_m)
        self._tracker.risers.resume(state.step_height_m, state.riser_strides)
        self._tracker.resume_flight(state.last_mode, state.last_abs_dh_m)
        # The saved floor, not the one nearest a height saved mid-flight; certain again when
        # the settle rule sees the foot on it. No floor walked before stands as an anchor: a
        # climb may have gone unseen in the outage.
        self._tracker.floors.floor, self._tracker.floors.certain = state.floor, False
        self._tracker.floors.forget_anchors()
        self._doubt = FloorDoubt(state.floor_doubt, state.floor_doubt_reach_m)
        self._last_stamp_ns, self._last_index = state.stamp_ns, state.cycle_index
        self._resumed = True
        self._floor = self._tracker.floor
        self._resume_decision = f'resuming: {why}'
        self.get_logger().info(f'{self._resume_decision}; resumed floor {self._floor}, riser '
                               f'height {self._tracker.step_height_m:.3f} m')
        self._publish_floor(self._floor, self._tracker.floor_certain)

    def _note_cycle_index(self, cycle):
        index = cycle.index
        if index > self._last_index + 1:
            lost = index - self._last_index - 1
            self._missed += lost
            self._pending_lost += lost
            for _ in range(min(lost, MAX_OUTAGE_CYCLES)):
                self._tracker.update(cycle.stamp_ns, None, cycle.x_m, cycle.y_m, valid=False)
            self.get_logger().warning(
                f'{lost} gait cycles never received (index {self._last_index} -> {index}): '
                'bridged if the stair mode on both sides agrees')
        elif index <= self._last_index:
            self.get_logger().info(f'the IMU node restarted its cycle count ({self._last_index} '
                                   f'-> {index}); carrying on from height '
                                   f'{self._tracker.height_m:.2f} m')

    def _save_state(self):
        self._state_writer.submit(ElevationState(
            stamp_ns=self._last_stamp_ns, wall_time_s=time.time(),
            source_id=self._source_id, height_m=self._tracker.height_m,
            floor=self._tracker.floor, cycle_index=self._last_index, walk_id=self._walk_id,
            step_height_m=self._tracker.step_height_m,
            riser_strides=self._tracker.risers.strides, last_mode=self._tracker.last_mode,
            last_abs_dh_m=self._tracker.last_abs_dh_m, floor_doubt=self._doubt.reason,
            floor_doubt_reach_m=self._doubt.reach_m))

    def _publish_floor_if_changed(self):
        floor = self._tracker.floor
        if floor != self._floor:
            self.get_logger().info(f'floor {self._floor} -> {floor} (parameters changed)')
            self._floor = floor
            self._publish_floor(floor, self._tracker.floor_certain)

    def _publish_floor(self, floor: int, certain: bool = True, tracked: bool = True):
        """
        Publish a floor, whether it is certain and the floors the height can be on.

        ``tracked`` False: a floor that is not the tracker's (a saved state's, until the
        first gait cycle decides), whose height nobody has checked: no floor range.
        """
        self._floor_pub.publish(Int32(data=int(floor)))
        # The settle rule's certainty (core/floors.py) and an outage's doubt (core/outage.py).
        self._floor_certain_pub.publish(Bool(data=bool(certain) and self._doubt.certain))
        # The tracker's range ((f, f) while certain); none after an outage (height in doubt).
        floors = self._tracker.floor_range if tracked and self._doubt.certain else None
        self._floor_range_pub.publish(Int32MultiArray(data=list(floors or ())))

    def diagnostics(self, now_ns: int) -> DiagnosticArray:
        """Build the classifier's diagnostics."""
        tracker = self._tracker
        problems = [f'{n} {what}' for n, what in (
            (self._malformed, 'malformed cycles'), (self._missed, 'cycles never received'),
            (tracker.unbridged_cycles, 'invalid cycles not bridged'),
            (tracker.implausible_cycles, 'implausible climbs'),
            (self._state_write_errors(), 'failed state writes'),
            (self._not_in_map_frame, 'cycles not in the map frame (no stair fixes)')) if n]
        if not self._doubt.certain:
            problems.append(f'floor uncertain: {self._doubt.reason}')
        if self._internal_errors:
            level, message = DiagnosticStatus.ERROR, f'{self._internal_errors} internal errors'
        elif problems:
            level, message = DiagnosticStatus.WARN, ', '.join(problems)
        else:
            level, message = DiagnosticStatus.OK, 'ok'
        values = {'classified': self._classified, 'invalid_cycles': self._invalid,
                  'bridged_cycles': tracker.bridged_cycles,
                  'unbridged_cycles': tracker.unbridged_cycles,
                  'recovered_strides': tracker.recovered_strides,
                  'level_calls_overruled': tracker.level_calls_overruled,
                  'stair_calls_overruled': tracker.stair_calls_overruled,
                  'implausible_cycles': tracker.implausible_cycles, 'missed_cycles': self._missed,
                  'already_counted': self._already_counted, 'malformed': self._malformed,
                  'height_m': tracker.height_m, 'floor': self._floor,
                  'floor_certain': tracker.floor_certain and self._doubt.certain,
                  'floor_doubt': self._doubt.reason, 'floor_doubts': self._doubt.doubts,
                  'step_height_m': tracker.step_height_m,
                  'riser_strides': tracker.risers.strides,
                  'stairwells': tracker.risers.stairwells,
                  'last_mode': self._last_mode, 'resumed': self._resumed,
                  'resume': self._resume_decision, 'resume_refusals': self._resume_refusals,
                  'state_write_errors': self._state_write_errors(),
                  'internal_errors': self._internal_errors}
        if self._stair_monitor is not None:
            values.update(self._stair_monitor.counters)
            values['stair_fix_not_in_map_frame'] = self._not_in_map_frame
        msg = DiagnosticArray(status=[diagnostic_status(
            f'{self.get_fully_qualified_name()}: elevation', level,
            message, self._map_frame_id, values)])
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
