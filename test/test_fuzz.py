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
Bad input everywhere: hypothesis fuzzes the nodes' message handlers and the file parsers.

Every property runs a fixed number of examples, derandomised (``fuzz``): CI tries the same
inputs on every run, and the whole file takes well under a minute.

- ``ImuNode._on_imu`` after good data (the navigator has started): random bytes, truncated
  or bit-flipped CDR Imu messages, Imu messages with any float, stamp and frame_id, then
  clean data again. No exception escapes, every message is counted once (received =
  malformed + accepted + refused), nothing raises inside the navigator, its track stays
  finite and every gait cycle published is finite.
- ``ClassifierNode._on_cycle``: valid gait cycles mixed with broken PointCloud2 messages
  (fields, point_step, data, sizes, NaN/Inf). Each message is counted once; a message
  ``cycle_from_msg`` refuses counts as malformed; the height stays finite.
- Live parameter changes with any value: refused (and the old value kept) or accepted as
  validated.
- Parsers: ``read_imu_bag`` / ``read_messages`` on damaged bags, ``read_imu_csv``,
  ``Anfis.load``, ``load_params_yaml`` / ``load_pipeline_params``: a result or InputError,
  never another exception.
- The command line: damaged bag, missing or corrupt model, bad parameter value: exit code 1,
  one line ``error: ...`` on stderr, no traceback.
"""

import json
import math
from pathlib import Path
import shutil
import struct
import subprocess
import sys
import tempfile
from unittest import mock

from anfis_elevation_ros.core.anfis import Anfis
from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.gait import GaitCycle, N_FEATURES
from anfis_elevation_ros.core.height import ElevationParams, ElevationTracker
from anfis_elevation_ros.core.imu_data import ImuRecording
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.core.params import all_specs, CLASSIFIER_NODE, IMU_NODE
from anfis_elevation_ros.core.params import elevation_params_from_dict, gate_params_from_dict
from anfis_elevation_ros.core.params import load_params_yaml, load_pipeline_params, node_specs
from anfis_elevation_ros.core.params import PipelineParams, validate_value
from anfis_elevation_ros.nodes.classifier_node import ClassifierNode
from anfis_elevation_ros.nodes.gait_cycle_msg import CYCLE_FIELDS, cycle_from_msg, cycle_to_msg
from anfis_elevation_ros.nodes.imu_node import ImuNode
from anfis_elevation_ros.tools.bags import BagWriter, IMU_MSGTYPE, read_imu_bag, read_messages
from anfis_elevation_ros.tools.bags import write_imu_bag
from anfis_elevation_ros.tools.import_csv import CsvImuFormat, read_imu_csv
from hypothesis import example, given, HealthCheck, settings
from hypothesis import strategies as st
from live_support import cli, cli_env, PACKAGE_ROOT, SAMPLE_BAG, write_linear_model
import numpy as np
import pytest
import rclpy
from rclpy.context import Context
from rclpy.exceptions import ParameterUninitializedException
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher
from rclpy.serialization import serialize_message
from sensor_msgs.msg import Imu, PointCloud2, PointField
import yaml

CONFIG_YAML = PACKAGE_ROOT / 'config' / 'params.yaml'
NO_STATE = [Parameter('persist_state', value=False)]
PREFIX_SAMPLES = 100          # the navigator starts at the 17th sample of the sample walk
CONTINUATION_SAMPLES = 80
STAMP_MIN_NS = -2 ** 31 * 1_000_000_000
STAMP_MAX_NS = (2 ** 31 - 1) * 1_000_000_000 + 999_999_999
INT32 = st.integers(-2 ** 31, 2 ** 31 - 1)
UINT32 = st.integers(0, 2 ** 32 - 1)


def fuzz(max_examples: int):
    """Return the settings of every property: bounded, derandomised, no example database."""
    return settings(max_examples=max_examples, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.function_scoped_fixture])


def damage(data: bytes, how) -> bytes:
    """Apply ('truncate', fraction), ('flip', [(fraction, bit), ...]) or ('replace', bytes)."""
    kind, arg = how
    if kind == 'truncate':
        return data[:int(arg * len(data))]
    if kind == 'replace':
        return arg
    out = bytearray(data)
    for fraction, bit in arg:
        if out:
            out[int(fraction * len(out))] ^= 1 << bit
    return bytes(out)


FRACTION = st.floats(0.0, 1.0, exclude_max=True)
DAMAGE = st.one_of(
    st.tuples(st.just('truncate'), FRACTION),
    st.tuples(st.just('flip'), st.lists(st.tuples(FRACTION, st.integers(0, 7)), min_size=1,
                                        max_size=12)),
    st.tuples(st.just('replace'), st.binary(max_size=600)))
ANY_FLOAT = st.floats()                                  # NaN, Inf, subnormal, huge
IMU_VALUE = st.one_of(st.floats(-60.0, 60.0), ANY_FLOAT,
                      st.sampled_from([0.0, -0.0, 5e-324, 1e308, -1e308, 39.9, 40.1, 999.0,
                                       1001.0, 9.80665]))


# -- rclpy and the clean input -----------------------------------------------------------------

@pytest.fixture(scope='module')
def context():
    """Give this module an rclpy context of its own."""
    ctx = Context()
    rclpy.init(context=ctx)
    yield ctx
    rclpy.try_shutdown(context=ctx)


@pytest.fixture(scope='module')
def walk():
    """Read the first samples of the bundled sample walk; return them and their CDR bytes."""
    recording = read_imu_bag(SAMPLE_BAG)
    n = PREFIX_SAMPLES + CONTINUATION_SAMPLES
    recording = ImuRecording(recording.stamp_ns[:n], recording.acc_b[:n], recording.gyr_b[:n],
                             recording.frame_id)
    cdr = [serialize_message(imu_msg(recording.stamp_ns[k], recording.acc_b[k],
                                     recording.gyr_b[k])) for k in range(n)]
    return recording, cdr


@pytest.fixture(scope='module')
def model_path(tmp_path_factory):
    """Write a small valid model file (32 rules)."""
    return write_linear_model(tmp_path_factory.mktemp('model') / 'model.json')


def imu_msg(stamp_ns, acc_b, gyr_b, frame_id='imu_link', sec_nanosec=None) -> Imu:
    """Build a sensor_msgs/Imu (stamp from stamp_ns, or a raw (sec, nanosec) pair)."""
    msg = Imu()
    sec, nanosec = sec_nanosec or divmod(int(stamp_ns), 1_000_000_000)
    msg.header.stamp.sec, msg.header.stamp.nanosec = sec, nanosec
    msg.header.frame_id = frame_id
    msg.orientation_covariance[0] = -1.0
    a, w = msg.linear_acceleration, msg.angular_velocity
    a.x, a.y, a.z = (float(v) for v in acc_b)
    w.x, w.y, w.z = (float(v) for v in gyr_b)
    return msg


def diagnostic_values(node) -> dict:
    """Return {key: value text} of every status of the node's diagnostics."""
    return {kv.key: kv.value for status in node.diagnostics(0).status for kv in status.values}


