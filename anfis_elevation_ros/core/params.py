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
Parameters: the one place that maps named parameters to the core's dataclasses.

A parameter's name is the path of its dataclass field: the navigator's fields at the top level
(``rate_hz``, ``zupt.threshold``, ``ekf.zupt_sigma_mps``, ``gait.min_swing_s``, ...), the
classifier's under ``elevation.`` (``ElevationParams``), the input gate's under ``gate.``
(``GateParams``; its ``max_gap_s`` is the navigator's ``max_gap_s``), plus ``model_path`` and a
few node-level parameters (topics, frames, rates); the command centre's (web server, discovery,
alarm timers under ``alarm.``, mirroring ``command_centre.alarms.AlarmParams``). Defaults
come from the dataclasses; the description, range and read-only flag of every parameter are
written once, in ``_DOCS`` below (in the spec itself for node-level ones), and serve the ROS
parameter descriptors, the validation of YAML files and of live changes, and
``config/params.yaml`` (``params_yaml_text`` renders it).

Value types follow ROS 2 parameters exactly, so a file that passes here also loads in the
nodes: ``bool``, ``int``, ``double`` (a whole number must be written ``400.0``: ROS refuses
an integer for a double), ``string`` and ``double_array`` (``mounting_rpy_deg``; empty or
absent means automatic).

