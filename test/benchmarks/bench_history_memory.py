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
Memory of the gait-cycle history: RSS against cycles published (a script, not a test).

Run from the repository root: ``python test/benchmarks/bench_history_memory.py [--depth N]``.
One process publishes ``--cycles`` gait-cycle messages on the nodes' ``gait_cycle`` QoS
(reliable, transient local, keep last ``--depth``, the ``cycle_history`` parameter) to a
subscriber of the same QoS, and prints the growth of its resident memory every tenth of the
run: it should rise while the history fills and stay flat after ``--depth`` cycles.
"""

import argparse
import os

import numpy as np


def rss_mb() -> float:
    """Resident set size of this process, MB."""
    with open('/proc/self/status') as status:
        for line in status:
            if line.startswith('VmRSS:'):
                return int(line.split()[1]) / 1024.0
    return float('nan')


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--depth', type=int, default=3600, help='history depth (cycle_history)')
    parser.add_argument('--cycles', type=int, default=6000, help='cycles to publish')
    args = parser.parse_args(argv)
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))

    import rclpy
    from sensor_msgs.msg import PointCloud2

    from anfis_elevation_ros.core.gait import GaitCycle, N_FEATURES
    from anfis_elevation_ros.nodes.gait_cycle_msg import cycle_to_msg
    from anfis_elevation_ros.nodes.qos import cycle_history_qos

    rclpy.init()
    node = rclpy.create_node('bench_history_memory')
    publisher = node.create_publisher(PointCloud2, 'gait_cycle', cycle_history_qos(args.depth))
    received = [0]

    def on_cycle(_msg):
        received[0] += 1

    node.create_subscription(PointCloud2, 'gait_cycle', on_cycle, cycle_history_qos(args.depth))
    start_mb = rss_mb()
    report_every = max(1, args.cycles // 10)
    stride_ns = 1_400_000_000
    for index in range(1, args.cycles + 1):
        stamp_ns = index * stride_ns
        cycle = GaitCycle(stamp_ns, stamp_ns - stride_ns // 2, np.array([float(index), 0.0, 0.0]),
                          np.full(N_FEATURES, 0.1), True)
        publisher.publish(cycle_to_msg(cycle, 'odom', index, 1))
        rclpy.spin_once(node, timeout_sec=0.0)
        if index % report_every == 0:
            # Let the subscriber catch up (keep-last may drop some: wait for a quiet 0.2 s).
            before = -1
            while received[0] != before:
                before = received[0]
                for _ in range(20):
                    rclpy.spin_once(node, timeout_sec=0.01)
            print(f'{index:6d} cycles published, {received[0]:6d} received: RSS '
                  f'{rss_mb() - start_mb:+.2f} MB', flush=True)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == '__main__':
    main()
