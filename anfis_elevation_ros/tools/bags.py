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
ROS 2 bags without a ROS install: IMU recordings in and out, and small generic helpers.

Uses the ``rosbags`` package with the ROS 2 Jazzy type store; bags are rosbag2 directories
(metadata version 9, as Jazzy writes) with sqlite3 or mcap storage. Reading also accepts a bare
``.db3`` or ``.mcap`` file.

sensor_msgs/msg/Imu follows REP 145: header.stamp is the sample time, orientation is unknown
(``orientation_covariance[0] = -1``), and a covariance of all zeros means "unknown".

Imu messages are encoded and decoded with numpy on their fixed CDR layout (little-endian CDR,
one frame_id), checked against the rosbags serializer in test_bags.py; anything else (another
encapsulation, mixed frame_ids) goes through rosbags' per-message deserializer. For a
10-minute 400 Hz recording (240 000 messages) this cuts reading from about 3 s to under 1 s and
writing from about 5 s to about 2 s on the development machine.

Public API: ``write_imu_bag``, ``read_imu_bag``, ``read_messages``, ``BagWriter``,
``typestore``, ``msg_type``, ``stamp_from_ns``, ``ns_from_stamp``.
"""

from collections import Counter
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import Reader, StoragePlugin, Writer, WriterError
from rosbags.typesys import get_typestore, Stores

from ..core.errors import InputError
from ..core.imu_data import ImuRecording

IMU_MSGTYPE = 'sensor_msgs/msg/Imu'
BAG_VERSION = 9                  # rosbag2 metadata version written by Jazzy
STORAGES = {'sqlite3': StoragePlugin.SQLITE3, 'mcap': StoragePlugin.MCAP}
_CDR_LE = b'\x00\x01\x00\x00'    # encapsulation header: plain CDR, little endian
_N_DOUBLES = 37                  # orientation 4 + covariance 9 + 2 x (vector 3 + covariance 9)
_TYPESTORE = []
# Reading a damaged bag, rosbags raises whatever its layers hit: ReaderError, SerdeError, the
# sqlite errors of apsw, struct.error, OverflowError or MemoryError for a garbled length,
# TypeError for a garbled metadata.yaml, ... Around the calls into rosbags that read a file or
# decode its bytes, every exception therefore means a bag that cannot be read (InputError).


def typestore():
    """Get the ROS 2 Jazzy type store, created on first use."""
    if not _TYPESTORE:
        _TYPESTORE.append(get_typestore(Stores.ROS2_JAZZY))
    return _TYPESTORE[0]


def msg_type(name: str):
    """Message class for a type name such as 'geometry_msgs/msg/PointStamped'."""
    try:
        return typestore().types[name]
    except KeyError:
        raise InputError(f'unknown message type {name!r} (not in the ROS 2 Jazzy type store)') \
            from None


def stamp_from_ns(stamp_ns: int):
    """builtin_interfaces/msg/Time of an integer stamp in nanoseconds."""
    sec, nanosec = divmod(int(stamp_ns), 1_000_000_000)
    return msg_type('builtin_interfaces/msg/Time')(sec=sec, nanosec=nanosec)


def ns_from_stamp(stamp) -> int:
    """Integer nanoseconds of a builtin_interfaces/msg/Time."""
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


# ----------------------------------------------------------------------------------------------
# Imu messages <-> arrays
# ----------------------------------------------------------------------------------------------

def _imu_layout(frame_id_bytes: bytes) -> tuple:
    """
    Byte length of an Imu CDR message and the offset of its first float64.

    Layout after the 4-byte encapsulation header (CDR aligns relative to its end):
    int32 sec, uint32 nanosec, uint32 len(frame_id)+1, frame_id, NUL, pad to 8,
    37 float64 (orientation xyzw, 9 cov, angular_velocity xyz, 9 cov, linear_acceleration xyz,
    9 cov).
    """
    end_of_string = 12 + len(frame_id_bytes) + 1
    doubles_at = 4 + -(-end_of_string // 8) * 8
    return doubles_at + 8 * _N_DOUBLES, doubles_at


def _encode_imu(recording: ImuRecording, gyr_var: float, acc_var: float) -> np.ndarray:
    """(N, L) uint8: the CDR bytes of one sensor_msgs/msg/Imu per sample."""
    frame = recording.frame_id.encode('utf-8')
    length, doubles_at = _imu_layout(frame)
    n = len(recording)
    buf = np.zeros((n, length), dtype=np.uint8)
    buf[:, :4] = np.frombuffer(_CDR_LE, dtype=np.uint8)
    sec, nanosec = np.divmod(np.asarray(recording.stamp_ns, dtype=np.int64), 1_000_000_000)
    if n and (sec.min() < -2**31 or sec.max() >= 2**31):
        raise InputError('IMU stamps do not fit builtin_interfaces/msg/Time (int32 seconds)')
    buf[:, 4:8] = sec.astype('<i4')[:, None].view(np.uint8)
    buf[:, 8:12] = nanosec.astype('<u4')[:, None].view(np.uint8)
    buf[:, 12:16] = np.frombuffer(np.array(len(frame) + 1, dtype='<u4').tobytes(), np.uint8)
    buf[:, 16:16 + len(frame)] = np.frombuffer(frame, dtype=np.uint8)
    doubles = np.zeros((n, _N_DOUBLES), dtype='<f8')
    doubles[:, 4] = -1.0                                # orientation unknown (REP 145)
    doubles[:, 13:16] = recording.gyr_b
    doubles[:, [16, 20, 24]] = gyr_var
    doubles[:, 25:28] = recording.acc_b
    doubles[:, [28, 32, 36]] = acc_var
    buf[:, doubles_at:] = doubles.view(np.uint8)
    return buf


def _decode_imu(raw: list) -> ImuRecording | None:
    """
    Decode Imu CDR messages with numpy.

    Returns None unless all messages share one plain little-endian layout and one frame_id
    (the caller then falls back to rosbags).
    """
    length = len(raw[0])
    if length < 16 or any(len(r) != length for r in raw):
        return None
    buf = np.frombuffer(b''.join(raw), dtype=np.uint8).reshape(len(raw), length)
    if np.any(buf[:, :4] != np.frombuffer(_CDR_LE, dtype=np.uint8)):
        return None
    string_len = int(buf[0, 12:16].view('<u4')[0])
    if string_len < 1 or 16 + string_len > length:
        return None
    frame_bytes = buf[0, 16:16 + string_len - 1].tobytes()
    if (_imu_layout(frame_bytes) != (length, length - 8 * _N_DOUBLES)
            or np.any(buf[:, 12:16 + string_len] != buf[0, 12:16 + string_len])
            or not _is_utf8(frame_bytes)):
        return None
    sec = buf[:, 4:8].copy().view('<i4')[:, 0].astype(np.int64)
    nanosec = buf[:, 8:12].copy().view('<u4')[:, 0].astype(np.int64)
    doubles = buf[:, length - 8 * _N_DOUBLES:].copy().view('<f8')
    return ImuRecording(stamp_ns=sec * 1_000_000_000 + nanosec,
                        acc_b=doubles[:, 25:28].astype(float),
                        gyr_b=doubles[:, 13:16].astype(float),
                        frame_id=frame_bytes.decode('utf-8'))


def _one_line(err: Exception) -> str:
    """Return 'ErrorType: message' on one line (rosbags quotes multi-line YAML errors)."""
    return f'{type(err).__name__}: ' + ' '.join(str(err).split())


def _is_utf8(data: bytes) -> bool:
    try:
        data.decode('utf-8')
    except UnicodeDecodeError:
        return False
    return True


def _deserialize(data: bytes, msgtype: str):
    """Deserialise one CDR message with rosbags; InputError for bytes that are not one."""
    try:
        return typestore().deserialize_cdr(data, msgtype)
    except Exception as err:   # noqa: B902 see above: rosbags raises many kinds on bad bytes
        raise InputError(f'cannot decode a {msgtype} message (corrupt message?): '
                         f'{_one_line(err)}') from None


def _deserialize_imu(raw: list) -> ImuRecording:
    """Decode Imu messages one by one with rosbags (any valid CDR)."""
    frames = Counter()
    rows = []
    for data in raw:
        msg = _deserialize(data, IMU_MSGTYPE)
        frames[msg.header.frame_id] += 1
        stamp, w, f = msg.header.stamp, msg.angular_velocity, msg.linear_acceleration
        rows.append((stamp.sec, stamp.nanosec, f.x, f.y, f.z, w.x, w.y, w.z))
    if len(frames) > 1:
        raise InputError(f'Imu messages carry several frame_ids {dict(frames)}; one recording '
                         'needs one sensor frame (split the topic)')
    stamps = np.array([row[:2] for row in rows], dtype=np.int64)
    values = np.array([row[2:] for row in rows], dtype=float)
    return ImuRecording(stamp_ns=stamps[:, 0] * 1_000_000_000 + stamps[:, 1],
                        acc_b=values[:, :3].copy(), gyr_b=values[:, 3:].copy(),
                        frame_id=next(iter(frames)))


# ----------------------------------------------------------------------------------------------
# Reading
# ----------------------------------------------------------------------------------------------

def _open_reader(path) -> Reader:
    """Open a bag directory or a bare .db3/.mcap file, with errors the user can act on."""
    path = Path(path)
    if not path.exists():
        raise InputError(f'no bag at {str(path)!r}: the path does not exist')
    if path.is_dir() and not (path / 'metadata.yaml').exists():
        raise InputError(f'{str(path)!r} is not a rosbag2 directory (no metadata.yaml); give '
                         'the bag directory or its .db3/.mcap file')
    try:
        reader = Reader(path)
        reader.open()
    except Exception as err:   # noqa: B902 see above: rosbags raises many kinds on bad files
        raise InputError(f'cannot read bag {str(path)!r} (not a rosbag2 bag, or corrupt or '
                         f'truncated): {_one_line(err)}') from None
    return reader


def _bag_messages(reader: Reader, connections, path):
    """Yield (connection, log stamp ns, raw CDR) and check every listed message was read."""
    expected = sum(c.msgcount for c in connections)
    count = 0
    try:
        for item in reader.messages(connections=connections):
            count += 1
            yield item
    except Exception as err:   # noqa: B902 see above: rosbags raises many kinds on bad files
        raise InputError(f'bag {str(path)!r} is corrupt or truncated after {count} messages: '
                         f'{_one_line(err)}') from None
    if expected and count != expected:
        raise InputError(f'bag {str(path)!r} is truncated: read {count} of the {expected} '
                         'messages its metadata lists')


def read_imu_bag(path, topic: str | None = None) -> ImuRecording:
    """
    Read the sensor_msgs/msg/Imu samples of one topic into an ImuRecording.

    Stamps are the messages' header stamps (the sample times), in the order stored in the bag;
    acc_b and gyr_b are linear_acceleration and angular_velocity (SI, REP 145).

    Parameters
    ----------
    path : str or Path
        Rosbag2 directory, or a bare .db3 / .mcap file; the storage is detected.
    topic : str or None
        The Imu topic; None picks the bag's only sensor_msgs/msg/Imu topic.

    Raises
    ------
    InputError
        Missing path, not a bag, corrupt or truncated bag, no such topic, no or several Imu
        topics (when topic is None), a topic that is not Imu, no messages.

    """
    reader = _open_reader(path)
    try:
        imu_topics = sorted({c.topic for c in reader.connections if c.msgtype == IMU_MSGTYPE})
        if topic is None:
            if len(imu_topics) != 1:
                found = ', '.join(imu_topics) or 'none'
                raise InputError(f'bag {str(path)!r} has {len(imu_topics)} {IMU_MSGTYPE} topics '
                                 f'({found}); {"pass --topic" if imu_topics else "record one"}')
            topic = imu_topics[0]
        connections = [c for c in reader.connections if c.topic == topic]
        if not connections:
            raise InputError(f'bag {str(path)!r} has no topic {topic!r}; its Imu topics: '
                             f'{", ".join(imu_topics) or "none"}')
        if any(c.msgtype != IMU_MSGTYPE for c in connections):
            raise InputError(f'topic {topic!r} in {str(path)!r} is {connections[0].msgtype}, '
                             f'not {IMU_MSGTYPE}')
        raw = [bytes(data) for _, _, data in _bag_messages(reader, connections, path)]
    finally:
        reader.close()
    if not raw:
        raise InputError(f'topic {topic!r} in bag {str(path)!r} has no messages')
    recording = _decode_imu(raw)
    if recording is None:
        try:
            recording = _deserialize_imu(raw)
        except InputError as err:
            raise InputError(f'bag {str(path)!r}, topic {topic!r}: {err}') from None
    return recording


def read_messages(path, topics=None):
    """
    Yield (topic, log stamp ns, message) for every message, deserialised.

    Parameters
    ----------
    path : str or Path
        Rosbag2 directory or bare .db3 / .mcap file.
    topics : iterable of str or None
        Topic names to keep; None keeps all.

    """
    reader = _open_reader(path)
    try:
        connections = [c for c in reader.connections if topics is None or c.topic in topics]
        store = typestore()
        for connection, stamp_ns, data in _bag_messages(reader, connections, path):
            if connection.msgtype not in store.types:
                raise InputError(f'topic {connection.topic!r} has type {connection.msgtype}, '
                                 'unknown to the ROS 2 Jazzy type store')
            try:
                msg = _deserialize(data, connection.msgtype)
            except InputError as err:
                raise InputError(f'bag {str(path)!r}, topic {connection.topic!r}: {err}') \
                    from None
            yield connection.topic, stamp_ns, msg
    finally:
        reader.close()


# ----------------------------------------------------------------------------------------------
# Writing
# ----------------------------------------------------------------------------------------------

class BagWriter:
    """
    Write typed messages to a new rosbag2 directory; a context manager.

    >>> with BagWriter(out_dir, storage='mcap') as bag:
    ...     bag.write('/floor', msg_type('std_msgs/msg/Int8')(data=1), stamp_ns)

    Connections are added on the first message of each topic, with the message's type.
    """

    def __init__(self, path, *, storage: str = 'sqlite3'):
        if storage not in STORAGES:
            raise InputError(f'storage={storage!r} is not one of {sorted(STORAGES)}')
        self.path = Path(path)
        if self.path.exists():
            raise InputError(f'output bag {str(self.path)!r} exists; remove it or choose another '
                             'path')
        self._writer = Writer(self.path, version=BAG_VERSION, storage_plugin=STORAGES[storage])
        self._connections = {}

    def __enter__(self):
        try:
            self._writer.open()
        except WriterError as err:
            raise InputError(f'cannot create bag {str(self.path)!r}: {err}') from None
        return self

    def __exit__(self, *exc):
        self._writer.close()

    def _connection(self, topic: str, msgtype: str):
        connection = self._connections.get(topic)
        if connection is None:
            connection = self._writer.add_connection(topic, msgtype, typestore=typestore())
            self._connections[topic] = connection
        elif connection.msgtype != msgtype:
            raise InputError(f'topic {topic!r} already carries {connection.msgtype}, not '
                             f'{msgtype}')
        return connection

    def write(self, topic: str, msg, stamp_ns: int):
        """Serialise ``msg`` and store it on ``topic`` with log time ``stamp_ns``."""
        msgtype = msg.__msgtype__
        self.write_raw(topic, msgtype, typestore().serialize_cdr(msg, msgtype), stamp_ns)

    def write_raw(self, topic: str, msgtype: str, data: bytes, stamp_ns: int):
        """Store already serialised CDR bytes of type ``msgtype`` on ``topic``."""
        self._writer.write(self._connection(topic, msgtype), int(stamp_ns), data)


def write_imu_bag(path, recording: ImuRecording, *, topic: str = '/imu/data',
                  storage: str = 'sqlite3', angular_velocity_variance: float = 0.0,
                  linear_acceleration_variance: float = 0.0) -> Path:
    """
    Write an ImuRecording as sensor_msgs/msg/Imu messages to a new rosbag2 directory.

    One message per sample (REP 145): header.stamp and the bag log time are the sample stamp,
    header.frame_id is recording.frame_id, orientation is unknown (orientation_covariance[0]
    = -1, orientation all zeros), angular_velocity and linear_acceleration covariances are
    diagonal with the given per-axis variances (0: unknown).

    Parameters
    ----------
    path : str or Path
        New bag directory (must not exist).
    recording : ImuRecording
        The samples.
    topic : str
        Topic name.
    storage : str
        'sqlite3' or 'mcap'.
    angular_velocity_variance : float
        Per-axis gyro variance, (rad/s)^2.
    linear_acceleration_variance : float
        Per-axis accelerometer variance, (m/s^2)^2.

    Returns
    -------
    The bag directory.

    """
    if not (angular_velocity_variance >= 0 and linear_acceleration_variance >= 0):
        raise InputError('covariances must be >= 0 (0 means unknown); got '
                         f'angular_velocity_variance={angular_velocity_variance}, '
                         f'linear_acceleration_variance={linear_acceleration_variance}')
    cdr = _encode_imu(recording, angular_velocity_variance, linear_acceleration_variance)
    with BagWriter(path, storage=storage) as bag:
        for stamp_ns, row in zip(recording.stamp_ns.tolist(), cdr):
            bag.write_raw(topic, IMU_MSGTYPE, row.tobytes(), stamp_ns)
    return Path(path)
