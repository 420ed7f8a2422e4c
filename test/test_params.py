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

"""The parameter table, its mapping to the core's dataclasses, and the ROS 2 YAML reader."""

from dataclasses import fields, is_dataclass
import math
from pathlib import Path

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.height import ElevationParams
from anfis_elevation_ros.core.input_gate import GateParams
from anfis_elevation_ros.core.navigator import NavigatorParams
from anfis_elevation_ros.core.params import all_specs, CLASSIFIER_NODE, config_search_paths
from anfis_elevation_ros.core.params import elevation_params_from_dict, find_config_file
from anfis_elevation_ros.core.params import gate_params_from_dict, IMU_NODE, load_model
from anfis_elevation_ros.core.params import load_params_yaml, load_pipeline_params
from anfis_elevation_ros.core.params import navigator_params_from_dict, node_params, node_specs
from anfis_elevation_ros.core.params import params_yaml_text, validate_value
import pytest
import yaml

PACKAGE_ROOT = Path(__file__).resolve().parents[1]
CONFIG_YAML = PACKAGE_ROOT / 'config' / 'params.yaml'


def field_paths(instance, prefix=''):
    """Dotted paths of every leaf field of a (nested) dataclass instance, with its value."""
    paths = {}
    for f in fields(instance):
        value = getattr(instance, f.name)
        if is_dataclass(value):
            paths.update(field_paths(value, f'{prefix}{f.name}.'))
        else:
            paths[prefix + f.name] = value
    return paths


def write(tmp_path, text, name='params.yaml'):
    path = tmp_path / name
    path.write_text(text)
    return path


# -- the table --------------------------------------------------------------------------------

def test_every_dataclass_field_is_a_parameter_with_its_default():
    """The table holds each field of the core's dataclasses, named by path, default from it."""
    specs = all_specs()
    expected = field_paths(NavigatorParams())
    expected.update({f'elevation.{k}': v for k, v in field_paths(ElevationParams()).items()})
    expected.update({f'gate.{k}': v for k, v in field_paths(GateParams()).items()
                     if k != 'max_gap_s'})                 # the navigator's max_gap_s
    for name, default in expected.items():
        assert name in specs, f'{name} has no parameter'
        want = () if default is None else default
        assert specs[name].default == want, name
    assert GateParams().max_gap_s == NavigatorParams().max_gap_s


def test_names_the_brief_lists():
    """The parameter names are the dataclass paths users see in the docs."""
    imu, classifier = node_specs(IMU_NODE), node_specs(CLASSIFIER_NODE)
    for name in ('zupt.threshold', 'zupt.window_s', 'ekf.zupt_sigma_mps', 'gait.min_swing_s',
                 'rate_hz', 'gravity_mps2', 'init_stance_s', 'still_gyr_rps', 'max_gap_s',
                 'mounting_rpy_deg', 'imu_topic', 'gate.acc_range_mps2', 'gate.frame_id'):
        assert name in imu
    for name in ('elevation.step_height_m', 'elevation.mode_threshold',
                 'elevation.floor_height_m', 'elevation.start_floor', 'model_path'):
        assert name in classifier
    # Only the persistence parameters (each node its own state file), the building and its
    # frame are on both nodes.
    assert set(imu) & set(classifier) == {'persist_state', 'state_dir', 'state_max_age_s',
                                          'resume_max_gap_s', 'cycle_history', 'building_file',
                                          'map_frame_id'}


def test_both_nodes_read_one_building_file(tmp_path):
    """A building on one node's section is the pipeline's; two different ones are refused."""
    one = tmp_path / 'one.yaml'
    one.write_text('classifier_node:\n  ros__parameters: {building_file: tower.yaml}\n')
    assert load_pipeline_params(one).building_file == 'tower.yaml'
    assert load_pipeline_params(one, 'other.yaml').building_file == 'other.yaml'
    two = tmp_path / 'two.yaml'
    two.write_text('classifier_node:\n  ros__parameters: {building_file: a.yaml}\n'
                   'imu_node:\n  ros__parameters: {building_file: b.yaml}\n')
    with pytest.raises(InputError, match='different building files'):
        load_pipeline_params(two)


def test_every_spec_has_a_description_and_a_range_for_numbers():
    """Descriptions end with a period; numbers have a range that holds the default."""
    for spec in all_specs().values():
        assert spec.description.endswith('.'), spec.name
        if spec.kind in ('int', 'double'):
            assert spec.min_value is not None, f'{spec.name} has no range'
            assert spec.min_value <= spec.default <= spec.max_value, spec.name
        assert validate_value(spec, spec.default) == spec.default


