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
One command with subcommands; each tool module registers its own subcommand.

A tool module defines ``add_parser(subparsers)`` that adds its subparser and sets
``handler=<function(args) -> int>``. Expected failures (``InputError``, ``OSError``) print one line
and exit 1; argparse exits 2 on bad usage.
"""

import argparse
import importlib
import sys

from ..core.errors import InputError

TOOL_MODULES = (
    'replay',
    'import_csv',
    'simulate',
    'train',
    'demo',
    'play',
    'plot',
    'record',
    'run',
    'command_centre',
    'discovery_server',
)


def build_parser() -> argparse.ArgumentParser:
    """Build the top-level parser with every tool's subcommand."""
    parser = argparse.ArgumentParser(
        prog='python -m anfis_elevation_ros',
        description='Floor and height from one foot-mounted IMU (ANFIS-aided elevation).',
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    subparsers = parser.add_subparsers(dest='command', required=True, metavar='COMMAND')
    for name in TOOL_MODULES:
        importlib.import_module(f'{__package__}.{name}').add_parser(subparsers)
    return parser


def report_error(err: Exception) -> int:
    """Print an expected failure as one line on stderr and return exit code 1."""
    print(f'error: {err}', file=sys.stderr)
    return 1


def without_ros_args(argv: list) -> list:
    """
    Return argv without its ROS arguments (``--ros-args ... [--]`` sections).

    rclpy is imported only when there are such arguments, so tools that need no ROS start
    without it.
    """
    if '--ros-args' not in argv:
        return list(argv)
    from rclpy.utilities import remove_ros_args
    return remove_ros_args(['prog'] + list(argv))[1:]


def main(argv=None) -> int:
    """
    Run the command named on the command line; return its exit code.

    The tools that start rclpy find the whole command line, ROS arguments included, in
    ``args.ros_argv``.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser().parse_args(without_ros_args(argv))
    args.ros_argv = argv
    try:
        return args.handler(args)
    except (InputError, OSError) as err:
        return report_error(err)
