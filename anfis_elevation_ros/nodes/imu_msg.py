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

"""sensor_msgs/Imu to (stamp_ns, acc_b, gyr_b, frame_id), from the message or its CDR bytes."""

import struct

from rclpy.serialization import deserialize_message
from sensor_msgs.msg import Imu

from ..core.errors import InputError

_CDR_LE = b'\x00\x01'                    # encapsulation: plain CDR, little endian
_CDR_HEADER = struct.Struct('<iII')        # stamp sec, nanosec, frame_id length
_IMU_DOUBLES_SIZE = 37 * 8
_VECTOR3 = struct.Struct('<3d')
_GYR_OFFSET = 13 * 8                       # after orientation (4) and its covariance (9)
_ACC_OFFSET = 25 * 8                       # after angular_velocity (3) and its covariance (9)


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
