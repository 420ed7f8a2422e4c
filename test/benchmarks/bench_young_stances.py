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
How long each stance lasts and how implausible its first ZUPT is, on every recording (a script).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_young_stances.py
[--sim-seeds 57,69,96,103,125]`` (about 2 minutes). The navigator runs with the default
parameters but the young-stance rule off (``zupt.young_stance_max_nis`` 0), one sample at a
time; at the first stance sample of each stance the normalised innovation squared of its
ZUPT (``NavigatorStatus.last_nis``) is read, and the stance's duration is its still samples
(the ``min_stance_s`` before the first ZUPT included). Printed per dataset: the stances, the
NIS of those shorter than the default ``young_stance_s`` (largest last), and the durations of
the stances whose NIS exceeds the default ``young_stance_max_nis``. The rule's two settings
sit between what real short stances read and what a foot gliding mid-swing reads.
"""

import argparse
from dataclasses import replace

from anfis_elevation_ros import sim
from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.tools.datasets import dataset_files, load_hugadb, load_mad_stairs
from anfis_elevation_ros.tools.datasets import load_pyshoe_vicon, load_xio
from anfis_elevation_ros.tools.gdin_hallway import GYRO_RANGE_RPS, load_gdin_walk
from anfis_elevation_ros.tools.training_data import hugadb_specs
import numpy as np

DEFAULTS = NavigatorParams().zupt


def stances(recording, params) -> list:
    """Return (duration s, first ZUPT's NIS) of every stance of a recording, rule off."""
    params = replace(params, zupt=replace(params.zupt, young_stance_max_nis=0.0))
    navigator = FootNavigator(params)
    found, start_ns, nis = [], None, 0.0
    for stamp, acc, gyr in zip(recording.stamp_ns, recording.acc_b, recording.gyr_b):
        for point, _ in navigator.step(int(stamp), acc, gyr):
            if point.stance and start_ns is None:
                start_ns, nis = point.stamp_ns, navigator.status.last_nis
            elif not point.stance and start_ns is not None:
                still_s = (point.stamp_ns - start_ns) * 1e-9 + DEFAULTS.min_stance_s
                found.append((still_s, nis))
                start_ns = None
    return found


def recordings(sim_seeds):
    """Yield (dataset, recording, navigator parameters) for every recording used."""
    plain = NavigatorParams()
    for path in dataset_files('pyshoe_vicon'):
        yield 'pyshoe_vicon', load_pyshoe_vicon(path)[0], plain
    for path in dataset_files('gdin_hallway'):
        yield 'gdin_hallway', load_gdin_walk(path).recording, replace(
            plain, gyro_range_rps=GYRO_RANGE_RPS)
    for path in dataset_files('mad_stairs'):
        for foot in ('left', 'right'):
            yield 'mad_stairs', load_mad_stairs(path, foot), plain
    for path in dataset_files('xio_foot'):
        yield 'xio_foot', load_xio(path), plain
    for spec in hugadb_specs(dataset_files('hugadb')[0].parent):
        yield 'hugadb', load_hugadb(spec.path, spec.foot,
                                    gyro_range_dps=spec.gyro_range_dps)[0], plain
    for seed in sim_seeds:
        walk = sim.simulate_walk(sim.random_walk(600.0, np.random.default_rng(seed)),
                                 rng=np.random.default_rng(seed), rate_hz=100.0,
                                 imu='tactical')
        yield 'sim random_walk', walk.to_recording(), plain


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--sim-seeds', default='57,69,96,103,125',
                        help='random walks (tactical, 100 Hz) with strides cut in two')
    args = parser.parse_args()
    found = {}
    for dataset, recording, params in recordings(int(s) for s in args.sim_seeds.split(',')):
        found.setdefault(dataset, []).extend(stances(recording, params))
    young_s, max_nis = DEFAULTS.young_stance_s, DEFAULTS.young_stance_max_nis
    print(f'young: under {young_s * 1000:.0f} ms; implausible: NIS above {max_nis:.0f}')
    for dataset, rows in found.items():
        duration = np.array([d for d, _ in rows])
        nis = np.array([n for _, n in rows])
        young = np.sort(nis[duration < young_s])
        implausible = np.sort(duration[nis > max_nis])
        largest = ' '.join(f'{n:.0f}' for n in young[-8:])
        print(f'{dataset}: {len(rows)} stances, {len(young)} young; largest NIS of those: '
              f'{largest}')
        print(f'  NIS above {max_nis:.0f}: {len(implausible)}, lasting (ms) '
              + ' '.join(f'{d * 1000:.0f}' for d in implausible[:12])
              + (' ...' if len(implausible) > 12 else ''))


if __name__ == '__main__':
    main()
