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

"""Helpers of the command-centre tests: a fake clock and a server running in a thread."""

import contextlib
import threading

from anfis_elevation_ros.command_centre.web import make_server

TOKEN = 'test-token-0123456789abcdef'


class FakeClock:
    """A clock the test moves by hand: ``clock()`` returns ``clock.t`` (s)."""

    def __init__(self, t: float = 0.0):
        self.t = t

    def __call__(self) -> float:
        return self.t


@contextlib.contextmanager
def running_server(incident, **kwargs):
    """Serve ``incident`` on a free loopback port in a thread; yield the server."""
    kwargs.setdefault('token', TOKEN)
    server = make_server(incident, kwargs.pop('host', '127.0.0.1'), 0, **kwargs)
    thread = threading.Thread(target=server.serve_forever, kwargs={'poll_interval': 0.05},
                              daemon=True)
    thread.start()
    try:
        yield server
    finally:
        server.shutdown()
        server.server_close()
        thread.join(5)
