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

"""The nodes' conversions without DDS: Imu CDR decoding, the gait-cycle layout, descriptors."""

import math
import struct

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.gait import GaitCycle, N_FEATURES, PATENT_FEATURE_NAMES
from anfis_elevation_ros.core.params import all_specs
from anfis_elevation_ros.core.state import ElevationState, load_state
from anfis_elevation_ros.nodes.gait_cycle_msg import CYCLE_FIELDS, cycle_from_msg, cycle_to_msg
from anfis_elevation_ros.nodes.imu_msg import imu_sample, imu_sample_from_cdr
from anfis_elevation_ros.nodes.node_params import parameter_descriptor
from anfis_elevation_ros.nodes.state_writer import StateWriter
import numpy as np
import pytest
from rclpy.serialization import serialize_message
from sensor_msgs.msg import Imu


def make_imu(frame_id, stamp_ns=1_700_000_123_456_789_012):
    msg = Imu()
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
    msg.header.frame_id = frame_id
    msg.orientation.w = 0.5
    msg.orientation_covariance = [float(i) for i in range(9)]
    msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z = 0.1, -2.5, 33.0
    msg.angular_velocity_covariance[4] = 7.0
    msg.linear_acceleration.x, msg.linear_acceleration.y = -1e-300, math.pi
    msg.linear_acceleration.z = 9.80665
    msg.linear_acceleration_covariance[8] = -3.0
    return msg


@pytest.mark.parametrize('frame_id', ['', 'a', 'imu', 'imu_lin', 'imu_link', 'foot/left_imu',
                                      'x' * 17, 'fuß'])
def test_cdr_decoding_equals_rclpy(frame_id):
    """The in-place decoder reads what rclpy serialised, for every string alignment."""
    msg = make_imu(frame_id)
    assert imu_sample_from_cdr(serialize_message(msg)) == imu_sample(msg)


def imu_cdr_big_endian(msg):
    """
    Serialise a sensor_msgs/Imu as plain big-endian CDR, by hand.

    Encapsulation 00 00 00 00 | int32 sec | uint32 nanosec | uint32 n | frame_id (n bytes, NUL
    included) | pad to 8 | 37 float64: orientation (4), orientation_covariance (9),
    angular_velocity (3), its covariance (9), linear_acceleration (3), its covariance (9).
    """
    header = msg.header
    frame_id = header.frame_id.encode('utf-8') + b'\0'
    body = struct.pack('>iII', header.stamp.sec, header.stamp.nanosec, len(frame_id)) + frame_id
    body += bytes(-len(body) % 8)
    q, w, a = msg.orientation, msg.angular_velocity, msg.linear_acceleration
    doubles = ([q.x, q.y, q.z, q.w, *msg.orientation_covariance,
                w.x, w.y, w.z, *msg.angular_velocity_covariance,
                a.x, a.y, a.z, *msg.linear_acceleration_covariance])
    return b'\x00\x00\x00\x00' + body + struct.pack('>37d', *doubles)


@pytest.mark.parametrize('frame_id', ['', 'a', 'imu_link', 'x' * 17, 'fuß'])
def test_cdr_decoding_other_encapsulation_falls_back(frame_id):
    """Big-endian CDR goes through rclpy's deserializer: the same sample as the message."""
    msg = make_imu(frame_id)
    data = imu_cdr_big_endian(msg)
    assert data[:2] == b'\x00\x00'                        # CDR_BE: not the in-place path
    assert imu_sample_from_cdr(data) == imu_sample(msg)


def test_cdr_decoding_other_encapsulation_truncated_is_refused():
    """A big-endian fragment rclpy cannot deserialise is refused with an InputError."""
    data = imu_cdr_big_endian(make_imu('imu_link'))
    with pytest.raises(InputError, match='not a sensor_msgs/Imu'):
        imu_sample_from_cdr(data[:20])


def test_cdr_decoding_truncated_is_refused():
    """Too few bytes for the 37 doubles: an InputError, never an exception of struct."""
    data = serialize_message(make_imu('imu_link'))
    with pytest.raises(InputError):
        imu_sample_from_cdr(data[:-8])


def test_cycle_message_round_trip_and_layout():
    """Stamp, position, validity and features survive; fields are named FLOAT64 at 8k."""
    cycle = GaitCycle(stamp_ns=1_700_000_001_000_000_001, start_stamp_ns=0,
                      pos_n=np.array([1.5, -2.25, 0.34]),
                      features=np.arange(1.0, N_FEATURES + 1.0) / 7.0, valid=True)
    msg = cycle_to_msg(cycle, 'odom', 17, 2 ** 31 - 1)
    assert [f.name for f in msg.fields] == list(CYCLE_FIELDS)
    assert [f.offset for f in msg.fields] == [8 * i for i in range(len(CYCLE_FIELDS))]
    # The patent's fields, the index and the walk keep their first offsets; motion features follow.
    assert CYCLE_FIELDS[:12] == ('x', 'y', 'z', 'valid') + PATENT_FEATURE_NAMES \
        + ('cycle_index', 'walk_id', 'outage')
    assert msg.header.frame_id == 'odom' and msg.is_dense and msg.point_step == 8 * 23
    back = cycle_from_msg(msg)
    assert back.stamp_ns == cycle.stamp_ns and back.valid and back.index == 17
    assert back.walk_id == 2 ** 31 - 1 and not back.outage
    assert cycle_from_msg(cycle_to_msg(cycle, 'odom', 18, 1, outage=True)).outage
    assert (back.x_m, back.y_m, back.z_m) == (1.5, -2.25, 0.34)
    assert np.array_equal(back.features, cycle.features)