def assert_one_line(err: InputError):
    """Check that an InputError says what is wrong in one line (the tools print one)."""
    text = str(err)
    assert text.strip() and '\n' not in text and '\r' not in text, repr(text)


def assert_published_finite(publish):
    """Check every message the mocked Publisher.publish received: no NaN or Inf anywhere."""
    for call in publish.call_args_list:
        msg = call.args[1]
        if isinstance(msg, PointCloud2):
            cycle = cycle_from_msg(msg)
            assert all(math.isfinite(v) for v in (cycle.x_m, cycle.y_m, cycle.z_m)), cycle
            assert np.all(np.isfinite(cycle.features)), cycle
        elif hasattr(msg, 'point'):                              # PointStamped
            assert all(math.isfinite(v) for v in (msg.point.x, msg.point.y, msg.point.z)), msg


# -- the IMU node ------------------------------------------------------------------------------

def run_imu_node(context, walk, garbage):
    """
    Feed a new ImuNode good data, the garbage (CDR bytes), then good data again; check it.

    The good data after the garbage are the rest of the clean samples, restamped to follow
    the last stamp the gate accepted.
    """
    recording, cdr = walk
    node = ImuNode(context=context, parameter_overrides=NO_STATE)
    try:
        with mock.patch.object(Publisher, 'publish', autospec=True) as publish:
            for data in cdr[:PREFIX_SAMPLES]:
                node._on_imu(data)
            assert node.navigator.status.initialised
            for data in garbage:
                node._on_imu(data)
            shift = node.gate.last_stamp_ns - int(recording.stamp_ns[PREFIX_SAMPLES - 1])
            continuation = [
                serialize_message(imu_msg(recording.stamp_ns[k] + shift, recording.acc_b[k],
                                          recording.gyr_b[k]))
                for k in range(PREFIX_SAMPLES, len(recording))
                if recording.stamp_ns[k] + shift <= STAMP_MAX_NS]
            for data in continuation:
                node._on_imu(data)
        values = diagnostic_values(node)
        received = PREFIX_SAMPLES + len(garbage) + len(continuation)
        assert int(values['received']) == received
        assert int(values['malformed']) + int(values['accepted']) + int(values['rejected']) \
            == received, values
        assert values['internal_errors'] == '0'
        point = node._last_point
        assert np.all(np.isfinite(point.pos_n)) and np.all(np.isfinite(point.quat_nb)), point
        assert_published_finite(publish)
        return node.gate
    finally:
        node.destroy_node()


@fuzz(40)
@given(garbage=st.lists(st.binary(max_size=400), min_size=1, max_size=30))
@example(garbage=[b'', b'\x00\x01\x00\x00', b'\x00\x01\x00\x00' + b'\xff' * 12,
                  b'\x00\x00\x00\x00' + struct.pack('>iII', 1, 2, 0x7fffffff) + bytes(8)])
def test_imu_node_survives_random_bytes(context, walk, garbage):
    """Random bytes are malformed messages, counted, and change nothing."""
    run_imu_node(context, walk, garbage)


@fuzz(40)
@given(damages=st.lists(st.tuples(st.integers(0, PREFIX_SAMPLES + CONTINUATION_SAMPLES - 1),
                                  DAMAGE), min_size=1, max_size=30))
def test_imu_node_survives_damaged_cdr(context, walk, damages):
    """Truncated, bit-flipped or replaced CDR Imu messages: decoded or refused, counted."""
    _, cdr = walk
    run_imu_node(context, walk, [damage(cdr[k], how) for k, how in damages])


