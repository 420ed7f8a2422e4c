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
QoS profiles of the nodes' topics: a decision per topic.

- ``imu_qos(depth)``: ``qos_profile_sensor_data`` (best effort, volatile) with a deep queue, so
  that a burst of a 400 Hz IMU waits instead of being dropped while a callback runs.
- ``cycle_history_qos(depth)``: reliable, transient local, keep last ``depth`` (parameter
  ``cycle_history``), for ``gait_cycle`` between the two nodes: an event stream where every
  message counts; a classifier that starts late or restarts gets the cycles it missed (it
  skips those it already counted: each cycle carries its index and stamp).
- ``CYCLE_QOS``: reliable, volatile, depth 100: what tools that only watch ``gait_cycle`` use
  (no history).
- ``LATEST_QOS``: reliable, transient local, depth 1, for "latest state" topics (``elevation``,
  ``stair_mode``, ``floor``, ``foot_odom``): a late subscriber gets the current value at once.
- ``DIAGNOSTICS_QOS``: reliable, volatile, depth 10 (what diagnostic_aggregator expects).
- ``STAIR_FIX_QOS``: reliable, transient local, depth ``STAIR_FIX_HISTORY`` (100), for
  ``stair_fix``, the classifier's stair-entry correction requests to the IMU node: every request
  counts (none is lost), and a restarted IMU node gets again those it may not have applied yet
  (it applies each at most once: ``core/position_fix.py``). A walk enters far fewer stairs
  than that between two restarts.
"""

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

CYCLE_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                       reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.VOLATILE)
LATEST_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                        reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.TRANSIENT_LOCAL)
DIAGNOSTICS_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                             reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.VOLATILE)
STAIR_FIX_HISTORY = 100
STAIR_FIX_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=STAIR_FIX_HISTORY,
                           reliability=ReliabilityPolicy.RELIABLE,
                           durability=DurabilityPolicy.TRANSIENT_LOCAL)


def cycle_history_qos(depth: int) -> QoSProfile:
    """Reliable, transient local, keep last ``depth``: the gait-cycle stream with history."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


def imu_qos(depth: int) -> QoSProfile:
    """``qos_profile_sensor_data`` (best effort, volatile, keep last) with the given depth."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.VOLATILE)
