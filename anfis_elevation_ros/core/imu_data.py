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

"""A recording of IMU samples as plain arrays, the unit every tool and the core exchange."""

from dataclasses import dataclass

import numpy as np

from .errors import InputError


@dataclass(frozen=True)
class ImuRecording:
    """
    IMU samples in the sensor frame, SI units (REP 145).

    Attributes
    ----------
    stamp_ns : (N,) int64 array, sample stamps in nanoseconds, strictly increasing.
    acc_b : (N, 3) float array, specific force in m/s^2 (about +9.81 on the up axis at rest).
    gyr_b : (N, 3) float array, angular rate in rad/s.
    frame_id : the sensor frame name carried in the messages' headers.

    """

    stamp_ns: np.ndarray
    acc_b: np.ndarray
    gyr_b: np.ndarray
    frame_id: str = 'imu_link'

    def __post_init__(self):
        n = len(self.stamp_ns)
        if self.acc_b.shape != (n, 3) or self.gyr_b.shape != (n, 3):
            raise InputError(
                f'IMU arrays disagree: {n} stamps, acc {self.acc_b.shape}, '
                f'gyr {self.gyr_b.shape}; '
                'expected (N,), (N, 3), (N, 3)')

    def __len__(self):
        return len(self.stamp_ns)

    @property
    def rate_hz(self) -> float:
        """Median sample rate in Hz."""
        return 1e9 / float(np.median(np.diff(self.stamp_ns)))