STAMP = st.one_of(
    st.tuples(st.just('delta'), st.sampled_from([0, 1, -1, 10_000_000, -10_000_000,
                                                 5_000_000_000])),
    st.tuples(st.just('delta'), st.integers(1, 60_000_000)),    # on time or a short gap
    st.tuples(st.just('delta'), st.integers(-10 ** 12, 10 ** 12)),
    st.tuples(st.just('absolute'), st.integers(STAMP_MIN_NS, STAMP_MAX_NS)),
    st.tuples(st.just('raw'), st.tuples(INT32, UINT32)),         # nanosec beyond 1e9 too
    st.tuples(st.just('jump'), st.integers(10 ** 9, 10 ** 18)))  # a confirmed clock jump
# Half the vectors pass the gate (|gyr| < 40 rad/s): they reach the navigator.
IMU_VECTOR = st.one_of(st.tuples(*[st.floats(-39.0, 39.0)] * 3),
                       st.tuples(IMU_VALUE, IMU_VALUE, IMU_VALUE))
IMU_SAMPLE = st.tuples(STAMP, IMU_VECTOR, IMU_VECTOR,
                       st.one_of(st.just('imu_link'), st.text(max_size=30)))


def imu_messages(samples, last_ns):
    """Return the CDR bytes of fuzzed samples; stamps relative to the one before (last_ns)."""
    out = []
    for (kind, arg), acc, gyr, frame_id in samples:
        stamps = [last_ns]
        sec_nanosec = None
        if kind == 'delta':
            stamps = [last_ns + arg]
        elif kind == 'absolute':
            stamps = [arg]
        elif kind == 'raw':
            sec_nanosec = arg           # the stamp as it is, even nanosec >= 1e9
        else:                   # three samples 10 ms apart confirm a jump (input_gate.py)
            stamps = [last_ns + arg + k * 10_000_000 for k in range(3)]
        for stamp_ns in stamps:
            stamp_ns = min(max(stamp_ns, STAMP_MIN_NS), STAMP_MAX_NS)
            msg = imu_msg(stamp_ns, acc, gyr, frame_id, sec_nanosec)
            out.append(serialize_message(msg))
            last_ns = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
    return out


@fuzz(60)
@given(samples=st.lists(IMU_SAMPLE, min_size=1, max_size=30))
def test_imu_node_survives_any_values_stamps_and_frames(context, walk, samples):
    """NaN/Inf/huge/subnormal values, stamps backwards, duplicate or far ahead, any frame_id."""
    recording, _ = walk
    run_imu_node(context, walk,
                 imu_messages(samples, int(recording.stamp_ns[PREFIX_SAMPLES - 1])))


def test_imu_node_after_a_clock_jump_of_years(context, walk):
    """A stamp jump confirmed by three samples is accepted as a gap; the track stays finite."""
    recording, _ = walk
    still = ((0.0, 0.0, 9.80665), (0.0, 0.0, 0.0), 'imu_link')
    samples = [(('jump', 10 * 365 * 86400 * 10 ** 9), *still),
               (('delta', 10_000_000), *still)]
    gate = run_imu_node(context, walk,
                        imu_messages(samples, int(recording.stamp_ns[PREFIX_SAMPLES - 1])))
    assert gate.flagged['gap'] >= 1


# -- the classifier node -----------------------------------------------------------------------

def cycle_message(stamp_ns, values, index):
    """Build a well-formed gait-cycle PointCloud2 (values: x, y, z, valid, the features)."""
    cycle = GaitCycle(stamp_ns=stamp_ns, start_stamp_ns=0, pos_n=np.array(values[:3]),
                      features=np.array(values[4:]), valid=bool(values[3]))
    return cycle_to_msg(cycle, 'odom', index, 1)


PLAUSIBLE_CYCLE = st.tuples(*[st.floats(-5.0, 5.0)] * 3, st.booleans(),
                            *[st.floats(-1.0, 1.0)] * N_FEATURES)
FIELD = st.builds(PointField, name=st.one_of(st.sampled_from(CYCLE_FIELDS), st.text(max_size=8)),
                  offset=st.one_of(st.integers(0, 100), UINT32), datatype=st.integers(0, 255),
                  count=st.one_of(st.integers(0, 3), UINT32))
CYCLE_DAMAGE = st.one_of(
    st.tuples(st.just('values'), st.lists(ANY_FLOAT, min_size=len(CYCLE_FIELDS),
                                          max_size=len(CYCLE_FIELDS))),
    st.tuples(st.just('fields'), st.lists(FIELD, max_size=12)),
    st.tuples(st.just('drop_field'), st.integers(0, len(CYCLE_FIELDS) - 1)),
    st.tuples(st.just('point_step'), UINT32),
    st.tuples(st.just('data'), DAMAGE),
    st.tuples(st.just('size'), st.tuples(UINT32, UINT32)),
    st.tuples(st.just('bigendian'), st.booleans()),
    st.tuples(st.just('stamp'), st.tuples(INT32, UINT32)))


def damaged_cycle_message(msg, how):
    """Apply one CYCLE_DAMAGE to a gait-cycle message (in place) and return it."""
    kind, arg = how
    if kind == 'values':
        msg.data = struct.pack(f'<{len(CYCLE_FIELDS)}d', *arg)
    elif kind == 'fields':
        msg.fields = arg
    elif kind == 'drop_field':
        msg.fields = [f for i, f in enumerate(msg.fields) if i != arg]
    elif kind == 'point_step':
        msg.point_step = arg
    elif kind == 'data':
        msg.data = damage(bytes(msg.data), arg)
    elif kind == 'size':
        msg.width, msg.height = arg
    elif kind == 'bigendian':
        msg.is_bigendian = arg
    else:
        msg.header.stamp.sec, msg.header.stamp.nanosec = arg
    return msg


