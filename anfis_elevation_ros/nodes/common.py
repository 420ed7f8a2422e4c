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
What both nodes share: QoS profiles, parameter declaration, message conversions.

QoS (a decision per topic):

- ``imu_qos(depth)``: ``qos_profile_sensor_data`` (best effort, volatile) with a deep queue, so
  that a burst of a 400 Hz IMU waits instead of being dropped while a callback runs.
- ``cycle_history_qos(depth)``: reliable, transient local, keep last ``depth`` (parameter
  ``cycle_history``), for ``gait_cycle`` between the two nodes: an event stream where every
  message counts; a classifier that starts late or restarts gets the cycles it missed (it
  skips those it already counted: each cycle carries its index and stamp).
- ``CYCLE_QOS``: reliable, volatile, depth 100: what tools that only watch ``gait_cycle`` use
  (no history).
- ``LATEST_QOS``: reliable, transient local, depth 1, for "latest state" topics (``elevation``,
  ``stair_mode``, ``floor``, ``foot_odom``): a late subscriber gets the current value at once.
- ``DIAGNOSTICS_QOS``: reliable, volatile, depth 10 (what diagnostic_aggregator expects).

The gait-cycle message (topic ``gait_cycle``) is a ``sensor_msgs/msg/PointCloud2`` holding ONE
point: a point cloud is stamped, has a frame, and names its fields, so the message documents
itself and rviz or ``ros2 topic echo`` show it. The point is the foot at the sample that closes
the cycle, in the odometry frame; its fields, all FLOAT64 (``CYCLE_FIELDS``):

=====  ====================  ==============================================================
 off   field                 meaning
=====  ====================  ==============================================================
   0   ``x``                 EKF position x (east) at the closing stance sample, m
   8   ``y``                 EKF position y (north), m
  16   ``z``                 EKF height (raw INS height, not quantised), m
  24   ``valid``             1.0 for a valid cycle, 0.0 for one with a gap or an overlong swing
  32   ``mean_height_m``     feature eq. (8), m
  40   ``std_height_m``      feature eq. (9), m
  48   ``height_change_m``   feature eq. (10), m
  56   ``max_abs_height_m``  feature eq. (11), m
  64   ``max_pitch_rad``     feature eq. (12), rad
  72   ``cycle_index``       index of the cycle, 1, 2, ... (continues after a resumed restart)
=====  ====================  ==============================================================

``header.stamp`` is the stamp of the IMU sample that closed the cycle; ``header.frame_id`` the
odometry frame; height = width = 1, point_step = row_step = 80, little endian, ``is_dense``
false when a value is not finite.
"""

from dataclasses import dataclass
import math
import struct
import threading
import time

from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
import numpy as np
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rcl_interfaces.msg import SetParametersResult
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import Imu, PointCloud2, PointField

from ..core.errors import InputError
from ..core.gait import FEATURE_NAMES
from ..core.params import is_ros_owned, node_specs, validate_value
from ..core.state import save_state

CYCLE_FIELDS = ('x', 'y', 'z', 'valid') + FEATURE_NAMES + ('cycle_index',)
_CYCLE_STRUCT = struct.Struct('<' + 'd' * len(CYCLE_FIELDS))
_CDR_LE = b'\x00\x01'                    # encapsulation: plain CDR, little endian
_CDR_HEADER = struct.Struct('<iII')        # stamp sec, nanosec, frame_id length
_IMU_DOUBLES_SIZE = 37 * 8
_VECTOR3 = struct.Struct('<3d')
_GYR_OFFSET = 13 * 8                       # after orientation (4) and its covariance (9)
_ACC_OFFSET = 25 * 8                       # after angular_velocity (3) and its covariance (9)

CYCLE_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                       reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.VOLATILE)
LATEST_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                        reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.TRANSIENT_LOCAL)
DIAGNOSTICS_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                             reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.VOLATILE)

EXECUTORS = ('events', 'single')

_ROS_TYPES = {'bool': Parameter.Type.BOOL, 'int': Parameter.Type.INTEGER,
              'double': Parameter.Type.DOUBLE, 'string': Parameter.Type.STRING,
              'double_array': Parameter.Type.DOUBLE_ARRAY}


def cycle_history_qos(depth: int) -> QoSProfile:
    """Reliable, transient local, keep last ``depth``: the gait-cycle stream with history."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