The YAML format is the ROS 2 parameter file: ``<node>: ros__parameters: {...}`` with nested
maps joined by dots, ``/**`` (or ``**``) for every node, and namespaces as outer keys or in
the node key (``/ns/imu_node``). Scalars are typed as rcl types them (``1.2e7`` is a double).
Parameters rclpy handles itself (``use_sim_time``, ``qos_overrides.*``) are let through.

Public API: ``ParamSpec``, ``PipelineParams``, ``IMU_NODE``, ``CLASSIFIER_NODE``,
``COMMAND_CENTRE_NODE``, ``ALARM_PREFIX``,
``node_specs``, ``all_specs``, ``validate_value``, ``is_ros_owned``,
``navigator_params_from_dict``, ``elevation_params_from_dict``, ``gate_params_from_dict``,
``load_params_yaml``, ``node_params``, ``load_pipeline_params``, ``config_search_paths``,
``find_config_file``, ``model_file``, ``load_model``, ``params_yaml_text``.
"""

from dataclasses import dataclass, fields, is_dataclass, replace
import difflib
import math
import numbers
import os
from pathlib import Path
import re
import sys
import textwrap

import yaml

from .errors import InputError
from .height import ElevationParams
from .input_gate import GateParams
from .navigator import NavigatorParams
from .stair_database import BuildingAidParams

PACKAGE = 'anfis_elevation_ros'
IMU_NODE = 'imu_node'
CLASSIFIER_NODE = 'classifier_node'
COMMAND_CENTRE_NODE = 'command_centre'
NODE_NAMES = (IMU_NODE, CLASSIFIER_NODE, COMMAND_CENTRE_NODE)
ALARM_PREFIX = 'alarm.'
DEFAULT_MODEL_FILE = 'forest_default.json'
PARAMS_FILE = 'params.yaml'
ELEVATION_PREFIX = 'elevation.'
BUILDING_AID_PREFIX = 'building_aid.'
CLASSIFIER_AIDS = ('building_aid.stair_fix_ratio',)   # the rest are the IMU node's
GATE_PREFIX = 'gate.'
SHARED_GATE_FIELDS = {'max_gap_s': 'max_gap_s'}   # GateParams field -> parameter it mirrors
MAX_YAML_BYTES = 1_000_000
ROS_OWNED_PARAMETERS = ('use_sim_time', 'start_type_description_service')
"""Parameters every rclpy node declares itself; passed through untouched (as qos_overrides.*)."""

KINDS = ('bool', 'int', 'double', 'string', 'double_array')


@dataclass(frozen=True)
class ParamSpec:
    """
    One parameter: name, default, description, range and whether it may change live.

    Attributes
    ----------
    name : str
        Dotted parameter name, the dataclass field path.
    default : bool, int, float, str or tuple of float
        Default value, in the parameter's type (``kind``).
    description : str
        One sentence with the unit, for the ParameterDescriptor and the YAML comment.
    min_value, max_value : float or None
        Inclusive range of a number (of each element of an array); None for no bound.
    read_only : bool
        True when changing it on a running node makes no sense (set it at start).

    """

    name: str
    default: object
    description: str
    min_value: float = None
    max_value: float = None
    read_only: bool = True

    @property
    def kind(self) -> str:
        """Return the ROS 2 parameter type: bool, int, double, string or double_array."""
        return _kind_of(self.default)


@dataclass(frozen=True)
class PipelineParams:
    """
    Everything the pipeline (input gate, navigator, classifier) needs.

    Attributes
    ----------
    navigator : NavigatorParams
        Detector, filter, gait segmentation and start-up.
    elevation : ElevationParams
        Step height, mode threshold, storey height, start floor and height.
    gate : GateParams
        Input checks.
    model_path : str
        ANFIS model file; '' is the packaged default (see ``load_model``).
    building_file : str
        Building file of the incident (``core/building.py``); '' for none.
    building_aid : BuildingAidParams
        Map frame and stair-position correction.

    """

    navigator: NavigatorParams
    elevation: ElevationParams
    gate: GateParams
    model_path: str = ''
    building_file: str = ''
    building_aid: BuildingAidParams = BuildingAidParams()


def _kind_of(value) -> str:
    if isinstance(value, bool):
        return 'bool'
    if isinstance(value, int):
        return 'int'
    if isinstance(value, float):
        return 'double'
    if isinstance(value, str):
        return 'string'
    if isinstance(value, tuple):
        return 'double_array'
    raise TypeError(f'no parameter type for {value!r}')


# -- the table: description, (min, max), read_only; defaults come from the dataclasses --------

_READ_ONLY, _LIVE = True, False
_DOCS = {
    # NavigatorParams
    'rate_hz': ('Nominal IMU sample rate, Hz; 0 estimates it from the first 16 stamps '
                '(else 20 to 2000).', 0.0, 2000.0, _READ_ONLY),
    'gravity_mps2': ('Local gravity magnitude, m/s^2.', 9.7, 9.9, _READ_ONLY),
    'init_stance_s': ('Stance needed before navigation starts, s.', 0.02, 10.0, _READ_ONLY),
    'still_gyr_rps': ('The start-up stance gives the gyro bias only if no rate in it exceeds '
                      'this, rad/s.', 0.0, 1.0, _READ_ONLY),
    'max_gap_s': ('An interval between samples longer than this is a gap: the gait cycle it '
                  'falls in is invalid, s.', 0.005, 1.0, _READ_ONLY),
    'gyro_range_rps': ('Gyroscope measurement range, rad/s: rates at it are clipped and add '
                       'attitude noise (ekf.gyr_rail_noise_rps), rebuilt with rail.enabled; 0 '
                       '= unknown.', 0.0, 200.0, _READ_ONLY),
    # GyroRailParams
    'rail.enabled': ('Rebuild runs of clipped gyro samples (needs gyro_range_rps; '
                     'core/gyro_rail.py).', None, None, _READ_ONLY),
    'rail.fit_samples': ('A run of clipped gyro samples is rebuilt from a polynomial fitted to '
                         'this many samples each side.', 1, 20, _READ_ONLY),
    'rail.fit_order': ('Degree of that polynomial (less than 2 x rail.fit_samples).', 1, 5,
                       _READ_ONLY),
    'rail.max_run_s': ('Samples are held while the gyro clips; a run longer than this is '
                       'released as it came, s.', 0.0, 1.0, _READ_ONLY),
    'rail.range_fraction': ('A rate at this fraction of gyro_range_rps or more is rebuilt as '
                            'clipped (sensors compress the last per cent before the rail).',
                            0.5, 1.0, _READ_ONLY),
    'mounting_rpy_deg': ('IMU mounting on the foot as roll, pitch, yaw, deg (as simulate '
                         '--mounting-rpy-deg; 180 0 0 is z down); empty = automatic (forward '
                         'axis from the first strides).', -360.0, 360.0, _READ_ONLY),
    # ZuptParams
    'zupt.window_s': ('SHOE window length, s (at least 3 samples).', 0.005, 0.5, _READ_ONLY),
    'zupt.threshold': ('SHOE threshold gamma_0 (dimensionless): fixed gamma, or gamma at the '
                       'reference intensity when adaptive.', 1.0, 1e12, _READ_ONLY),
    'zupt.sigma_acc_mps2': ('Accelerometer noise scale sigma_a of eq. (4), m/s^2.', 1e-5, 10.0,
                            _READ_ONLY),
    'zupt.sigma_gyr_rps': ('Gyroscope noise scale sigma_w of eq. (4), rad/s.', 1e-6, 1.0,
                           _READ_ONLY),
    'zupt.adaptive': ('Scale the threshold with the gait intensity.', None, None, _READ_ONLY),
    'zupt.ref_peak_gyr_rps': ('Intensity m_0 at which gamma = gamma_0, rad/s.', 0.5, 30.0,
                              _READ_ONLY),
    'zupt.intensity_exponent': ('Exponent p of gamma = gamma_0 (m / m_0)^p.', 0.0, 10.0,
                                _READ_ONLY),
    'zupt.min_threshold': ('Lower bound of the adaptive threshold.', 1.0, 1e13, _READ_ONLY),
    'zupt.max_threshold': ('Upper bound of the adaptive threshold.', 1.0, 1e13, _READ_ONLY),
    'zupt.min_stance_s': ('A stance counts only after the statistic stayed below the threshold '
                          'this long, s.', 0.0, 0.5, _READ_ONLY),
    'zupt.young_stance_s': ('A stance younger than this gets no ZUPT while its innovation is '
                            'implausible (zupt.young_stance_max_nis), s.', 0.0, 0.5, _READ_ONLY),
    'zupt.young_stance_max_nis': ("Largest normalised innovation squared of a young stance's "
                                  'ZUPT (0: no limit).', 0.0, 1e12, _READ_ONLY),
    'zupt.intensity_block_s': ('Block over which the peak angular rate is taken, s.', 0.2, 10.0,
                               _READ_ONLY),
    'zupt.intensity_blocks': ('Blocks whose median peak rate is the gait intensity.', 1, 60,
                              _READ_ONLY),
    # StrideGateParams
    'stride_gate.enabled': ('Stance detection from the gait structure: one stance between two '
                            'swings (core/stride_gate.py).', None, None, _READ_ONLY),
    'stride_gate.relaxed_factor': ('A relaxed stance (the stillest point after a swing) needs '
                                   'a SHOE statistic below this multiple of gamma.', 1.0, 100.0,
                                   _READ_ONLY),
    'stride_gate.relaxed_floor': ('... or below this (the threshold of the first, gentle '
                                  'steps after a stand is low).', 0.0, 1e13, _READ_ONLY),
    'stride_gate.refractory_fraction': ('No relaxed stance before this fraction of the running '
                                        'stride period since the last stance sample.', 0.0,
                                        1.0, _READ_ONLY),
    'stride_gate.swing_level': ('SHOE statistic of a swing (dimensionless; 3e8: a foot turning '
                                'at about 1.5 rad/s).', 1.0, 1e13,
                                _READ_ONLY),
    'stride_gate.swing_arm_s': ('Time above swing_level that makes a swing, s.', 0.0, 1.0,
                                _READ_ONLY),
    'stride_gate.confirm_s': ('A minimum of the statistic is a relaxed stance when no lower one '
                              'follows for this long, s.', 0.0, 0.5, _READ_ONLY),
    'stride_gate.min_period_s': ('Lower bound of the running stride period, s.', 0.1, 10.0,
                                 _READ_ONLY),
    'stride_gate.max_period_s': ('Upper bound of the running stride period, s.', 0.1, 10.0,
                                 _READ_ONLY),
    'stride_gate.current_factor': ('The sample that confirms a relaxed stance (and gets its '
                                   'ZUPT) needs a statistic below this multiple of the bound.',
                                   1.0, 1e6, _READ_ONLY),
    'stride_gate.max_break_s': ('A stance this soon after the last stance sample continues it, '
                                's.', 0.0, 1.0, _READ_ONLY),
    'stride_gate.relaxed_sigma_mps': ('Standard deviation of the ZUPT at a relaxed stance, '
                                      'm/s.', 1e-4, 10.0, _READ_ONLY),
    'stride_gate.late_stances': ('A second swing with no stance since the first makes the '
                                 'lowest statistic between them a stance, its ZUPT applied '
                                 'late.', None, None, _READ_ONLY),
    'stride_gate.late_balance': ('... when no stance follows it within this fraction of the '
                                 'time from the last stance to it (a dip mid-swing is followed '
                                 'by a stance sooner).', 0.0, 2.0, _READ_ONLY),
    'stride_gate.late_sigma_mps': ("Standard deviation of the late stance's ZUPT (its velocity "
                                   'error carried to the sample that finds it), m/s.', 1e-4,
                                   10.0, _READ_ONLY),
    'stride_gate.late_max_nis': ("... and when its velocity is plausible as the filter's "
                                 'velocity error: NIS of its ZUPT at most this.', 0.0, 1e12,
                                 _READ_ONLY),
    'stride_gate.late_max_slope': ('A late stance closes its gait cycle when the foot reached '
                                   'it along a slope |dh| / run of at most this, as in the '
                                   'cycle before (level ground, a ramp; stairs climb 0.5-0.8); '
                                   'else the cycle runs on to the next stance.', 0.0, 10.0,
                                   _READ_ONLY),
    # EkfParams
    'ekf.acc_noise_mps2_sqrt_hz': ('Accelerometer white-noise density, m/s^2/sqrt(Hz).', 1e-6,
                                   10.0, _READ_ONLY),
    'ekf.gyr_noise_rps_sqrt_hz': ('Gyroscope white-noise density, rad/s/sqrt(Hz).', 1e-7, 1.0,
                                  _READ_ONLY),
    'ekf.acc_bias_walk_mps3_sqrt_hz': ('Accelerometer bias random-walk density, '
                                       'm/s^3/sqrt(Hz).', 1e-9, 1.0, _READ_ONLY),
    'ekf.gyr_bias_walk_rps2_sqrt_hz': ('Gyroscope bias random-walk density, rad/s^2/sqrt(Hz).',
                                       1e-10, 1.0, _READ_ONLY),
    'ekf.zupt_sigma_mps': ('Standard deviation of the zero-velocity pseudo-measurement, m/s.',
                           1e-4, 1.0, _READ_ONLY),
    'ekf.init_att_sigma_rad': ('Initial roll and pitch uncertainty, rad.', 1e-5, 1.0,
                               _READ_ONLY),
    'ekf.init_yaw_sigma_rad': ('Initial heading uncertainty, rad.', 1e-6, 1.0, _READ_ONLY),
    'ekf.init_acc_bias_sigma_mps2': ('Initial accelerometer bias uncertainty, m/s^2.', 1e-5,
                                     5.0, _READ_ONLY),
    'ekf.gyr_rail_noise_rps': ('Rate by which the true rotation may exceed a clipped gyro '
                               'sample, rad/s.', 1e-6, 100.0, _READ_ONLY),
    'ekf.init_gyr_bias_sigma_rps': ('Initial gyroscope bias uncertainty, rad/s.', 1e-6, 1.0,
                                    _READ_ONLY),
    # HeadingAidParams
    'heading.hde_enabled': ('Heuristic drift elimination: at each stride along a dominant '
                            'direction (building file, else learned from the first stride), a '
                            'heading measurement towards it.', None, None, _READ_ONLY),
    'heading.hde_tolerance_deg': ('A stride within this of a dominant direction is taken to be '
                                  'along it, deg.', 0.5, 45.0, _READ_ONLY),
    'heading.hde_sigma_deg': ('Standard deviation of the HDE heading measurement, deg.', 0.01,
                              90.0, _READ_ONLY),
    'heading.hde_straight_strides': ('Strides before one whose directions must agree with it '
                                     'within the tolerance for HDE (a straight walk).', 1, 20,
                                     _READ_ONLY),
    'heading.zaru_enabled': ('Zero angular rate update of the gyro bias at each stance sample '
                             'while the foot stands still.',
                             None, None, _READ_ONLY),
    'heading.zaru_max_gyr_rps': ('A stance is still for ZARU when no |w| of the detector window '
                                 'exceeds this, rad/s.', 1e-4, 1.0, _READ_ONLY),
    'heading.zaru_sigma_rps': ('Standard deviation of the ZARU measurement of one sample '
                               '(a standing foot sways), rad/s.', 1e-6, 1.0,
                               _READ_ONLY),
    'heading.min_stride_m': ('Shorter strides have no direction for HDE, m.', 0.05, 2.0,
                             _READ_ONLY),
    # GaitParams
    'gait.min_swing_s': ('Shorter swings make no gait cycle, s.', 0.02, 10.0, _READ_ONLY),
    'gait.max_swing_s': ('Longer swings make an invalid gait cycle (bounds the swing buffer), '
                         's.', 0.02, 10.0, _READ_ONLY),
    'gait.min_stride_m': ('Shorter horizontal strides say nothing of the forward axis, m.', 0.05,
                          2.0, _READ_ONLY),
    'gait.mounting_strides': ('Strides averaged by the automatic mounting mode.', 1, 100,
                              _READ_ONLY),
    # GateParams
    'gate.acc_range_mps2': ('Accelerometer full scale, m/s^2 (16 g); components at it are '
                            'saturated.', 19.6133, 1000.0, _LIVE),
    'gate.gyr_range_rps': ('Gyroscope full scale, rad/s (2000 deg/s); components at it are '
                           'saturated.', 1.0, 40.0, _LIVE),
    'gate.reject_saturated': ('Refuse saturated samples (false: accept them and count them).',
                              None, None, _LIVE),
    'gate.frame_id': ("Expected header.frame_id of the Imu messages; others are refused ('' "
                      'accepts any).', None, None, _LIVE),
    'gate.max_future_jump_s': ('A stamp further ahead of the last one is refused until 3 '
                               'samples confirm it, s.', 0.005, 3600.0, _LIVE),
    # ElevationParams
    'elevation.step_height_m': ('Stair step height K of eq. (14), m: the prior of the online '
                                "estimate (a building file's riser height replaces both).", 0.10,
                                0.25, _LIVE),
    'elevation.step_height_sigma_m': ('Width of the prior of K around step_height_m, m; 0 takes '
                                      'step_height_m as known (no online estimate).', 0.0, 0.1,
                                      _LIVE),
    'elevation.mode_threshold': ('Stair-mode threshold sigma_th of eq. (13); negative: the '
                                 "model's own (chosen in training, in its metadata).", -1.0, 1.0,
                                 _LIVE),
    'elevation.floor_height_m': ('Storey height H without a building file, m: the guess of the '
                                 'floor index (certain only where floor_height_min_m and '
                                 'floor_height_max_m agree).', 2.0, 20.0, _LIVE),
    'elevation.start_floor': ('Floor of the start point (changing it shifts the floor index).',
                              -100, 1000, _LIVE),
    'elevation.start_height_m': ('Height of the start point above its floor reference, m.',
                                 -1000.0, 1000.0, _READ_ONLY),
    'elevation.floor_height_min_m': ('Lowest plausible storey without a building file, m: the '
                                     'floor is certain only where every storey height from '
                                     'floor_height_min_m to floor_height_max_m, counted from '
                                     'the start and the floors walked, gives the same floor '
                                     '(floor_height_m is the guess in between).', 2.0, 20.0,
                                     _LIVE),
    'elevation.floor_height_max_m': ('Highest plausible storey without a building file, m.',
                                     2.0, 20.0, _LIVE),
    'elevation.lobby_height_max_m': ('How tall the ground storey (floor 0 to 1) can be without '
                                     'a building file, m; at most floor_height_max_m: no taller '
                                     'than the others.', 0.0, 20.0, _LIVE),
    'elevation.floor_tolerance_m': ('The floor changes at a level cycle whose height is this '
                                    "close to the floor's elevation, m (else it is not "
                                    'certain).', 0.05, 1.5, _LIVE),
    # BuildingAidParams
    'building_aid.align_strides': ("With a building's start: strides whose direction is taken "
                                   'as start.heading_deg (the map frame is fixed after them).',
                                   1, 50, _READ_ONLY),
    'building_aid.stair_fix_ratio': ('Stair-entry association threshold th_st = ratio x '
                                     'distance walked since the last correction (seed 003 eq. '
                                     '18).', 0.0, 1.0, _READ_ONLY),
    'building_aid.stair_fix_sigma_m': ('Standard deviation of a stair-entry position fix, m.',
                                       0.01, 10.0, _READ_ONLY),
    'building_aid.stair_fix_delay_s': ('A stair-entry correction is applied at the first stance '
                                       'sample this much sensor time after its gait cycle, s '
                                       '(above the classifier latency).', 0.05, 10.0,
                                       _READ_ONLY),
}

_PERSISTENCE = (
    ParamSpec('persist_state', True, 'Write the tracking state at every gait cycle and resume '
              'from it at start when fresh and from the same source.'),
    ParamSpec('state_dir', '', "Directory of the node's state file; '' is "
              '$ROS_HOME/anfis_elevation_ros (~/.ros/anfis_elevation_ros).'),
    ParamSpec('state_max_age_s', 300.0, 'A saved state older than this is not resumed, s (0: '
              'never resume).', 0.0, 86400.0),
    ParamSpec('resume_max_gap_s', 30.0, 'A saved state is resumed only when the first sensor '
              'stamp after the start follows its own by at most this, s (a restart, not '
              'another walk, a replay or a reset sensor clock).', 0.0, 3600.0),
    ParamSpec('cycle_history', 3600, 'Gait cycles kept for a late or restarted classifier '
              '(transient local), messages; about an hour of walking.', 1, 100000),
)
_MODEL_PATH = ParamSpec('model_path', '', 'Stair-classifier model JSON file (forest or ANFIS, '
                        "by its format key); '' is the packaged config/forest_default.json.")
_BUILDING_FILE = ParamSpec('building_file', '', 'Building file of the incident (YAML, format '
                           "anfis_elevation_ros/building: floors, stairs, entrance); '' for "
                           'none.')
_MAP_FRAME_ID = ParamSpec('map_frame_id', 'map', 'Frame of building coordinates (REP 105 '
                          'map): the elevation points, and the foot track and gait cycles when '
                          'the building file has a start.')
_IMU_NODE_ONLY = (
    ParamSpec('imu_topic', 'imu/data', 'sensor_msgs/Imu topic to subscribe to (relative: in the '
              "node's namespace, /imu/data without one, /ff1/imu/data under /ff1)."),
    ParamSpec('imu_qos_depth', 2000, 'Depth of the Imu subscription queue, messages (5 s of a '
              '400 Hz sensor: a busy CPU or slow disk must not drop samples).', 1, 10000),
    ParamSpec('imu_batch_period_s', 0.008, 'Imu messages are taken in batches this often, s '
              '(at 400 Hz about a fifth less CPU than one callback per message, for at most this '
              'much more latency); 0 handles each message in its own callback.', 0.0, 0.05),
    ParamSpec('odom_frame_id', 'odom', 'Frame of the published foot track and gait cycles '
              'without a building start (REP 105).'),
    _MAP_FRAME_ID,
    ParamSpec('track_rate_hz', 10.0, 'Rate of the foot_odom track, Hz; 0 publishes none.', 0.0,
              100.0),
    ParamSpec('centre_track_rate_hz', 2.0, 'Rate of foot_odom_throttle, the same track thinned '
              'for the command centre over a radio network (breadcrumbs a stride apart), Hz; 0 '
              'publishes none.', 0.0, 100.0),
    ParamSpec('diagnostics_rate_hz', 1.0, 'Rate of the /diagnostics status, Hz.', 0.1, 10.0),
    _BUILDING_FILE,
) + _PERSISTENCE
_CLASSIFIER_NODE_ONLY = (
    _MODEL_PATH,
    _MAP_FRAME_ID,
    _BUILDING_FILE,
) + _PERSISTENCE
_COMMAND_CENTRE_SPECS = (
    _BUILDING_FILE,
    ParamSpec('host', '127.0.0.1', 'Address the web page is served on; one other than the '
              'loopback needs TLS (tls_cert_file, tls_key_file) or insecure.'),
    ParamSpec('port', 8088, 'TCP port of the web page; 0 picks a free one.', 0, 65535),
    ParamSpec('insecure', False, 'Serve plain HTTP on an address other than the loopback (a '
              'closed network only: the session token would cross it in clear).'),
    ParamSpec('tls_cert_file', '', "PEM certificate of the web page (HTTPS); '' for none."),
    ParamSpec('tls_key_file', '', "PEM private key of tls_cert_file; '' for none."),
    ParamSpec('discovery_period_s', 1.0, 'The ROS graph is searched for new responders (a '
              "namespace publishing 'elevation') this often, s.", 0.1, 60.0),
    ParamSpec('tick_rate_hz', 4.0, 'Rate at which the alarm timers are evaluated, Hz.', 0.5,
              20.0),
    ParamSpec(ALARM_PREFIX + 'no_motion_prealarm_s', 20.0, 'Time without motion before the '
              'man-down pre-alarm, s (PASS devices: 20 s).', 0.5, 600.0),
    ParamSpec(ALARM_PREFIX + 'no_motion_alarm_s', 30.0, 'Time without motion before the man-down '
              'alarm, s (PASS devices: about 30 s); at least the pre-alarm time.', 0.5, 600.0),
    ParamSpec(ALARM_PREFIX + 'motion_threshold_m', 0.3, 'A move of the foot larger than this '
              'from where it last moved is motion, m.', 0.05, 5.0),
    ParamSpec(ALARM_PREFIX + 'lost_contact_s', 10.0, 'Time without any message from a '
              'responder before the lost-contact alarm, s.', 0.5, 600.0),
    ParamSpec(ALARM_PREFIX + 'floor_unknown_s', 30.0, 'Time with the floor uncertain before the '
              'floor-unknown alarm, s.', 0.5, 3600.0),
)


def _param_value(value):
    """Return a dataclass field value as a parameter value (None mounting -> empty array)."""
    if value is None:
        return ()
    if isinstance(value, (list, tuple)):
        return tuple(float(v) for v in value)
    return value


def _dataclass_specs(instance, prefix: str, skip=()):
    specs = []
    for f in fields(instance):
        value = getattr(instance, f.name)
        if f.name in skip:
            continue
        name = prefix + f.name
        if is_dataclass(value):
            specs.extend(_dataclass_specs(value, name + '.'))
            continue
        if name not in _DOCS:
            raise RuntimeError(f'parameter {name} has no entry in core/params.py _DOCS')
        description, low, high, read_only = _DOCS[name]
        specs.append(ParamSpec(name, _param_value(value), description, low, high, read_only))
    return specs


_NAVIGATOR_SPECS = tuple(_dataclass_specs(NavigatorParams(), ''))
_GATE_SPECS = tuple(_dataclass_specs(GateParams(), GATE_PREFIX, skip=SHARED_GATE_FIELDS))
_ELEVATION_SPECS = tuple(_dataclass_specs(ElevationParams(), ELEVATION_PREFIX))
_AID_SPECS = tuple(_dataclass_specs(BuildingAidParams(), BUILDING_AID_PREFIX))
_NODE_SPECS = {
    IMU_NODE: {s.name: s for s in _NAVIGATOR_SPECS + _GATE_SPECS + _IMU_NODE_ONLY
               + tuple(a for a in _AID_SPECS if a.name not in CLASSIFIER_AIDS)},
    CLASSIFIER_NODE: {s.name: s for s in _ELEVATION_SPECS + _CLASSIFIER_NODE_ONLY
                      + tuple(a for a in _AID_SPECS if a.name in CLASSIFIER_AIDS)},
    COMMAND_CENTRE_NODE: {s.name: s for s in _COMMAND_CENTRE_SPECS},
}
_ALL_SPECS = {name: spec for node in NODE_NAMES for name, spec in _NODE_SPECS[node].items()}
if set(_DOCS) - set(_ALL_SPECS):
    raise RuntimeError(f'_DOCS names no field: {sorted(set(_DOCS) - set(_ALL_SPECS))}')


def node_specs(node_name: str) -> dict:
    """Return {name: ParamSpec} of the parameters a node declares (IMU_NODE, CLASSIFIER_NODE)."""
    try:
        return dict(_NODE_SPECS[node_name])
    except KeyError:
        raise InputError(f'unknown node {node_name!r}; the nodes are {", ".join(NODE_NAMES)}') \
            from None


def all_specs() -> dict:
    """Return {name: ParamSpec} of every parameter of every node."""
    return dict(_ALL_SPECS)


# -- validation -------------------------------------------------------------------------------

def _unknown(name: str, known, where: str) -> InputError:
    close = difflib.get_close_matches(name, list(known), n=1)
    hint = f'; did you mean {close[0]!r}?' if close else '; see config/params.yaml for the list'
    return InputError(f'unknown parameter {name!r}{where}{hint}')


def _is_real(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, numbers.Integral))


def _range_text(spec: ParamSpec) -> str:
    return f'[{spec.min_value:g}, {spec.max_value:g}]'


def validate_value(spec: ParamSpec, value):
    """
    Check a value against its parameter's type and range; return it normalised.

    Integers are not accepted for a double (ROS 2 refuses them too: write 400.0); a
    double_array accepts a list, tuple or array of floats, and None or an empty one (returned
    as ``()``).

    Parameters
    ----------
    spec : ParamSpec
        The parameter.
    value : object
        The value as read from YAML or from a ROS parameter.

    Returns
    -------
    The value as a bool, int, float, str or tuple of float.

    Raises
    ------
    InputError : naming the parameter, the value and what is expected.

    """
    kind = spec.kind
    if kind == 'bool':
        if not isinstance(value, bool):
            raise InputError(f'{spec.name} = {value!r} must be true or false')
        return value
    if kind == 'string':
        if not isinstance(value, str):
            raise InputError(f'{spec.name} = {value!r} must be a string (quote it)')
        return value
    if kind == 'double_array':
        return _validate_array(spec, value)
    if kind == 'int':
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise InputError(f'{spec.name} = {value!r} must be an integer')
        value = int(value)
    else:
        if isinstance(value, numbers.Integral) and not isinstance(value, bool):
            raise InputError(f'{spec.name} = {value!r} is an integer but must be a floating-point '
                             f'number: write {value}.0 (ROS 2 parameters are typed)')
        if not _is_real(value):
            raise InputError(f'{spec.name} = {value!r} must be a floating-point number')
        value = float(value)
        if not math.isfinite(value):
            raise InputError(f'{spec.name} = {value!r} must be finite')
    if spec.min_value is not None and not spec.min_value <= value <= spec.max_value:
        raise InputError(f'{spec.name} = {value!r} is outside {_range_text(spec)}')
    return value


def _validate_array(spec: ParamSpec, value):
    if value is None:
        return ()
    if isinstance(value, (str, bytes)) or not hasattr(value, '__len__'):
        raise InputError(f'{spec.name} = {value!r} must be a list of floating-point numbers '
                         '([] for automatic)')
    items = list(value)
    if any(isinstance(v, numbers.Integral) for v in items):
        fixed = ', '.join(f'{float(v)!r}' for v in items if isinstance(v, numbers.Real))
        raise InputError(f'{spec.name} = {items!r} holds integers; write floating-point numbers, '
                         f'e.g. [{fixed}] (ROS 2 parameters are typed)')
    if not all(_is_real(v) and math.isfinite(v) for v in items):
        raise InputError(f'{spec.name} = {items!r} must hold finite floating-point numbers')
    if spec.name == 'mounting_rpy_deg' and len(items) not in (0, 3):
        raise InputError(f'mounting_rpy_deg = {items!r} must be 3 angles (roll, pitch, yaw, '
                         'deg) or [] for automatic mounting')
    if spec.min_value is not None and not all(spec.min_value <= v <= spec.max_value
                                              for v in items):
        raise InputError(f'{spec.name} = {items!r}: every element must be in '
                         f'{_range_text(spec)}')
    return tuple(float(v) for v in items)


def is_ros_owned(name: str) -> bool:
    """Tell whether rclpy itself handles a parameter (use_sim_time, qos_overrides.*, ...)."""
    return name in ROS_OWNED_PARAMETERS or name.startswith('qos_overrides.')


def _validated(flat: dict, specs: dict, where: str = '') -> dict:
    """Check names against every known parameter and values against their specs."""
    values = {}
    for name, value in flat.items():
        if is_ros_owned(name):
            continue
        if name not in _ALL_SPECS:
            raise _unknown(name, _ALL_SPECS, where)
        if name in specs:
            values[name] = validate_value(specs[name], value)
    return values


def _build(group: str, make):
    """Call make(); turn a dataclass's ValueError into an InputError naming the group."""
    try:
        return make()
    except ValueError as err:          # InputError is a ValueError too
        raise InputError(f'{group} parameters: {err}') from None


def _fill(instance, values: dict, prefix: str):
    """Return the dataclass with the fields named in values (prefix-relative paths) replaced."""
    changes = {}
    for f in fields(instance):
        current = getattr(instance, f.name)
        name = prefix + f.name
        if is_dataclass(current):
            changes[f.name] = _fill(current, values, name + '.')
        elif name in values:
            value = values[name]
            if f.name == 'mounting_rpy_deg':
                value = value or None
            changes[f.name] = value
    return replace(instance, **changes)


def navigator_params_from_dict(flat: dict) -> NavigatorParams:
    """
    Build NavigatorParams from flat parameters (missing names keep their defaults).

    Parameters
    ----------
    flat : dict
        {dotted name: value}; names of other groups (gate., elevation., node-level) are
        ignored, unknown names are refused.

    Raises
    ------
    InputError : an unknown name, a wrong type, a value out of range, or inconsistent values
        (e.g. gait.min_swing_s >= gait.max_swing_s).

    """
    specs = {s.name: s for s in _NAVIGATOR_SPECS}
    values = _validated(flat, specs)
    # _fill rebuilds every nested dataclass, so their __post_init__ checks (min_threshold <=
    # max_threshold, ...) run on the new values.
    return _build('navigator', lambda: _fill(NavigatorParams(), values, ''))


def elevation_params_from_dict(flat: dict) -> ElevationParams:
    """
    Build ElevationParams from flat ``elevation.*`` parameters (others are ignored).

    Parameters
    ----------
    flat : dict
        {dotted name: value}.

    Raises
    ------
    InputError : an unknown name, a wrong type, a value out of range.

    """
    specs = {s.name: s for s in _ELEVATION_SPECS}
    values = _validated(flat, specs)
    return _build('elevation', lambda: _fill(ElevationParams(), values, ELEVATION_PREFIX))


def building_aid_params_from_dict(flat: dict) -> BuildingAidParams:
    """
    Build BuildingAidParams from flat ``building_aid.*`` parameters (others are ignored).

    Raises
    ------
    InputError : an unknown name, a wrong type, a value out of range.

    """
    values = _validated(flat, {s.name: s for s in _AID_SPECS})
    return _build('building_aid', lambda: _fill(BuildingAidParams(), values,
                                                BUILDING_AID_PREFIX))


def gate_params_from_dict(flat: dict) -> GateParams:
    """
    Build GateParams from flat ``gate.*`` parameters and the navigator's ``max_gap_s``.

    Parameters
    ----------
    flat : dict
        {dotted name: value}.

    Raises
    ------
    InputError : an unknown name, a wrong type, a value out of range.

    """
    specs = {s.name: s for s in _GATE_SPECS}
    specs['max_gap_s'] = _ALL_SPECS['max_gap_s']
    values = _validated(flat, specs)
    values.update({GATE_PREFIX + field: values[name]
                   for field, name in SHARED_GATE_FIELDS.items() if name in values})
    return _build('gate', lambda: _fill(GateParams(), values, GATE_PREFIX))


# -- YAML -------------------------------------------------------------------------------------

class _RosYamlLoader(yaml.SafeLoader):
    """SafeLoader that types plain scalars as rcl does: 1.2e7 and 1e-5 are doubles, ints int64."""

    def construct_yaml_int(self, node):
        """Construct an integer; refuse one beyond int64, as rcl does."""
        try:
            value = super().construct_yaml_int(node)
        except ValueError:          # more than 4300 digits
            value = None
        if value is None or not -2 ** 63 <= value < 2 ** 63:
            text = node.value if len(node.value) <= 30 else node.value[:30] + '...'
            raise yaml.constructor.ConstructorError(
                None, None, f'integer {text} does not fit in 64 bits', node.start_mark)
        return value


_RosYamlLoader.add_constructor('tag:yaml.org,2002:int', _RosYamlLoader.construct_yaml_int)

_FLOAT_RE = re.compile(r'^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)(?:[eE][-+]?[0-9]+)?$'
                       r'|^[-+]?\.(?:inf|Inf|INF)$|^\.(?:nan|NaN|NAN)$')
_RosYamlLoader.add_implicit_resolver('tag:yaml.org,2002:float', _FLOAT_RE,
                                     list('-+0123456789.'))
# Keep integers integers: the int resolver must win for plain digits.
_RosYamlLoader.yaml_implicit_resolvers = {
    key: sorted(resolvers, key=lambda r: r[0] != 'tag:yaml.org,2002:int')
    for key, resolvers in _RosYamlLoader.yaml_implicit_resolvers.items()}


def _flatten(tree: dict, prefix: str, out: dict, where: str):
    for key, value in tree.items():
        if not isinstance(key, str):
            raise InputError(f'{where}: parameter name {key!r} is not a string')
        name = prefix + key
        if isinstance(value, dict):
            _flatten(value, name + '.', out, where)
        else:
            out[name] = value


def _node_entries(tree: dict, namespace: str, out: dict, where: str):
    for key, value in tree.items():
        if not isinstance(key, str) or not isinstance(value, dict):
            raise InputError(f'{where}: expected "<node name>: ros__parameters: {{...}}" at the '
                             f'top, got {key!r}: {type(value).__name__}')
        node_key = f'{namespace}/{key.strip("/")}' if namespace else key.strip('/')
        if 'ros__parameters' in value:
            extra = sorted(set(value) - {'ros__parameters'})
            if extra:
                raise InputError(f'{where}: node {key!r} has {extra} beside ros__parameters')
            params = value['ros__parameters']
            if params is None:
                params = {}
            if not isinstance(params, dict):
                raise InputError(f'{where}: {key}.ros__parameters must be a map of parameters')
            flat = {}
            _flatten(params, '', flat, where)
            out[node_key] = flat
        else:
            _node_entries(value, node_key, out, where)


def _is_wildcard(node_key: str) -> bool:
    return '*' in node_key


def _key_matches(node_key: str, node_name: str) -> bool:
    """Tell whether a YAML node key (no leading /) applies to a node in the root namespace."""
    # A run of 3+ stars matches what '**' does; collapsed, as '.*.*...' backtracks
    # exponentially on a key that does not match.
    node_key = re.sub(r'\*{3,}', '**', node_key)
    # '**/' is any namespace, the root included (rcl: '/**/imu_node' matches '/imu_node').
    pattern = ''.join('(?:.*/)?' if part == '**/' else '.*' if part == '**' else
                      '[^/]*' if part == '*' else re.escape(part)
                      for part in re.split(r'(\*\*/|\*\*|\*)', node_key))
    return re.fullmatch(pattern, node_name) is not None or node_key == node_name