COUNTERS = ('classified', 'invalid_cycles', 'malformed', 'already_counted')


@fuzz(30)
@given(stream=st.lists(st.tuples(PLAUSIBLE_CYCLE, st.booleans(), CYCLE_DAMAGE), min_size=1,
                       max_size=20))
def test_classifier_node_survives_any_cycle_message(context, model_path, stream):
    """Each message counts once; a malformed one is counted so; the height stays finite."""
    node = ClassifierNode(context=context, parameter_overrides=NO_STATE + [
        Parameter('model_path', value=str(model_path))])
    try:
        with mock.patch.object(Publisher, 'publish', autospec=True) as publish:
            for k, (values, damaged, how) in enumerate(stream):
                msg = cycle_message(1_000_000_000 * (k + 1), values, k + 1)
                if damaged:
                    msg = damaged_cycle_message(msg, how)
                try:
                    cycle_from_msg(msg)
                    parses = True
                except InputError:
                    parses = False
                before = diagnostic_values(node)
                height_m = node.tracker.height_m
                node._on_cycle(msg)
                after = diagnostic_values(node)
                changed = [c for c in COUNTERS if after[c] != before[c]]
                assert len(changed) == 1 and int(after[changed[0]]) == int(before[changed[0]]) + 1
                if not parses:
                    assert changed == ['malformed']
                if changed != ['classified']:
                    assert node.tracker.height_m == height_m
                assert math.isfinite(node.tracker.height_m)
        assert_published_finite(publish)
    finally:
        node.destroy_node()


# -- live parameter changes --------------------------------------------------------------------

PARAMETER_VALUE = st.one_of(
    st.booleans(), st.integers(-2 ** 63, 2 ** 63 - 1), st.sampled_from([0, 1, -1, 10 ** 6]),
    ANY_FLOAT, st.floats(-10.0, 1000.0), st.text(max_size=20),
    st.lists(ANY_FLOAT, max_size=5), st.lists(st.floats(-400.0, 400.0), min_size=3, max_size=3))


@pytest.fixture(scope='module')
def live_nodes(context, model_path):
    """One IMU node and one classifier node, kept for every example of the property."""
    nodes = {IMU_NODE: ImuNode(context=context, parameter_overrides=NO_STATE),
             CLASSIFIER_NODE: ClassifierNode(context=context, parameter_overrides=NO_STATE + [
                 Parameter('model_path', value=str(model_path))])}
    yield nodes
    for node in nodes.values():
        node.destroy_node()


@fuzz(80)
@given(node_name=st.sampled_from([IMU_NODE, CLASSIFIER_NODE]), data=st.data())
def test_live_parameter_changes_are_validated_or_refused(live_nodes, node_name, data):
    """
    Any value: refused with a reason and the old value kept, or accepted as validated.

    Either way the node runs with what its parameters say (the gate's or the tracker's
    parameters are those built from the current values).
    """
    node = live_nodes[node_name]
    specs = node_specs(node_name)
    live_names = sorted(n for n, spec in specs.items() if not spec.read_only)
    # Half the draws are of a live parameter, half the values in its type and range.
    names = live_names if data.draw(st.booleans(), label='live') else sorted(specs)
    name = data.draw(st.sampled_from(names), label='name')
    in_range = data.draw(st.booleans(), label='in range')
    value = data.draw(valid_values(specs[name]) if in_range else PARAMETER_VALUE, label='value')
    old = parameter_value(node, name)
    result = node.set_parameters([Parameter(name, value=value)])[0]
    now = parameter_value(node, name)
    if result.successful:
        assert not specs[name].read_only
        assert validate_value(specs[name], value) == validate_value(specs[name], now)
    else:
        assert result.reason
        assert repr(as_plain(now)) == repr(as_plain(old))        # NaN == NaN here
    current = {n: node.get_parameter(n).value for n in specs
               if n.startswith(('gate.', 'elevation.')) or n == 'max_gap_s'}
    if node_name == IMU_NODE:
        assert node.gate.params == gate_params_from_dict(current)
    else:
        assert node.tracker.params == elevation_params_from_dict(current)


def valid_values(spec):
    """Return a strategy of values of the parameter's type within its range."""
    if spec.kind == 'double' and spec.min_value is not None:
        return st.floats(spec.min_value, spec.max_value)
    if spec.kind == 'int':
        return st.integers(spec.min_value, spec.max_value)
    others = {'bool': st.booleans(), 'string': st.text(max_size=20)}
    return others.get(spec.kind, PARAMETER_VALUE)


def parameter_value(node, name: str):
    """Return a parameter's value; None while it has none (mounting_rpy_deg: automatic)."""
    try:
        return node.get_parameter(name).value
    except ParameterUninitializedException:
        return None


def as_plain(value):
    """Return a parameter value with arrays as lists, for comparisons."""
    return list(value) if hasattr(value, '__len__') and not isinstance(value, str) else value


# -- bags --------------------------------------------------------------------------------------

@pytest.fixture(scope='module')
def small_bags(tmp_path_factory):
    """Write a valid 40-sample Imu bag in each storage."""
    base = tmp_path_factory.mktemp('bags')
    n = 40
    recording = ImuRecording(1_700_000_000_000_000_000 + np.arange(n, dtype=np.int64) * 10 ** 7,
                             np.tile([0.0, 0.0, 9.81], (n, 1)), np.zeros((n, 3)))
    return {storage: write_imu_bag(base / storage, recording, storage=storage)
            for storage in ('sqlite3', 'mcap')}


