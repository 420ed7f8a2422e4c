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
The command centre node: responder discovery, the feeds into the Incident, bad input.

The pure helpers are checked alone; the node itself in one process with a fake responder
(publishers under /ff7 and /ff8, as ``run --namespace`` has them) over real DDS.
"""

from dataclasses import fields
import math
import threading

from anfis_elevation_ros.command_centre.alarms import AlarmParams
from anfis_elevation_ros.core.params import ALARM_PREFIX, COMMAND_CENTRE_NODE, node_specs
from anfis_elevation_ros.nodes.command_centre_node import level_of, responder_of_status
from anfis_elevation_ros.nodes.command_centre_node import responder_of_topic, TravelHeading
from anfis_elevation_ros.nodes.command_centre_node import yaw_deg
from live_support import wait_for
import pytest

POINT = ['geometry_msgs/msg/PointStamped']


def test_responders_are_the_namespaces_publishing_elevation():
    assert responder_of_topic('/ff1/elevation', POINT) == '/ff1'
    assert responder_of_topic('/team/a/elevation', POINT) == '/team/a'
    assert responder_of_topic('/elevation', POINT) is None            # root: no name
    assert responder_of_topic('/ff1/floor', ['std_msgs/msg/Int32']) is None
    assert responder_of_topic('/ff1/elevation', ['std_msgs/msg/String']) is None
    assert responder_of_topic('/ff1/elevation_x', POINT) is None


def test_a_status_belongs_to_the_responder_whose_node_names_it():
    known = {'/ff1', '/ff2'}
    assert responder_of_status('/ff1/imu_node: IMU input', known) == '/ff1'
    assert responder_of_status('/ff2/classifier_node: elevation', known) == '/ff2'
    assert responder_of_status('/ff3/imu_node: IMU input', known) is None
    assert responder_of_status('/imu_node: IMU input', known) is None
    assert responder_of_status('no colon here', known) is None
    assert level_of(b'\x02') == 2 and level_of(1) == 1


def test_yaw_and_direction_of_travel():
    half = math.sqrt(0.5)
    assert yaw_deg(1.0, 0.0, 0.0, 0.0) == 0.0
    assert yaw_deg(half, 0.0, 0.0, half) == pytest.approx(90.0)       # x axis to north
    heading = TravelHeading(base_m=0.5)
    assert heading.update(0.0, 0.0, 33.0) == 33.0                     # not moved: IMU yaw
    assert heading.update(0.0, 0.3, 33.0) == 33.0
    assert heading.update(0.0, 0.6, 33.0) == pytest.approx(90.0)      # walked north
    assert heading.update(math.nan, 0.6, 33.0) == 33.0                # refused, anchor kept
    assert heading.update(-0.6, 0.6, 0.0) == pytest.approx(180.0)     # then west


def test_alarm_parameters_mirror_the_incident_alarm_params():
    """Each AlarmParams field is a parameter alarm.<field> with the same default."""
    specs = node_specs(COMMAND_CENTRE_NODE)
    alarm = {name[len(ALARM_PREFIX):]: spec.default for name, spec in specs.items()
             if name.startswith(ALARM_PREFIX)}
    defaults = AlarmParams()
    assert alarm == {f.name: getattr(defaults, f.name) for f in fields(AlarmParams)}


def test_command_centre_options_become_parameters(tmp_path):
    """An option given overrides the parameter file; one not given leaves it alone."""
    import argparse

    from anfis_elevation_ros.tools.command_centre import ros_init_args

    args = argparse.Namespace(params=tmp_path / 'p.yaml', building=None, host=None, port=0,
                              tls_cert=None, tls_key=None, insecure=False,
                              ros_argv=['--ros-args', '-p', 'tick_rate_hz:=2.0'])
    argv = ros_init_args(args)
    assert argv[:5] == ['command_centre', '--ros-args', '--params-file',
                        str(tmp_path / 'p.yaml'), '--']
    assert 'port:=0' in argv and not any(a.startswith('host:=') for a in argv)
    assert argv[-3:] == ['--ros-args', '-p', 'tick_rate_hz:=2.0']


@pytest.fixture()
def centre_and_responder():
    """Spin a CommandCentreNode and a node publishing as two responders in a thread."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    from anfis_elevation_ros.nodes.command_centre_node import CommandCentreNode

    rclpy.init(args=['test', '--ros-args', '-p', 'discovery_period_s:=0.2'])
    executor = SingleThreadedExecutor()
    centre = CommandCentreNode()
    responder = rclpy.create_node('fake_responder')
    executor.add_node(centre)
    executor.add_node(responder)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        yield centre, responder
    finally:
        executor.shutdown()
        centre.destroy_node()
        responder.destroy_node()
        rclpy.try_shutdown()
        thread.join(timeout=5.0)


