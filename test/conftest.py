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
Keep the tests' ROS 2 traffic on this machine and apart from other test runs.

Set before any test imports rclpy, and inherited by the nodes that tests start as subprocesses:

- ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST: DDS discovery stays on the loopback interface (by
  default Fast DDS also multicasts discovery on every network interface).
- ROS_DOMAIN_ID: a domain of its own per test run (1..101, from the process id), so that test
  runs side by side on one machine do not see each other's topics.

A value already set in the environment is kept, except ROS_HOME: it points to a new temporary
directory, so that the nodes' state files (``$ROS_HOME/anfis_elevation_ros``) and ROS logs of
a test run never touch ~/.ros nor resume a state from another run; it is removed at the end.

Before the first test the navigator's numba code is compiled (about 20 s on a new checkout) or
loaded from its cache, so that no node a test starts spends its start-up compiling.
"""

import os
import shutil
import tempfile

os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))
os.environ['ROS_HOME'] = tempfile.mkdtemp(prefix='anfis_elevation_ros_test_')


def pytest_report_header(config):
    """Show the ROS 2 isolation settings in the header of the test run."""
    return (f"ROS_AUTOMATIC_DISCOVERY_RANGE={os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE']} "
            f"ROS_DOMAIN_ID={os.environ['ROS_DOMAIN_ID']}")


def pytest_sessionstart(session):
    """Compile the navigator (or load it from numba's cache) once, before any test."""
    from anfis_elevation_ros.core.navigator import compile_navigator
    compile_navigator()


def pytest_unconfigure(config):
    """Remove the test run's ROS_HOME."""
    shutil.rmtree(os.environ['ROS_HOME'], ignore_errors=True)
