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

"""nav_msgs/Odometry decoded from its CDR bytes (the command centre's foot_odom)."""

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.nodes.odometry_msg import odometry_from_cdr
import pytest


def _odometry():
    from nav_msgs.msg import Odometry

    msg = Odometry()
    msg.header.stamp.sec, msg.header.stamp.nanosec = 1_796_000_000, 123_456_789
    msg.header.frame_id, msg.child_frame_id = 'map', 'ff1/imu_link'
    msg.pose.pose.position.x, msg.pose.pose.position.y, msg.pose.pose.position.z = 1.5, -2.0, 3.0
    q = msg.pose.pose.orientation
    q.w, q.x, q.y, q.z = 0.5, 0.5, -0.5, 0.5
    msg.pose.covariance = [0.01 * k for k in range(36)]
    msg.twist.twist.linear.x = 7.0
    return msg


def test_decodes_what_rclpy_serialises():
    from rclpy.serialization import serialize_message

    msg = _odometry()
    decoded = odometry_from_cdr(serialize_message(msg))
    stamp = decoded.header.stamp
    assert (stamp.sec, stamp.nanosec) == (1_796_000_000, 123_456_789)
    assert decoded.child_frame_id == 'ff1/imu_link'
    p, q = decoded.pose.pose.position, decoded.pose.pose.orientation
    assert (p.x, p.y, p.z, q.w, q.x, q.y, q.z) == (1.5, -2.0, 3.0, 0.5, 0.5, -0.5, 0.5)
    assert list(decoded.pose.covariance) == list(msg.pose.covariance)
    assert decoded.twist.twist.linear.x == 7.0


@pytest.mark.parametrize('cut', [
    lambda b: b[:100],                        # truncated
    lambda b: b'',                            # empty
    lambda b: b'\x00\x07\x00\x00' + b[4:],    # unknown encapsulation
    lambda b: b[:12] + b'\xff\xff\xff\x7f' + b[16:],  # frame_id length past the end
])
def test_bytes_that_are_no_odometry_raise_input_error(cut):
    from rclpy.serialization import serialize_message

    with pytest.raises(InputError, match='not a nav_msgs/msg/Odometry message'):
        odometry_from_cdr(cut(serialize_message(_odometry())))