def read_bag_or_input_error(path):
    """Read a bag both ways; return True if it was read, False if refused with InputError."""
    try:
        recording = read_imu_bag(path)
        messages = list(read_messages(path))
    except InputError as err:
        assert_one_line(err)
        return False
    assert isinstance(recording, ImuRecording) and len(recording) >= 1
    assert len(messages) >= len(recording)
    return True


@fuzz(80)
@given(storage=st.sampled_from(['sqlite3', 'mcap']), target=st.sampled_from(['storage',
                                                                             'metadata']),
       how=DAMAGE, bare_file=st.booleans())
@example(storage='sqlite3', target='storage', how=('truncate', 0.5), bare_file=False)
@example(storage='mcap', target='storage', how=('flip', [(0.5, 3)]), bare_file=False)
@example(storage='mcap', target='metadata', how=('replace', b'rosbag2_bagfile_information: 1'),
         bare_file=False)
def test_damaged_bags_read_or_raise_input_error(small_bags, storage, target, how, bare_file):
    """Truncated, bit-flipped or replaced storage or metadata file: read or InputError."""
    with tempfile.TemporaryDirectory() as tmp:
        bag = Path(shutil.copytree(small_bags[storage], Path(tmp) / 'bag'))
        storage_file = next(p for p in bag.iterdir() if p.suffix in ('.db3', '.mcap'))
        victim = bag / 'metadata.yaml' if target == 'metadata' else storage_file
        victim.write_bytes(damage(victim.read_bytes(), how))
        read_bag_or_input_error(storage_file if bare_file else bag)


@fuzz(20)
@given(storage=st.sampled_from(['sqlite3', 'mcap']),
       messages=st.lists(st.one_of(st.binary(max_size=400),
                                   st.tuples(FRACTION, DAMAGE)), min_size=1, max_size=8))
def test_bags_of_broken_imu_messages_read_or_raise_input_error(walk, storage, messages):
    """A valid bag whose Imu messages are random or damaged CDR bytes: read or InputError."""
    _, cdr = walk
    with tempfile.TemporaryDirectory() as tmp:
        with BagWriter(Path(tmp) / 'bag', storage=storage) as bag:
            for k, item in enumerate(messages):
                data = item if isinstance(item, bytes) else damage(cdr[int(item[0] * 100)],
                                                                   item[1])
                bag.write_raw('/imu/data', IMU_MSGTYPE, data, k + 1)
        read_bag_or_input_error(Path(tmp) / 'bag')


@fuzz(20)
@given(suffix=st.sampled_from(['.db3', '.mcap']), data=st.binary(max_size=2000))
@example(suffix='.mcap', data=b'\x89MCAP0\r\n' + bytes(100))
@example(suffix='.db3', data=b'SQLite format 3\x00' + bytes(200))
def test_random_files_are_no_bags(suffix, data):
    """Random bytes named .db3 or .mcap: InputError."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f'random{suffix}'
        path.write_bytes(data)
        assert not read_bag_or_input_error(path)


# -- CSV ---------------------------------------------------------------------------------------

CSV_COLUMNS = ('t', 'acc_x', 'acc_y', 'acc_z', 'gyr_x', 'gyr_y', 'gyr_z')
CSV_CELL = st.one_of(
    st.floats(-50.0, 50.0).map(repr), ANY_FLOAT.map(repr), st.integers().map(str),
    st.sampled_from(['', ' ', 'nan', '-inf', 'sNaN', '1e999999', '-1e999999999', '1e-999999999',
                     '1_0', '0x10', '"', '"1,2"', '\x00', '\ufeff1', '1' * 5000]),
    st.text(max_size=8))


@st.composite
def csv_texts(draw):
    """Draw a CSV: a header (the expected columns, shuffled or not, or any), then rows."""
    header = list(CSV_COLUMNS)
    if draw(st.booleans()):
        header = draw(st.permutations(header))
    if draw(st.integers(0, 4)) == 0:
        header = draw(st.lists(st.text(max_size=6), max_size=8))
    lines = [','.join(header)]
    for k in range(draw(st.integers(0, 20))):
        row = [repr(0.01 * (k + 1))] + [repr(draw(st.floats(-20.0, 20.0))) for _ in range(6)]
        for i in draw(st.lists(st.integers(0, 8), max_size=2)):   # break a cell or two
            if i < len(row):
                row[i] = draw(CSV_CELL)
            else:
                row = row[:draw(st.integers(0, 6))]
        lines.append(','.join(row))
    return '\n'.join(lines) + draw(st.sampled_from(['\n', '', '\r\n', '\n\n']))


CSV_FORMAT = st.one_of(
    st.builds(CsvImuFormat, time_col=st.just('t'),
              time_unit=st.sampled_from(['s', 'ms', 'us', 'ns']), skip_rows=st.integers(0, 2)),
    st.builds(CsvImuFormat, rate_hz=st.sampled_from([100.0, 1e9, 1e12]),
              skip_rows=st.integers(0, 1)))


@fuzz(100)
@given(text=st.one_of(csv_texts(), st.text(max_size=300)), fmt=CSV_FORMAT)
@example(text=','.join(CSV_COLUMNS) + '\n1e999999999,0,0,9.8,0,0,0\n',
         fmt=CsvImuFormat(time_col='t'))
def test_csv_import_reads_or_raises_input_error(text, fmt):
    """Any text and columns: an ImuRecording with increasing stamps, or InputError."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / 'imu.csv'
        path.write_text(text, encoding='utf-8')
        try:
            recording = read_imu_csv(path, fmt)
        except InputError as err:
            assert_one_line(err)
            return
    assert len(recording) >= 10
    assert np.all(np.diff(recording.stamp_ns) > 0)
    assert np.all(np.isfinite(recording.acc_b)) and np.all(np.isfinite(recording.gyr_b))


