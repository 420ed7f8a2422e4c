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
Persisted tracking state: what a restarted node needs to carry on without a wrong floor.

The state is data (JSON), never code: a small versioned document written atomically
(temporary file in the same directory, fsync, rename) with permissions 0600 at every gait
cycle, and read back on start when it is fresh enough and comes from the same IMU.
"""

from dataclasses import asdict, dataclass
import json
import math
import os
from pathlib import Path
import tempfile
import time

from .errors import InputError

STATE_FORMAT = 'anfis_elevation_ros.state'
STATE_VERSION = 1
MAX_STATE_BYTES = 64 * 1024  # a state file is a few hundred bytes; refuse anything large


@dataclass(frozen=True)
class TrackingState:
    """
    Minimal state of the tracking pipeline at a gait cycle.

    Attributes
    ----------
    stamp_ns : int
        IMU stamp of the gait cycle the state was taken at, ns.
    wall_time_s : float
        Wall-clock time (Unix seconds) when it was written; the freshness test uses it.
    imu_id : str
        Identity of the IMU (the Imu messages' frame_id and topic); a state from another IMU
        is never resumed.
    height_m : float
        Quantised height (eq. 14), m.
    floor : int
        Floor index.
    x_m, y_m, z_m : float
        INS position at the cycle, m (ENU, the track's origin).
    heading_rad : float
        Yaw of the IMU at the cycle, rad.
    filter_ok : bool
        False when the filter was not navigating normally (no resume of the INS then).

    """

    stamp_ns: int
    wall_time_s: float
    imu_id: str
    height_m: float
    floor: int
    x_m: float
    y_m: float
    z_m: float
    heading_rad: float
    filter_ok: bool = True

    def __post_init__(self):
        for name in ('wall_time_s', 'height_m', 'x_m', 'y_m', 'z_m', 'heading_rad'):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value):
                raise InputError(f'state {name} must be a finite number, got {value!r}')
        for name in ('stamp_ns', 'floor'):
            if isinstance(getattr(self, name), bool) or not isinstance(getattr(self, name), int):
                raise InputError(f'state {name} must be an integer, got {getattr(self, name)!r}')
        if not isinstance(self.imu_id, str) or not isinstance(self.filter_ok, bool):
            raise InputError('state imu_id must be a string and filter_ok a boolean')


def save_state(path, state: TrackingState) -> None:
    """
    Write the state atomically with permissions 0600.

    A reader sees either the previous file or the new one, never a partial write: the JSON
    goes to a temporary file in the same directory, is flushed to disk, and replaces the file
    with ``os.replace``.

    Parameters
    ----------
    path : str or Path
        State file.
    state : TrackingState
        What to write.

    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    document = {'format': STATE_FORMAT, 'version': STATE_VERSION, **asdict(state)}
    fd, tmp = tempfile.mkstemp(prefix=f'.{path.name}.', dir=path.parent)
    try:
        os.fchmod(fd, 0o600)
        with os.fdopen(fd, 'w') as f:
            json.dump(document, f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def load_state(path) -> TrackingState:
    """
    Read a state file written by ``save_state``.

    Raises
    ------
    InputError
        Missing, oversized, not JSON, another format or version, or fields missing, unknown
        or of the wrong type.

    """
    path = Path(path)
    try:
        if path.stat().st_size > MAX_STATE_BYTES:
            raise InputError(f'{path}: {path.stat().st_size} bytes is too large for a state file')
        document = json.loads(path.read_text())
    except FileNotFoundError:
        raise InputError(f'{path}: no state file') from None
    except (OSError, UnicodeDecodeError, ValueError) as err:
        raise InputError(f'{path}: not a readable state file ({err})') from None
    if not isinstance(document, dict) or document.get('format') != STATE_FORMAT \
            or document.get('version') != STATE_VERSION:
        raise InputError(f'{path}: not a {STATE_FORMAT} version {STATE_VERSION} file')
    fields = {k: v for k, v in document.items() if k not in ('format', 'version')}
    try:
        return TrackingState(**fields)
    except TypeError as err:
        raise InputError(f'{path}: wrong state fields ({err})') from None


def resumable_state(path, imu_id: str, max_age_s: float, now_s: float = None):
    """
    Return the saved state if it may be resumed, with the reason either way.

    A state is resumed when it reads cleanly, comes from the same IMU and is younger than
    ``max_age_s`` (a firefighter who left the building an hour ago starts fresh).

    Parameters
    ----------
    path : str or Path
        State file.
    imu_id : str
        Identity of the IMU now connected.
    max_age_s : float
        Age limit, s.
    now_s : float or None
        Current wall-clock time (Unix seconds); default ``time.time()``.

    Returns
    -------
    (TrackingState or None, str)
        The state to resume, or None, and a sentence for the log.

    """
    try:
        state = load_state(path)
    except InputError as err:
        return None, f'starting fresh: {err}'
    age_s = (time.time() if now_s is None else now_s) - state.wall_time_s
    if state.imu_id != imu_id:
        return None, f'starting fresh: saved state is from IMU {state.imu_id!r}, not {imu_id!r}'
    if not 0.0 <= age_s <= max_age_s:
        return None, f'starting fresh: saved state is {age_s:.0f} s old (limit {max_age_s:.0f} s)'
    return state, (f'resuming from saved state {age_s:.1f} s old: floor {state.floor}, '
                   f'height {state.height_m:.2f} m')
