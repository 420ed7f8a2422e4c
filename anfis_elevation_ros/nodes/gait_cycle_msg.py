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
The gait-cycle message: one GaitCycle as a sensor_msgs/PointCloud2 of one point.

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
  80   ``walk_id``           identity of the walk, 1 .. 2^31 - 1 (kept by a resumed restart,
                            new when the IMU node starts fresh: ``core/state.py``)
  88   ``outage``            1.0 for a cycle lost while the IMU node was down (then invalid,
                            its stamp interpolated: ``core/outage.py``), else 0.0
  96   ``acc_x_min_mps2``    then the eleven motion features of ``core/motion_features.py``,
 ...   ...                   in ``MOTION_FEATURE_NAMES`` order, up to offset 176
=====  ====================  ==============================================================

``header.stamp`` is the stamp of the IMU sample that closed the cycle; ``header.frame_id`` the
odometry frame; height = width = 1, point_step = row_step = 184, little endian, ``is_dense``
false when a value is not finite.
"""

from dataclasses import dataclass
import math

import numpy as np
from sensor_msgs.msg import PointCloud2

from .float64_point import Float64Point
from .stamps import stamp_to_ns
from ..core.errors import InputError
from ..core.gait import FEATURE_NAMES, PATENT_FEATURE_NAMES
from ..core.state import MAX_WALK_ID

# The motion features come after walk_id and outage, so the first fields keep their offsets.
CYCLE_FIELDS = ('x', 'y', 'z', 'valid') + PATENT_FEATURE_NAMES + ('cycle_index', 'walk_id',
                                                                  'outage') \
    + FEATURE_NAMES[len(PATENT_FEATURE_NAMES):]
_INDEX_FIELD = CYCLE_FIELDS.index('cycle_index')
_MOTION_FIELD = CYCLE_FIELDS.index('outage') + 1


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
    features : (N_FEATURES,) array
        In ``FEATURE_NAMES`` order.
    index : int
        Index of the cycle (1, 2, ...).
    walk_id : int
        Identity of the walk the cycle belongs to (``core/state.py``, ``new_walk_id``).
    outage : bool
        True for a cycle lost while the IMU node was down (then invalid).

    """

    stamp_ns: int
    x_m: float
    y_m: float
    z_m: float
    valid: bool
    features: np.ndarray
    index: int
    walk_id: int
    outage: bool = False


_CYCLE_POINT = Float64Point('gait_cycle', CYCLE_FIELDS)


def cycle_to_msg(cycle, frame_id: str, index: int, walk_id: int,
                 outage: bool = False) -> PointCloud2:
    """
    PointCloud2 of one GaitCycle with its index and walk (layout in the module docstring).

    A cycle with a non-finite value is sent as invalid (valid = 0), never classified.
    """
    position = [float(v) for v in cycle.pos_n]
    features = [float(v) for v in cycle.features]
    finite = all(math.isfinite(v) for v in position + features)
    values = (*position, 1.0 if cycle.valid and finite else 0.0, *features[:_INDEX_FIELD - 4],
              float(index), float(walk_id), 1.0 if outage else 0.0,
              *features[_INDEX_FIELD - 4:])
    return _CYCLE_POINT.to_msg(cycle.stamp_ns, frame_id, values, is_dense=finite)


def cycle_from_msg(msg) -> CycleMessage:
    """
    Decode a gait-cycle PointCloud2, checking its layout.

    Raises
    ------
    InputError : not one point with exactly ``CYCLE_FIELDS`` as little-endian FLOAT64.

    """
    values = _CYCLE_POINT.values_from_msg(msg)
    index, walk_id, outage = values[_INDEX_FIELD:_MOTION_FIELD]
    if not (math.isfinite(index) and index == int(index) and 1 <= index < 2 ** 53):
        raise InputError(f'gait_cycle message has cycle_index {index!r}, not a count')
    if not (math.isfinite(walk_id) and walk_id == int(walk_id) and 1 <= walk_id <= MAX_WALK_ID):
        raise InputError(f'gait_cycle message has walk_id {walk_id!r}, not a walk identity')
    if outage not in (0.0, 1.0):
        raise InputError(f'gait_cycle message has outage {outage!r}, not 0 or 1')
    return CycleMessage(stamp_ns=stamp_to_ns(msg.header.stamp), x_m=values[0], y_m=values[1],
                        z_m=values[2], valid=values[3] == 1.0,
                        features=np.array(values[4:_INDEX_FIELD] + values[_MOTION_FIELD:],
                                          dtype=float), index=int(index),
                        walk_id=int(walk_id), outage=outage == 1.0)
