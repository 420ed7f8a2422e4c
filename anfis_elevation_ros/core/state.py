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

Each node owns one state file (two processes never write the same file):

- the IMU node writes a ``NavigationState`` (position, heading, filter status, IMU identity,
  cycle count, walk identity, the frame of the position and the stair-entry corrections
  already in it) and resumes the INS from it;
- the classifier node writes an ``ElevationState`` (quantised height, floor, the last cycle it
  counted, the walk it belongs to) and resumes the height from it.

A state is data (JSON), never code: a small versioned document written atomically (temporary
file in the same directory, fsync, rename) with permissions 0600 at every gait cycle, and read
back on start when it is fresh enough and comes from the same source (:func:`resumable_state`).

Resume only what continues (our policy; the method does not cover restarts). A fresh state
from the same source is only a candidate: the sensor's own stamps decide. The IMU node resumes
when the first stamp after its start follows the saved one by at most ``resume_max_gap_s``
(:func:`walk_continues`): a second play of the same bag, a sensor whose clock was reset, or a
walk taken up again much later starts fresh. A walk identity (``walk_id``,
:func:`new_walk_id`) is drawn when the IMU node starts a walk fresh, carried on when it
resumes, and sent with every gait cycle, so that the classifier resumes only the walk it saved,
never a new walk whose stamps happen to repeat the old ones.
"""

from dataclasses import asdict, dataclass, field, fields
import json
import math
import os
from pathlib import Path
import secrets
import tempfile
import time

from .errors import InputError
from .validation import check_range

STATE_FORMAT = 'anfis_elevation_ros.state'
STATE_VERSION = 4
MAX_STATE_BYTES = 64 * 1024  # a state file is a few hundred bytes; refuse anything large
MAX_STAIR_FIXES = 1000       # identities of applied corrections kept (core/position_fix.py: 256)
MAX_WALK_ID = 2 ** 31 - 1    # sent as a FLOAT64 field of the gait-cycle message: exact


def new_walk_id() -> int:
    """Draw the identity of a new walk: a random integer in [1, MAX_WALK_ID]."""
    return 1 + secrets.randbelow(MAX_WALK_ID)


def is_walk_id(value) -> bool:
    """Whether value is a walk identity: an int in [1, MAX_WALK_ID] (not a bool)."""
    return isinstance(value, int) and not isinstance(value, bool) and 1 <= value <= MAX_WALK_ID


def _check_fields(state):
    """Refuse a state whose fields are not of their declared type (floats finite)."""
    for f in fields(state):
        value = getattr(state, f.name)
        if f.type is float:
            ok = isinstance(value, (int, float)) and not isinstance(value, bool) \
                and math.isfinite(value)
        elif f.type is int:
            ok = isinstance(value, int) and not isinstance(value, bool)
        else:
            ok = isinstance(value, f.type)
        if not ok:
            raise InputError(f'state {f.name} must be a{" finite" if f.type is float else ""} '
                             f'{f.type.__name__}, got {value!r}')


def _check_walk_id(walk_id):
    if not is_walk_id(walk_id):
        raise InputError(f'state walk_id = {walk_id!r} is not a walk identity (an integer in '
                         f'[1, {MAX_WALK_ID}])')


@dataclass(frozen=True)
class NavigationState:
    """
    What the IMU node needs to resume the INS where it stopped.

    Attributes
    ----------
    stamp_ns : int
        IMU stamp of the gait cycle the state was taken at, ns.
    wall_time_s : float
        Wall-clock time (Unix seconds) when it was written; the freshness test uses it.
    source_id : str
        Identity of the IMU (Imu topic and frame_id); a state from another IMU is never resumed.
    x_m, y_m, z_m : float
        INS position at the cycle, m (ENU, the track's origin).
    heading_rad : float
        Yaw of the IMU at the cycle, rad.
    filter_ok : bool
        False when the filter was not navigating normally (the INS is then not resumed).
    cycles : int
        Gait cycles published so far (the cycle index carries on from it).
    stride_period_s : float
        Recent median time between gait cycles, s (estimates the cycles lost in an outage).
    walk_id : int
        Identity of the walk (:func:`new_walk_id`), carried on by a resume.
    map_frame : bool
        True when the position is in a building's map frame (``core/map_frame.py``), False in
        the track's own start frame; a state is resumed only into the same kind of frame.
    stair_fixes : list of int
        Identities (cycle stamps, ns) of the stair-entry corrections already contained in the
        position (``core/position_fix.py``): never applied again after a resume.
    pos_sigma_m, yaw_sigma_rad : float
        Uncertainty of the position (sqrt of the trace of its covariance, m) and of the heading
        (rad) at the cycle: the resumed filter starts with it (0: as a fresh start).

    """

    stamp_ns: int
    wall_time_s: float
    source_id: str
    x_m: float
    y_m: float
    z_m: float
    heading_rad: float
    filter_ok: bool
    cycles: int
    stride_period_s: float
    walk_id: int
    map_frame: bool = False
    stair_fixes: list = field(default_factory=list)
    pos_sigma_m: float = 0.0
    yaw_sigma_rad: float = 0.0

    def __post_init__(self):
        _check_fields(self)
        _check_walk_id(self.walk_id)
        check_range('state stride_period_s', self.stride_period_s, 0.1, 10.0)
        if len(self.stair_fixes) > MAX_STAIR_FIXES or not all(
                isinstance(v, int) and not isinstance(v, bool) for v in self.stair_fixes):
            raise InputError(f'state stair_fixes must be at most {MAX_STAIR_FIXES} integers '
                             '(cycle stamps, ns)')
        check_range('state pos_sigma_m', self.pos_sigma_m, 0.0, 1e4)
        check_range('state yaw_sigma_rad', self.yaw_sigma_rad, 0.0, 10.0)


@dataclass(frozen=True)
class ElevationState:
    """
    What the classifier node needs to resume the height without counting a cycle twice.

    Attributes
    ----------
    stamp_ns : int
        Stamp of the last gait cycle counted, ns; cycles up to it are not counted again.
    wall_time_s : float
        Wall-clock time (Unix seconds) when it was written.
    source_id : str
        The gait-cycle topic the cycles came from.
    height_m : float
        Quantised height (eq. 14), m.
    floor : int
        Floor index.
    cycle_index : int
        Index of the last gait cycle counted (the IMU node numbers them from 1).
    walk_id : int
        The walk the counted cycles belong to (sent by the IMU node with every cycle).
    step_height_m : float
        Riser height K in use (online estimate or the building file's), m, in [0.10, 0.25].
    riser_strides : int
        Stair strides behind that estimate (a resumed estimate is as sure as they made it).
    last_mode : int
        Stair mode (-1, 0, +1) of the last valid cycle: bridges an outage across a restart.
    last_abs_dh_m : float
        Raw |dh| of the last stair cycle, m, in [0, 10].
    floor_doubt : str
        Why the floor is in doubt ('' when it is not; ``core/outage.py``).
    floor_doubt_reach_m : float
        How far the true height may be from ``height_m`` while in doubt, m, in [0, 10000].

    """

    stamp_ns: int
    wall_time_s: float
    source_id: str
    height_m: float
    floor: int
    cycle_index: int
    walk_id: int
    step_height_m: float
    riser_strides: int
    last_mode: int = 0
    last_abs_dh_m: float = 0.0
    floor_doubt: str = ''
    floor_doubt_reach_m: float = 0.0

    def __post_init__(self):
        _check_fields(self)
        _check_walk_id(self.walk_id)
        check_range('state step_height_m', self.step_height_m, 0.10, 0.25)
        check_range('state riser_strides', self.riser_strides, 0, math.inf)
        if self.last_mode not in (-1, 0, 1) or not 0.0 <= self.last_abs_dh_m <= 10.0 \
                or len(self.floor_doubt) > 500 or not 0.0 <= self.floor_doubt_reach_m <= 1e4:
            raise InputError(f'state last_mode = {self.last_mode}, last_abs_dh_m = '
                             f'{self.last_abs_dh_m}, floor_doubt of {len(self.floor_doubt)} '
                             'characters: not a stair mode, a height change in [0, 10] m and '
                             'a reason')


_KINDS = {cls.__name__: cls for cls in (NavigationState, ElevationState)}


def save_state(path, state) -> None:
    """
    Write the state atomically with permissions 0600.

    A reader sees either the previous file or the new one, never a partial write: the JSON
    goes to a temporary file in the same directory, is flushed to disk, and replaces the file
    with ``os.replace``.

    Parameters
    ----------
    path : str or Path
        State file.
    state : NavigationState or ElevationState
        What to write.

    """
    path = Path(path)
    path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
    document = {'format': STATE_FORMAT, 'version': STATE_VERSION,
                'kind': type(state).__name__, **asdict(state)}
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


def load_state(path, kind):
    """
    Read a state file written by ``save_state``.

    Parameters
    ----------
    path : str or Path
        State file.
    kind : type
        ``NavigationState`` or ``ElevationState``: the kind of state expected.

    Raises
    ------
    InputError
        Missing, oversized, not JSON, another format, version or kind, or fields missing,
        unknown or of the wrong type.

    """
    path = Path(path)
    try:
        if path.stat().st_size > MAX_STATE_BYTES:
            raise InputError(f'{path}: {path.stat().st_size} bytes is too large for a state file')
        document = json.loads(path.read_text())
    except FileNotFoundError:
        raise InputError(f'{path}: no state file') from None
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as err:
        raise InputError(f'{path}: not a readable state file ({err})') from None
    if isinstance(document, dict) and document.get('format') == STATE_FORMAT \
            and document.get('version') != STATE_VERSION:
        raise InputError(f'{path}: state file version {document.get("version")!r}, written by '
                         f'another version of the package (this one reads version '
                         f'{STATE_VERSION}; version 4 added the riser height)')
    if not isinstance(document, dict) or document.get('format') != STATE_FORMAT \
            or _KINDS.get(document.get('kind')) is not kind:
        raise InputError(f'{path}: not a {STATE_FORMAT} version {STATE_VERSION} '
                         f'{kind.__name__} file')
    values = {k: v for k, v in document.items() if k not in ('format', 'version', 'kind')}
    try:
        return kind(**values)
    except TypeError as err:
        raise InputError(f'{path}: wrong state fields ({err})') from None


def resumable_state(path, kind, source_id: str, max_age_s: float, now_s: float = None):
    """
    Return the saved state if it may be resumed, with the reason either way.

    A state is resumed when it reads cleanly, comes from the same source and is younger than
    ``max_age_s`` (a firefighter who left the building an hour ago starts fresh).

    Parameters
    ----------
    path : str or Path
        State file.
    kind : type
        ``NavigationState`` or ``ElevationState``.
    source_id : str
        Identity of the source now connected (IMU, or gait-cycle topic).
    max_age_s : float
        Age limit, s.
    now_s : float or None
        Current wall-clock time (Unix seconds); default ``time.time()``.

    Returns
    -------
    (state or None, str)
        The state to resume, or None, and a sentence for the log.

    """
    try:
        state = load_state(path, kind)
    except InputError as err:
        return None, f'starting fresh: {err}'
    age_s = (time.time() if now_s is None else now_s) - state.wall_time_s
    if state.source_id != source_id:
        return None, (f'starting fresh: saved state is from {state.source_id!r}, '
                      f'not {source_id!r}')
    if not 0.0 <= age_s <= max_age_s:
        return None, f'starting fresh: saved state is {age_s:.0f} s old (limit {max_age_s:.0f} s)'
    return state, f'resuming from {path} (saved {age_s:.1f} s ago)'


def walk_continues(saved_stamp_ns: int, first_stamp_ns: int, max_gap_s: float) -> tuple:
    """
    Whether the first sensor stamp after a start continues a saved walk, with the reason.

    continues  <=>  0 < t_first - t_saved <= max_gap

    Parameters
    ----------
    saved_stamp_ns : int
        Stamp of the saved state (its last gait cycle), ns.
    first_stamp_ns : int
        First stamp received after the start, ns.
    max_gap_s : float
        Longest outage resumed (``resume_max_gap_s``), s.

    Returns
    -------
    (bool, str)
        Whether to resume, and a sentence for the log.

    """
    gap_ns = int(first_stamp_ns) - int(saved_stamp_ns)
    gap_s = gap_ns * 1e-9
    if gap_ns <= 0:
        return False, (f'the sensor stamps begin {-gap_s:.1f} s before the saved state (another '
                       'walk, a replay, or a sensor clock that was reset)')
    if gap_ns > round(max_gap_s * 1e9):
        return False, (f'the sensor stamps begin {gap_s:.1f} s after the saved state (limit '
                       f'resume_max_gap_s = {max_gap_s:g} s)')
    return True, f'the sensor stamps continue the saved state after {gap_s:.1f} s'


def default_state_dir() -> Path:
    """Return ``$ROS_HOME/anfis_elevation_ros`` (``~/.ros/anfis_elevation_ros`` by default)."""
    ros_home = os.environ.get('ROS_HOME') or os.path.join(os.path.expanduser('~'), '.ros')
    return Path(ros_home) / 'anfis_elevation_ros'


def state_file(state_dir: str, node_fqn: str) -> Path:
    """
    Return the state file of a node: ``<state_dir>/<namespace.node>.state.json``.

    Parameters
    ----------
    state_dir : str
        Directory; '' is ``default_state_dir()``.
    node_fqn : str
        Fully qualified node name, e.g. ``/left_boot/imu_node``.

    """
    directory = Path(state_dir) if state_dir else default_state_dir()
    return directory / (node_fqn.strip('/').replace('/', '.') + '.state.json')
