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
Floor and height of a firefighter from one foot-mounted IMU (patent CN111649742A).

The numpy core (``anfis_elevation_ros.core``) holds the method; ROS 2 nodes and the command-line
tools are thin adapters around it.
"""

__all__ = ['Anfis']


def __getattr__(name):
    # Lazy (PEP 562): `import anfis_elevation_ros.nodes...` need not load the ANFIS module.
    if name == 'Anfis':
        from .core.anfis import Anfis
        return Anfis
    raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