def test_non_finite_cycle_is_sent_invalid():
    """A cycle with a NaN is marked invalid (never classified) and not dense."""
    cycle = GaitCycle(stamp_ns=1, start_stamp_ns=0, pos_n=np.zeros(3),
                      features=np.r_[0.1, np.nan, np.zeros(N_FEATURES - 2)], valid=True)
    msg = cycle_to_msg(cycle, 'odom', 1, 1)
    assert not msg.is_dense and not cycle_from_msg(msg).valid


def test_cycle_message_with_another_layout_is_refused():
    """Fewer fields, another type or two points: InputError naming the expected fields."""
    cycle = GaitCycle(stamp_ns=1, start_stamp_ns=0, pos_n=np.zeros(3),
                      features=np.zeros(N_FEATURES), valid=True)
    msg = cycle_to_msg(cycle, 'odom', 1, 1)
    msg.fields[3].datatype = 7                              # FLOAT32
    with pytest.raises(InputError, match='expected layout'):
        cycle_from_msg(msg)


@pytest.mark.parametrize('index', [0.0, -3.0, 2.5, float('nan'), 2.0 ** 60])
def test_cycle_message_with_a_bad_index_is_refused(index):
    """The index is a count from 1: anything else is a malformed message."""
    cycle = GaitCycle(stamp_ns=1, start_stamp_ns=0, pos_n=np.zeros(3),
                      features=np.zeros(N_FEATURES), valid=True)
    msg = cycle_to_msg(cycle, 'odom', 1, 1)
    msg.data = bytes(msg.data)[:72] + struct.pack('<d', index) + bytes(msg.data)[80:]
    with pytest.raises(InputError, match='cycle_index'):
        cycle_from_msg(msg)


@pytest.mark.parametrize('walk_id', [0.0, -1.0, 7.5, float('inf'), 2.0 ** 31])
def test_cycle_message_with_a_bad_walk_id_is_refused(walk_id):
    """The walk identity is an integer in [1, 2^31 - 1]: anything else is malformed."""
    cycle = GaitCycle(stamp_ns=1, start_stamp_ns=0, pos_n=np.zeros(3),
                      features=np.zeros(N_FEATURES), valid=True)
    msg = cycle_to_msg(cycle, 'odom', 1, 1)
    msg.data = bytes(msg.data)[:80] + struct.pack('<d', walk_id) + bytes(msg.data)[88:]
    with pytest.raises(InputError, match='walk_id'):
        cycle_from_msg(msg)


@pytest.mark.parametrize('outage', [0.5, -1.0, float('nan')])
def test_cycle_message_with_a_bad_outage_flag_is_refused(outage):
    """The outage flag is 0 or 1: anything else is malformed."""
    cycle = GaitCycle(stamp_ns=1, start_stamp_ns=0, pos_n=np.zeros(3),
                      features=np.zeros(N_FEATURES), valid=True)
    msg = cycle_to_msg(cycle, 'odom', 1, 1)
    msg.data = bytes(msg.data)[:88] + struct.pack('<d', outage) + bytes(msg.data)[96:]
    with pytest.raises(InputError, match='outage'):
        cycle_from_msg(msg)


def test_descriptors_carry_the_table():
    """Ranges, types, read-only flags and descriptions come from the ParamSpec table."""
    specs = all_specs()
    d = parameter_descriptor(specs['zupt.window_s'])
    assert d.read_only and d.description == specs['zupt.window_s'].description
    assert (d.floating_point_range[0].from_value, d.floating_point_range[0].to_value) == \
        (0.005, 0.5)
    d = parameter_descriptor(specs['imu_qos_depth'])
    assert (d.integer_range[0].from_value, d.integer_range[0].to_value) == (1, 10000)
    d = parameter_descriptor(specs['elevation.start_floor'])
    assert not d.read_only
    d = parameter_descriptor(specs['mounting_rpy_deg'])
    assert 'each element' in d.additional_constraints


def _elevation(index):
    return ElevationState(stamp_ns=1_700_000_000_000_000_000 + index, wall_time_s=1000.0,
                          source_id='/gait_cycle', height_m=0.17 * index, floor=0,
                          cycle_index=index, walk_id=1, step_height_m=0.17,
                          riser_strides=index)


def test_state_writer_writes_the_latest_state_and_flushes_on_close(tmp_path):
    errors = []
    writer = StateWriter(tmp_path / 'classifier.state.json', errors.append)
    for index in range(1, 51):
        writer.submit(_elevation(index))
    writer.close()
    assert load_state(tmp_path / 'classifier.state.json', ElevationState).cycle_index == 50
    assert errors == [] and writer.errors == 0


def test_state_writer_counts_failed_writes_and_goes_on(tmp_path):
    (tmp_path / 'blocked').write_text('a file where the state directory should be')
    errors = []
    writer = StateWriter(tmp_path / 'blocked' / 'classifier.state.json', errors.append)
    writer.submit(_elevation(1))
    writer.close()
    assert writer.errors == 1 and isinstance(errors[0], OSError)
    writer = StateWriter(tmp_path / 'ok' / 'classifier.state.json', errors.append)
    writer.submit(_elevation(2))
    writer.close()
    assert load_state(tmp_path / 'ok' / 'classifier.state.json', ElevationState).cycle_index == 2
