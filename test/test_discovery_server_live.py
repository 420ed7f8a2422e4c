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
The incident network on loopback: a Fast DDS discovery server, three responders, the centre.

Every participant but one has ``ROS_DISCOVERY_SERVER`` set: they find each other only through
the server (a Fast DDS client sends no multicast discovery). The outsider, ``/outsider``,
runs with the plain multicast discovery of the same domain on the same machine: the command
centre must not see it, which shows that its discovery goes through the server alone.
"""

import socket

from anfis_elevation_ros.sim.responders import ResponderPlan
from anfis_elevation_ros.tools.incident_demo import write_incident
from incident_support import Processes, START_TIMEOUT_S, wait_state

PLANS = tuple(ResponderPlan(f'/ds{k}', (0,), 1.0, 30 + k) for k in (1, 2, 3))


def free_udp_port() -> int:
    """Return a UDP port of the loopback that nothing listens on now."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.bind(('127.0.0.1', 0))
        return sock.getsockname()[1]


def test_three_responders_and_the_centre_through_a_discovery_server(tmp_path):
    port = free_udp_port()
    building, bags = write_incident(tmp_path, PLANS)
    through_server = {'ROS_DISCOVERY_SERVER': f'127.0.0.1:{port}',
                      'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST'}
    with Processes(tmp_path) as procs:
        procs.start('discovery_server', 'discovery-server', '--address', '127.0.0.1',
                    '--port', port)
        procs.start('command_centre', 'command-centre', '--building', building, '--port', 0,
                    env_changes=through_server)
        url, _ = procs.url_and_token()
        procs.start('outsider', 'run', '--namespace', '/outsider', '--ros-args', '-p',
                    f'state_dir:={tmp_path / "state"}', drop=('ROS_DISCOVERY_SERVER',))
        for plan in PLANS:
            name = plan.namespace.strip('/')
            procs.start(name, 'run', '--namespace', plan.namespace, '--building', building,
                        '--ros-args', '-p', f'state_dir:={tmp_path / "state"}',
                        env_changes=through_server)
            procs.start(f'play_{name}', 'play', bags[plan.namespace], '--topic',
                        f'{plan.namespace}/imu/data', '--rate', 2, '--wait-s', START_TIMEOUT_S,
                        env_changes=through_server)
        for plan in PLANS:
            name = plan.namespace.strip('/')
            assert procs.wait(f'play_{name}', START_TIMEOUT_S + 60) == 0, procs.log(name)
        on_map = wait_state(
            url, lambda s: {r['id'] for r in s['responders'] if r['x_m'] is not None} ==
            {p.namespace for p in PLANS}, 30.0, 'the three responders on the map')
        assert procs.log('outsider').count('running') == 1          # it was up all along
        assert all(r['floor'] == 0 for r in on_map['responders'])
        assert '/outsider' not in {r['id'] for r in on_map['responders']}
        assert 'responder /outsider' not in procs.log('command_centre')
        assert procs.stop('command_centre') == 0, procs.log('command_centre')
        assert procs.stop('discovery_server') == 0, procs.log('discovery_server')
