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
``play`` subcommand: publish a bag's sensor_msgs/Imu messages live, paced by their stamps.

Waits until the topic has a subscriber (``--wait-s``) and the IMU node reading it is ready
(its first diagnostics, ``--ready-s``: on a new machine it compiles for 30-60 s first, and a
walk played meanwhile would lose its start), then publishes every message at the
recorded pace (``--rate 1``), scaled (``--rate 2`` is twice as fast), or with ``--rate 0`` as
fast as a Python subscriber can follow: at most ``--max-rate-hz`` messages per second (the
IMU node handles about 2000 Imu messages/s). The publisher stays up until every message is
out, plus ``--linger-s``. ``--log-publish CSV`` writes ``stamp_ns,publish_time_ns`` per message
(wall clock, for latency measurements). ``--topic`` is the topic published on (``/ff1/imu/data``
for a responder run with ``--namespace /ff1``); ``--bag-topic`` the one read from the bag.

Example: ``python -m anfis_elevation_ros play anfis_elevation_ros/data/sample_walk/imu``
"""

import argparse
from pathlib import Path
import sys
import time

import numpy as np

from ..core.errors import InputError


def run_play(args) -> int:
    """Publish the bag; return the exit code."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    from .bags import read_imu_bag
    from .ros_io import ImuPlayer

    topic = args.topic
    recording = read_imu_bag(args.bag, topic=args.bag_topic)
    rclpy.init(args=['play'] + list(getattr(args, 'ros_argv', [])))
    player = None
    try:
        player = ImuPlayer(recording, topic=topic)
        log(f'{len(recording)} messages ({recording.rate_hz:.0f} Hz, '
            f'{(recording.stamp_ns[-1] - recording.stamp_ns[0]) * 1e-9:.1f} s) for {topic}; '
            'waiting for a subscriber')
        if not player.wait_for_subscribers(args.subscribers, timeout_s=args.wait_s):
            raise InputError(f'no subscriber on {topic} after {args.wait_s:g} s; start the '
                             'nodes first (python -m anfis_elevation_ros run)')
        if args.ready_s > 0:
            log('waiting for the IMU node to be ready (its first diagnostics; the first run on '
                'a machine compiles for 30-60 s)')
            if not player.wait_until_ready(args.ready_s):
                raise InputError(f'no IMU node reading {topic} reported ready in '
                                 f'{args.ready_s:g} s; --ready-s 0 plays as soon as a '
                                 'subscriber appears')
        result = player.play(rate=args.rate, max_rate_hz=args.max_rate_hz)
        time.sleep(args.linger_s)
        log(f'published {result.published} messages in {result.wall_s:.1f} s '
            f'({result.published / max(result.wall_s, 1e-9):.0f} msg/s)')
        if args.log_publish is not None:
            write_publish_log(args.log_publish, recording.stamp_ns[:result.published],
                              result.publish_time_ns)
    except (KeyboardInterrupt, ExternalShutdownException):
        return 1
    finally:
        if player is not None:
            player.destroy_node()
        rclpy.try_shutdown()
    return 0


def write_publish_log(path, stamp_ns, publish_time_ns):
    """Write stamp_ns,publish_time_ns (wall clock, ns) per published message."""
    table = np.column_stack([np.asarray(stamp_ns, dtype=np.int64),
                             np.asarray(publish_time_ns, dtype=np.int64)])
    np.savetxt(path, table, fmt='%d', delimiter=',', header='stamp_ns,publish_time_ns',
               comments='')


def log(message: str):
    """Progress to stderr."""
    print(f'[play] {message}', file=sys.stderr, flush=True)


def add_parser(subparsers):
    """Register the ``play`` subcommand."""
    parser = subparsers.add_parser(
        'play', help="publish a bag's Imu messages live, paced by their stamps",
        description=__doc__.strip().split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('bag', type=Path, help='bag directory or .db3/.mcap file')
    parser.add_argument('--rate', type=float, default=1.0,
                        help='speed factor; 0 = as fast as --max-rate-hz allows')
    parser.add_argument('--topic', default='/imu/data',
                        help='Imu topic to publish on (/ff1/imu/data for the responder '
                        'run --namespace /ff1)')
    parser.add_argument('--bag-topic', default=None,
                        help="Imu topic to read from the bag (default: the bag's only one)")
    parser.add_argument('--max-rate-hz', type=float, default=2000.0,
                        help='never publish more messages per second than this')
    parser.add_argument('--wait-s', type=float, default=10.0,
                        help='how long to wait for a subscriber')
    parser.add_argument('--ready-s', type=float, default=180.0,
                        help="then wait this long for the IMU node's first diagnostics (it is "
                        'compiled); 0 does not wait (a subscriber of another kind)')
    parser.add_argument('--subscribers', type=int, default=1,
                        help='subscribers to wait for')
    parser.add_argument('--linger-s', type=float, default=1.0,
                        help='keep the publisher up this long after the last message')
    parser.add_argument('--log-publish', type=Path, default=None, metavar='CSV',
                        help='write stamp_ns,publish_time_ns of every message')
    parser.set_defaults(handler=run_play)
    return parser
