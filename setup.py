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
Packaging of anfis_elevation_ros for colcon (ament_python) and for plain pip.

colcon (with ROS 2 Jazzy from apt) reads ``package.xml`` for the dependencies and runs this file;
the executables go to ``lib/anfis_elevation_ros`` (see ``setup.cfg``) where ``ros2 run`` looks.
pip reads the same file: ``pip install -e '.[standalone]'`` pulls the pinned ROS 2 Jazzy wheels
from PyPI so that the nodes and tools run with no ROS install; ``[train]`` adds scikit-learn
(only ``train --backend forest`` needs it) and ``[test]`` the test tools.
"""

from glob import glob

from setuptools import find_packages
from setuptools import setup

PACKAGE_NAME = 'anfis_elevation_ros'

# numpy: the core; numba: compiles its per-sample step (core/jit.py); PyYAML:
# config/params.yaml. Lower bounds are the versions of Ubuntu 24.04 (ROS 2 Jazzy's platform),
# so an apt install satisfies them too; numba 0.58 is the oldest tested (test venv, numpy 1.26).
INSTALL_REQUIRES = [
    'numpy>=1.26',
    'numba>=0.58',
    'PyYAML>=6.0',
]

# Optional features, installed by apt on a ROS machine (package.xml) and by [standalone] on pip.
PLOT_REQUIRES = ['matplotlib>=3.6']        # PNG plot of height and floor
DATASETS_REQUIRES = ['scipy>=1.11']        # scipy.io.loadmat for the public .mat datasets
# Growing the random-forest classifier (train --backend forest); inference needs none of it.
TRAIN_REQUIRES = ['scikit-learn==1.9.1']

# Everything needed to run the nodes and tools with no ROS install: ROS 2 Jazzy wheels from
# PyPI, pinned exactly (they are built together), plus the tested versions of the rest.
STANDALONE_REQUIRES = [
    'ros-rclpy==7.1.6',
    'ros-rmw-fastrtps-cpp==8.4.3',
    'ros-sensor-msgs==5.3.6',
    'ros-geometry-msgs==5.3.6',
    'ros-std-msgs==5.3.6',
    'ros-diagnostic-msgs==5.3.6',
    'ros-nav-msgs==5.3.6',
    'rosbags==0.11.9',
    'numpy==2.4.6',
    'numba==0.68.1',
    'llvmlite==0.50.0',
    'PyYAML==6.0.3',
    'matplotlib==3.11.2',
    'scipy==1.17.1',
    'XStatic-Leaflet==1.9.3.0',     # the command centre's map, served offline (no CDN)
]

# Test and lint tools, pinned so that CI gives the same verdict next year. flake8 7.0 with
# pycodestyle 2.11 and pyflakes 3.2 are chosen to match Ubuntu 24.04, where Jazzy's apt
# ament_flake8 runs, so that `colcon test` there and pip CI here agree.
TEST_REQUIRES = [
    'pytest==9.2.0',
    'hypothesis==6.170.15',
    'ros-ament-flake8==0.17.3',
    'ros-ament-pep257==0.17.3',
    'flake8==7.0.0',
    'pycodestyle==2.11.1',
    'pyflakes==3.2.0',
    'flake8-builtins==2.1.0',
    'flake8-comprehensions==3.14.0',
    'flake8-docstrings==1.7.0',
    'flake8-import-order==0.18.2',
    'flake8-quotes==3.4.0',
    'pydocstyle==6.3.0',
    'colcon-core==0.21.3',
    'colcon-ros==0.5.0',
    'selenium==4.50.0',     # the command centre's page in Debian's chromium + chromium-driver
] + TRAIN_REQUIRES

setup(
    name=PACKAGE_NAME,
    version='0.1.0',
    packages=find_packages(exclude=['test', 'test.*']),
    package_data={PACKAGE_NAME: ['data/**/*', 'command_centre/static/*']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + PACKAGE_NAME]),
        ('share/' + PACKAGE_NAME, ['package.xml']),
        ('share/' + PACKAGE_NAME + '/config',
         sorted(glob('config/*.yaml') + glob('config/*.json'))),
    ],
    python_requires='>=3.11',
    install_requires=INSTALL_REQUIRES,
    extras_require={
        'plot': PLOT_REQUIRES,
        'datasets': DATASETS_REQUIRES,
        'standalone': STANDALONE_REQUIRES,
        'train': TRAIN_REQUIRES,
        'test': TEST_REQUIRES,
    },
    zip_safe=False,
    maintainer='The anfis_elevation_ros Authors',
    maintainer_email='maintainers@users.noreply.h-seed-57a0be65.example',
    description='Floor and height of a firefighter from one foot-mounted IMU (ANFIS-aided '
                'elevation, patent CN111649742A), as ROS 2 nodes and command-line tools.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'anfis_elevation_ros = anfis_elevation_ros.tools.cli:main',
            'imu_node = anfis_elevation_ros.nodes.imu_node:main',
            'classifier_node = anfis_elevation_ros.nodes.classifier_node:main',
        ],
    },
)