def _nodes_of_key(node_key: str):
    """Nodes a YAML key applies to: any of ours for a wildcard, else by the base name."""
    if _is_wildcard(node_key):
        return [n for n in NODE_NAMES if _key_matches(node_key.rsplit('/', 1)[-1], n)]
    base = node_key.rsplit('/', 1)[-1]
    return [base] if base in NODE_NAMES else []


def load_params_yaml(path) -> dict:
    """
    Read a ROS 2 parameter YAML file and validate it.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    {node key: {dotted name: value}} as written in the file (keys without a leading '/',
    e.g. 'imu_node', '**', 'ns/classifier_node'), values validated and normalised.

    Raises
    ------
    InputError : missing or unreadable file, invalid YAML, not the ROS 2 parameter layout, a
        node other than imu_node / classifier_node, an unknown parameter, a wrong type, a value
        out of range, inconsistent values.

    """
    where = str(path)
    try:
        with open(path, 'rb') as stream:
            data = stream.read(MAX_YAML_BYTES + 1)
    except OSError as err:
        raise InputError(f'cannot read parameter file {where!r}: {err.strerror or err}') \
            from None
    if len(data) > MAX_YAML_BYTES:
        raise InputError(f'parameter file {where!r} is larger than {MAX_YAML_BYTES} bytes')
    try:
        tree = yaml.load(data.decode('utf-8'), Loader=_RosYamlLoader)   # noqa: S506 safe loader
    # ValueError: a date that does not exist, such as 2024-13-45.
    except (yaml.YAMLError, UnicodeDecodeError, ValueError) as err:
        message = ' '.join(str(err).split())       # PyYAML's messages span several lines
        raise InputError(f'{where} is not valid YAML: {message}') from None
    except RecursionError:
        raise InputError(f'{where}: the YAML is nested too deeply') from None
    if tree is None:
        return {}
    if not isinstance(tree, dict):
        raise InputError(f'{where}: expected "<node name>: ros__parameters: {{...}}", got a '
                         f'{type(tree).__name__}')
    entries = {}
    try:
        _node_entries(tree, '', entries, where)
    except RecursionError:      # a map that holds itself through an alias: &a {x: *a}
        raise InputError(f'{where}: maps nested too deeply (a recursive alias?)') from None
    result = {}
    for node_key, flat in entries.items():
        nodes = _nodes_of_key(node_key)
        if not nodes:
            raise InputError(f'{where}: unknown node {node_key!r}; the nodes are '
                             f'{", ".join(NODE_NAMES)} (or /** for all)')
        specs = {}
        for node in nodes:
            specs.update(_NODE_SPECS[node])
        where_node = f' for node {node_key!r} in {where}'
        for name in flat:
            if name not in specs and not is_ros_owned(name):
                raise _unknown(name, specs, where_node)
        try:
            result[node_key] = _validated(flat, specs)
        except InputError as err:
            raise InputError(f'{where}, node {node_key!r}: {err}') from None
    for node in NODE_NAMES:
        try:
            _check_node_consistent(node, node_params(result, node))
        except InputError as err:
            raise InputError(f'{where}: {err}') from None
    return result


