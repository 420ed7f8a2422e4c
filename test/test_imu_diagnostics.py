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
"""The IMU node's diagnostic statuses from its counters, without DDS (nodes/imu_diagnostics.py)."""

from anfis_elevation_ros.core.input_gate import GateParams, InputGate
from anfis_elevation_ros.core.navigator import NavigatorStatus
from anfis_elevation_ros.nodes.imu_diagnostics import input_status, InputPeriod
from anfis_elevation_ros.nodes.imu_diagnostics import navigator_status
from diagnostic_msgs.msg import DiagnosticStatus
import numpy as np

SECOND_NS = 1_000_000_000


def _feed(gate, n, start_ns=0, dt_ns=10_000_000):
    acc, gyr = np.array([0.0, 0.0, 9.81]), np.zeros(3)
    for k in range(n):
        assert gate.check(start_ns + k * dt_ns, acc, gyr, 'imu_link') is None


def _input(period, gate, status, received):
    return input_status('/imu_node', 'imu_link', '/imu/data', period, gate, status, received,
                        0, 0)


def test_levels_and_rates_are_over_the_period():
    gate, status = InputGate(GateParams()), NavigatorStatus()
    periods = InputPeriod(gate, 0)
    first = periods.close(SECOND_NS, 0, gate, status)
    assert _input(first, gate, status, 0).level == DiagnosticStatus.STALE

    _feed(gate, 100)
    status.samples, status.stance_samples = 100, 40
    status.zaru_samples, status.rail_filled_samples, status.relaxed_stances = 12, 3, 7
    status.late_stances, status.late_cycles = 2, 1
    second = periods.close(3 * SECOND_NS, 100, gate, status)
    assert second.period_s == 2.0 and second.received == 100
    ok = _input(second, gate, status, 100)
    values = {kv.key: kv.value for kv in ok.values}
    assert ok.level == DiagnosticStatus.OK and ok.name == '/imu_node: IMU input'
    assert values['input_rate_hz'] == '50' and values['imu_topic'] == '/imu/data'
    nav = navigator_status('/imu_node', 'imu_link', second, status, 0, 0, 0, 0, {'x': 1})
    nav_values = {kv.key: kv.value for kv in nav.values}
    assert nav.level == DiagnosticStatus.WARN and nav.message == 'waiting for the first stance'
    assert nav_values['stance_fraction'] == '0.4' and nav_values['x'] == '1'
    assert (nav_values['zaru_samples'], nav_values['rail_filled_samples'],
            nav_values['relaxed_stances'], nav_values['late_stances'],
            nav_values['late_cycles']) == ('12', '3', '7', '2', '1')

    # 98 samples navigated and 2 lost in transit in this period: 2 % lost
    status.samples, status.missing_samples = 198, 2
    lossy = _input(periods.close(4 * SECOND_NS, 198, gate, status), gate, status, 198)
    assert lossy.level == DiagnosticStatus.WARN and lossy.message.startswith('2.0 % of samples')


def test_navigator_problems_in_order_of_severity():
    gate, status = InputGate(GateParams()), NavigatorStatus(initialised=True)
    period = InputPeriod(gate, 0).close(SECOND_NS, 0, gate, status)
    for counts, level, message in (
            ((1, 1, 1, 1), DiagnosticStatus.ERROR, '1 internal errors'),
            ((0, 2, 1, 0), DiagnosticStatus.WARN, '2 failed state writes'),
            ((0, 0, 1, 0), DiagnosticStatus.WARN, 'stair-entry corrections: 1 late, 0 malformed'),
            ((0, 0, 0, 0), DiagnosticStatus.OK, 'navigating')):
        nav = navigator_status('/ff1/imu_node', 'imu', period, status, *counts, {})
        assert (nav.level, nav.message) == (level, message)
        assert nav.name == '/ff1/imu_node: foot navigator'
