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

"""The building file: every documented key read, every bad key refused with one clear line."""

import copy

from anfis_elevation_ros.core.building import building_from_dict, load_building, save_building
from anfis_elevation_ros.core.errors import InputError
import pytest
import yaml

# The example of the format's documentation (README, "The building file"), key for key.
EXAMPLE = """
format: anfis_elevation_ros/building
version: 1
name: Training tower
floors:
  - index: 0
    elevation_m: 0.0
    name: Ground
    outline: [[0, 0], [60, 0], [60, 24], [0, 24]]
  - index: 1
    elevation_m: 3.0
step_height_m: 0.15
stairs:
  - stairwell: A
    floor: 0
    direction: up
    x_m: 12.30
    y_m: 4.10
    step_height_m: 0.15
start:
  x_m: 0.0
  y_m: 0.0
  floor: 0
  heading_deg: 90.0
dominant_directions_deg: [0.0]
"""


def example() -> dict:
    return yaml.safe_load(EXAMPLE)


def test_the_documented_example_is_read_key_for_key(tmp_path):
    path = tmp_path / 'tower.yaml'
    path.write_text(EXAMPLE)
    building = load_building(path)
    assert building.name == 'Training tower'
    assert [(f.index, f.elevation_m, f.name) for f in building.floors] == [
        (0, 0.0, 'Ground'), (1, 3.0, '')]
    assert building.floors[0].outline == ((0, 0), (60, 0), (60, 24), (0, 24))
    assert building.step_height_m == 0.15
    (entry,) = building.stairs
    assert (entry.stairwell, entry.floor, entry.direction, entry.x_m, entry.y_m,
            entry.step_height_m) == ('A', 0, 1, 12.3, 4.1, 0.15)
    assert building.start.heading_deg == 90.0 and building.start.floor == 0
    assert building.dominant_directions_deg == (0.0,)
    assert building.source == str(path)


def test_a_saved_building_reads_back_equal(tmp_path):
    building = building_from_dict(example(), where=str(tmp_path / 'tower.yaml'))
    save_building(tmp_path / 'tower.yaml', building)
    assert load_building(tmp_path / 'tower.yaml') == building
    minimal = building_from_dict({'format': 'anfis_elevation_ros/building', 'version': 1,
                                  'floors': [{'index': 0, 'elevation_m': 0.0}]},
                                 where=str(tmp_path / 'minimal.yaml'))
    save_building(tmp_path / 'minimal.yaml', minimal)
    assert load_building(tmp_path / 'minimal.yaml') == minimal


def test_only_the_required_keys_make_a_building():
    building = building_from_dict({'format': 'anfis_elevation_ros/building', 'version': 1,
                                   'floors': [{'index': -1, 'elevation_m': -3.5}]})
    assert building.floors[0].index == -1
    assert building.start is None and building.stairs == () and building.step_height_m is None
    assert building.riser_height_m('A') is None


def test_floors_are_sorted_and_looked_up_by_elevation():
    tree = example()
    tree['floors'] = [{'index': 2, 'elevation_m': 9.5}, {'index': 0, 'elevation_m': 0.0},
                      {'index': 1, 'elevation_m': 4.5}]
    building = building_from_dict(tree)
    assert list(building.indices) == [0, 1, 2]
    assert building.nearest_floor(4.0) == (1, pytest.approx(-0.5))
    assert building.nearest_floor(7.4) == (2, pytest.approx(-2.1))
    assert building.nearest_floor(-20.0)[0] == 0


def test_stair_tables_per_floor_and_direction_and_riser_heights():
    tree = example()
    tree['stairs'] += [{'stairwell': 'A', 'floor': 1, 'direction': 'down', 'x_m': 12.3,
                        'y_m': 8.0},
                       {'stairwell': 'B', 'floor': 0, 'direction': 'up', 'x_m': 50.0,
                        'y_m': 20.0}]
    building = building_from_dict(tree)
    assert [e.stairwell for e in building.stair_table(0, 1)] == ['A', 'B']
    assert [e.stairwell for e in building.stair_table(1, -1)] == ['A']
    assert building.stair_table(1, 1) == ()
    assert building.riser_height_m('A') == 0.15          # the stairwell's own
    assert building.riser_height_m('B') == 0.15          # the building's
    del tree['step_height_m']
    assert building_from_dict(tree).riser_height_m('B') is None


def _set(tree, path, value):
    node = tree
    for key in path[:-1]:
        node = node[key]
    if value is DELETE:
        del node[path[-1]]
    else:
        node[path[-1]] = value


DELETE = object()

