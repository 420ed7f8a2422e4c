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
The stair_fix message and the IMU node's handling of it: round trip, and bad input.

hypothesis (derandomised, as ``test_fuzz.py``) feeds ``ImuNode._on_stair_fix`` well-formed
requests, requests with any float in any field, and broken PointCloud2 messages (fields,
sizes, data, stamps). No exception escapes, every message is counted once (``stair_fix_requests``
or ``stair_fix_malformed``), nothing is counted as an internal error, and a request in another
frame than the track's is refused.
"""

import struct

from anfis_elevation_ros.core.building import Building, Floor, save_building, StairEntry, Start
from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.stair_database import CorrectionRequest
from anfis_elevation_ros.nodes.imu_node import ImuNode
from anfis_elevation_ros.nodes.stair_fix_msg import FIX_FIELDS, request_from_msg, request_to_msg
from hypothesis import given, HealthCheck, settings
from hypothesis import strategies as st
import pytest
import rclpy
from rclpy.context import Context
from rclpy.parameter import Parameter
from sensor_msgs.msg import PointField

REQUEST = CorrectionRequest(cycle_index=12, stamp_ns=1_700_000_000_123_456_789, x_m=3.5,
                            y_m=-1.25, entry_x_m=3.9, entry_y_m=-1.0, stairwell='A', floor=-1,
                            direction=-1)
UINT32 = st.integers(0, 2 ** 32 - 1)
FIELD = st.builds(PointField, name=st.one_of(st.sampled_from(FIX_FIELDS), st.text(max_size=8)),
                  offset=st.integers(0, 100), datatype=st.integers(0, 255),
                  count=st.integers(0, 3))
DAMAGE = st.one_of(
    st.tuples(st.just('values'), st.lists(st.floats(), min_size=7, max_size=7)),
    st.tuples(st.just('fields'), st.lists(FIELD, max_size=9)),
    st.tuples(st.just('data'), st.binary(max_size=80)),
    st.tuples(st.just('size'), st.tuples(UINT32, UINT32)),
    st.tuples(st.just('bigendian'), st.booleans()),
    st.tuples(st.just('frame'), st.text(max_size=10)),
    st.tuples(st.just('stamp'), st.tuples(st.integers(-2 ** 31, 2 ** 31 - 1), UINT32)))


def damaged(msg, how):
    """Apply one DAMAGE to a stair_fix message (in place) and return it."""
    kind, arg = how
    if kind == 'values':
        msg.data = struct.pack('<7d', *arg)
    elif kind == 'fields':
        msg.fields = arg
    elif kind == 'data':
        msg.data = arg
    elif kind == 'size':
        msg.width, msg.height = arg
    elif kind == 'bigendian':
        msg.is_bigendian = arg
    elif kind == 'frame':
        msg.header.frame_id = arg
    else:
        msg.header.stamp.sec, msg.header.stamp.nanosec = arg
    return msg


def test_round_trip_keeps_every_value_but_the_stairwell_name():
    msg = request_to_msg(REQUEST, 'map')
    assert msg.header.frame_id == 'map' and [f.name for f in msg.fields] == list(FIX_FIELDS)
    back = request_from_msg(msg)
    assert back == CorrectionRequest(**{**REQUEST.__dict__, 'stairwell': ''})


@pytest.mark.parametrize('index, value', [(4, 0.5), (5, 0.0), (5, 2.0), (6, float('nan')),
                                          (0, float('inf'))])
def test_values_that_are_no_correction_are_refused(index, value):
    msg = request_to_msg(REQUEST, 'map')
    values = list(struct.unpack('<7d', bytes(msg.data)))
    values[index] = value
    msg.data = struct.pack('<7d', *values)
    with pytest.raises(InputError):
        request_from_msg(msg)


@pytest.fixture(scope='module')
def context():
    """Give this module an rclpy context of its own."""
    ctx = Context()
    rclpy.init(context=ctx)
    yield ctx
    rclpy.try_shutdown(context=ctx)


@pytest.fixture(scope='module')
def building_file(tmp_path_factory):
    """Write a building with a start and one stair entry."""
    path = tmp_path_factory.mktemp('building') / 'building.yaml'
    save_building(path, Building(name='b', floors=(Floor(-1, -3.0), Floor(0, 0.0)),
                                 stairs=(StairEntry('A', -1, -1, 3.9, -1.0),),
                                 start=Start(0.0, 0.0, 0, 90.0)))
    return path


def fix_counts(node):
    """Return (requests, malformed, internal errors) of the node's diagnostics."""
    values = {kv.key: kv.value for status in node.diagnostics(0).status for kv in status.values}
    return (int(values['stair_fix_requests']), int(values['stair_fix_malformed']),
            int(values['internal_errors']))


@settings(max_examples=25, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(stream=st.lists(st.tuples(st.booleans(), DAMAGE), min_size=1, max_size=10))
def test_imu_node_counts_any_stair_fix_message_once(context, building_file, stream):
    node = ImuNode(context=context, parameter_overrides=[
        Parameter('persist_state', value=False),
        Parameter('building_file', value=str(building_file))])
    try:
        for k, (is_damaged, how) in enumerate(stream):
            msg = request_to_msg(CorrectionRequest(**{**REQUEST.__dict__, 'stamp_ns': k}), 'map')
            if is_damaged:
                msg = damaged(msg, how)
            try:
                request_from_msg(msg)
                parses = msg.header.frame_id == 'map'
            except InputError:
                parses = False
            requests, malformed, _ = fix_counts(node)
            node._on_stair_fix(msg)
            after = fix_counts(node)
            assert after == (requests + parses, malformed + (not parses), 0)
    finally:
        node.destroy_node()