def node_params(per_node: dict, node_name: str) -> dict:
    """
    Merge the entries of ``load_params_yaml`` that apply to a node in the root namespace.

    Wildcard entries (``/**``) first, then the node's own entry (which wins), as rcl does.

    Returns
    -------
    {dotted name: value} of that node's parameters given in the file.

    """
    specs = node_specs(node_name)
    merged = {}
    for wildcard in (True, False):
        for node_key, flat in per_node.items():
            if _is_wildcard(node_key) == wildcard and _key_matches(node_key, node_name):
                merged.update({k: v for k, v in flat.items() if k in specs})
    return merged


def _check_node_consistent(node_name: str, flat: dict):
    if node_name == IMU_NODE:
        navigator_params_from_dict(flat)
        gate_params_from_dict(flat)
    elif node_name == COMMAND_CENTRE_NODE:
        check_command_centre_params(flat)
    else:
        elevation_params_from_dict(flat)


def check_command_centre_params(flat: dict):
    """Raise InputError when the command centre's values (defaults filled in) do not agree."""
    specs = _NODE_SPECS[COMMAND_CENTRE_NODE]
    values = {name: flat.get(name, spec.default) for name, spec in specs.items()}
    if values['alarm.no_motion_alarm_s'] < values['alarm.no_motion_prealarm_s']:
        raise InputError('alarm.no_motion_alarm_s must not be less than '
                         'alarm.no_motion_prealarm_s')
    if bool(values['tls_cert_file']) != bool(values['tls_key_file']):
        raise InputError('tls_cert_file and tls_key_file go together: give both or neither')