# (path to the key, bad value, text the one-line error must contain)
BAD = [
    (('format',), 'anfis/building', 'format'),
    (('format',), DELETE, 'format'),
    (('version',), 2, 'version'),
    (('version',), True, 'version'),
    (('name',), ['x'], 'name'),
    (('floors',), [], 'floors'),
    (('floors',), DELETE, 'floors'),
    (('floors',), {'index': 0}, 'floors'),
    (('floors', 0, 'index'), 0.5, 'floors[0].index'),
    (('floors', 0, 'index'), True, 'floors[0].index'),
    (('floors', 0, 'index'), DELETE, 'floors[0].index'),
    (('floors', 1, 'index'), 0, 'index 0 is given twice'),
    (('floors', 0, 'elevation_m'), '0', 'floors[0].elevation_m'),
    (('floors', 0, 'elevation_m'), float('nan'), 'floors[0].elevation_m'),
    (('floors', 1, 'elevation_m'), 0.5, 'floor 1'),
    (('floors', 1, 'elevation_m'), -3.0, 'floor 1'),
    (('floors', 0, 'outline'), [[0, 0], [1, 1]], 'floors[0].outline'),
    (('floors', 0, 'outline', 1), [60, 'x'], 'floors[0].outline[1]'),
    (('floors', 0, 'outline', 1), [60], 'floors[0].outline[1]'),
    (('floors', 0, 'elevaton_m'), 0.0, 'floors[0].elevaton_m: unknown key'),
    (('step_height_m',), 0.5, 'step_height_m'),
    (('step_height_m',), 'tall', 'step_height_m'),
    (('step_hieght_m',), 0.15, 'step_hieght_m: unknown key'),
    (('stairs',), {'stairwell': 'A'}, 'stairs'),
    (('stairs', 0, 'stairwell'), '', 'stairs[0].stairwell'),
    (('stairs', 0, 'stairwell'), DELETE, 'stairs[0].stairwell'),
    (('stairs', 0, 'floor'), 7, 'stairs[0].floor'),
    (('stairs', 0, 'direction'), 'upward', 'stairs[0].direction'),
    (('stairs', 0, 'direction'), 1, 'stairs[0].direction'),
    (('stairs', 0, 'x_m'), None, 'stairs[0].x_m'),
    (('stairs', 0, 'y_m'), DELETE, 'stairs[0].y_m'),
    (('stairs', 0, 'step_height_m'), 0.02, 'stairs[0].step_height_m'),
    (('stairs', 0, 'landing'), 1, 'stairs[0].landing: unknown key'),
    (('start',), [0, 0], 'start'),
    (('start', 'floor'), 3, 'start.floor'),
    (('start', 'heading_deg'), DELETE, 'start.heading_deg'),
    (('start', 'heading_deg'), float('inf'), 'start.heading_deg'),
    (('start', 'x_m'), 'east', 'start.x_m'),
    (('start', 'z_m'), 0.0, 'start.z_m: unknown key'),
    (('dominant_directions_deg',), 45.0, 'dominant_directions_deg'),
    (('dominant_directions_deg',), [0.0, 'north'], 'dominant_directions_deg[1]'),
]


@pytest.mark.parametrize('path, value, names', BAD, ids=[f'{"/".join(map(str, p))}={v!r:.20}'
                                                         for p, v, _ in BAD])
def test_a_bad_key_is_refused_with_one_line_that_names_it(tmp_path, path, value, names):
    tree = copy.deepcopy(example())
    _set(tree, path, value)
    file = tmp_path / 'bad.yaml'
    file.write_text(yaml.safe_dump(tree))
    with pytest.raises(InputError) as err:
        load_building(file)
    message = str(err.value)
    assert names in message and str(file) in message
    assert '\n' not in message


@pytest.mark.parametrize('text, names', [
    ('', 'a building file is a YAML mapping'),
    ('floors: [\n', 'invalid YAML'),
    ('format: a\nformat: b\n', 'given twice'),
    ('!!python/object/apply:os.system ["true"]', 'invalid YAML'),
    ('- 1\n- 2\n', 'a building file is a YAML mapping'),
])
def test_damaged_or_hostile_files_are_refused(tmp_path, text, names):
    file = tmp_path / 'bad.yaml'
    file.write_text(text)
    with pytest.raises(InputError, match=names):
        load_building(file)


def test_binary_oversized_and_missing_files_are_refused(tmp_path):
    binary = tmp_path / 'binary.yaml'
    binary.write_bytes(b'\xff\xfe\x00garbage')
    with pytest.raises(InputError, match='not UTF-8'):
        load_building(binary)
    big = tmp_path / 'big.yaml'
    big.write_text('#' * 1_000_001)
    with pytest.raises(InputError, match='larger than'):
        load_building(big)
    with pytest.raises(InputError, match='cannot read'):
        load_building(tmp_path / 'missing.yaml')


def test_replay_refuses_a_bad_building_file_in_one_line(tmp_path, capsys):
    from anfis_elevation_ros.tools.cli import main
    from anfis_elevation_ros.tools.demo import SAMPLE_DIR

    bad = tmp_path / 'bad.yaml'
    bad.write_text(EXAMPLE.replace('direction: up', 'direction: sideways'))
    code = main(['replay', str(SAMPLE_DIR / 'imu'), '--out', str(tmp_path / 'out'),
                 '--building', str(bad)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1
    assert err == [f"error: {bad}: stairs[0].direction: must be 'up' or 'down', got "
                   "'sideways'"]
