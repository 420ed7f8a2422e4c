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
``plot`` subcommand: height and floor against time as a PNG, like the method's Fig. 3.

The input is either a bag recorded from the nodes (``run --record``, ``record``, ``demo``) or
the ``cycles.csv`` of an offline replay (or its folder). The upper panel shows the quantised
height (eq. 14, a staircase), the raw INS height at the end of each gait cycle and, with
``--truth``, the true height; the lower panel the floor. A truth CSV has a ``stamp_ns`` column
and either ``height_m`` (per stride, as simulate's ``strides.csv``) or ``z_m`` (per sample, as
``truth.csv``).

Example: ``python -m anfis_elevation_ros plot /tmp/demo/outputs --truth strides.csv --out fig.png``
"""

import argparse
import csv
from dataclasses import dataclass
from pathlib import Path
import sys

import numpy as np

from ..core.errors import InputError


@dataclass
class HeightSeries:
    """
    What the plot shows; stamps in ns on the IMU clock.

    Attributes
    ----------
    stamp_ns, height_m : (N,) arrays
        Quantised height after each classified cycle.
    raw_stamp_ns, raw_height_m : (M,) arrays
        Raw INS height at the end of each gait cycle (valid or not).
    floor_stamp_ns, floor : (K,) arrays
        Floor index from that time on.

    """

    stamp_ns: np.ndarray
    height_m: np.ndarray
    raw_stamp_ns: np.ndarray
    raw_height_m: np.ndarray
    floor_stamp_ns: np.ndarray
    floor: np.ndarray


def _array(values, dtype=float):
    return np.asarray(values, dtype=dtype)


def read_cycles_csv(path) -> HeightSeries:
    """
    Read an offline replay's cycles.csv (columns stamp_ns, height_m, floor, raw_height_m, valid).

    Raises
    ------
    InputError : missing file or columns.

    """
    rows = _read_csv(path, ('stamp_ns', 'height_m', 'floor', 'raw_height_m'))
    stamp = _array([int(r['stamp_ns']) for r in rows], np.int64)
    valid = np.array([r.get('valid', '1') != '0' for r in rows], dtype=bool)
    return HeightSeries(stamp[valid], _array([float(r['height_m']) for r in rows])[valid],
                        stamp, _array([float(r['raw_height_m']) for r in rows]),
                        stamp[valid], _array([int(r['floor']) for r in rows], np.int64)[valid])


def read_outputs_bag(path) -> HeightSeries:
    """
    Read a bag of the nodes' outputs (/elevation, /gait_cycle, /floor).

    Floor messages carry no stamp. Each is placed on the IMU clock by interpolating its log
    (receive) time between those of the elevation messages, whose stamps are known; this holds
    at any playback speed. A floor logged before the first elevation (the start floor) goes
    to the first stamp.
    """
    from .bags import ns_from_stamp, read_messages

    elevation, raw, floors = [], [], []
    topics = ('/elevation', '/gait_cycle', '/floor')
    for topic, log_ns, msg in read_messages(path, topics=topics):
        if topic == '/elevation':
            elevation.append((ns_from_stamp(msg.header.stamp), msg.point.z, log_ns))
        elif topic == '/gait_cycle':
            values = _point_values(msg)
            if values is not None:
                raw.append((ns_from_stamp(msg.header.stamp), values['z']))
        else:
            floors.append((log_ns, int(msg.data)))
    if not elevation and not raw:
        raise InputError(f'{path}: no /elevation or /gait_cycle messages to plot')
    floor_stamp_ns = np.zeros(0, dtype=np.int64)
    if elevation and floors:
        log_ns = np.array([e[2] for e in elevation], dtype=float)
        stamp_ns = np.array([e[0] for e in elevation], dtype=float)
        floor_stamp_ns = np.interp([f[0] for f in floors], log_ns, stamp_ns).astype(np.int64)
    return HeightSeries(
        _array([e[0] for e in elevation], np.int64), _array([e[1] for e in elevation]),
        _array([r[0] for r in raw], np.int64), _array([r[1] for r in raw]),
        floor_stamp_ns, _array([f[1] for f in floors] if len(floor_stamp_ns) else [], np.int64))


def _point_values(msg):
    """Field values of a one-point FLOAT64 PointCloud2 (rosbags message), or None."""
    data = np.asarray(msg.data, dtype=np.uint8).tobytes()
    if msg.width * msg.height != 1 or msg.is_bigendian:
        return None
    values = {}
    for field in msg.fields:
        if field.datatype != 8 or field.offset + 8 > len(data):
            return None
        values[field.name] = float(np.frombuffer(data, '<f8', 1, field.offset)[0])
    return values if 'z' in values else None


def read_truth_csv(path):
    """
    Return (stamp_ns, height_m, is_per_stride) from a truth CSV.

    Raises
    ------
    InputError : missing file, or neither a height_m nor a z_m column.

    """
    rows = _read_csv(path, ('stamp_ns',))
    column = 'height_m' if rows and 'height_m' in rows[0] else 'z_m'
    if rows and column not in rows[0]:
        raise InputError(f'{path}: a truth CSV needs a height_m or z_m column')
    return (_array([int(r['stamp_ns']) for r in rows], np.int64),
            _array([float(r[column]) for r in rows]), column == 'height_m')


def _read_csv(path, required):
    try:
        with open(path, newline='') as stream:
            rows = list(csv.DictReader(stream))
    except OSError as err:
        raise InputError(f'cannot read {path}: {err.strerror or err}') from None
    missing = [c for c in required if rows and c not in rows[0]]
    if missing:
        raise InputError(f'{path}: missing column(s) {", ".join(missing)}')
    return rows


def read_series(path) -> HeightSeries:
    """Read a replay cycles.csv (or its folder) or a recorded outputs bag."""
    path = Path(path)
    if path.is_dir() and (path / 'cycles.csv').is_file():
        return read_cycles_csv(path / 'cycles.csv')
    if path.suffix == '.csv':
        return read_cycles_csv(path)
    return read_outputs_bag(path)


def plot_height(series: HeightSeries, out_png, truth=None, title: str = '') -> Path:
    """
    Write the PNG: height (quantised, raw INS, truth) and floor against time.

    Parameters
    ----------
    series : HeightSeries
        The estimates.
    out_png : str or Path
        Output file.
    truth : tuple or None
        (stamp_ns, height_m, is_per_stride) from ``read_truth_csv``.
    title : str
        Figure title.

    """
    import matplotlib
    matplotlib.use('Agg')
    from matplotlib import pyplot as plt

    stamps = [s for s in (series.stamp_ns, series.raw_stamp_ns) if len(s)]
    if truth is not None and len(truth[0]):
        stamps.append(truth[0])
    t0 = min(int(s.min()) for s in stamps) if stamps else 0

    def seconds(stamp_ns):
        return (np.asarray(stamp_ns, dtype=np.int64) - t0) * 1e-9

    fig, (ax_h, ax_f) = plt.subplots(2, 1, sharex=True, figsize=(10, 6),
                                     gridspec_kw={'height_ratios': [3, 1]})
    if truth is not None:
        t_stamp, t_height, per_stride = truth
        ax_h.plot(seconds(t_stamp), t_height, '--', color='0.4', lw=1.2,
                  drawstyle='steps-post' if per_stride else 'default', label='truth')
    if len(series.raw_stamp_ns):
        ax_h.plot(seconds(series.raw_stamp_ns), series.raw_height_m, '.-', color='tab:orange',
                  lw=0.8, ms=4, label='INS height (end of each gait cycle)')
    if len(series.stamp_ns):
        ax_h.step(seconds(series.stamp_ns), series.height_m, where='post', color='tab:blue',
                  lw=2.0, label='quantised height (eq. 14)')
    ax_h.set_ylabel('height (m)')
    ax_h.grid(True, alpha=0.3)
    ax_h.legend(loc='best')
    if title:
        ax_h.set_title(title)
    if len(series.floor_stamp_ns):
        end_ns = max(int(s.max()) for s in stamps)          # hold the last floor to the end
        ax_f.step(seconds(np.append(series.floor_stamp_ns, end_ns)),
                  np.append(series.floor, series.floor[-1]), where='post', color='tab:green',
                  lw=2.0)
    ax_f.set_ylabel('floor')
    ax_f.set_xlabel('time (s)')
    ax_f.yaxis.get_major_locator().set_params(integer=True)
    ax_f.grid(True, alpha=0.3)
    fig.tight_layout()
    out_png = Path(out_png)
    fig.savefig(out_png, dpi=110)
    plt.close(fig)
    return out_png


def run_plot(args) -> int:
    """Read the input and the truth, write the PNG; return the exit code."""
    series = read_series(args.input)
    truth = read_truth_csv(args.truth) if args.truth is not None else None
    out = plot_height(series, args.out, truth, title=args.title or str(args.input))
    print(f'[plot] wrote {out}', file=sys.stderr)
    return 0


def add_parser(subparsers):
    """Register the ``plot`` subcommand."""
    parser = subparsers.add_parser(
        'plot', help='PNG of height and floor against time (Fig. 3)',
        description=__doc__.strip().split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('input', type=Path,
                        help='recorded outputs bag, or a replay cycles.csv (or its folder)')
    parser.add_argument('--truth', type=Path, default=None,
                        help='truth CSV (stamp_ns and height_m or z_m)')
    parser.add_argument('--out', type=Path, default=Path('height.png'), help='output PNG')
    parser.add_argument('--title', default='', help='figure title (default: the input path)')
    parser.set_defaults(handler=run_plot)
    return parser