def test_memory_bounds():
    """Values that size buffers are bounded: windows, swings, queues, strides, blocks."""
    specs = all_specs()
    bounds = {'zupt.window_s': 0.5, 'init_stance_s': 10.0, 'gait.max_swing_s': 10.0,
              'imu_qos_depth': 10000, 'gait.mounting_strides': 100, 'zupt.intensity_blocks': 60}
    for name, bound in bounds.items():
        assert specs[name].max_value == bound, name


# -- values -----------------------------------------------------------------------------------

def test_validate_value_types_like_ros():
    """An int is refused for a double (ROS refuses it too), with the fix in the message."""
    specs = all_specs()
    with pytest.raises(InputError, match=r'write 400\.0'):
        validate_value(specs['rate_hz'], 400)
    with pytest.raises(InputError, match='true or false'):
        validate_value(specs['zupt.adaptive'], 1)
    with pytest.raises(InputError, match='integer'):
        validate_value(specs['zupt.intensity_blocks'], 3.0)
    with pytest.raises(InputError, match='string'):
        validate_value(specs['imu_topic'], 5)
    with pytest.raises(InputError, match='finite'):
        validate_value(specs['gravity_mps2'], math.nan)
    with pytest.raises(InputError, match=r'outside \[0\.005, 0\.5\]'):
        validate_value(specs['zupt.window_s'], 0.6)


def test_mounting_rpy_deg_empty_or_three_angles():
    """[] and None (ROS 'not set') are automatic; 3 floats are a mounting; else refused."""
    spec = all_specs()['mounting_rpy_deg']
    assert validate_value(spec, None) == () == validate_value(spec, [])
    assert validate_value(spec, [180.0, 0.0, 0.0]) == (180.0, 0.0, 0.0)
    assert navigator_params_from_dict({'mounting_rpy_deg': []}).mounting_rpy_deg is None
    assert navigator_params_from_dict(
        {'mounting_rpy_deg': [180.0, 0.0, 90.0]}).mounting_rpy_deg == (180.0, 0.0, 90.0)
    for bad, match in (([1.0, 2.0], '3 angles'), ([180, 0, 0], 'integers'),
                       ([400.0, 0.0, 0.0], 'every element')):
        with pytest.raises(InputError, match=match):
            validate_value(spec, bad)


def test_from_dict_builds_the_dataclasses():
    """Flat dotted names fill the nested dataclasses; missing names keep defaults."""
    nav = navigator_params_from_dict({'zupt.threshold': 3e6, 'ekf.zupt_sigma_mps': 0.02,
                                      'gait.min_swing_s': 0.2, 'rate_hz': 400.0,
                                      'elevation.step_height_m': 0.15})
    assert nav.zupt.threshold == 3e6 and nav.ekf.zupt_sigma_mps == 0.02
    assert nav.gait.min_swing_s == 0.2 and nav.rate_hz == 400.0
    assert nav.zupt.window_s == NavigatorParams().zupt.window_s
    assert elevation_params_from_dict({'elevation.step_height_m': 0.15,
                                       'elevation.start_floor': 3}) == ElevationParams(
        step_height_m=0.15, start_floor=3)
    gate = gate_params_from_dict({'gate.frame_id': 'imu_link', 'max_gap_s': 0.1})
    assert gate.frame_id == 'imu_link' and gate.max_gap_s == 0.1


@pytest.mark.parametrize(('flat', 'match'), [
    ({'zupt.treshold': 1e6}, "did you mean 'zupt.threshold'"),
    ({'gait.min_swing_s': 3.0, 'gait.max_swing_s': 2.0}, 'min_swing_s'),
    ({'zupt.min_threshold': 1e9, 'zupt.max_threshold': 1e8}, 'min_threshold'),
    ({'rate_hz': 10.0}, 'rate_hz'),
])
def test_from_dict_refuses_unknown_and_inconsistent(flat, match):
    """Unknown names (with a suggestion) and values the dataclasses refuse raise InputError."""
    with pytest.raises(InputError, match=match):
        navigator_params_from_dict(flat)


def test_elevation_range_errors_name_the_parameter():
    """The elevation dataclass's ValueError becomes an InputError naming the parameter."""
    with pytest.raises(InputError, match='elevation.step_height_m'):
        elevation_params_from_dict({'elevation.step_height_m': 0.3})


# -- YAML -------------------------------------------------------------------------------------

