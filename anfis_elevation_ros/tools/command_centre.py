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
``command-centre`` subcommand: the incident map of every responder, one process.

An rclpy node (``nodes/command_centre_node.py``) finds the responders on the DDS domain (every
namespace publishing ``elevation``) and feeds their floor, position, stair mode and
diagnostics to the incident model; the web server (``command_centre/web.py``) serves the page
from a thread. The node spins in rclpy's EventsExecutor: 50 responders over DDS cost 20 % of
one core with it against 27 % with the SingleThreadedExecutor
(test/benchmarks/bench_command_centre_dds.py). At start the command prints the page's URL
and the session token that acknowledging an alarm, evacuation and roll call need (a new one
each start). Stop it with Ctrl-C (SIGINT) or SIGTERM.

The page is served on the loopback unless ``--host`` says otherwise; any other address needs
``--tls-cert`` and ``--tls-key`` (HTTPS) or, on a closed network, ``--insecure``. The
options set the node's parameters (``command_centre`` in config/params.yaml), which
``--params YAML`` or ``--ros-args -p name:=value`` may also give; an option given wins.

With ``ROS_DISCOVERY_SERVER`` set (the incident network, see ``discovery-server``), the
command centre is a Fast DDS "super client" (``ROS_SUPER_CLIENT=TRUE`` unless set): a plain
client learns only the topics it subscribes to, and the centre must see every responder's.

Example: ``python -m anfis_elevation_ros command-centre --building tower.yaml``
"""

import argparse
import os
from pathlib import Path
import secrets
import sys
import threading

from ..core.errors import InputError

TOKEN_BYTES = 18          # 24 URL-safe characters, 144 bits


def ros_init_args(args) -> list:
    """Return rclpy.init's argument list: the parameter file, the options, the user's args."""
    argv = ['command_centre']
    if args.params is not None:
        argv += ['--ros-args', '--params-file', str(args.params), '--']
    overrides = {'building_file': args.building and Path(args.building).resolve(),
                 'host': args.host, 'port': args.port,
                 'tls_cert_file': args.tls_cert and Path(args.tls_cert).resolve(),
                 'tls_key_file': args.tls_key and Path(args.tls_key).resolve(),
                 'insecure': 'true' if args.insecure else None}
    for name, value in overrides.items():
        if value is not None:
            argv += ['--ros-args', '-p', f'{name}:={value}', '--']
    return argv + list(getattr(args, 'ros_argv', []))


def serve(node, token: str):
    """Build the web server of the node's incident from its parameters; return it."""
    from ..command_centre.web import make_server, tls_context_from_files

    values = node.values
    tls = None
    if values['tls_cert_file']:
        try:
            tls = tls_context_from_files(values['tls_cert_file'], values['tls_key_file'])
        except (OSError, ValueError) as err:
            raise InputError(f"cannot use the TLS certificate {values['tls_cert_file']} and "
                             f"key {values['tls_key_file']}: {err}") from None
    try:
        return make_server(node.incident, values['host'], values['port'], token, tls,
                           insecure=values['insecure'])
    except ValueError as err:
        raise InputError(str(err)) from None


def run_command_centre(args) -> int:
    """Start the node and the web server, spin until SIGINT/SIGTERM; return the exit code."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    from ..core.building import load_building
    from ..core.params import load_params_yaml
    from ..nodes.command_centre_node import CommandCentreNode
    from ..nodes.spin import init_without_signal_handlers, Spinner

    if args.params is not None:
        load_params_yaml(args.params)          # clear errors before ROS sees the file
    if args.building is not None:
        load_building(args.building)
    if os.environ.get('ROS_DISCOVERY_SERVER'):
        os.environ.setdefault('ROS_SUPER_CLIENT', 'TRUE')
    token = secrets.token_urlsafe(TOKEN_BYTES)
    init_without_signal_handlers(ros_init_args(args))
    node = server = None
    code = 0
    spinner = Spinner('events')
    spinner.handle_signals()
    try:
        node = CommandCentreNode()
        server = serve(node, token)
        threading.Thread(target=server.serve_forever, kwargs={'poll_interval': 0.2},
                         name='web', daemon=True).start()
        spinner.add_node(node)
        print(f'command-centre: {server.url}  (pid {os.getpid()}; Ctrl-C to stop)\n'
              f'command-centre: session token {token}', flush=True)
        spinner.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except InputError as err:
        print(f'error: cannot start the command centre: {err}', file=sys.stderr)
        code = 1
    finally:
        if server is not None:
            server.shutdown()
            server.server_close()
        spinner.shutdown()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return code


def add_parser(subparsers):
    """Register the ``command-centre`` subcommand."""
    parser = subparsers.add_parser(
        'command-centre', help="the incident map: every responder's floor, track and alarms",
        description=__doc__.strip().split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--building', type=Path, default=None, metavar='FILE',
                        help='building file of the incident (floors, outlines, stairs)')
    parser.add_argument('--host', default=None,
                        help='address to serve the page on (parameter default: 127.0.0.1)')
    parser.add_argument('--port', type=int, default=None,
                        help='TCP port of the page (parameter default: 8088; 0 = any free)')
    parser.add_argument('--insecure', action='store_true',
                        help='allow plain HTTP on an address other than the loopback')
    parser.add_argument('--tls-cert', type=Path, default=None, metavar='PEM',
                        help='certificate: serve HTTPS')
    parser.add_argument('--tls-key', type=Path, default=None, metavar='PEM',
                        help='private key of --tls-cert')
    parser.add_argument('--params', type=Path, default=None,
                        help="ROS 2 parameter YAML (the command_centre node's section)")
    parser.set_defaults(handler=run_command_centre)
    return parser
