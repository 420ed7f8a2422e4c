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
Bad input through the live nodes: refused or handled as documented, counted, never garbage.

The nodes run in this process with one executor (fast), and receive their input over DDS
from a publisher in this process, in batches the subscription queue can hold. The clean input
is the first 14 s of the bundled sample walk (start-up and a handful of strides). For input
the gate refuses, the gait cycles the node publishes must equal, bit for bit, those of the
core navigator on the clean samples alone: the refused messages changed nothing. Every case
also checks the count in the published /diagnostics and that every published value is finite.
"""

import math
import subprocess
import sys
import time

from anfis_elevation_ros.core.navigator import FootNavigator, NavigatorParams
from anfis_elevation_ros.core.state import ElevationState, load_state, NavigationState
from anfis_elevation_ros.core.state import save_state, state_file
from anfis_elevation_ros.nodes.classifier_node import ClassifierNode
from anfis_elevation_ros.nodes.gait_cycle_msg import cycle_to_msg
from anfis_elevation_ros.nodes.imu_node import ImuNode
from anfis_elevation_ros.tools.bags import read_imu_bag
from anfis_elevation_ros.tools.ros_io import CycleListener, PLAYER_QOS
from live_support import cli_env, PACKAGE_ROOT, SAMPLE_BAG, write_linear_model
import numpy as np
import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from sensor_msgs.msg import Imu

CLEAN_SECONDS = 14.0
BATCH = 50
IMU_INPUT = '/imu_node: IMU input'
NAVIGATOR = '/imu_node: foot navigator'


@pytest.fixture(scope='module')
def clean():
    """(stamp_ns, acc_b, gyr_b) of the clean samples and the navigator's cycles on them."""
    rec = read_imu_bag(SAMPLE_BAG)
    n = int(CLEAN_SECONDS * rec.rate_hz)
    samples = [(int(rec.stamp_ns[k]), rec.acc_b[k].copy(), rec.gyr_b[k].copy())
               for k in range(n)]
    _, cycles = FootNavigator(NavigatorParams()).run(rec.stamp_ns[:n], rec.acc_b[:n],
                                                     rec.gyr_b[:n])
    assert len(cycles) >= 5, 'the clean part should hold several gait cycles'
    return samples, cycles


@pytest.fixture(scope='module')
def ros(tmp_path_factory):
    """Rclpy for this module, and a known model file."""
    rclpy.init()
    yield {'model': write_linear_model(tmp_path_factory.mktemp('model') / 'model.json')}
    rclpy.try_shutdown()


def imu_msg(stamp_ns, acc_b, gyr_b, frame_id='imu_link'):
    """Build the sensor_msgs/Imu of one sample."""
    msg = Imu()
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(int(stamp_ns), 1_000_000_000)
    msg.header.frame_id = frame_id
    msg.orientation_covariance[0] = -1.0
    a, w = msg.linear_acceleration, msg.angular_velocity
    a.x, a.y, a.z = (float(v) for v in acc_b)
    w.x, w.y, w.z = (float(v) for v in gyr_b)
    return msg


class LiveRun:
    """The nodes, a publisher and a listener in this process; results of one input stream."""

    def __init__(self, ros, overrides=None, classifier=False):
        params = [Parameter(k, value=v) for k, v in {'diagnostics_rate_hz': 10.0,
                                                     'persist_state': False,
                                                     **(overrides or {})}.items()]
        self.imu = ImuNode(parameter_overrides=params)
        self.nodes = [self.imu]
        self.classifier = None
        if classifier:
            self.classifier = ClassifierNode(parameter_overrides=[
                Parameter('model_path', value=str(ros['model'])),
                Parameter('persist_state', value=False)])
            self.nodes.append(self.classifier)
        self.listener = CycleListener()
        self.source = rclpy.create_node('bad_input_source')
        self.publisher = self.source.create_publisher(Imu, '/imu/data', PLAYER_QOS)
        self.nodes += [self.listener, self.source]
        self.executor = SingleThreadedExecutor()
        for node in self.nodes:
            self.executor.add_node(node)

    def spin_until(self, condition, timeout_s=10.0):
        deadline = time.monotonic() + timeout_s
        while not condition() and time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.01)
        return condition()

    def feed(self, messages):
        """Publish in batches the queue holds; wait until the node received each batch."""
        assert self.spin_until(lambda: self.publisher.get_subscription_count() >= 1
                               and self.listener.count_publishers('/gait_cycle') >= 1)
        self.spin_until(lambda: False, 0.3)                 # let discovery settle
        for start in range(0, len(messages), BATCH):
            batch = messages[start:start + BATCH]
            for msg in batch:
                self.publisher.publish(msg)
            received = start + len(batch)
            assert self.spin_until(lambda: self.imu._received >= received), \
                f'the node received {self.imu._received} of {received} messages'
        published = self.imu.navigator.status.cycles
        self.spin_until(lambda: len(self.listener.cycles) >= published, 5.0)
        # A diagnostics message published after the last input (one already in flight may
        # still be delivered after it, so check its count).
        self.listener.diagnostics.clear()
        self.imu._publish_diagnostics()
        assert self.spin_until(
            lambda: self.listener.diagnostic_value(IMU_INPUT, 'received') == str(len(messages))
            and NAVIGATOR in self.listener.diagnostics, 5.0)
        return self

    def close(self):
        for node in self.nodes:
            self.executor.remove_node(node)
            node.destroy_node()
        if self.nodes:
            self.executor.shutdown()
        self.nodes = []

    @property
    def cycles(self):
        return [c for c, _ in self.listener.cycles]

    def count(self, key, status=IMU_INPUT):
        return int(self.listener.diagnostic_value(status, key))

    def classifier_count(self, key):
        status = self.classifier.diagnostics(0).status[0]
        return int({kv.key: kv.value for kv in status.values}[key])