# -- ANFIS model files -------------------------------------------------------------------------

JSON_VALUE = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), ANY_FLOAT, st.text(max_size=10)),
    lambda children: st.one_of(st.lists(children, max_size=5),
                               st.dictionaries(st.text(max_size=10), children, max_size=5)),
    max_leaves=30)
MODEL_KEYS = ('format', 'version', 'mf', 'n_inputs', 'n_mfs', 'rule_base', 'input_range',
              'mf_params', 'consequents', 'metadata')
MODEL_ARRAYS = st.sampled_from(['input_range', 'mf_params', 'consequents'])
MODEL_COUNT = st.one_of(st.integers(-3, 12), st.sampled_from([243, 10 ** 6, 10 ** 18]),
                        st.integers())
MODEL_DAMAGE = st.one_of(
    st.tuples(st.just('drop'), st.sampled_from(MODEL_KEYS)),
    st.tuples(st.just('set'), st.tuples(st.sampled_from(MODEL_KEYS), JSON_VALUE)),
    st.tuples(st.just('count'), st.tuples(st.sampled_from(['n_inputs', 'n_mfs']), MODEL_COUNT)),
    st.tuples(st.just('element'), st.tuples(MODEL_ARRAYS, FRACTION,
                                            st.one_of(ANY_FLOAT, JSON_VALUE))),
    st.tuples(st.just('row'), st.tuples(MODEL_ARRAYS,
                                        st.sampled_from(['drop', 'repeat', 'nest']))))


def damaged_model(doc: dict, how) -> dict:
    """Apply one MODEL_DAMAGE to a copy of a model document."""
    doc = json.loads(json.dumps(doc))
    kind, arg = how
    if kind == 'drop':
        doc.pop(arg, None)
    elif kind in ('set', 'count'):
        doc[arg[0]] = arg[1]
    elif kind == 'element':
        key, fraction, value = arg
        row = doc.get(key)
        while isinstance(row, list) and row and isinstance(row[0], list):   # down to a leaf
            row = row[int(fraction * len(row))]
        if isinstance(row, list) and row:
            row[int(fraction * len(row))] = value
    elif isinstance(doc.get(arg[0]), list):
        key, what = arg
        rows = doc[key]
        doc[key] = rows[1:] if what == 'drop' else rows + rows[:1] if what == 'repeat' \
            else [rows]
    return doc


