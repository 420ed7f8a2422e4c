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
``record`` subcommand: the nodes' outputs to a new bag, until Ctrl-C.

Records /elevation, /stair_mode, /floor and /gait_cycle as they arrive, serialised as
received, with the receive time as the bag's log time (the messages keep their own stamps).
``run --record OUT`` does the same inside the nodes' process.

Example: ``python -m anfis_elevation_ros record /tmp/outputs --storage mcap``
"""

import argparse
from pathlib import Path


def run_record(args) -> int:
    """Record the outputs until Ctrl-C or SIGTERM; return the exit code."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    from .ros_io import OutputRecorder
    from ..nodes.spin import init_without_signal_handlers, Spinner

    init_without_signal_handlers(['record'] + list(getattr(args, 'ros_argv', [])))
    recorder = None
    try:
        spinner = Spinner('single')
        spinner.handle_signals()
        recorder = OutputRecorder(args.out, storage=args.storage)
        spinner.add_node(recorder)
        spinner.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if recorder is not None:
            recorder.close()
            recorder.destroy_node()
        rclpy.try_shutdown()
    return 0


def add_parser(subparsers):
    """Register the ``record`` subcommand."""
    parser = subparsers.add_parser(
        'record', help="record the nodes' outputs to a bag",
        description=__doc__.strip().split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('out', type=Path, help='new bag directory (must not exist)')
    parser.add_argument('--storage', choices=('mcap', 'sqlite3'), default='mcap',
                        help='bag storage format')
    parser.set_defaults(handler=run_record)
    return parser
