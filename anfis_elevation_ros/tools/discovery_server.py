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
``discovery-server`` subcommand: the incident network's Fast DDS discovery server.

Over radio, multicast discovery often fails; DDS then needs a place where participants meet.
This runs eProsima's ``fast-discovery-server`` (in the pinned Fast DDS wheels; ``fastdds
discovery`` on an apt install of ROS 2) at the command post and prints what to set on the
other machines: ``ROS_DISCOVERY_SERVER=<address>:<port>`` on each responder and on the
command centre (``command-centre`` then makes itself a "super client", which sees every
responder's topics). A participant with ``ROS_DISCOVERY_SERVER`` set discovers only through
the server: no multicast. Keep one ``ROS_DOMAIN_ID`` per incident on every machine.

Stop it with Ctrl-C (SIGINT) or SIGTERM; participants already matched keep talking, new ones
are found again once it is back.

Example: ``python -m anfis_elevation_ros discovery-server --address 0.0.0.0 --port 11811``
"""

import argparse
import ipaddress
from pathlib import Path
import shutil
import signal
import subprocess
import sys

from ..core.errors import InputError

SERVER_BINARY = 'fast-discovery-server'


def server_command() -> list:
    """
    Return the command that starts a Fast DDS discovery server, found on this machine.

    ``fast-discovery-server`` beside this Python (the venv of a pip install) or on PATH, else
    ``fastdds discovery`` (a ROS 2 apt install).
    """
    beside = Path(sys.executable).parent / SERVER_BINARY
    if beside.is_file():
        return [str(beside)]
    found = shutil.which(SERVER_BINARY)
    if found:
        return [found]
    fastdds = shutil.which('fastdds')
    if fastdds:
        return [fastdds, 'discovery']
    raise InputError(f'neither {SERVER_BINARY} nor fastdds found: install the standalone '
                     "extra (pip install -e '.[standalone]') or source a ROS 2 install")


def discovery_server_variable(address: str, port: int, server_id: int) -> str:
    """
    Return the ROS_DISCOVERY_SERVER value that names this server.

    The variable lists servers by id, separated by ';': server 1 alone is ``;address:port``.
    """
    host = f'[{address}]' if ':' in address else address
    return ';' * server_id + f'{host}:{port}'


def run_discovery_server(args) -> int:
    """Run the server until SIGINT/SIGTERM; return the exit code."""
    try:
        address = ipaddress.ip_address(args.address)
    except ValueError:
        raise InputError(f'--address {args.address!r} is not an IP address') from None
    if not 0 < args.port < 65536:
        raise InputError(f'--port {args.port} is not a UDP port (1-65535)')
    command = server_command() + ['-i', str(args.server_id), '-l', str(address),
                                  '-p', str(args.port)]
    shown = "<this machine's address>" if address.is_unspecified else str(address)
    value = discovery_server_variable(shown, args.port, args.server_id)
    print(f'discovery-server: Fast DDS discovery server {args.server_id} on UDP '
          f'{address}:{args.port}; Ctrl-C to stop\n'
          f'discovery-server: on every responder and on the command centre, before starting '
          f'them:\n  export ROS_DISCOVERY_SERVER="{value}"', flush=True)
    proc = subprocess.Popen(command, stdin=subprocess.DEVNULL)

    def forward(signum, _frame):
        proc.send_signal(signal.SIGINT)

    signal.signal(signal.SIGINT, forward)
    signal.signal(signal.SIGTERM, forward)
    code = proc.wait()
    if code != 0:
        raise InputError(f'{Path(command[0]).name} exited with code {code} (is the port in '
                         'use by another server?)')
    return 0


def add_parser(subparsers):
    """Register the ``discovery-server`` subcommand."""
    parser = subparsers.add_parser(
        'discovery-server', help="the incident network's Fast DDS discovery server",
        description=__doc__.strip().split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--address', default='0.0.0.0',
                        help='IP address to listen on (0.0.0.0: every interface)')
    parser.add_argument('--port', type=int, default=11811, help='UDP port to listen on')
    parser.add_argument('--server-id', type=int, default=0, choices=range(0, 256),
                        metavar='ID', help="the server's position in ROS_DISCOVERY_SERVER")
    parser.set_defaults(handler=run_discovery_server)
    return parser
