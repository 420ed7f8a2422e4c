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

"""nav_msgs/Odometry from its CDR bytes, decoded by rosbags: the command centre's track."""

from rosbags.serde import SerdeError

from ..core.errors import InputError
from ..tools.bags import typestore

ODOMETRY = 'nav_msgs/msg/Odometry'


def odometry_from_cdr(data: bytes):
    """
    Return the nav_msgs/Odometry of a serialised message (rosbags' class, same field names).

    The command centre subscribes ``foot_odom_throttle`` with ``raw=True`` and decodes here:
    rclpy's conversion to its Python message (nine objects and two 36-float covariance arrays)
    costs about 150 us per message against about 27 us for rosbags' generated deserializer,
    and at 50 responders x 10 Hz (``foot_odom``, before the throttled track) it was half of
    the command centre's CPU (test/benchmarks/bench_command_centre_dds.py).

    Raises
    ------
    InputError : bytes that are not a nav_msgs/Odometry.

    """
    try:
        return typestore().deserialize_cdr(data, ODOMETRY)
    except SerdeError as err:      # rosbags wraps every decoding error (length, UTF-8, ...)
        raise InputError(f'not a {ODOMETRY} message ({len(data)} bytes): {err}') from None