def load_or_input_error(text: str):
    """Write a model file and load it; return the model, or None if refused with InputError."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / 'model.json'
        path.write_text(text, encoding='utf-8')
        try:
            model = Anfis.load(path)
        except InputError as err:
            assert_one_line(err)
            return None
    x = np.linspace(-1.0, 1.0, 3 * model.n_inputs).reshape(3, model.n_inputs)
    assert model.predict(x).shape == (3,)
    return model


@fuzz(60)
@given(doc=JSON_VALUE, text=st.text(max_size=200))
def test_random_json_is_no_model(doc, text):
    """Random JSON documents and random text: InputError."""
    assert load_or_input_error(json.dumps(doc)) is None
    assert load_or_input_error(text) is None


@fuzz(120)
@given(damages=st.lists(MODEL_DAMAGE, min_size=1, max_size=3), cut=st.none() | FRACTION)
@example(damages=[('count', ('n_inputs', 10 ** 18))], cut=None)
@example(damages=[('count', ('n_mfs', 10 ** 6))], cut=None)
@example(damages=[('row', ('input_range', 'nest'))] * 3, cut=None)
def test_damaged_models_load_or_raise_input_error(model_path, damages, cut):
    """A saved model with keys dropped, types changed, NaN, wrong shapes, huge sizes."""
    doc = json.loads(Path(model_path).read_text())
    for how in damages:
        doc = damaged_model(doc, how)
    text = json.dumps(doc)
    if cut is not None:
        text = text[:int(cut * len(text))]
    load_or_input_error(text)


@pytest.mark.parametrize('text', [
    '[' * 100_000, '{"a": ' * 100_000, '1' * 5000, '{"n_inputs": ' + '9' * 5000 + '}',
    '{"format": "anfis_elevation_ros.anfis", "version": 1, "mf": "triangle", "n_inputs": 1, '
    '"n_mfs": 2, "rule_base": "grid", "input_range": ' + '[' * 600 + ']' * 600 + ', '
    '"mf_params": [], "consequents": []}'])
def test_model_parser_limits_are_input_errors(text):
    """Nesting beyond the recursion limit and integers of thousands of digits: InputError."""
    assert load_or_input_error(text) is None


def test_model_file_size_is_bounded(tmp_path):
    """A file far larger than any model (e.g. a bag passed by mistake) is refused unread."""
    path = tmp_path / 'huge.json'
    with open(path, 'wb') as stream:
        stream.truncate(50_000_000)
    with pytest.raises(InputError, match='larger than'):
        Anfis.load(path)


# -- parameter files ---------------------------------------------------------------------------

SPEC_NAMES = sorted(all_specs())
YAML_VALUE = st.one_of(
    st.booleans(), st.integers(-2 ** 70, 2 ** 70), ANY_FLOAT, st.floats(-10.0, 3000.0),
    st.text(max_size=10), st.none(), st.lists(st.floats(-400.0, 400.0), max_size=4),
    st.lists(JSON_VALUE, max_size=3), st.dictionaries(st.text(max_size=5), st.integers(),
                                                      max_size=2))
YAML_PARAMS = st.dictionaries(
    st.one_of(st.sampled_from(SPEC_NAMES), st.sampled_from(['use_sim_time', 'qos_overrides']),
              st.text(max_size=12)),
    YAML_VALUE, max_size=6)
YAML_NODE_KEY = st.one_of(st.sampled_from(['imu_node', 'classifier_node', '/**', '**', '/*',
                                           'ns/imu_node', '/imu_node', '***']),
                          st.text(max_size=10))


@st.composite
def param_documents(draw):
    """Draw a ROS 2 parameter file: node keys with ros__parameters maps, or misshapen."""
    doc = {}
    for key in draw(st.lists(YAML_NODE_KEY, min_size=1, max_size=3)):
        params = draw(YAML_PARAMS)
        doc[key] = {'ros__parameters': params} if draw(st.integers(0, 5)) else params
    return yaml.safe_dump(doc) if draw(st.integers(0, 5)) else yaml.safe_dump(
        draw(JSON_VALUE))


@st.composite
def damaged_config(draw):
    """config/params.yaml with lines changed: a value replaced, a line dropped or cut."""
    lines = CONFIG_YAML.read_text().splitlines()
    for _ in range(draw(st.integers(1, 3))):
        k = draw(st.integers(0, len(lines) - 1))
        kind = draw(st.sampled_from(['value', 'drop', 'cut', 'indent']))
        if kind == 'value' and ':' in lines[k]:
            key = lines[k].split(':', 1)[0]
            lines[k] = f'{key}: ' + draw(st.one_of(
                st.sampled_from(['.nan', '-.inf', '1e400', '0x' + 'f' * 40, '1' * 5000, 'null',
                                 '[]', '[1, 2]', '{a: 1}', '*x', '&x [*x]', '!!binary aGk=',
                                 "'text'", '2024-13-45', 'yes', '-1', '1000000000']),
                st.text(max_size=10)))
        elif kind == 'drop':
            del lines[k]
        elif kind == 'cut':
            lines[k] = lines[k][:draw(st.integers(0, len(lines[k])))]
        else:
            lines[k] = ' ' + lines[k]
    return '\n'.join(lines) + '\n'


def load_params_or_input_error(text: str):
    """Load a parameter file both ways; both succeed or both raise InputError."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / 'params.yaml'
        path.write_text(text, encoding='utf-8')
        try:
            per_node = load_params_yaml(path)
        except InputError as err:
            assert_one_line(err)
            per_node = None
        try:
            pipeline = load_pipeline_params(path)
        except InputError as err:
            assert_one_line(err)
            pipeline = None
    assert (per_node is None) == (pipeline is None), (per_node, pipeline)
    assert pipeline is None or isinstance(pipeline, PipelineParams)


@fuzz(120)
@given(text=st.one_of(param_documents(), damaged_config(), st.text(max_size=200)))
@example(text='imu_node: &a {ros__parameters: {x: *a}}')
@example(text='&a {ns: *a}')
@example(text='a: ' + '[' * 600 + ']' * 600)
@example(text='imu_node: {ros__parameters: {imu_qos_depth: ' + '1' * 5000 + '}}')
@example(text='imu_node: {ros__parameters: {rate_hz: 0x' + 'f' * 5000 + '}}')
@example(text='imu_node: {ros__parameters: {rate_hz: 2024-13-45}}')
@example(text="'" + '**' * 40 + "z': {ros__parameters: {}}")
def test_parameter_files_load_or_raise_input_error(text):
    """Random, misshapen and damaged parameter YAML: parameters or InputError, never else."""
    load_params_or_input_error(text)


# -- defects the fuzzing found in the node, the navigator and the tracker ----------------------

def test_samples_the_navigator_refuses_count_once(context, walk):
    """Accelerometer data in g, refused by the navigator at start-up: each sample counts once."""
    recording, _ = walk
    node = ImuNode(context=context, parameter_overrides=NO_STATE)
    try:
        for k in range(len(recording)):
            node._on_imu(serialize_message(imu_msg(recording.stamp_ns[k],
                                                   recording.acc_b[k] / 9.80665,
                                                   recording.gyr_b[k])))
        values = diagnostic_values(node)
        assert int(values['rejected_wrong_units']) > 0
        assert int(values['malformed']) + int(values['accepted']) + int(values['rejected']) \
            == int(values['received']), values
    finally:
        node.destroy_node()


def test_a_dropout_does_not_throw_the_track_away(walk):
    """After an hour without samples the track goes on near where it was, not 1e7 m away."""
    recording, _ = walk

    def final_position(dropout_ns):
        navigator = FootNavigator(NavigatorParams())
        for k in range(len(recording)):
            stamp_ns = int(recording.stamp_ns[k]) + (dropout_ns if k >= PREFIX_SAMPLES else 0)
            outputs = navigator.step(stamp_ns, recording.acc_b[k], recording.gyr_b[k])
        return outputs[-1][0].pos_n

    assert np.linalg.norm(final_position(3600 * 10 ** 9) - final_position(0)) < 100.0