def test_config_params_yaml_is_the_rendered_table():
    """
    Check that config/params.yaml mirrors every parameter with its default and comment.

    Regenerate it with params_yaml_text() after changing the table.
    """
    assert CONFIG_YAML.read_text() == params_yaml_text()
    per_node = load_params_yaml(CONFIG_YAML)
    for node in (IMU_NODE, CLASSIFIER_NODE):
        specs = node_specs(node)
        assert node_params(per_node, node) == {n: s.default for n, s in specs.items()}
    assert load_pipeline_params(CONFIG_YAML) == load_pipeline_params()


def test_yaml_nested_dotted_and_wildcard(tmp_path):
    """Nested maps and dotted keys flatten alike; /** applies to both; the node's own wins."""
    path = write(tmp_path, """
/**:
  ros__parameters:
    max_gap_s: 0.08
    elevation.floor_height_m: 3.5
imu_node:
  ros__parameters:
    rate_hz: 400.0
    max_gap_s: 0.1
    zupt:
      threshold: 1.5e7
      adaptive: false
classifier_node:
  ros__parameters:
    elevation: {step_height_m: 0.16, start_floor: -1}
""")
    per_node = load_params_yaml(path)
    imu = node_params(per_node, IMU_NODE)
    assert imu == {'max_gap_s': 0.1, 'rate_hz': 400.0, 'zupt.threshold': 1.5e7,
                   'zupt.adaptive': False}
    pipeline = load_pipeline_params(path)
    assert pipeline.navigator.zupt.threshold == 1.5e7 and pipeline.gate.max_gap_s == 0.1
    assert pipeline.elevation == ElevationParams(step_height_m=0.16, start_floor=-1,
                                                 floor_height_m=3.5)


def test_yaml_namespaced_node_keys(tmp_path):
    """Namespaces as outer keys or in the key are read; they do not apply to root nodes."""
    path = write(tmp_path, """
boot:
  imu_node:
    ros__parameters: {rate_hz: 200.0}
/boot/classifier_node:
  ros__parameters: {model_path: x.json}
""")
    per_node = load_params_yaml(path)
    assert per_node == {'boot/imu_node': {'rate_hz': 200.0},
                        'boot/classifier_node': {'model_path': 'x.json'}}
    assert node_params(per_node, IMU_NODE) == {}


@pytest.mark.parametrize(('text', 'match'), [
    ('imu_node:\n  ros__parameters:\n    zupt: {treshold: 1.0e6}\n', 'zupt.treshold'),
    ('imu_node:\n  ros__parameters:\n    model_path: x\n', "unknown parameter 'model_path'"),
    ('imu_nod:\n  ros__parameters: {rate_hz: 0.0}\n', "unknown node 'imu_nod'"),
    ('imu_node:\n  ros__parameters: {rate_hz: 400}\n', r'write 400\.0'),
    ('imu_node:\n  ros__parameters: {imu_qos_depth: 100000}\n', 'outside'),
    ('imu_node:\n  ros__parameters: {gait: {min_swing_s: 3.0}}\n', 'min_swing_s'),
    ('imu_node: [1, 2]\n', 'ros__parameters'),
    ('imu_node:\n  ros__parameters: [1]\n', 'map of parameters'),
    ('- a\n- b\n', 'list'),
    ('imu_node:\n  ros__parameters: {rate_hz: 1.0\n', 'not valid YAML'),
])
def test_yaml_errors_are_clear(tmp_path, text, match):
    """Bad files raise InputError saying what is wrong and where."""
    with pytest.raises(InputError, match=match):
        load_params_yaml(write(tmp_path, text))


def test_yaml_missing_file(tmp_path):
    """A missing file is an InputError naming it."""
    with pytest.raises(InputError, match='cannot read parameter file'):
        load_params_yaml(tmp_path / 'nope.yaml')


def test_yaml_scalars_typed_as_rcl_does(tmp_path):
    """1.2e7 and 1e-5 are doubles (PyYAML alone reads them as strings), 400 an int."""
    path = write(tmp_path, 'imu_node:\n  ros__parameters:\n    zupt: {threshold: 1.2e7, '
                           'sigma_acc_mps2: 1e-3}\n    imu_qos_depth: 400\n')
    assert node_params(load_params_yaml(path), IMU_NODE) == {
        'zupt.threshold': 1.2e7, 'zupt.sigma_acc_mps2': 1e-3, 'imu_qos_depth': 400}
    assert yaml.safe_load('a: 1.2e7')['a'] == '1.2e7'       # why the custom loader exists


def test_ros_owned_parameters_pass(tmp_path):
    """use_sim_time and qos_overrides.* belong to rclpy: accepted, not ours to validate."""
    path = write(tmp_path, '/**:\n  ros__parameters:\n    use_sim_time: true\n'
                           '    qos_overrides./imu/data.subscription.depth: 10\n')
    assert node_params(load_params_yaml(path), IMU_NODE) == {}
    assert navigator_params_from_dict({'use_sim_time': True}) == NavigatorParams()


