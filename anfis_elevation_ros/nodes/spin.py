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

"""Spinning the nodes: the executor, signal handling and the Jazzy ``main()``."""

from ..core.errors import InputError

EXECUTORS = ('events', 'single')


class Spinner:
    """
    The executor of the nodes: rclpy's EventsExecutor ('events') or SingleThreadedExecutor.

    The events executor costs about a third of the CPU per message of the
    SingleThreadedExecutor at 400 Hz (test/benchmarks/bench_live.py). Its ``spin()`` busy-waits
    and ignores shutdown in rclpy 7.1 (Jazzy), so ``spin`` here runs it a period at a time
    (``spin_until_future_complete`` with a timeout) until ``stop`` is called or the context
    shuts down. Where rclpy has no EventsExecutor, 'events' falls back to the
    SingleThreadedExecutor.

    ``handle_signals`` makes SIGINT and SIGTERM call ``stop``: the callback that is running
    finishes, then ``spin`` returns. (rclpy's own handlers chain to Python's, which raises
    KeyboardInterrupt inside whatever callback runs; that would abort a sample half-way.)

    Parameters
    ----------
    kind : str
        'events' or 'single'.

    """

    def __init__(self, kind: str = 'events'):
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.task import Future
        from rclpy.utilities import get_default_context

        if kind not in EXECUTORS:
            raise InputError(f'executor {kind!r} is not one of {", ".join(EXECUTORS)}')
        self.kind = kind
        self._context = get_default_context()
        self._stop = False
        self.signal = None
        self._never_done = Future()      # spin() returns on stop or shutdown, not on this
        if kind == 'events':
            try:
                from rclpy.experimental import EventsExecutor
            except ImportError:
                self.kind = 'single'
            else:
                self.executor = EventsExecutor()
                return
        self.executor = SingleThreadedExecutor()

    def add_node(self, node):
        """Add a node to the executor."""
        self.executor.add_node(node)

    def handle_signals(self):
        """Stop spinning on SIGINT and SIGTERM (main thread only)."""
        import signal

        def handler(signum, _frame):
            self.signal = signum
            self.stop()

        signal.signal(signal.SIGINT, handler)
        signal.signal(signal.SIGTERM, handler)

    def stop(self):
        """Make ``spin`` return after the callback that is running (safe in a signal handler)."""
        self._stop = True

    def spin(self, period_s: float = 0.1):
        """Run callbacks until ``stop`` or the context shuts down."""
        while not self._stop and self._context.ok():
            # The callbacks of a whole period in one call: the events executor then dispatches
            # them in C++, not through a Python loop per message (about 1.5 % of one core at
            # 400 Hz, test/benchmarks/bench_live.py).
            self.executor.spin_until_future_complete(self._never_done, timeout_sec=period_s)

    def shutdown(self):
        """Shut the executor down."""
        self.executor.shutdown()


def init_without_signal_handlers(args=None):
    """rclpy.init without rclpy's signal handlers (``Spinner.handle_signals`` does it)."""
    import rclpy
    from rclpy.signals import SignalHandlerOptions

    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)


def spin_node(node_class, node_name: str, args=None, executor: str = 'events') -> int:
    """
    Jazzy main(): init, build the node, spin until SIGINT/SIGTERM or shutdown, clean up.

    Returns
    -------
    0, or 1 when the node could not start (bad parameters or model: logged as fatal).

    """
    import rclpy
    from rclpy.executors import ExternalShutdownException

    init_without_signal_handlers(args)
    node = None
    try:
        spinner = Spinner(executor)
        spinner.handle_signals()
        node = node_class()
        spinner.add_node(node)
        spinner.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except InputError as err:
        rclpy.logging.get_logger(node_name).fatal(f'cannot start: {err}')
        return 1
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