def load_pipeline_params(path=None, building_file=None) -> PipelineParams:
    """
    Pipeline parameters from a parameter YAML (both nodes' sections), or the defaults.

    Parameters
    ----------
    path : str, Path or None
        ROS 2 parameter YAML as the nodes read; None gives the defaults.
    building_file : str, Path or None
        Building file given on the command line; it overrides the YAML's ``building_file``.

    Raises
    ------
    InputError : as ``load_params_yaml``, or the two nodes' sections name different building
        files.

    """
    per_node = load_params_yaml(path) if path is not None else {}
    imu = node_params(per_node, IMU_NODE)
    classifier = node_params(per_node, CLASSIFIER_NODE)
    if building_file is None:
        files = {imu.get('building_file', ''), classifier.get('building_file', '')} - {''}
        if len(files) > 1:
            raise InputError(f'{path}: imu_node and classifier_node name different building '
                             f'files ({", ".join(sorted(files))}); give both the same')
        building_file = files.pop() if files else ''
    return PipelineParams(navigator=navigator_params_from_dict(imu),
                          elevation=elevation_params_from_dict(classifier),
                          gate=gate_params_from_dict(imu),
                          model_path=classifier.get('model_path', ''),
                          building_file=str(building_file),
                          building_aid=building_aid_params_from_dict({**imu, **classifier}))