def test_empty_file_is_all_defaults(tmp_path):
    """An empty file sets nothing."""
    assert load_params_yaml(write(tmp_path, '')) == {}


# -- packaged files ---------------------------------------------------------------------------

def test_config_lookup_order(tmp_path, monkeypatch):
    """
    Look in an ament prefix with the package's index marker first, then sys.prefix, then src.

    That is where ament_index_python, a pip install and a checkout put config/.
    """
    prefix = tmp_path / 'install'
    (prefix / 'share' / 'ament_index' / 'resource_index' / 'packages').mkdir(parents=True)
    (prefix / 'share' / 'ament_index' / 'resource_index' / 'packages' /
     'anfis_elevation_ros').write_text('')
    config = prefix / 'share' / 'anfis_elevation_ros' / 'config'
    config.mkdir(parents=True)
    (config / 'params.yaml').write_text('')
    monkeypatch.setenv('AMENT_PREFIX_PATH', f'{tmp_path / "other"}:{prefix}')
    paths = config_search_paths('params.yaml')
    assert paths[0] == config / 'params.yaml'
    assert paths[-1] == CONFIG_YAML
    assert find_config_file('params.yaml') == config / 'params.yaml'
    monkeypatch.setenv('AMENT_PREFIX_PATH', '')
    assert find_config_file('params.yaml') == CONFIG_YAML
    with pytest.raises(InputError, match='not found'):
        find_config_file('no_such_file.json')


def test_load_model_errors(tmp_path):
    """A missing or corrupt model file is an InputError."""
    with pytest.raises(InputError, match='not found'):
        load_model(str(tmp_path / 'missing.json'))
    (tmp_path / 'bad.json').write_text('{')
    with pytest.raises(InputError, match='not valid JSON'):
        load_model(str(tmp_path / 'bad.json'))


def test_wildcard_namespace_key_applies_in_the_root_and_any_namespace(tmp_path):
    """The key '/**/imu_node' matches /imu_node and /ff1/imu_node: the packaged file keys so."""
    from anfis_elevation_ros.core.params import load_params_yaml, node_params

    path = tmp_path / 'p.yaml'
    path.write_text('/**/imu_node:\n  ros__parameters:\n    imu_qos_depth: 100\n')
    assert node_params(load_params_yaml(path), 'imu_node') == {'imu_qos_depth': 100}
    assert node_params(load_params_yaml(path), 'classifier_node') == {}
    assert CONFIG_YAML.read_text().count('\n/**/') == 3      # imu_node, classifier_node,
    #                                                        command_centre


def test_command_centre_values_must_agree(tmp_path):
    """The alarm comes after the pre-alarm; a TLS certificate needs its key."""
    from anfis_elevation_ros.core.params import COMMAND_CENTRE_NODE, load_params_yaml

    path = tmp_path / 'p.yaml'
    path.write_text('command_centre:\n  ros__parameters:\n    alarm:\n'
                    '      no_motion_prealarm_s: 20.0\n      no_motion_alarm_s: 10.0\n')
    with pytest.raises(InputError, match='no_motion_alarm_s must not be less'):
        load_params_yaml(path)
    path.write_text('/**/command_centre:\n  ros__parameters:\n    tls_cert_file: c.pem\n')
    with pytest.raises(InputError, match='give both or neither'):
        load_params_yaml(path)
    path.write_text('command_centre:\n  ros__parameters:\n    port: 70000\n')
    with pytest.raises(InputError, match='port'):
        load_params_yaml(path)
    path.write_text('/**/command_centre:\n  ros__parameters:\n    port: 0\n'
                    '    alarm: {lost_contact_s: 2.0}\n')
    assert node_params(load_params_yaml(path), COMMAND_CENTRE_NODE) == {
        'port': 0, 'alarm.lost_contact_s': 2.0}


def test_run_namespace_is_checked_and_remaps_both_nodes():
    """--namespace /ff1 becomes rcl's __ns remap; a malformed namespace is refused."""
    import argparse

    from anfis_elevation_ros.tools.run import check_namespace, ros_init_args

    args = argparse.Namespace(params=None, building=None, namespace='/ff1', ros_argv=[])
    assert ros_init_args(args) == ['anfis_elevation_ros', '--ros-args', '-r', '__ns:=/ff1',
                                   '--']
    check_namespace('/fire/ff_2')
    for bad in ('ff1', '/1ff', '/ff 1', '/ff1/', ''):
        with pytest.raises(InputError, match='not a ROS namespace'):
            check_namespace(bad)
