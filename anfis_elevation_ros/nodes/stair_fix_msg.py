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
The stair-fix message: a stair-entry correction request as a one-point PointCloud2.

The classifier node publishes one on ``stair_fix`` for every stair entry it associated with the
building's stair-position database (``core/stair_database.py``); the IMU node applies each
exactly once (``core/position_fix.py``). Like the gait-cycle message (``gait_cycle_msg.py``) it
is a one-point cloud: stamped, framed, its fields named. ``header.stamp`` is the stamp of the
gait cycle that entered the stairs (the request's identity, and the time the correction is due
from); ``header.frame_id`` the map frame. Fields, all FLOAT64 (``FIX_FIELDS``):

=====  ================  ===================================================================
 off   field             meaning
=====  ================  ===================================================================
   0   ``x``             the cycle's position x (map frame), m
   8   ``y``             its y, m
  16   ``entry_x``       the database entry's x (centre of the first step), m
  24   ``entry_y``       its y, m
  32   ``floor``         the floor the entry lies on
  40   ``direction``     +1 up, -1 down
  48   ``cycle_index``   index of the gait cycle (for logs)
=====  ================  ===================================================================

The stairwell's name stays in the classifier's log; the IMU node does not need it.
"""

import math
import struct

from sensor_msgs.msg import PointCloud2, PointField

from .stamps import ns_to_stamp, stamp_to_ns
from ..core.errors import InputError
from ..core.stair_database import CorrectionRequest

FIX_FIELDS = ('x', 'y', 'entry_x', 'entry_y', 'floor', 'direction', 'cycle_index')
_FIX_STRUCT = struct.Struct('<' + 'd' * len(FIX_FIELDS))
_FIX_LAYOUT = tuple((name, 8 * i, PointField.FLOAT64, 1) for i, name in enumerate(FIX_FIELDS))


def request_to_msg(request: CorrectionRequest, frame_id: str) -> PointCloud2:
    """PointCloud2 of one correction request (layout in the module docstring)."""
    msg = PointCloud2()
    msg.header.stamp = ns_to_stamp(request.stamp_ns)
    msg.header.frame_id = frame_id
    msg.height = 1
    msg.width = 1
    msg.fields = [PointField(name=name, offset=offset, datatype=datatype, count=count)
                  for name, offset, datatype, count in _FIX_LAYOUT]
    msg.is_bigendian = False
    msg.point_step = _FIX_STRUCT.size
    msg.row_step = _FIX_STRUCT.size
    msg.data = _FIX_STRUCT.pack(request.x_m, request.y_m, request.entry_x_m, request.entry_y_m,
                                float(request.floor), float(request.direction),
                                float(request.cycle_index))
    msg.is_dense = True
    return msg


def request_from_msg(msg) -> CorrectionRequest:
    """
    Decode a stair-fix PointCloud2, checking its layout and values.

    Raises
    ------
    InputError : not one point with exactly ``FIX_FIELDS`` as little-endian FLOAT64, or values
        that are not a correction (non-finite position, direction not +-1, floor or index not
        whole numbers).

    """
    layout = tuple((f.name, f.offset, f.datatype, f.count) for f in msg.fields)
    if layout != _FIX_LAYOUT or msg.is_bigendian or msg.width * msg.height != 1 \
            or msg.point_step != _FIX_STRUCT.size or len(msg.data) != _FIX_STRUCT.size:
        raise InputError(f'stair_fix message does not have the expected layout (one point, '
                         f'fields {", ".join(FIX_FIELDS)} as FLOAT64); got fields '
                         f'{[f.name for f in msg.fields]}, {msg.width}x{msg.height} points, '
                         f'{len(msg.data)} bytes')
    x, y, entry_x, entry_y, floor, direction, index = _FIX_STRUCT.unpack(bytes(msg.data))
    for name, value in (('floor', floor), ('direction', direction), ('cycle_index', index)):
        if not (math.isfinite(value) and value == int(value) and abs(value) < 2 ** 53):
            raise InputError(f'stair_fix message has {name} {value!r}, not a whole number')
    return CorrectionRequest(cycle_index=int(index), stamp_ns=stamp_to_ns(msg.header.stamp),
                             x_m=x, y_m=y, entry_x_m=entry_x, entry_y_m=entry_y, stairwell='',
                             floor=int(floor), direction=int(direction))
