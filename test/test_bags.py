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

"""Tests of the bag helpers (rosbags, no ROS install) and of the simulate tool's output."""

import csv
import os

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.imu_data import ImuRecording
from anfis_elevation_ros.tools import bags
from anfis_elevation_ros.tools.cli import main
import numpy as np
import pytest

EPOCH_NS = 1_700_000_000_000_000_000


def make_recording(n=500, frame_id='imu_link', seed=0):
    """Random readings with irregular stamps (jitter, a gap) and extreme float64 values."""
    rng = np.random.default_rng(seed)
    stamp_ns = EPOCH_NS + np.cumsum(rng.integers(4_000_000, 6_000_001, n)).astype(np.int64)
    stamp_ns[n // 2:] += 3_000_000_123         # a 3 s gap crossing a second boundary
    acc_b = rng.normal(0.0, 20.0, (n, 3))
    gyr_b = rng.normal(0.0, 5.0, (n, 3))
    acc_b[0] = [np.finfo(float).tiny, -0.0, 1e300]
    gyr_b[0] = [np.nextafter(1.0, 2.0), -np.finfo(float).max, 5e-324]
    return ImuRecording(stamp_ns, acc_b, gyr_b, frame_id)


@pytest.mark.parametrize('storage', ['sqlite3', 'mcap'])
@pytest.mark.parametrize('frame_id', ['imu', 'imu_link', 'left_boot_imu_x'])
def test_imu_round_trip_is_exact(tmp_path, storage, frame_id):
    # frame_id lengths 3, 8, 15 put the float64 block at all the CDR alignment paddings.
    recording = make_recording(frame_id=frame_id)
    bags.write_imu_bag(tmp_path / 'bag', recording, storage=storage)
    back = bags.read_imu_bag(tmp_path / 'bag')
    assert back.frame_id == frame_id
    assert back.stamp_ns.dtype == np.int64
    assert np.array_equal(back.stamp_ns, recording.stamp_ns)
    # Bit-exact float64, including -0.0, subnormals and the largest values.
    assert back.acc_b.tobytes() == recording.acc_b.tobytes()
    assert back.gyr_b.tobytes() == recording.gyr_b.tobytes()
    # The storage file alone (no metadata.yaml) reads the same.
    storage_file = next(p for p in (tmp_path / 'bag').iterdir() if p.suffix in ('.db3', '.mcap'))
    assert storage_file.suffix == {'sqlite3': '.db3', 'mcap': '.mcap'}[storage]
    assert np.array_equal(bags.read_imu_bag(storage_file).stamp_ns, recording.stamp_ns)


def test_numpy_codec_agrees_with_rosbags(tmp_path):
    recording = make_recording(n=20, frame_id='foot')
    encoded = bags._encode_imu(recording, 1e-4, 2e-3)
    store = bags.typestore()
    for row in encoded:
        msg = store.deserialize_cdr(row.tobytes(), bags.IMU_MSGTYPE)
        assert bytes(store.serialize_cdr(msg, bags.IMU_MSGTYPE)) == row.tobytes()
    fast = bags._decode_imu([row.tobytes() for row in encoded])
    slow = bags._deserialize_imu([row.tobytes() for row in encoded])
    for name in ('stamp_ns', 'acc_b', 'gyr_b'):
        assert np.array_equal(getattr(fast, name), getattr(slow, name))
        assert np.array_equal(getattr(fast, name), getattr(recording, name))
    assert fast.frame_id == slow.frame_id == 'foot'


def test_imu_messages_follow_rep_145(tmp_path):
    recording = make_recording(n=30)
    bags.write_imu_bag(tmp_path / 'bag', recording, topic='/foot/imu', storage='mcap',
                       angular_velocity_variance=3e-5, linear_acceleration_variance=2e-3)
    messages = list(bags.read_messages(tmp_path / 'bag'))
    assert len(messages) == 30
    for (topic, log_ns, msg), stamp_ns in zip(messages, recording.stamp_ns):
        assert topic == '/foot/imu' and msg.__msgtype__ == 'sensor_msgs/msg/Imu'
        assert bags.ns_from_stamp(msg.header.stamp) == stamp_ns == log_ns
        assert msg.header.frame_id == 'imu_link'
        assert msg.orientation_covariance[0] == -1.0           # orientation not provided
        assert np.array_equal(msg.angular_velocity_covariance, np.diag([3e-5] * 3).ravel())
        assert np.array_equal(msg.linear_acceleration_covariance, np.diag([2e-3] * 3).ravel())
    # Default covariances are all zero: "unknown" (REP 145).
    bags.write_imu_bag(tmp_path / 'zero', recording)
    _, _, msg = next(iter(bags.read_messages(tmp_path / 'zero')))
    assert not np.any(msg.angular_velocity_covariance)
    assert not np.any(msg.linear_acceleration_covariance)


def test_generic_messages_round_trip_and_topic_choice(tmp_path):
    point_type = bags.msg_type('geometry_msgs/msg/PointStamped')
    header_type = bags.msg_type('std_msgs/msg/Header')
    int8_type = bags.msg_type('std_msgs/msg/Int8')
    recording = make_recording(n=10)
    with bags.BagWriter(tmp_path / 'out', storage='mcap') as bag:
        for k, stamp_ns in enumerate(recording.stamp_ns.tolist()):
            header = header_type(stamp=bags.stamp_from_ns(stamp_ns), frame_id='odom')
            point = bags.msg_type('geometry_msgs/msg/Point')(x=0.5 * k, y=0.0, z=-3.0)
            bag.write('/height', point_type(header=header, point=point), stamp_ns)
            bag.write('/floor', int8_type(data=-k), stamp_ns)
    floors = [(t, msg.data) for t, _, msg in bags.read_messages(tmp_path / 'out', ['/floor'])]
    assert floors == [('/floor', -k) for k in range(10)]
    heights = [msg for _, _, msg in bags.read_messages(tmp_path / 'out', ['/height'])]
    assert [h.point.x for h in heights] == [0.5 * k for k in range(10)]
    assert [bags.ns_from_stamp(h.header.stamp) for h in heights] == recording.stamp_ns.tolist()
    with pytest.raises(InputError, match='no.*Imu|0 sensor_msgs/msg/Imu'):
        bags.read_imu_bag(tmp_path / 'out')
    with pytest.raises(InputError, match='is std_msgs/msg/Int8, not sensor_msgs/msg/Imu'):
        bags.read_imu_bag(tmp_path / 'out', topic='/floor')
    with pytest.raises(InputError, match='unknown message type'):
        bags.msg_type('my_msgs/msg/Nothing')


def test_several_imu_topics_need_a_topic(tmp_path):
    left, right = make_recording(n=5, seed=1), make_recording(n=7, seed=2)
    with bags.BagWriter(tmp_path / 'two') as bag:
        for name, recording in (('/left/imu', left), ('/right/imu', right)):
            rows = bags._encode_imu(recording, 0.0, 0.0)
            for stamp_ns, row in zip(recording.stamp_ns.tolist(), rows):
                bag.write_raw(name, bags.IMU_MSGTYPE, row.tobytes(), stamp_ns)
    with pytest.raises(InputError, match='2 sensor_msgs/msg/Imu topics.*/left/imu, /right/imu'):
        bags.read_imu_bag(tmp_path / 'two')
    assert np.array_equal(bags.read_imu_bag(tmp_path / 'two', '/right/imu').acc_b, right.acc_b)
    with pytest.raises(InputError, match="no topic '/imu'"):
        bags.read_imu_bag(tmp_path / 'two', topic='/imu')


def test_mixed_frame_ids_are_refused(tmp_path):
    imu_type = bags.msg_type(bags.IMU_MSGTYPE)
    with bags.BagWriter(tmp_path / 'mixed') as bag:
        for k, frame in enumerate(('a', 'b')):
            msg = bags.typestore().deserialize_cdr(
                bags._encode_imu(make_recording(n=1, frame_id=frame), 0, 0)[0].tobytes(),
                bags.IMU_MSGTYPE)
            assert isinstance(msg, imu_type)
            bag.write('/imu/data', msg, EPOCH_NS + k)
    with pytest.raises(InputError, match='several frame_ids'):
        bags.read_imu_bag(tmp_path / 'mixed')


def _corrupt(path, how):
    """Damage the storage file of a bag directory: 'truncate' to half or 'garble' its head."""
    storage_file = next(p for p in path.iterdir() if p.suffix in ('.db3', '.mcap'))
    size = storage_file.stat().st_size
    with open(storage_file, 'r+b') as f:
        if how == 'truncate':
            f.truncate(size // 2)
        else:
            f.write(bytes(range(256)) * 16)
    return storage_file


@pytest.mark.parametrize('storage', ['sqlite3', 'mcap'])
@pytest.mark.parametrize('how', ['truncate', 'garble'])
def test_damaged_bags_raise_input_error(tmp_path, storage, how):
    bags.write_imu_bag(tmp_path / 'bag', make_recording(n=3000), storage=storage)
    storage_file = _corrupt(tmp_path / 'bag', how)
    with pytest.raises(InputError, match='corrupt or truncated|truncated'):
        bags.read_imu_bag(tmp_path / 'bag')
    with pytest.raises(InputError, match='corrupt or truncated|truncated'):
        bags.read_imu_bag(storage_file)


def test_fewer_messages_than_the_metadata_lists_is_truncation(tmp_path):
    # A recorder killed mid-write can leave a storage file that opens but lacks messages.
    bags.write_imu_bag(tmp_path / 'bag', make_recording(n=50))
    metadata = tmp_path / 'bag' / 'metadata.yaml'
    text = metadata.read_text()
    assert text.count('message_count: 50') == 3      # bag, file and topic counts
    metadata.write_text(text.replace('message_count: 50', 'message_count: 60'))
    with pytest.raises(InputError, match='truncated: read 50 of the 60 messages'):
        bags.read_imu_bag(tmp_path / 'bag')


def test_missing_and_non_bag_paths_raise_input_error(tmp_path):
    with pytest.raises(InputError, match='does not exist'):
        bags.read_imu_bag(tmp_path / 'missing')
    (tmp_path / 'empty').mkdir()
    with pytest.raises(InputError, match='no metadata.yaml'):
        bags.read_imu_bag(tmp_path / 'empty')
    (tmp_path / 'notes.txt').write_text('not a bag\n')
    with pytest.raises(InputError, match='not a rosbag2 bag'):
        bags.read_imu_bag(tmp_path / 'notes.txt')
    (tmp_path / 'fake.mcap').write_bytes(b'hello')
    with pytest.raises(InputError, match='not a rosbag2 bag'):
        bags.read_imu_bag(tmp_path / 'fake.mcap')
    with pytest.raises(InputError, match='does not exist'):
        list(bags.read_messages(tmp_path / 'missing'))


def test_writing_refuses_existing_paths_and_bad_options(tmp_path):
    recording = make_recording(n=3)
    bags.write_imu_bag(tmp_path / 'bag', recording)
    with pytest.raises(InputError, match='exists'):
        bags.write_imu_bag(tmp_path / 'bag', recording)
    with pytest.raises(InputError, match='storage'):
        bags.write_imu_bag(tmp_path / 'other', recording, storage='rosbag1')
    with pytest.raises(InputError, match='covariances'):
        bags.write_imu_bag(tmp_path / 'other', recording, angular_velocity_variance=-1.0)


def test_simulate_tool_writes_bag_and_truth(tmp_path, capsys):
    out = tmp_path / 'sim'
    rc = main(['simulate', '--scenario', 'sample', '--out', str(out), '--rate-hz', '100',
               '--imu', 'consumer', '--seed', '3', '--storage', 'mcap',
               '--mounting-rpy-deg', '180', '0', '0'])
    assert rc == 0
    assert '[simulate]' in capsys.readouterr().err
    recording = bags.read_imu_bag(out / 'imu')
    assert 60.0 < (recording.stamp_ns[-1] - recording.stamp_ns[0]) * 1e-9 < 90.0
    assert recording.acc_b[:100, 2].mean() < -9.0                    # z-down mounting at rest
    with open(out / 'truth.csv') as f:
        truth = list(csv.DictReader(f))
    assert list(truth[0]) == ['stamp_ns', 'x_m', 'y_m', 'z_m', 'qw', 'qx', 'qy', 'qz', 'stance']
    assert [int(row['stamp_ns']) for row in truth] == recording.stamp_ns.tolist()
    assert truth[0]['stance'] == '1' and float(truth[0]['z_m']) == 0.0
    with open(out / 'strides.csv') as f:
        strides = list(csv.DictReader(f))
    assert list(strides[0])[:5] == ['stamp_ns', 'mode', 'height_change_m', 'n_steps',
                                    'height_m']
    heights = [float(row['height_m']) for row in strides]
    assert max(heights) == pytest.approx(14 * 0.17, abs=1e-6)
    assert {row['mode'] for row in strides} == {'-1', '0', '1'}
    # A second run into the same directory refuses to overwrite the bag (exit code 1).
    assert main(['simulate', '--scenario', 'sample', '--out', str(out)]) == 1
    assert 'exists' in capsys.readouterr().err


def test_simulate_tool_is_repeatable_by_seed(tmp_path):
    for name, seed in (('a', 5), ('b', 5), ('c', 6)):
        assert main(['simulate', '--scenario', 'random', '--duration-s', '40', '--seed',
                     str(seed), '--rate-hz', '100', '--out', str(tmp_path / name)]) == 0
    a, b, c = (bags.read_imu_bag(tmp_path / n / 'imu') for n in 'abc')
    assert np.array_equal(a.acc_b, b.acc_b) and not np.array_equal(a.acc_b, c.acc_b)
    assert (tmp_path / 'a' / 'strides.csv').read_text() == \
        (tmp_path / 'b' / 'strides.csv').read_text()
    assert os.path.getsize(tmp_path / 'a' / 'truth.csv') > 0