@pytest.fixture
def live(ros):
    """Make LiveRun objects; close them after the test."""
    runs = []

    def make(**kwargs):
        runs.append(LiveRun(ros, **kwargs))
        return runs[-1]

    yield make
    for run in runs:
        run.close()


def clean_messages(samples, frame_id='imu_link'):
    return [imu_msg(s, a, g, frame_id) for s, a, g in samples]


def assert_cycles_equal(published, expected):
    """Check that the published cycles are the navigator's on the clean samples, bit for bit."""
    assert len(published) == len(expected)
    for got, want in zip(published, expected):
        assert got.stamp_ns == want.stamp_ns
        assert got.valid == want.valid
        assert (got.x_m, got.y_m, got.z_m) == tuple(float(v) for v in want.pos_n)
        assert np.array_equal(got.features, want.features)


def assert_all_finite(run):
    for cycle in run.cycles:
        assert all(math.isfinite(v) for v in (cycle.x_m, cycle.y_m, cycle.z_m))
        assert np.all(np.isfinite(cycle.features))
    for item in run.listener.elevations:
        assert all(math.isfinite(v) for v in item[1:4])


@pytest.mark.parametrize('batch_period_s', [0.01, 0.0])
def test_clean_input_gives_the_navigator_cycles(live, clean, batch_period_s):
    """Baseline: clean input, nothing refused, the core navigator's cycles (batched or not)."""
    samples, cycles = clean
    run = live(overrides={'imu_batch_period_s': batch_period_s}).feed(clean_messages(samples))
    assert_cycles_equal(run.cycles, cycles)
    assert run.count('accepted') == len(samples)
    assert run.count('rejected') == 0
    level, _, values = run.listener.diagnostics[NAVIGATOR]
    assert values['initialised'] == 'true' and int(values['cycles']) == len(cycles)


def test_nan_and_inf_are_refused(live, clean):
    """Refuse NaN or Inf in any of the six values as non_finite; nothing else changes."""
    samples, cycles = clean
    ks = list(range(10, len(samples), 100))
    messages = clean_messages(samples)
    for i, k in reversed(list(enumerate(ks))):
        stamp, acc, gyr = samples[k]
        acc, gyr = acc.copy(), gyr.copy()
        (acc if i % 2 else gyr)[i % 3] = (math.nan, math.inf, -math.inf)[i % 3]
        messages.insert(k + 1, imu_msg(stamp + 1_000_000, acc, gyr))   # between two stamps
    run = live().feed(messages)
    assert run.count('rejected_non_finite') == len(ks)
    assert_cycles_equal(run.cycles, cycles)
    assert_all_finite(run)


def test_out_of_order_stamps_are_refused(live, clean):
    """A message stamped before the last accepted one is refused; the rest is unchanged."""
    samples, cycles = clean
    old = [imu_msg(samples[k][0] - 25_000_000, samples[k][1], samples[k][2])
           for k in range(50, len(samples), 97)]
    messages = clean_messages(samples)
    for i, k in reversed(list(enumerate(range(50, len(samples), 97)))):
        messages.insert(k + 1, old[i])
    run = live().feed(messages)
    assert run.count('rejected_out_of_order') == len(old)
    assert_cycles_equal(run.cycles, cycles)