# -- files shipped with the package -----------------------------------------------------------

def config_search_paths(name: str) -> list:
    """
    Where a packaged config file is looked for, in order.

    1. ``<prefix>/share/anfis_elevation_ros/config/<name>`` for every prefix of
       AMENT_PREFIX_PATH holding the package's ament index marker (what
       ``ament_index_python.get_package_share_directory`` finds; a colcon install);
    2. ``sys.prefix/share/anfis_elevation_ros/config/<name>`` (a pip install);
    3. the source tree's ``config/<name>`` (a checkout or an editable install).
    """
    candidates = []
    for prefix in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep):
        if prefix and (Path(prefix) / 'share' / 'ament_index' / 'resource_index' / 'packages'
                       / PACKAGE).is_file():
            candidates.append(Path(prefix) / 'share' / PACKAGE / 'config' / name)
    candidates.append(Path(sys.prefix) / 'share' / PACKAGE / 'config' / name)
    candidates.append(Path(__file__).resolve().parents[2] / 'config' / name)
    return candidates


def find_config_file(name: str) -> Path:
    """
    Return the first existing packaged config file ``name`` (see ``config_search_paths``).

    Raises
    ------
    InputError : the file is in none of the places, listing them.

    """
    candidates = config_search_paths(name)
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    places = ', '.join(str(c) for c in candidates)
    raise InputError(f'packaged file config/{name} not found (looked in {places}); reinstall '
                     'the package or pass an explicit path')


