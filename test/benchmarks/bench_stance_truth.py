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
The detector's stances and the strides' INS heights against the simulator's truth (a script).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_stance_truth.py
[--seed 69] [--imu tactical] [--rate-hz 100] [--duration-s 600]`` (10-20 s). One
``sim.random_walk`` through ``replay_recording`` with the default parameters and model, as
``bench_riser_height.py`` runs it. Printed:

- the raw INS height change of each cycle minus the true one, by the cycle's place: the first
  stair stride of a flight, the strides inside it, its last, the level cycle after it and the
  other level cycles (mean and sd, mm);
- the samples the detector calls stance where the foot moves: those that continue a true
  stance (the trailing SHOE window lagging the lift-off) and those in mid-swing, with the
  foot's true speed there (most are a foot pausing just above the ground; a ZUPT on one
  faster than 0.5 m/s cuts the stride in two and stops the INS);
- the cycles shorter than 0.5 s (a stride cut in two) and the walk's largest height error.

The cycles and their truth come from ``bench_riser_height.replay`` (the last true stride
ending up to 0.2 s after a cycle).
"""

import argparse

from anfis_elevation_ros import sim
from bench_riser_height import replay
from bench_vertical import stance_runs
import numpy as np

STAIR_DH_M = 0.05           # a true stride climbing more than this is a stair stride
SHORT_CYCLE_S = 0.5
FAST_MPS = 0.5              # a ZUPT on a foot this fast stops the INS mid-stride


def height_errors_by_place(true_dh: np.ndarray, raw_dh: np.ndarray) -> dict:
    """Return {place: raw - true height change of its cycles, m}."""
    stair = np.abs(true_dh) > STAIR_DH_M
    before, after = np.r_[False, stair[:-1]], np.r_[stair[1:], False]
    places = {'first stair stride': stair & ~before, 'inside a flight': stair & before & after,
              'last stair stride': stair & before & ~after,
              'level after a flight': ~stair & before, 'other level': ~stair & ~before}
    return {place: (raw_dh - true_dh)[mask] for place, mask in places.items()}


def false_stances(detected: np.ndarray, still: np.ndarray) -> tuple:
    """Split detected stance samples of a moving foot: (lagging a true stance, in mid-swing)."""
    lagging = np.zeros_like(detected)
    for start, stop in zip(*stance_runs(detected)):
        if still[start:stop].any():
            lagging[start:stop] = ~still[start:stop]
    return lagging, detected & ~still & ~lagging


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--seed', type=int, default=69)
    parser.add_argument('--imu', default='tactical', choices=sorted(sim.IMU_PRESETS))
    parser.add_argument('--rate-hz', type=float, default=100.0)
    parser.add_argument('--duration-s', type=float, default=600.0)
    args = parser.parse_args(argv)
    walk = sim.simulate_walk(sim.random_walk(args.duration_s, np.random.default_rng(args.seed)),
                             rng=np.random.default_rng(args.seed), rate_hz=args.rate_hz,
                             imu=args.imu)
    out = replay(walk)
    result, stamp_ns = out['result'], out['stamp_ns']
    print(f'random_walk seed {args.seed}, {args.imu} IMU at {args.rate_hz:.0f} Hz, '
          f'{len(stamp_ns)} cycles')
    print('raw INS height change minus the true one, by place:')
    for place, errors in height_errors_by_place(
            np.diff(out['true_height']), np.diff(out['raw_height'])).items():
        if not len(errors):
            continue
        print(f'  {place:22s} {len(errors):4d} cycles  mean {1e3 * errors.mean():+6.1f} mm  '
              f'sd {1e3 * errors.std():5.1f} mm')
    sample = np.minimum(np.searchsorted(walk.stamp_ns, result.track_stamp_ns), len(walk) - 1)
    detected = result.track[:, -1] > 0.5
    lagging, mid_swing = false_stances(detected, walk.stance[sample])
    speed = np.linalg.norm(walk.vel_n[sample], axis=1)
    print(f'stance samples of a moving foot: {int(lagging.sum())} lagging a lift-off '
          f'(true speed up to {speed[lagging].max(initial=0.0):.2f} m/s), '
          f'{int(mid_swing.sum())} in mid-swing, {int(np.sum(mid_swing & (speed > FAST_MPS)))} '
          f'of them faster than {FAST_MPS} m/s:')
    for k in np.flatnonzero(mid_swing & (speed > FAST_MPS)):
        print(f'  mid-swing at {(result.track_stamp_ns[k] - walk.stamp_ns[0]) * 1e-9:7.2f} s, '
              f'true speed {speed[k]:.2f} m/s')
    cycle_s = np.diff(stamp_ns) * 1e-9
    print(f'cycles shorter than {SHORT_CYCLE_S} s: {int(np.sum(cycle_s < SHORT_CYCLE_S))}')
    error = out['height'] - out['true_height']
    worst = int(np.argmax(np.abs(error)))
    print(f'largest height error {error[worst]:+.3f} m at '
          f'{(stamp_ns[worst] - walk.stamp_ns[0]) * 1e-9:.1f} s')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
