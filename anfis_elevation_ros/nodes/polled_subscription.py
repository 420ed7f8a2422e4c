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

"""A raw subscription whose messages a thread of its own takes in batches."""

import threading


class PolledSubscription:
    """
    A raw subscription whose messages a thread of its own takes in batches, every ``period_s``.

    At 400 Hz the executor's dispatch of one callback per message costs more CPU than the
    pipeline it calls: the thread wakes for every message, with cold caches. Taking what
    arrived in the last period in one go (test/benchmarks/bench_live.py, 400 Hz, both nodes)
    cut the nodes' CPU by 24 % at 10 ms (three alternating runs: 7.2 % against 9.5 % of one
    core) and by 5 % at 5 ms, for up to one period more latency: 8 ms, the IMU node's default,
    gave 7.8 % in two runs of the 10-minute walk, with a p99 latency of 13 ms in one and 22 ms
    in the other (one callback per message: 7 and 10 ms, but 9.2 and 10.8 % CPU).

    The one message whose latency counts can be foreseen: ``due_s``, asked after every batch,
    says when it is due (the IMU node: the sample that will close a gait cycle, once the foot
    is still), and the thread wakes then instead of a whole period later. That costs a wake-up
    or two per stride and takes the batching's delay off the cycle's latency: with it (and the
    state files written 0.1 s later, ``StateWriter``) two runs of the 10-minute walk gave p99
    12.8 and 9.7 ms at 8.9 and 7.6 % CPU.

    The subscription belongs to a helper node, ``<node name>_input``, that no executor spins
    (an executor would take its messages first); it has no global arguments (the topic comes
    resolved and remapped by the owning node), no parameter services and no rosout. Messages are
    taken with the subscription handle's ``take_message``, the call rclpy's executors and
    ``wait_for_message`` make.

    Parameters
    ----------
    node : rclpy Node
        The owner: name, namespace, context and logger.
    msg_type : message class
    topic : str
        Fully resolved topic name.
    qos : QoSProfile
    handler : callable
        Called with the serialised bytes of each message, in the thread, with ``lock`` held
        over a batch: the owner holds the same lock in its callbacks that share state with it.
        It must catch its own errors: one that escapes ends the thread (the IMU node's
        ``_on_imu`` counts them as internal errors).
    period_s : float
        Time between batches, s.
    lock : threading.Lock
    due_s : callable or None
        Called after each batch, with ``lock`` held: seconds until the next message that must
        not wait for the period (from the newest message taken), or None. The next batch is
        then taken ``DUE_MARGIN_S`` after that time, if it is sooner than the period. Like
        ``handler``, it must not raise.

    """

    DUE_MARGIN_S = 0.001    # transit from the publisher; a late message costs another wait

    def __init__(self, node, msg_type, topic: str, qos, handler, period_s: float, lock,
                 due_s=None):
        import rclpy

        self._helper = rclpy.create_node(
            f'{node.get_name()}_input', namespace=node.get_namespace(), context=node.context,
            use_global_arguments=False, start_parameter_services=False, enable_rosout=False)
        self._subscription = self._helper.create_subscription(msg_type, topic, _not_dispatched,
                                                              qos, raw=True)
        self._msg_type = msg_type
        self._handler = handler
        self._period_s = period_s
        self._lock = lock
        self._due_s = due_s
        self._context = node.context
        self._logger = node.get_logger()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=f'{node.get_name()}_input',
                                        daemon=True)
        self._thread.start()

    def close(self, timeout_s: float = 2.0):
        """Handle the messages already received, stop the thread, destroy the helper node."""
        self._stop.set()
        self._thread.join(timeout_s)
        self._helper.destroy_node()

    def _run(self):
        wait_s = self._period_s
        while not self._stop.wait(wait_s):
            wait_s = self._take_all()
        self._take_all()

    def _take_all(self) -> float:
        """Handle every message waiting; return the time to wait before the next batch, s."""
        take = self._subscription.handle.take_message
        with self._lock:
            while True:
                try:
                    taken = take(self._msg_type, True)
                except Exception as err:   # noqa: B902 rclpy raises several kinds
                    if self._context.ok():
                        self._logger.error(f'taking a message failed: {err}',
                                           throttle_duration_sec=5.0)
                    break
                if taken is None:
                    break
                self._handler(taken[0])
            due_s = None if self._due_s is None else self._due_s()
        if due_s is None:
            return self._period_s
        return min(self._period_s, due_s + self.DUE_MARGIN_S)


def _not_dispatched(_msg):
    """Do nothing: no executor spins the helper node of a PolledSubscription."""
