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
``run`` subcommand: the IMU node and the classifier node in one process.

Both nodes share one single-threaded executor: the work is one chain (IMU message -> navigator
-> gait cycle -> classifier) that never runs in parallel anyway, one thread costs the least CPU
and wakes fastest (no thread hand-over between the two callbacks), and the two nodes still
talk over DDS like separate processes, so ``ros2 node list`` and remapping work as usual.
(Two processes would add a second interpreter, about 40 MB, and a second executor loop; a
MultiThreadedExecutor would only add locking to a chain that cannot run in parallel.)
The executor is rclpy's EventsExecutor (``--executor events``, the default): at 400 Hz it
costs about a third of the CPU per message of the SingleThreadedExecutor (``--executor single``).
The nodes stop cleanly on Ctrl-C (SIGINT) and on SIGTERM.

``--namespace /ff1`` puts both nodes and all their topics, the Imu input included
(``/ff1/imu/data``), under one namespace, one per responder (the same as the ROS argument
``-r __ns:=/ff1``); the packaged parameter file keys its nodes ``/**/imu_node``, so it applies
in any namespace.

``--params YAML`` is checked first (unknown names, types, ranges, with a clear message) and
then passed to rclpy as ``--params-file``; ROS arguments after ``--ros-args`` (remapping,
``-p name:=value``, log levels) reach rclpy unchanged. ``--record OUT`` also records the
outputs to a new bag (see ``record``).

Example: ``python -m anfis_elevation_ros run --params config/params.yaml --record /tmp/out``
"""

import argparse
import os
from pathlib import Path
import re
import sys

NAMESPACE = re.compile(r'(/[A-Za-z][A-Za-z0-9_]*)+')


def ros_init_args(args) -> list:
    """
    Return the argument list for rclpy.init: the parameter file, the building, the user's args.

    The user's ROS arguments come last, so their ``-p`` overrides win.
    """
    argv = ['anfis_elevation_ros']
    if getattr(args, 'namespace', None) is not None:
        argv += ['--ros-args', '-r', f'__ns:={args.namespace}', '--']
    if args.params is not None:
        argv += ['--ros-args', '--params-file', str(args.params), '--']
    if getattr(args, 'building', None) is not None:
        argv += ['--ros-args', '-p', f'building_file:={Path(args.building).resolve()}', '--']
    return argv + list(getattr(args, 'ros_argv', []))


def check_namespace(namespace):
    """Raise InputError unless ``namespace`` is None or a ROS namespace such as ``/ff1``."""
    from ..core.errors import InputError

    if namespace is not None and not NAMESPACE.fullmatch(namespace):
        raise InputError(f'namespace {namespace!r} is not a ROS namespace: /name[/name...], '
                         'each name a letter then letters, digits or _ (e.g. /ff1)')


def run_run(args) -> int:
    """Start both nodes, spin until SIGINT/SIGTERM; return the exit code."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    from ..core.building import load_building
    from ..core.errors import InputError
    from ..core.params import load_params_yaml
    from ..nodes.classifier_node import ClassifierNode
    from ..nodes.spin import init_without_signal_handlers, Spinner
    from ..nodes.imu_node import ImuNode

    check_namespace(args.namespace)
    if args.params is not None:
        load_params_yaml(args.params)          # clear errors before ROS sees the file
    if args.building is not None:
        load_building(args.building)           # the same for the building file
    if args.record is not None and args.namespace is not None:
        raise InputError("--record records the root namespace's topics; it cannot be used "
                         'with --namespace')
    if args.record is not None and args.record.exists():
        raise InputError(f'{args.record} exists; remove it or choose another --record path')
    init_without_signal_handlers(ros_init_args(args))
    nodes, recorder, code = [], None, 0
    executor = Spinner(args.executor)
    executor.handle_signals()
    try:
        nodes.append(ImuNode())
        nodes.append(ClassifierNode())
        if args.record is not None:
            from .ros_io import OutputRecorder
            recorder = OutputRecorder(args.record, storage=args.storage)
            nodes.append(recorder)
        for node in nodes:
            executor.add_node(node)
        names = ' and '.join(node.get_fully_qualified_name() for node in nodes[:2])
        print(f'run: {names} running (pid {os.getpid()}); Ctrl-C to stop',
              file=sys.stderr, flush=True)
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except InputError as err:
        print(f'error: cannot start the nodes: {err}', file=sys.stderr)
        code = 1
    finally:
        if recorder is not None:
            recorder.close()
            counts = ', '.join(f'{t} {n}' for t, n in recorder.counts.items())
            print(f'run: recorded {args.record} ({counts})', file=sys.stderr)
        executor.shutdown()
        for node in reversed(nodes):
            node.destroy_node()
        rclpy.try_shutdown()
    return code


def add_parser(subparsers):
    """Register the ``run`` subcommand."""
    parser = subparsers.add_parser(
        'run', help='run the IMU node and the classifier node in one process',
        description=__doc__.strip().split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--params', type=Path, default=None,
                        help='ROS 2 parameter YAML for both nodes (default: built-in defaults, '
                        'which config/params.yaml lists)')
    parser.add_argument('--building', type=Path, default=None, metavar='FILE',
                        help='building file of the incident (floors, stairs, entrance) for both '
                        'nodes: sets their building_file parameter')
    parser.add_argument('--namespace', default=None, metavar='/NS',
                        help='ROS namespace of both nodes and all their topics, one per '
                        'responder (e.g. /ff1: Imu input on /ff1/imu/data)')
    parser.add_argument('--record', type=Path, default=None, metavar='OUT',
                        help='also record the outputs to this new bag directory')
    parser.add_argument('--storage', choices=('mcap', 'sqlite3'), default='mcap',
                        help='storage of the --record bag')
    parser.add_argument('--executor', choices=('events', 'single'), default='events',
                        help="rclpy executor: 'events' (rclpy.experimental.EventsExecutor, "
                        "a third of the CPU per message) or 'single' (SingleThreadedExecutor)")
    parser.set_defaults(handler=run_run)
    return parser