def imu_qos(depth: int) -> QoSProfile:
    """``qos_profile_sensor_data`` (best effort, volatile, keep last) with the given depth."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.VOLATILE)


class PolledSubscription:
    """
    A raw subscription whose messages a thread of its own takes in batches, every ``period_s``.

    At 400 Hz the executor's dispatch of one callback per message costs more CPU than the
    pipeline it calls: the thread wakes for every message, with cold caches. Taking what
    arrived in the last period in one go (test/benchmarks/bench_live.py, 400 Hz, both nodes)
    cut the nodes' CPU by 24 % at 10 ms (three alternating runs: 7.2 % against 9.5 % of one
    core) and by 5 % at 5 ms, for up to one period more latency: 8 ms, the IMU node's default,
    gave 7.8 % in two runs of the 10-minute walk, with a p99 latency of 13 ms in one and 22 ms
    in the other (one callback per message: 7 and 10 ms, but 9.2 and 10.8 % CPU).

    The one message whose latency counts can be foreseen: ``due_s``, asked after every batch,
    says when it is due (the IMU node: the sample that will close a gait cycle, once the foot
    is still), and the thread wakes then instead of a whole period later. That costs a wake-up
    or two per stride and takes the batching's delay off the cycle's latency: with it (and the
    state files written 0.1 s later, ``StateWriter``) two runs of the 10-minute walk gave p99
    12.8 and 9.7 ms at 8.9 and 7.6 % CPU.

    The subscription belongs to a helper node, ``<node name>_input``, that no executor spins
    (an executor would take its messages first); it has no global arguments (the topic comes
    resolved and remapped by the owning node), no parameter services and no rosout. Messages are
    taken with the subscription handle's ``take_message``, the call rclpy's executors and
    ``wait_for_message`` make.

    Parameters
    ----------
    node : rclpy Node
        The owner: name, namespace, context and logger.
    msg_type : message class
    topic : str
        Fully resolved topic name.
    qos : QoSProfile
    handler : callable
        Called with the serialised bytes of each message, in the thread, with ``lock`` held
        over a batch: the owner holds the same lock in its callbacks that share state with it.
        It must catch its own errors: one that escapes ends the thread (the IMU node's
        ``_on_imu`` counts them as internal errors).
    period_s : float
        Time between batches, s.
    lock : threading.Lock
    due_s : callable or None
        Called after each batch, with ``lock`` held: seconds until the next message that must
        not wait for the period (from the newest message taken), or None. The next batch is
        then taken ``DUE_MARGIN_S`` after that time, if it is sooner than the period. Like
        ``handler``, it must not raise.

    """

    DUE_MARGIN_S = 0.001    # transit from the publisher; a late message costs another wait

    def __init__(self, node, msg_type, topic: str, qos, handler, period_s: float, lock,
                 due_s=None):
        import rclpy

        self._helper = rclpy.create_node(
            f'{node.get_name()}_input', namespace=node.get_namespace(), context=node.context,
            use_global_arguments=False, start_parameter_services=False, enable_rosout=False)
        self._subscription = self._helper.create_subscription(msg_type, topic, _not_dispatched,
                                                              qos, raw=True)
        self._msg_type = msg_type
        self._handler = handler
        self._period_s = period_s
        self._lock = lock
        self._due_s = due_s
        self._context = node.context
        self._logger = node.get_logger()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=f'{node.get_name()}_input',
                                        daemon=True)
        self._thread.start()

    def close(self, timeout_s: float = 2.0):
        """Handle the messages already received, stop the thread, destroy the helper node."""
        self._stop.set()
        self._thread.join(timeout_s)
        self._helper.destroy_node()

    def _run(self):
        wait_s = self._period_s
        while not self._stop.wait(wait_s):
            wait_s = self._take_all()
        self._take_all()

    def _take_all(self) -> float:
        """Handle every message waiting; return the time to wait before the next batch, s."""
        take = self._subscription.handle.take_message
        with self._lock:
            while True:
                try:
                    taken = take(self._msg_type, True)
                except Exception as err:   # noqa: B902 rclpy raises several kinds
                    if self._context.ok():
                        self._logger.error(f'taking a message failed: {err}',
                                           throttle_duration_sec=5.0)
                    break
                if taken is None:
                    break
                self._handler(taken[0])
            due_s = None if self._due_s is None else self._due_s()
        if due_s is None:
            return self._period_s
        return min(self._period_s, due_s + self.DUE_MARGIN_S)


def _not_dispatched(_msg):
    """Do nothing: no executor spins the helper node of a PolledSubscription."""


class Spinner:
    """
    The executor of the nodes: rclpy's EventsExecutor ('events') or SingleThreadedExecutor.

    The events executor costs about a third of the CPU per message of the
    SingleThreadedExecutor at 400 Hz (test/benchmarks/bench_live.py). Its ``spin()`` busy-waits
    and ignores shutdown in rclpy 7.1 (Jazzy), so ``spin`` here runs it a period at a time
    (``spin_until_future_complete`` with a timeout) until ``stop`` is called or the context
    shuts down. Where rclpy has no EventsExecutor, 'events' falls back to the
    SingleThreadedExecutor.

    ``handle_signals`` makes SIGINT and SIGTERM call ``stop``: the callback that is running
    finishes, then ``spin`` returns. (rclpy's own handlers chain to Python's, which raises
    KeyboardInterrupt inside whatever callback runs; that would abort a sample half-way.)

    Parameters
    ----------
    kind : str
        'events' or 'single'.

    """

    def __init__(self, kind: str = 'events'):
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.task import Future
        from rclpy.utilities import get_default_context

        if kind not in EXECUTORS:
            raise InputError(f'executor {kind!r} is not one of {", ".join(EXECUTORS)}')
        self.kind = kind
        self._context = get_default_context()
        self._stop = False
        self.signal = None
        self._never_done = Future()      # spin() returns on stop or shutdown, not on this
        if kind == 'events':
            try:
                from rclpy.experimental import EventsExecutor
            except ImportError:
                self.kind = 'single'
            else:
                self.executor = EventsExecutor()
                return
        self.executor = SingleThreadedExecutor()

    def add_node(self, node):
        """Add a node to the executor."""
        self.executor.add_node(node)

    def handle_signals(self):
        """Stop spinning on SIGINT and SIGTERM (main thread only)."""
        import signal

        def handler(signum, _frame):
            self.signal = signum
            self.stop()

        signal.signal(signal.SIGINT, handler)
        signal.signal(signal.SIGTERM, handler)

    def stop(self):
        """Make ``spin`` return after the callback that is running (safe in a signal handler)."""
        self._stop = True

    def spin(self, period_s: float = 0.1):
        """Run callbacks until ``stop`` or the context shuts down."""
        while not self._stop and self._context.ok():
            # The callbacks of a whole period in one call: the events executor then dispatches
            # them in C++, not through a Python loop per message (about 1.5 % of one core at
            # 400 Hz, test/benchmarks/bench_live.py).
            self.executor.spin_until_future_complete(self._never_done, timeout_sec=period_s)

    def shutdown(self):
        """Shut the executor down."""
        self.executor.shutdown()


def init_without_signal_handlers(args=None):
    """rclpy.init without rclpy's signal handlers (``Spinner.handle_signals`` does it)."""
    import rclpy
    from rclpy.signals import SignalHandlerOptions

    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)