def test_node_finds_responders_and_feeds_the_incident(centre_and_responder):
    """Late start, all feeds, a NaN position refused and counted, the other responder intact."""
    from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
    from geometry_msgs.msg import PointStamped
    from nav_msgs.msg import Odometry
    from rclpy.serialization import serialize_message
    from std_msgs.msg import Bool, Int32, Int32MultiArray, Int8

    from anfis_elevation_ros.nodes.qos import DIAGNOSTICS_QOS, LATEST_QOS

    centre, node = centre_and_responder
    pubs = {}
    for ns in ('/ff7', '/ff8'):
        pubs[ns] = {name: node.create_publisher(msg_type, f'{ns}/{name}', LATEST_QOS)
                    for msg_type, name in ((PointStamped, 'elevation'), (Int32, 'floor'),
                                           (Bool, 'floor_certain'), (Int8, 'stair_mode'),
                                           (Int32MultiArray, 'floor_range'),
                                           (Odometry, 'foot_odom_throttle'))}
    diagnostics = node.create_publisher(DiagnosticArray, '/diagnostics', DIAGNOSTICS_QOS)
    point = PointStamped()
    point.header.stamp.sec = 5
    point.point.x, point.point.y, point.point.z = 1.0, 2.0, 3.06
    # Published before the centre subscribes: transient local delivers them on discovery.
    pubs['/ff7']['elevation'].publish(point)
    pubs['/ff7']['floor'].publish(Int32(data=1))
    pubs['/ff7']['floor_certain'].publish(Bool(data=True))
    pubs['/ff7']['floor_range'].publish(Int32MultiArray(data=[1, 1]))
    pubs['/ff7']['stair_mode'].publish(Int8(data=1))
    odom = Odometry()
    odom.header.stamp.sec = 6
    odom.pose.pose.position.x, odom.pose.pose.position.y = 1.5, 2.0
    odom.pose.pose.orientation.w = 1.0
    odom.pose.covariance[0] = odom.pose.covariance[7] = 0.08
    pubs['/ff7']['foot_odom_throttle'].publish(odom)

    def responder(rid):
        return next((r for r in centre.incident.snapshot()['responders'] if r['id'] == rid),
                    None)

    assert wait_for(lambda: centre.responders == {'/ff7', '/ff8'}, 10.0), centre.responders

    # Each topic's latest message arrives on its own: wait for every feed.
    def ff7_state():
        r = responder('/ff7') or {}
        return tuple(r.get(k) for k in ('x_m', 'floor', 'floor_certain', 'mode', 'z_m',
                                        'floor_range'))

    assert wait_for(lambda: ff7_state() == (1.5, 1, True, 1, 3.06, [1, 1]), 10.0), \
        responder('/ff7')
    ff7 = responder('/ff7')
    assert (ff7['floor'], ff7['floor_certain'], ff7['mode'], ff7['z_m']) == (1, True, 1, 3.06)
    assert ff7['sigma_xy_m'] == pytest.approx(0.4)          # sqrt(0.08 + 0.08)
    status = DiagnosticStatus(level=b'\x02', name='/ff7/imu_node: IMU input',
                              message='no IMU message for 3 s')
    other = DiagnosticStatus(level=b'\x02', name='/elsewhere/node: x', message='not ours')
    diagnostics.publish(DiagnosticArray(status=[status, other]))
    assert wait_for(lambda: any(a['kind'] == 'diagnostics_error'
                                for a in responder('/ff7')['alarms']), 10.0), responder('/ff7')
    bad = PointStamped()
    bad.point.x = math.nan
    pubs['/ff8']['elevation'].publish(bad)
    assert wait_for(lambda: sum(centre.incident.snapshot()['rejected'].values()) == 1, 10.0)
    assert responder('/ff7')['x_m'] == 1.5 and responder('/ff7')['floor'] == 1
    # The track is decoded from its bytes in the node: bytes that are no Odometry are counted.
    pubs['/ff8']['foot_odom_throttle'].publish(serialize_message(odom)[:100])
    assert wait_for(lambda: centre.rejected == 1, 10.0), centre.rejected
    assert responder('/ff7')['x_m'] == 1.5


@pytest.mark.parametrize('args, message', [
    (['--building', 'BAD'], 'floors'),                   # a building file that does not parse
    (['--host', '0.0.0.0', '--port', '0'], 'refusing to serve 0.0.0.0 over plain HTTP'),
    (['--tls-cert', 'cert.pem', '--port', '0'], 'tls_cert_file and tls_key_file go together'),
])
def test_command_centre_refuses_to_start_in_one_line(tmp_path, args, message):
    """A bad building, the LAN without TLS, half a TLS pair: exit code 1, one line, why."""
    import subprocess

    from live_support import cli, cli_env, PACKAGE_ROOT

    bad = tmp_path / 'bad.yaml'
    bad.write_text('format: anfis_elevation_ros/building\nversion: 1\nfloors: high\n')
    args = [str(bad) if a == 'BAD' else a for a in args]
    done = subprocess.run(cli('command-centre', *args), env=cli_env(), cwd=PACKAGE_ROOT,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, done.stderr
    errors = [line for line in done.stderr.splitlines() if line.startswith('error:')]
    assert len(errors) == 1 and message in errors[0], done.stderr
    assert 'Traceback' not in done.stderr