def test_duplicate_stamps_are_refused(live, clean):
    """A second message with the last accepted stamp is refused as a duplicate."""
    samples, cycles = clean
    ks = list(range(20, len(samples), 61))
    messages = clean_messages(samples)
    for k in reversed(ks):
        stamp, acc, gyr = samples[k]
        messages.insert(k + 1, imu_msg(stamp, acc * 1.01, gyr))
    run = live().feed(messages)
    assert run.count('rejected_duplicate') == len(ks)
    assert_cycles_equal(run.cycles, cycles)


def test_gap_invalidates_its_cycle_and_is_counted(live, clean):
    """
    Samples missing for 150 ms in a swing: counted as a gap, that cycle invalid, not classified.

    The gap changes the track from there on, so the cycles after it are not compared with the
    clean run; they must still be finite, and the classifier must publish one elevation per
    valid cycle only.
    """
    samples, cycles = clean
    target = cycles[len(cycles) // 2]
    start = next(k for k, s in enumerate(samples) if s[0] > target.start_stamp_ns) + 10
    kept = samples[:start] + samples[start + 15:]                  # 150 ms at 100 Hz
    run = live(classifier=True).feed(clean_messages(kept))
    run.spin_until(lambda: False, 0.3)
    assert run.count('gap_count') == 1
    assert int(run.listener.diagnostic_value(NAVIGATOR, 'gaps')) == 1
    invalid = [c for c in run.cycles if not c.valid]
    assert [c.stamp_ns for c in invalid] == [target.stamp_ns]
    assert_cycles_equal(run.cycles[:cycles.index(target)], cycles[:cycles.index(target)])
    valid_stamps = [c.stamp_ns for c in run.cycles if c.valid]
    assert [e[0] for e in run.listener.elevations] == valid_stamps
    assert run.classifier_count('invalid_cycles') == 1
    assert_all_finite(run)


def test_random_message_loss_is_reported(live, clean):
    """
    10 % of the messages lost: estimated from the stamps, reported as a warning.

    Single lost samples (10 ms at 100 Hz) are not gaps: the cycles stay valid.
    """
    samples, cycles = clean
    kept = [s for s, r in zip(samples, np.random.default_rng(5).random(len(samples)))
            if r >= 0.1]
    run = live(overrides={'diagnostics_rate_hz': 0.1}).feed(clean_messages(kept))
    level, message, values = run.listener.diagnostics[IMU_INPUT]
    lost = len(samples) - len(kept)      # (a few are lost before navigation starts: not seen)
    assert 0.9 * lost <= int(values['missing_samples']) <= lost
    assert 0.08 < float(values['loss_fraction']) < 0.12
    assert level == b'\x01' and '% of samples lost' in message     # WARN
    assert all(c.valid for c in run.cycles) and len(run.cycles) == len(cycles)


def test_saturated_samples_are_accepted_and_flagged(live, clean):
    """At a 2 g full scale the heel strikes saturate: flagged, passed on unchanged."""
    samples, cycles = clean
    full_scale = 19.6133
    saturated = sum(1 for _, a, g in samples if np.max(np.abs(a)) >= 0.999 * full_scale)
    assert saturated > 10, 'the walk should exceed 2 g at some heel strikes'
    run = live(overrides={'gate.acc_range_mps2': full_scale}).feed(clean_messages(samples))
    assert run.count('saturated_count') == saturated
    assert run.count('rejected') == 0
    assert_cycles_equal(run.cycles, cycles)


def test_saturated_samples_can_be_refused(live, clean):
    """With gate.reject_saturated they are refused instead, and counted as such."""
    samples, _ = clean
    full_scale = 19.6133
    saturated = sum(1 for _, a, g in samples if np.max(np.abs(a)) >= 0.999 * full_scale)
    run = live(overrides={'gate.acc_range_mps2': full_scale, 'gate.reject_saturated': True})
    run.feed(clean_messages(samples))
    assert run.count('rejected_saturated') == saturated
    assert_all_finite(run)


def test_gyro_spikes_beyond_40_rps_are_refused(live, clean):
    """A few samples past any MEMS range are refused as wrong_units; the gate does not latch."""
    samples, cycles = clean
    ks = list(range(30, len(samples), 250))
    messages = clean_messages(samples)
    for k in reversed(ks):
        stamp, acc, gyr = samples[k]
        messages.insert(k + 1, imu_msg(stamp + 2_000_000, acc, gyr + 100.0))
    run = live().feed(messages)
    assert run.count('rejected_wrong_units') == len(ks)
    assert run.listener.diagnostic_value(IMU_INPUT, 'units_latched') == 'false'
    assert_cycles_equal(run.cycles, cycles)


def test_gyro_in_deg_per_s_latches_and_publishes_nothing(live, clean):
    """A deg/s stream: the gate latches, everything is refused, no cycle is published."""
    samples, _ = clean
    run = live().feed([imu_msg(s, a, np.degrees(g)) for s, a, g in samples])
    level, message, values = run.listener.diagnostics[IMU_INPUT]
    assert values['units_latched'] == 'true'
    assert level == b'\x02', message                                # ERROR
    assert int(values['rejected_wrong_units']) > len(samples) // 2
    assert run.cycles == []


def test_accelerometer_in_g_is_refused_by_the_navigator(live, clean):
    """Specific force in g: the navigator refuses to start; counted, the node stays up."""
    samples, _ = clean
    run = live().feed([imu_msg(s, a / 9.80665, g) for s, a, g in samples])
    assert run.count('rejected_wrong_units') >= 1
    assert run.listener.diagnostics[NAVIGATOR][2]['initialised'] == 'false'
    assert run.cycles == []


def test_wrong_frame_is_refused(live, clean):
    """With gate.frame_id set, messages of another frame are refused."""
    samples, cycles = clean
    ks = list(range(40, len(samples), 77))
    messages = clean_messages(samples)
    for k in reversed(ks):
        stamp, acc, gyr = samples[k]
        messages.insert(k + 1, imu_msg(stamp + 3_000_000, acc, gyr, frame_id='camera_link'))
    run = live(overrides={'gate.frame_id': 'imu_link'}).feed(messages)
    assert run.count('rejected_wrong_frame') == len(ks)
    assert_cycles_equal(run.cycles, cycles)


@pytest.mark.parametrize('gap_s, resumes, why', [
    (None, False, 'before the saved state'),         # a second play, or a reset sensor clock
    (60.0, False, 'limit resume_max_gap_s = 30 s'),  # taken up again much later
    (2.0, True, 'continue the saved state after')])  # a restart
def test_a_restart_resumes_only_when_the_sensor_stamps_continue(
        live, clean, tmp_path, gap_s, resumes, why):
    """
    A restarted node resumes only when its first IMU stamp continues the saved state.

    The same samples played again begin before the saved state; shifted to begin 60 s after it
    they begin beyond ``resume_max_gap_s``: both start fresh (cycle indices from 1, a new walk
    identity, the refusal counted and said in the diagnostics). Shifted to begin 2 s after it
    they continue it: the node resumes, its cycle indices and walk identity carry on, and it
    goes on saving its state.
    """
    samples, cycles = clean
    overrides = {'persist_state': True, 'state_dir': str(tmp_path)}
    first = live(overrides=overrides).feed(clean_messages(samples))
    first_walk = first.cycles[-1].walk_id
    first.close()
    saved = load_state(state_file(tmp_path, '/imu_node'), NavigationState)
    assert saved.cycles == len(cycles) and saved.stamp_ns == cycles[-1].stamp_ns
    assert saved.walk_id == first_walk

    shift_ns = 0 if gap_s is None else saved.stamp_ns + int(gap_s * 1e9) - samples[0][0]
    run = live(overrides=overrides).feed(clean_messages(
        [(stamp + shift_ns, acc, gyr) for stamp, acc, gyr in samples]))
    navigator = run.listener.diagnostics[NAVIGATOR][2]
    assert navigator['resumed'] == str(resumes).lower() and why in navigator['resume']
    assert navigator['resume_refusals'] == ('0' if resumes else '1')
    assert run.count('internal_errors') == 0
    assert len(run.cycles) >= len(cycles)
    first_index = len(cycles) + 1 if resumes else 1
    assert [c.index for c in run.cycles] == list(range(first_index,
                                                       first_index + len(run.cycles)))
    assert {c.walk_id for c in run.cycles} == ({first_walk} if resumes else
                                               {run.cycles[0].walk_id} - {first_walk})
    run.close()
    resaved = load_state(state_file(tmp_path, '/imu_node'), NavigationState)
    assert resaved.cycles == run.cycles[-1].index and resaved.walk_id == run.cycles[-1].walk_id
    assert resaved.stamp_ns == cycles[-1].stamp_ns + shift_ns
    assert 0.1 <= resaved.stride_period_s <= 3.0


def test_a_saved_floor_is_published_uncertain_and_without_a_floor_range(ros, tmp_path):
    """
    Publish a saved state's floor in doubt, with no floor range, until a gait cycle decides.

    The saved height is not yet the tracker's: the range of a fresh tracker (the start floor)
    would contradict the floor published.
    """
    save_state(state_file(str(tmp_path), '/classifier_node'), ElevationState(
        stamp_ns=1_700_000_000_000_000_000, wall_time_s=time.time(), source_id='/gait_cycle',
        height_m=6.12, floor=2, cycle_index=40, walk_id=1, step_height_m=0.17,
        riser_strides=36))
    classifier = ClassifierNode(parameter_overrides=[
        Parameter('model_path', value=str(ros['model'])), Parameter('persist_state', value=True),
        Parameter('state_dir', value=str(tmp_path))])
    listener = CycleListener()
    executor = SingleThreadedExecutor()
    for node in (classifier, listener):
        executor.add_node(node)
    try:
        deadline = time.monotonic() + 10.0
        while not (listener.floors and listener.floor_certain and listener.floor_ranges) \
                and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.01)
        assert (listener.floors[-1][0], listener.floor_certain[-1][0],
                listener.floor_ranges[-1][0]) == (2, False, [])
    finally:
        for node in (classifier, listener):
            executor.remove_node(node)
            node.destroy_node()
        executor.shutdown()


