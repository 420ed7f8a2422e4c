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

"""diagnostic_msgs/DiagnosticStatus of a node's figures."""

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue


def diagnostic_status(name: str, level: bytes, message: str, hardware_id: str,
                      values: dict) -> DiagnosticStatus:
    """Build a DiagnosticStatus with one KeyValue per item (floats: 6 significant digits)."""
    def text(value):
        if isinstance(value, bool):
            return 'true' if value else 'false'
        if isinstance(value, float):
            return f'{value:.6g}'
        return str(value)

    return DiagnosticStatus(level=level, name=name, message=message, hardware_id=hardware_id,
                            values=[KeyValue(key=k, value=text(v)) for k, v in values.items()])