def model_file(model_path: str = '') -> Path:
    """Return the model file a ``model_path`` parameter names ('' = the packaged default)."""
    return Path(model_path).expanduser() if model_path else find_config_file(DEFAULT_MODEL_FILE)


def load_model(model_path: str = ''):
    """
    Load the stair classifier a ``model_path`` parameter names.

    Parameters
    ----------
    model_path : str
        Path of a model JSON file (ANFIS or forest, ``core/classifier.py``); '' loads the
        packaged default.

    Returns
    -------
    StairClassifier.

    Raises
    ------
    InputError : no such file, unreadable or corrupt model, a model of unknown features.

    """
    from .classifier import load_classifier

    return load_classifier(model_file(model_path))


# -- config/params.yaml -----------------------------------------------------------------------

def _yaml_scalar(value) -> str:
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, str):
        plain = value and yaml.load(value, Loader=_RosYamlLoader) == value  # noqa: S506
        return value if plain else "'" + value.replace("'", "''") + "'"
    if isinstance(value, tuple):
        return '[' + ', '.join(_yaml_scalar(v) for v in value) + ']'
    if isinstance(value, float):
        text = repr(value)
        return text if ('.' in text or 'e' in text or 'n' in text) else text + '.0'
    return repr(value)


def _comment(spec: ParamSpec) -> str:
    extra = [f'Range {_range_text(spec)}.'] if spec.min_value is not None else []
    extra.append('Set at start.' if spec.read_only else 'Can change live.')
    return ' '.join([spec.description] + extra)