def test_malformed_cycle_message_is_skipped(live, clean):
    """
    A gait_cycle message of another layout is counted and not classified: no elevation.

    The same cycle in the right layout then is classified and its elevation reaches the
    listener, so the counters and the listener checked for the bad one could have seen it.
    """
    samples, cycles = clean
    assert cycles[0].valid
    run = live(classifier=True)
    assert run.spin_until(lambda: run.listener.count_publishers('elevation') >= 1)
    msg = cycle_to_msg(cycles[0], 'odom', 1, 1)
    msg.fields = msg.fields[:-1]
    run.classifier._on_cycle(msg)
    run.spin_until(lambda: False, 0.3)                  # time for an elevation to arrive
    assert run.classifier_count('malformed') == 1
    assert [run.classifier_count(key) for key in (
        'classified', 'invalid_cycles', 'already_counted', 'internal_errors')] == [0, 0, 0, 0]
    assert run.listener.elevations == []
    run.classifier._on_cycle(cycle_to_msg(cycles[0], 'odom', 1, 1))
    assert run.classifier_count('classified') == 1 and run.classifier_count('malformed') == 1
    assert run.spin_until(lambda: len(run.listener.elevations) == 1, 5.0)


def test_bad_parameter_changes_are_refused_with_a_reason(live):
    """Out of range, wrong type, read-only and inconsistent values are refused live."""
    run = live(classifier=True)
    imu, classifier = run.imu, run.classifier
    result = imu.set_parameters([Parameter('gate.acc_range_mps2', value=5.0)])[0]
    assert not result.successful and 'range' in result.reason.lower()
    result = imu.set_parameters([Parameter('rate_hz', value=400.0)])[0]
    assert not result.successful and 'read-only' in result.reason
    result = classifier.set_parameters([Parameter('elevation.step_height_m', value=0.5)])[0]
    assert not result.successful
    result = imu.set_parameters([Parameter('gate.frame_id', value=3)])[0]
    assert not result.successful
    assert imu.set_parameters([Parameter('use_sim_time', value=False)])[0].successful
    result = classifier.set_parameters([Parameter('elevation.start_floor', value=2)])[0]
    assert result.successful
    assert classifier.tracker.floor == 2
    run.spin_until(lambda: run.listener.floors and run.listener.floors[-1][0] == 2, 5.0)
    assert run.listener.floors[-1][0] == 2


@pytest.mark.parametrize('content', [None, '{"format": "anfis_elevation_ros.anfis", "vers'])
def test_classifier_refuses_a_missing_or_corrupt_model(content, tmp_path):
    """The classifier node exits with code 1 and says why, instead of running without a model."""
    model = tmp_path / 'model.json'
    if content is not None:
        model.write_text(content)
    result = subprocess.run(
        [sys.executable, '-m', 'anfis_elevation_ros.nodes.classifier_node', '--ros-args', '-p',
         f'model_path:={model}'],
        env=cli_env(), cwd=PACKAGE_ROOT, capture_output=True, text=True, timeout=60)
    assert result.returncode == 1, result.stdout + result.stderr
    assert ('not found' if content is None else 'not valid JSON') in result.stderr