def spin_node(node_class, node_name: str, args=None, executor: str = 'events') -> int:
    """
    Jazzy main(): init, build the node, spin until SIGINT/SIGTERM or shutdown, clean up.

    Returns
    -------
    0, or 1 when the node could not start (bad parameters or model: logged as fatal).

    """
    import rclpy
    from rclpy.executors import ExternalShutdownException

    init_without_signal_handlers(args)
    node = None
    try:
        spinner = Spinner(executor)
        spinner.handle_signals()
        node = node_class()
        spinner.add_node(node)
        spinner.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except InputError as err:
        rclpy.logging.get_logger(node_name).fatal(f'cannot start: {err}')
        return 1
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


class StateWriter:
    """
    Writes a node's state file in a thread of its own, newest state first.

    ``save_state`` flushes the file to disk (fsync), which takes a millisecond on a quiet disk
    and up to half a second on a busy one; done in the executor's thread it delayed every
    output behind it (test/benchmarks/bench_live.py, 400 Hz: cycle-to-PointStamped latency
    p99 15 ms with the write in the callback, 4 ms without it; one 558 ms outlier in 10
    minutes). ``submit`` hands a state over and returns at once; a state still waiting when a
    newer one arrives is dropped (only the latest matters after a crash). ``close`` writes what
    is pending and stops the thread.

    The write starts ``DELAY_S`` after the submit: a state comes with a gait cycle, just when
    the cycle is being classified and published, and the writer's Python work (building and
    checking the JSON) would take the interpreter lock from those callbacks. Strides are about
    a second apart, so every cycle's state is still written.

    Parameters
    ----------
    path : Path
        State file.
    on_error : callable
        Called with the OSError or InputError of a failed write (from the writer's thread);
        ``errors`` counts them.

    """

    DELAY_S = 0.1     # s, between a submit and the write

    def __init__(self, path, on_error):
        self.path = path
        self.errors = 0
        self._on_error = on_error
        self._pending = None
        self._closed = False
        self._wake = threading.Condition()
        self._thread = threading.Thread(target=self._run, name='state_writer', daemon=True)
        self._thread.start()

    def submit(self, state):
        """Write this state soon (replacing one not yet written)."""
        with self._wake:
            self._pending = state
            self._wake.notify()

    def close(self, timeout_s: float = 2.0):
        """Write the pending state, then stop (waiting at most ``timeout_s``)."""
        with self._wake:
            self._closed = True
            self._wake.notify()
        self._thread.join(timeout_s)

    def _run(self):
        while True:
            with self._wake:
                while self._pending is None and not self._closed:
                    self._wake.wait()
                write_at = time.monotonic() + self.DELAY_S
                while not self._closed and time.monotonic() < write_at:
                    self._wake.wait(write_at - time.monotonic())
                state, self._pending = self._pending, None
            if state is None:
                return
            try:
                save_state(self.path, state)
            except (OSError, InputError) as err:
                self.errors += 1
                self._on_error(err)


