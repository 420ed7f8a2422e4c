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

from sensor_msgs.msg import PointCloud2

from .float64_point import Float64Point
from .stamps import stamp_to_ns
from ..core.errors import InputError
from ..core.stair_database import CorrectionRequest

FIX_FIELDS = ('x', 'y', 'entry_x', 'entry_y', 'floor', 'direction', 'cycle_index')
_FIX_POINT = Float64Point('stair_fix', FIX_FIELDS)


def request_to_msg(request: CorrectionRequest, frame_id: str) -> PointCloud2:
    """PointCloud2 of one correction request (layout in the module docstring)."""
    return _FIX_POINT.to_msg(request.stamp_ns, frame_id, (
        request.x_m, request.y_m, request.entry_x_m, request.entry_y_m, float(request.floor),
        float(request.direction), float(request.cycle_index)))


def request_from_msg(msg) -> CorrectionRequest:
    """
    Decode a stair-fix PointCloud2, checking its layout and values.

    Raises
    ------
    InputError : not one point with exactly ``FIX_FIELDS`` as little-endian FLOAT64, or values
        that are not a correction (non-finite position, direction not +-1, floor or index not
        whole numbers).

    """
    x, y, entry_x, entry_y, floor, direction, index = _FIX_POINT.values_from_msg(msg)
    for name, value in (('floor', floor), ('direction', direction), ('cycle_index', index)):
        if not (math.isfinite(value) and value == int(value) and abs(value) < 2 ** 53):
            raise InputError(f'stair_fix message has {name} {value!r}, not a whole number')
    return CorrectionRequest(cycle_index=int(index), stamp_ns=stamp_to_ns(msg.header.stamp),
                             x_m=x, y_m=y, entry_x_m=entry_x, entry_y_m=entry_y, stairwell='',
                             floor=int(floor), direction=int(direction))
