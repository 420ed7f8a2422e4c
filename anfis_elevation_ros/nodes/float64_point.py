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
One point of named little-endian FLOAT64 fields carried in a sensor_msgs/PointCloud2.

The package's own records (``gait_cycle``, ``stair_fix``) travel this way so that standard
tools (``ros2 topic echo``, rosbag, PlotJuggler) can read them without a custom message
package. ``Float64Point`` holds one record's layout, packs it, and unpacks it only when the
message has exactly that layout.
"""

import struct

from sensor_msgs.msg import PointCloud2, PointField

from .stamps import ns_to_stamp
from ..core.errors import InputError


class Float64Point:
    """The layout of one record: ``field_names`` at offsets 0, 8, 16, ... as FLOAT64."""

    def __init__(self, topic: str, field_names):
        self.topic = topic
        self.field_names = tuple(field_names)
        self._struct = struct.Struct('<' + 'd' * len(self.field_names))
        self._layout = tuple((name, 8 * i, PointField.FLOAT64, 1)
                             for i, name in enumerate(self.field_names))

    def to_msg(self, stamp_ns: int, frame_id: str, values, is_dense: bool = True) -> PointCloud2:
        """PointCloud2 of one point holding ``values`` in field order."""
        msg = PointCloud2()
        msg.header.stamp = ns_to_stamp(stamp_ns)
        msg.header.frame_id = frame_id
        msg.height = 1
        msg.width = 1
        msg.fields = [PointField(name=name, offset=offset, datatype=datatype, count=count)
                      for name, offset, datatype, count in self._layout]
        msg.is_bigendian = False
        msg.point_step = self._struct.size
        msg.row_step = self._struct.size
        msg.data = self._struct.pack(*values)
        msg.is_dense = is_dense
        return msg

    def values_from_msg(self, msg) -> tuple:
        """
        Return the point's values in field order.

        Raises
        ------
        InputError : not one point with exactly these fields as little-endian FLOAT64.

        """
        layout = tuple((f.name, f.offset, f.datatype, f.count) for f in msg.fields)
        if layout != self._layout or msg.is_bigendian or msg.width * msg.height != 1 \
                or msg.point_step != self._struct.size or len(msg.data) != self._struct.size:
            raise InputError(f'{self.topic} message does not have the expected layout (one '
                             f'point, fields {", ".join(self.field_names)} as FLOAT64); got '
                             f'fields {[f.name for f in msg.fields]}, {msg.width}x{msg.height} '
                             f'points, {len(msg.data)} bytes')
        return self._struct.unpack(bytes(msg.data))


__all__ = ['Float64Point']