def test_an_absurd_climb_does_not_wrap_the_height(model_path):
    """A finite but absurd height change (a diverged INS) is not trusted: an invalid cycle."""
    tracker = ElevationTracker(Anfis.load(model_path), ElevationParams())
    for dh in (1e20, -1e20, 10.5):
        features = np.zeros(N_FEATURES)
        features[:5] = [0.1, 0.01, dh, 0.5, 0.1]
        estimate = tracker.update(1, features, 0.0, 0.0)
        assert estimate.mode == 0 and estimate.height_m == 0.0, estimate
    assert tracker.implausible_cycles == 3 and tracker.unbridged_cycles == 0


# -- the command line and the node processes ---------------------------------------------------

def run_cli(*args, module=None):
    """Run the command line (or a node module) in a subprocess; return the result."""
    command = cli(*args) if module is None else [sys.executable, '-m', module, *args]
    return subprocess.run(command, env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True,
                          text=True, timeout=60, stdin=subprocess.DEVNULL)


def assert_one_line_error(result, fragment):
    """Exit code 1, one line ``error: ...`` naming the fragment on stderr, no traceback."""
    assert result.returncode == 1, result.stdout + result.stderr
    assert 'Traceback' not in result.stderr, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith('error: '), result.stderr
    assert fragment in lines[0], lines[0]


def write_params(path, imu=None, classifier=None) -> Path:
    """Write a parameter YAML for both nodes."""
    path.write_text(yaml.safe_dump({'imu_node': {'ros__parameters': imu or {}},
                                    'classifier_node': {'ros__parameters': classifier or {}}}))
    return path


@pytest.mark.parametrize('how', ['truncated', 'random', 'metadata'])
def test_cli_replay_of_a_damaged_bag_is_one_line_error(tmp_path, how):
    """The sample bag truncated, its storage file random bytes, a garbled metadata.yaml."""
    bag = Path(shutil.copytree(SAMPLE_BAG, tmp_path / 'bag'))
    victim = bag / 'metadata.yaml' if how == 'metadata' else next(bag.glob('*.mcap'))
    data = victim.read_bytes()
    if how == 'truncated':
        data = data[:len(data) // 2]
    elif how == 'random':
        data = bytes(range(256)) * 64
    else:
        data = data.replace(b'duration:', b'duration: [')
    victim.write_bytes(data)
    result = run_cli('replay', bag, '--out', tmp_path / 'out')
    assert_one_line_error(result, 'bag')


@pytest.mark.parametrize('case', ['missing', 'corrupt', 'huge_rule_base'])
def test_cli_replay_with_a_bad_model_is_one_line_error(tmp_path, model_path, case):
    """model_path naming a missing, truncated or absurdly sized model: exit 1, one line."""
    model = tmp_path / 'model.json'
    text = Path(model_path).read_text()
    if case == 'corrupt':
        model.write_text(text[:len(text) // 2])
    elif case == 'huge_rule_base':
        doc = json.loads(text)
        doc['n_inputs'] = 10 ** 6
        model.write_text(json.dumps(doc))
    params = write_params(tmp_path / 'params.yaml', classifier={'model_path': str(model)})
    result = run_cli('replay', SAMPLE_BAG, '--out', tmp_path / 'out', '--params', params)
    assert_one_line_error(result, {'missing': 'not found', 'corrupt': 'not valid JSON',
                                   'huge_rule_base': 'exceed'}[case])


@pytest.mark.parametrize('imu, classifier, fragment', [
    ({'imu_qos_depth': 10 ** 9}, {}, 'imu_qos_depth'),
    ({'gait.max_swing_s': 1e6}, {}, 'gait.max_swing_s'),
    ({'rate_hz': float('nan')}, {}, 'finite'),
    ({}, {'elevation.step_height_m': 'tall'}, 'elevation.step_height_m'),
])
def test_cli_replay_with_a_bad_parameter_is_one_line_error(tmp_path, imu, classifier, fragment):
    """A parameter of the wrong type or beyond its bound in --params: exit 1, one line."""
    params = write_params(tmp_path / 'params.yaml', imu, classifier)
    result = run_cli('replay', SAMPLE_BAG, '--out', tmp_path / 'out', '--params', params)
    assert_one_line_error(result, fragment)


def test_cli_import_of_a_bad_csv_is_one_line_error(tmp_path):
    """A time too large for any decimal context: exit 1, one line."""
    csv_path = tmp_path / 'imu.csv'
    csv_path.write_text(','.join(CSV_COLUMNS) + '\n1e999999999,0,0,9.8,0,0,0\n')
    result = run_cli('import-csv', csv_path, '--out', tmp_path / 'bag', '--time-col', 't')
    assert_one_line_error(result, 'too large')


def test_imu_node_refuses_to_start_with_an_unbounded_queue(tmp_path):
    """An imu_qos_depth beyond its bound stops the node at start, exit 1, saying why."""
    result = run_cli('--ros-args', '-p', 'imu_qos_depth:=1000000000',
                     module='anfis_elevation_ros.nodes.imu_node')
    assert result.returncode == 1, result.stdout + result.stderr
    assert 'cannot start' in result.stderr and 'imu_qos_depth' in result.stderr, result.stderr
    assert 'Traceback' not in result.stderr