def params_yaml_text() -> str:
    """
    Render config/params.yaml: every parameter of every node, its default and a comment.

    Nested names are written as nested maps, as ROS 2 parameter files usually are. Each node
    is keyed ``/**/<node>``, so that the file applies in any namespace (``run --namespace``).
    """
    lines = ['# Parameters of the anfis_elevation_ros nodes, with their defaults.',
             '# Generated from anfis_elevation_ros/core/params.py (params_yaml_text); the',
             '# descriptions and ranges there are the ones the nodes declare and enforce.',
             '# Doubles need a decimal point (400.0): ROS 2 parameters are typed.']
    for node in NODE_NAMES:
        lines += ['', f'/**/{node}:', '  ros__parameters:']
        opened = []
        for spec in _NODE_SPECS[node].values():
            parts = spec.name.split('.')
            groups, leaf = parts[:-1], parts[-1]
            common = 0
            while common < min(len(opened), len(groups)) and opened[common] == groups[common]:
                common += 1
            opened = opened[:common]
            for group in groups[common:]:
                lines.append('    ' + '  ' * len(opened) + f'{group}:')
                opened.append(group)
            indent = '    ' + '  ' * len(opened)
            lines += textwrap.wrap(_comment(spec), width=99, initial_indent=indent + '# ',
                                   subsequent_indent=indent + '#   ')
            lines.append(f'{indent}{leaf}: {_yaml_scalar(spec.default)}')
    return '\n'.join(lines) + '\n'


__all__ = ['ALARM_PREFIX', 'building_aid_params_from_dict', 'check_command_centre_params',
           'CLASSIFIER_NODE', 'COMMAND_CENTRE_NODE', 'IMU_NODE', 'ParamSpec',
           'PipelineParams', 'all_specs',
           'config_search_paths', 'elevation_params_from_dict', 'find_config_file',
           'gate_params_from_dict', 'is_ros_owned', 'load_model', 'load_params_yaml',
           'load_pipeline_params', 'model_file', 'navigator_params_from_dict', 'node_params',
           'node_specs', 'params_yaml_text', 'validate_value']
