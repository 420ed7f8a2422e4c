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
Offline replay: the live pipeline over a bag, as fast as it runs, to CSV files.

``python -m anfis_elevation_ros replay BAG --out DIR [--params YAML] [--building FILE]`` feeds
every Imu message of the bag through the same objects the nodes run (input gate,
``FootNavigator``, ``ElevationTracker``) and writes

- ``DIR/track.csv``: one row per navigated IMU sample: ``stamp_ns,x_m,y_m,z_m`` (EKF-corrected
  IMU position, ENU, origin where navigation starts), then ``qw,qx,qy,qz`` (attitude q_nb)
  and ``stance`` (zero-velocity flag). Samples before start-up (the first stance) and
  rejected samples have no row. With a building that has a ``start``, x/y are in the
  building's map frame (``core/map_frame.py``), and its ``stairs`` correct the track where the
  walk enters them (``core/stair_database.py``, ``core/position_fix.py``); a corrected sample's
  row holds the position before the correction.
- ``DIR/cycles.csv``: one row per gait cycle: ``stamp_ns,mode,height_m,x_m,y_m`` (stamp of
  the first stance sample closing the cycle, stair mode, quantised height), then ``floor``,
  ``anfis_output``, ``valid``, ``raw_height_m`` (INS height), the five features, then
  ``floor_certain`` (1 when the height is settled on the floor) and ``step_height_m`` (the riser
  height K in use: the online estimate, or the building file's), then ``floor_lowest`` and
  ``floor_highest``: the floors the height can be on (both the floor while certain; empty when
  not known: on the stairs, off every floor; ``core/floors.py``).
"""

import argparse
import csv
from dataclasses import dataclass
import math
from pathlib import Path
import sys
import time

import numpy as np

from ..core.building import load_building_file
from ..core.errors import InputError
from ..core.gait import FEATURE_NAMES
from ..core.heading_aids import hde_directions_deg
from ..core.height import ElevationTracker
from ..core.input_gate import InputGate
from ..core.map_frame import map_alignment_for
from ..core.navigator import FootNavigator
from ..core.params import load_model, load_pipeline_params
from ..core.position_fix import PositionFixQueue
from ..core.stair_database import stair_monitor_for

TRACK_COLUMNS = ('stamp_ns', 'x_m', 'y_m', 'z_m', 'qw', 'qx', 'qy', 'qz', 'stance')
CYCLE_COLUMNS = ('stamp_ns', 'mode', 'height_m', 'x_m', 'y_m', 'floor', 'anfis_output', 'valid',
                 'raw_height_m') + FEATURE_NAMES + ('floor_certain', 'step_height_m',
                                                    'floor_lowest', 'floor_highest')
PROGRESS_PERIOD_S = 5.0


@dataclass
class ReplayResult:
    """
    What a replay produced.

    Attributes
    ----------
    track_stamp_ns : (M,) int64 array
        Stamp of each navigated sample (float64 cannot hold a stamp in ns exactly).
    track : (M, 8) array
        The other ``TRACK_COLUMNS`` of each row: position, attitude, stance flag.
    cycles : list of tuple
        Rows of ``CYCLE_COLUMNS``.
    rejected : dict
        Samples the input gate refused, by reason.
    navigator : FootNavigator
        The navigator after the last sample (its ``status`` holds the health counters).
    stair_monitor : StairEntryMonitor or None
        Stair-entry associations (counters), when the building has stairs and a start.
    fixes : PositionFixQueue
        The stair-entry corrections requested and applied.

    """

    track_stamp_ns: np.ndarray
    track: np.ndarray
    cycles: list
    rejected: dict
    navigator: FootNavigator
    stair_monitor: object = None
    fixes: PositionFixQueue = None


def navigated_samples(recording, gate: InputGate, navigator: FootNavigator):
    """
    Feed a recording through the input gate and the navigator, in the IMU node's order.

    Parameters
    ----------
    recording : ImuRecording or SimulatedWalk
        Anything with ``stamp_ns``, ``acc_b`` (m/s^2), ``gyr_b`` (rad/s) and optionally
        ``frame_id``.
    gate : InputGate
        Refuses samples (its counters record why).
    navigator : FootNavigator
        Navigates the samples the gate passes.

    Yields
    ------
    (k, TrackPoint, GaitCycle or None)
        Index of the sample and the navigator's output, for every sample it navigated. While
        the navigator holds clipped gyro samples (``core/gyro_rail.py``) k is the index of the
        sample that released them; those still held at the end are released as they came
        (``FootNavigator.flush``; a live node holds them until its next sample).

    """
    frame_id = getattr(recording, 'frame_id', None)
    acc, gyr = np.asarray(recording.acc_b), np.asarray(recording.gyr_b)
    k = -1
    for k, stamp_ns in enumerate(np.asarray(recording.stamp_ns).tolist()):
        if gate.check(stamp_ns, acc[k], gyr[k], frame_id) is not None:
            continue
        for point, cycle in navigator.step(stamp_ns, acc[k], gyr[k]):
            yield k, point, cycle
    for point, cycle in navigator.flush():
        yield k, point, cycle


def replay_recording(recording, pipeline, model, progress=None, building=None) -> ReplayResult:
    """
    Run the live pipeline over a recording.

    The order is the live one: each sample through the navigator, then the stair-entry
    corrections due at it (``PositionFixQueue.after_step``, as the IMU node), and a cycle it
    closes through the classifier and the stair-entry association (as the classifier node),
    whose request is due ``stair_fix_delay_s`` later.

    Parameters
    ----------
    recording : ImuRecording
        The samples, in bag order.
    pipeline : PipelineParams
        Navigator, elevation and input-gate parameters (from ``load_pipeline_params``).
    model : Anfis
        The stair-mode classifier.
    progress : callable or None
        Called as ``progress(done, total)`` every few seconds.
    building : Building or None
        The building (map frame, stair-position database).

    """
    aid = pipeline.building_aid
    gate = InputGate(pipeline.gate)
    map_alignment = map_alignment_for(building, aid.align_strides)
    navigator = FootNavigator(pipeline.navigator, map_alignment=map_alignment,
                              dominant_directions_deg=hde_directions_deg(
                                  building, map_alignment is not None))
    tracker = ElevationTracker(model, pipeline.elevation, building=building)
    monitor = stair_monitor_for(building, aid.stair_fix_ratio)
    fixes = PositionFixQueue(aid.stair_fix_delay_s, aid.stair_fix_sigma_m)
    n = len(recording)
    track_stamp_ns = np.empty(n, dtype=np.int64)
    track = np.empty((n, len(TRACK_COLUMNS) - 1))
    rows = 0
    cycles = []
    next_report = time.monotonic() + PROGRESS_PERIOD_S
    for k, point, cycle in navigated_samples(recording, gate, navigator):
        track_stamp_ns[rows] = point.stamp_ns
        track[rows, 0:3] = point.pos_n
        track[rows, 3:7] = point.quat_nb
        track[rows, 7] = point.stance
        rows += 1
        fixes.after_step(navigator, point)
        if cycle is not None:
            row = cycle_row(cycle, tracker)
            cycles.append(row)
            if monitor is not None:
                request = monitor.update(len(cycles), row[0], row[3], row[4], cycle.valid,
                                         row[1], row[5])
                if request is not None:
                    fixes.submit(request)
        if progress is not None and time.monotonic() > next_report:
            progress(k + 1, n)
            next_report += PROGRESS_PERIOD_S
    return ReplayResult(track_stamp_ns[:rows], track[:rows], cycles, dict(gate.rejected),
                        navigator, monitor, fixes)


def cycle_row(cycle, tracker: ElevationTracker) -> tuple:
    """
    Classify one gait cycle and return its ``CYCLE_COLUMNS`` row.

    An invalid cycle (gap or overlong swing) is not classified: mode 0, height unchanged
    until the next valid cycle bridges it (``ElevationTracker.update``), exactly as the
    classifier node does.
    """
    x_m, y_m, raw_height_m = (float(v) for v in cycle.pos_n)
    estimate = tracker.update(cycle.stamp_ns, cycle.features, x_m, y_m, cycle.valid)
    return (cycle.stamp_ns, estimate.mode, estimate.height_m, x_m, y_m, estimate.floor,
            estimate.anfis_output, int(cycle.valid), raw_height_m,
            *(float(f) for f in cycle.features), int(estimate.floor_certain),
            estimate.step_height_m, *(estimate.floor_range or (math.nan, math.nan)))


def write_csv(path: Path, columns, rows, integer_columns=()) -> None:
    """
    Write rows under a header, integer columns as integers, the rest with full precision.

    An integer column's NaN (not known) is written empty.
    """
    integer = [name in integer_columns for name in columns]
    with open(path, 'w', newline='') as f:
        writer = csv.writer(f)
        writer.writerow(columns)
        for row in rows:
            writer.writerow([repr(float(v)) if not is_int else '' if v != v else int(v)
                             for v, is_int in zip(row, integer)])


def _report_progress(done, total):
    print(f'replay: {done}/{total} samples ({100.0 * done / total:.0f} %)', file=sys.stderr)


def run_replay(args: argparse.Namespace) -> int:
    """Replay a bag through the pipeline and write track.csv and cycles.csv."""
    from .bags import read_imu_bag  # rosbags is only needed here, not by `--help`

    pipeline = load_pipeline_params(args.params, args.building)
    model = load_model(pipeline.model_path)
    building = load_building_file(pipeline.building_file)
    if building is not None:
        print(f'replay: building {building.name or building.source} ({len(building.floors)} '
              f'floors, {len(building.stairs)} stair entries)', file=sys.stderr)
    recording = read_imu_bag(args.bag, topic=args.topic)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.monotonic()
    result = replay_recording(recording, pipeline, model, progress=_report_progress,
                              building=building)
    elapsed_s = time.monotonic() - start
    write_csv(out / 'track.csv', TRACK_COLUMNS,
              ((stamp, *row) for stamp, row in zip(result.track_stamp_ns.tolist(), result.track)),
              ('stamp_ns', 'stance'))
    write_csv(out / 'cycles.csv', CYCLE_COLUMNS, result.cycles,
              ('stamp_ns', 'mode', 'floor', 'valid', 'floor_certain', 'floor_lowest',
               'floor_highest'))
    status = result.navigator.status
    if not status.initialised:
        raise InputError(f'{args.bag}: the foot never stood still long enough to start '
                         'navigating; no track was produced')
    rejected = ', '.join(f'{k} {v}' for k, v in sorted(result.rejected.items()) if v) or 'none'
    final = result.cycles[-1] if result.cycles else None
    print(f'replay: {len(recording)} samples in {elapsed_s:.1f} s '
          f'({len(recording) / max(elapsed_s, 1e-9):.0f} samples/s), {len(result.cycles)} gait '
          f'cycles ({status.invalid_cycles} invalid), rejected: {rejected}; final height '
          f'{final[2] if final else 0.0:.2f} m, floor {final[5] if final else "-"}',
          file=sys.stderr)
    if result.stair_monitor is not None:
        monitor = result.stair_monitor
        print(f'replay: {monitor.entries} stair entries, {monitor.accepted} associated with the '
              f'database, {monitor.refused_far} too far, {monitor.refused_no_entry} with no '
              f'entry; {result.fixes.applied_count} corrections applied', file=sys.stderr)
    return 0


def add_parser(subparsers) -> None:
    """Add the ``replay`` subcommand."""
    parser = subparsers.add_parser(
        'replay', help='run the pipeline over a bag and write track.csv and cycles.csv',
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('bag', help='bag directory or .db3/.mcap file with sensor_msgs/Imu')
    parser.add_argument('--out', required=True, help='output directory')
    parser.add_argument('--params', default=None,
                        help='ROS 2 parameter YAML as the nodes read (default: built-in defaults)')
    parser.add_argument('--building', default=None, metavar='FILE',
                        help='building file of the incident (floors, stairs, entrance; format '
                        "in the README); overrides the YAML's building_file")
    parser.add_argument('--topic', default=None,
                        help="Imu topic (default: the bag's only sensor_msgs/Imu topic)")
    parser.set_defaults(handler=run_replay)