class PersistsState:
    """
    What both nodes do with their ``StateWriter``: log its errors, count them, flush at the end.

    Mixed in before ``Node``; the node calls ``_start_state_writer`` in its constructor.
    """

    STATE_ERROR_LOG_PERIOD_S = 5.0

    def _start_state_writer(self, path, persist: bool):
        """Write state files to ``path`` from now on if ``persist``, else never."""
        self._state_writer = StateWriter(path, self._log_state_error) if persist else None

    def _log_state_error(self, err):
        self.get_logger().error(f'cannot write the state file: {err}',
                                throttle_duration_sec=self.STATE_ERROR_LOG_PERIOD_S)

    def _state_write_errors(self) -> int:
        return self._state_writer.errors if self._state_writer is not None else 0

    def destroy_node(self):
        """Write the pending state, then destroy the node."""
        if self._state_writer is not None:
            self._state_writer.close()
        super().destroy_node()


# -- stamps -----------------------------------------------------------------------------------

def stamp_to_ns(stamp) -> int:
    """Integer nanoseconds of a builtin_interfaces/Time."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def ns_to_stamp(stamp_ns: int) -> Time:
    """builtin_interfaces/Time of integer nanoseconds."""
    sec, nanosec = divmod(int(stamp_ns), 1_000_000_000)
    return Time(sec=sec, nanosec=nanosec)


# -- parameters -------------------------------------------------------------------------------

def parameter_descriptor(spec) -> ParameterDescriptor:
    """Build the ParameterDescriptor of a ParamSpec: type, description, range, read-only."""
    descriptor = ParameterDescriptor(name=spec.name, type=_ROS_TYPES[spec.kind].value,
                                     description=spec.description, read_only=spec.read_only)
    if spec.min_value is not None:
        if spec.kind == 'int':
            descriptor.integer_range = [IntegerRange(
                from_value=int(spec.min_value), to_value=int(spec.max_value), step=1)]
        elif spec.kind == 'double':
            descriptor.floating_point_range = [FloatingPointRange(
                from_value=float(spec.min_value), to_value=float(spec.max_value), step=0.0)]
        else:
            descriptor.additional_constraints = (
                f'each element in [{spec.min_value:g}, {spec.max_value:g}]')
    return descriptor


def declare_node_parameters(node, node_name: str) -> dict:
    """
    Declare every parameter of a node with its descriptor; return the validated values.

    Parameters
    ----------
    node : rclpy.node.Node
        The node (its overrides come from --params-file / -p).
    node_name : str
        ``IMU_NODE`` or ``CLASSIFIER_NODE`` (core.params).

    Raises
    ------
    InputError : an override of the wrong type or out of range.

    """
    values = {}
    for spec in node_specs(node_name).values():
        default = spec.default
        if spec.kind == 'double_array':
            default = list(default) if default else Parameter.Type.DOUBLE_ARRAY
        try:
            param = node.declare_parameter(spec.name, default, parameter_descriptor(spec))
        except InvalidParameterTypeException as err:
            hint = ' (write doubles with a decimal point, e.g. 400.0)' \
                if spec.kind in ('double', 'double_array') else ''
            raise InputError(f'parameter {spec.name}: {err}{hint}') from None
        except InvalidParameterValueException as err:
            raise InputError(f'parameter {spec.name}: {err}') from None
        values[spec.name] = validate_value(spec, param.value)
    return values


class LiveParameters:
    """
    Validates parameter changes on a running node and applies them.

    The on-set callback checks each new value against its ParamSpec, then calls
    ``check(values)`` with all values as they would be (it builds the core's dataclasses and
    raises InputError on inconsistent values); a refusal carries the reason. The post-set
    callback stores the values and calls ``apply(values, changed_names)``.

    Parameters
    ----------
    node : rclpy.node.Node
        The node, whose parameters are already declared.
    node_name : str
        ``IMU_NODE`` or ``CLASSIFIER_NODE``.
    values : dict
        Current values (from ``declare_node_parameters``).
    check : callable
        ``check(values)``, raising InputError when the set is unusable.
    apply : callable
        ``apply(values, changed)`` once accepted.

    """

    def __init__(self, node, node_name: str, values: dict, check, apply):
        self.values = dict(values)
        self._specs = node_specs(node_name)
        self._check = check
        self._apply = apply
        node.add_on_set_parameters_callback(self._on_set)
        node.add_post_set_parameters_callback(self._post_set)

    def _proposed(self, params) -> dict:
        values = dict(self.values)
        for param in params:
            spec = self._specs.get(param.name)
            if spec is None:
                if is_ros_owned(param.name):        # use_sim_time...: rclpy's business
                    continue
                raise InputError(f'{param.name} is not a parameter of this node')
            values[param.name] = validate_value(spec, param.value)
        return values

    def _on_set(self, params) -> SetParametersResult:
        try:
            self._check(self._proposed(params))
        except InputError as err:
            return SetParametersResult(successful=False, reason=str(err))
        return SetParametersResult(successful=True)

    def _post_set(self, params):
        changed = [p.name for p in params if p.name in self._specs]
        if changed:
            self.values = self._proposed(params)
            self._apply(self.values, changed)


# -- messages ---------------------------------------------------------------------------------

def imu_sample(msg):
    """Return (stamp_ns, acc_b, gyr_b, frame_id) of a sensor_msgs/Imu (tuples of 3 floats)."""
    acc, gyr, header = msg.linear_acceleration, msg.angular_velocity, msg.header
    return (header.stamp.sec * 1_000_000_000 + header.stamp.nanosec, (acc.x, acc.y, acc.z),
            (gyr.x, gyr.y, gyr.z), header.frame_id)


def imu_sample_from_cdr(data: bytes):
    """
    Return (stamp_ns, acc_b, gyr_b, frame_id) of a serialised sensor_msgs/Imu.

    The IMU node subscribes with ``raw=True`` and decodes here: building the Python message
    (nine objects and three numpy covariance arrays per sample) costs more than the rest of
    the transport. Plain little-endian CDR (what ROS 2 middlewares send) is read in place:

        4-byte encapsulation 00 01 00 00 | int32 sec | uint32 nanosec | uint32 n |
        frame_id (n bytes, NUL included) | pad to 8 | 37 float64: orientation (4),
        orientation_covariance (9), angular_velocity (3), its covariance (9),
        linear_acceleration (3), its covariance (9)

    (alignment counts from the end of the encapsulation); any other encoding goes through
    rclpy's deserializer.

    Raises
    ------
    InputError : bytes that are not a sensor_msgs/Imu.

    """
    if data[:2] == _CDR_LE and len(data) >= 16:
        sec, nanosec, length = _CDR_HEADER.unpack_from(data, 4)
        doubles_at = 4 + -(-(12 + length) // 8) * 8
        if length >= 1 and len(data) >= doubles_at + _IMU_DOUBLES_SIZE:
            return (sec * 1_000_000_000 + nanosec,
                    _VECTOR3.unpack_from(data, doubles_at + _ACC_OFFSET),
                    _VECTOR3.unpack_from(data, doubles_at + _GYR_OFFSET),
                    data[16:15 + length].decode('utf-8', errors='replace'))
    try:
        return imu_sample(deserialize_message(data, Imu))
    except Exception as err:   # noqa: B902 the deserializer raises several kinds
        raise InputError(f'not a sensor_msgs/Imu message ({len(data)} bytes): {err}') from None


@dataclass(frozen=True)
class CycleMessage:
    """
    A decoded gait-cycle message.

    Attributes
    ----------
    stamp_ns : int
        Stamp of the sample that closed the cycle, ns.
    x_m, y_m, z_m : float
        EKF position at that sample (z: raw INS height), m, odometry frame.
    valid : bool
        False for a cycle with a gap or an overlong swing.
    features : (5,) array
        In ``FEATURE_NAMES`` order.
    index : int
        Index of the cycle (1, 2, ...).

    """

    stamp_ns: int
    x_m: float
    y_m: float
    z_m: float
    valid: bool
    features: np.ndarray
    index: int


_CYCLE_LAYOUT = tuple((name, 8 * i, PointField.FLOAT64, 1) for i, name in enumerate(CYCLE_FIELDS))


def cycle_to_msg(cycle, frame_id: str, index: int) -> PointCloud2:
    """
    PointCloud2 of one GaitCycle with its index (layout in the module docstring).

    A cycle with a non-finite value is sent as invalid (valid = 0), never classified.
    """
    position = [float(v) for v in cycle.pos_n]
    features = [float(v) for v in cycle.features]
    finite = all(math.isfinite(v) for v in position + features)
    values = (*position, 1.0 if cycle.valid and finite else 0.0, *features, float(index))
    msg = PointCloud2()
    msg.header.stamp = ns_to_stamp(cycle.stamp_ns)
    msg.header.frame_id = frame_id
    msg.height = 1
    msg.width = 1
    msg.fields = [PointField(name=name, offset=offset, datatype=datatype, count=count)
                  for name, offset, datatype, count in _CYCLE_LAYOUT]
    msg.is_bigendian = False
    msg.point_step = _CYCLE_STRUCT.size
    msg.row_step = _CYCLE_STRUCT.size
    msg.data = _CYCLE_STRUCT.pack(*values)
    msg.is_dense = finite
    return msg


def cycle_from_msg(msg) -> CycleMessage:
    """
    Decode a gait-cycle PointCloud2, checking its layout.

    Raises
    ------
    InputError : not one point with exactly ``CYCLE_FIELDS`` as little-endian FLOAT64.

    """
    layout = tuple((f.name, f.offset, f.datatype, f.count) for f in msg.fields)
    if layout != _CYCLE_LAYOUT or msg.is_bigendian or msg.width * msg.height != 1 \
            or msg.point_step != _CYCLE_STRUCT.size or len(msg.data) != _CYCLE_STRUCT.size:
        raise InputError(f'gait_cycle message does not have the expected layout (one point, '
                         f'fields {", ".join(CYCLE_FIELDS)} as FLOAT64); got fields '
                         f'{[f.name for f in msg.fields]}, {msg.width}x{msg.height} points, '
                         f'{len(msg.data)} bytes')
    values = _CYCLE_STRUCT.unpack(bytes(msg.data))
    index = values[-1]
    if not (math.isfinite(index) and index == int(index) and 1 <= index < 2 ** 53):
        raise InputError(f'gait_cycle message has cycle_index {index!r}, not a count')
    return CycleMessage(stamp_ns=stamp_to_ns(msg.header.stamp), x_m=values[0], y_m=values[1],
                        z_m=values[2], valid=values[3] == 1.0,
                        features=np.array(values[4:-1], dtype=float), index=int(index))


def diagnostic_status(name: str, level: bytes, message: str, hardware_id: str,
                      values: dict) -> DiagnosticStatus:
    """Build a DiagnosticStatus with one KeyValue per item (floats: 6 significant digits)."""
    def text(value):
        if isinstance(value, bool):
            return 'true' if value else 'false'
        if isinstance(value, float):
            return f'{value:.6g}'
        return str(value)

    return DiagnosticStatus(level=level, name=name, message=message, hardware_id=hardware_id,
                            values=[KeyValue(key=k, value=text(v)) for k, v in values.items()])
