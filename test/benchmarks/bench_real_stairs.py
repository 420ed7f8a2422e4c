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
The whole pipeline's height on the real stair recordings (a script, not a test).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_real_stairs.py``
(under a minute). ``mad_stairs`` (both feet) and ``xio_foot`` have no height truth; the raw
EKF height at the end (``test/test_real_data.py``) says which way they went. Per recording:
gait cycles, the raw and the quantised (``replay``: classifier, eq. 14, riser height) height
at the last cycle, and how often the stride's geometry overruled the classifier
(``height_checked_mode``: stairs called level, level called stairs).
"""

from anfis_elevation_ros.core.height import ElevationTracker, HEIGHT_CHANGE
from anfis_elevation_ros.core.navigator import FootNavigator
from anfis_elevation_ros.core.params import load_model, load_pipeline_params
from anfis_elevation_ros.tools.datasets import dataset_files, load_mad_stairs, load_xio


def recordings():
    """Yield (name, ImuRecording) of every real stair recording."""
    for path in dataset_files('mad_stairs'):
        for foot in ('left', 'right'):
            yield f'{path.stem.replace("gaitmap_imu_sample_", "mad ")} {foot}', \
                load_mad_stairs(path, foot)
    for path in dataset_files('xio_foot'):
        yield f'xio {path.name.split("_")[1]}', load_xio(path)


def main():
    pipeline = load_pipeline_params()
    model = load_model('')
    print(f'{"recording":32s} {"cycles":>6s} {"raw m":>7s} {"height m":>8s} '
          f'{"stairs->level":>13s} {"level->stairs":>13s}')
    for name, recording in recordings():
        _, cycles = FootNavigator(pipeline.navigator).run(
            recording.stamp_ns, recording.acc_b, recording.gyr_b)
        tracker = ElevationTracker(model, pipeline.elevation)
        for cycle in cycles:
            tracker.update(cycle.stamp_ns, cycle.features, *cycle.pos_n[:2], cycle.valid)
        raw_m = cycles[-1].pos_n[2] - cycles[0].pos_n[2] + cycles[0].features[HEIGHT_CHANGE]
        print(f'{name:32s} {len(cycles):6d} {raw_m:+7.2f} {tracker.height_m:+8.2f} '
              f'{tracker.stair_calls_overruled:13d} {tracker.level_calls_overruled:13d}')


if __name__ == '__main__':
    main()
