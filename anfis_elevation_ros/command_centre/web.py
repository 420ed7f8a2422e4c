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
The command centre's web server: the page, ``/api/state``, the push stream and the writes.

Standard library only (``http.server.ThreadingHTTPServer``, one thread per connection):

- ``GET /``: the page; ``GET /static/<file>``: its script and style; ``GET /static/leaflet/
  <file>``: Leaflet, from the ``XStatic-Leaflet`` wheel (no CDN: the incident laptop is
  offline).
- ``GET /api/state``: :meth:`Incident.snapshot` as JSON (documented in the README).
- ``GET /api/events?since=SEQ``: Server-Sent Events, one ``batch`` event (JSON
  ``{"seq": N, "events": [...]}``, :meth:`Incident.events_since`) whenever the incident
  changed, at most every ``PUSH_PERIOD_S``; a comment line every ``KEEPALIVE_S`` otherwise.
- ``GET /api/log.csv``: the incident log.
- ``POST /api/ack`` ``{"alarm_id": "A3", "by": "IC Smith"}``, ``POST /api/evacuate``,
  ``POST /api/roll_call`` (``{"by": ...}``): only with ``Authorization: Bearer <token>``
  (compared in constant time); 401 without it, 413 for a body over ``MAX_BODY_BYTES``, 400
  for one that is not a JSON object, 404 for an unknown alarm. A refused request never stops
  the server.

Reads need no token (the page must show at once on the command post's screen); bind to the
loopback (the default) or serve the LAN over TLS: any other host is refused unless a TLS
context is given or ``insecure=True``.
"""

import hmac
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
import ipaddress
import json
import logging
from pathlib import Path
import socket
import ssl
import threading
import time
from urllib.parse import parse_qs, urlsplit

STATIC_DIR = Path(__file__).resolve().parent / 'static'
MAX_BODY_BYTES = 16 * 1024
PUSH_PERIOD_S = 0.25        # at most 4 pushes a second: the page stays within 1 s
KEEPALIVE_S = 15.0
CLOSING_POLL_S = 0.5        # an open push stream notices the server stopping within this
MAX_STREAMS = 32            # open push streams (each holds a thread)
REQUEST_TIMEOUT_S = 30.0    # a client that stalls mid-request is dropped
MIN_TOKEN_CHARS = 16
CONTENT_TYPES = {'.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8',
                 '.css': 'text/css; charset=utf-8', '.png': 'image/png',
                 '.svg': 'image/svg+xml'}
SECURITY_HEADERS = {
    'Content-Security-Policy': "default-src 'self'; img-src 'self' data:; "
                               "style-src 'self' 'unsafe-inline'; frame-ancestors 'none'",
    'X-Content-Type-Options': 'nosniff',
    'Referrer-Policy': 'no-referrer',
    'Cache-Control': 'no-store',
}

log = logging.getLogger(__name__)


def leaflet_dir() -> Path:
    """Return the folder of Leaflet's files in the XStatic-Leaflet wheel."""
    import xstatic.pkg.leaflet
    return Path(xstatic.pkg.leaflet.BASE_DIR)


def tls_context_from_files(cert_file, key_file) -> ssl.SSLContext:
    """Return a server TLS context (TLS 1.2 or newer) from a PEM certificate and key."""
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.minimum_version = ssl.TLSVersion.TLSv1_2
    context.load_cert_chain(str(cert_file), str(key_file))
    return context


def is_loopback(host: str) -> bool:
    """Tell whether ``host`` is a loopback address or ``localhost``."""
    if host == 'localhost':
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


class CommandCentreServer(ThreadingHTTPServer):
    """ThreadingHTTPServer that holds the incident, the token and the open push streams."""

    daemon_threads = True

    def __init__(self, address, incident, token: str, family=socket.AF_INET):
        self.address_family = family
        self.incident = incident
        self.token = token.encode()
        self.closing = threading.Event()
        self.streams = threading.BoundedSemaphore(MAX_STREAMS)
        self.refused = {}
        super().__init__(address, Handler)

    def shutdown(self):
        """Stop serving and end the push streams."""
        self.closing.set()
        super().shutdown()

    def server_close(self):
        """Close the socket and end the push streams."""
        self.closing.set()
        super().server_close()

    def handle_error(self, request, client_address):
        """Log a failed request (a dropped client, a bug) and keep serving."""
        log.warning('request from %s failed', client_address[0], exc_info=True)

    def count_refusal(self, status: int) -> None:
        """Count a refused request by HTTP status (shown in the server's log)."""
        self.refused[status] = self.refused.get(status, 0) + 1

    @property
    def url(self) -> str:
        """Return the page's URL."""
        host, port = self.server_address[:2]
        scheme = 'https' if isinstance(self.socket, ssl.SSLSocket) else 'http'
        host = f'[{host}]' if ':' in host else host
        return f'{scheme}://{host}:{port}/'


def make_server(incident, host: str = '127.0.0.1', port: int = 8088, token: str = '',
                tls_context: ssl.SSLContext = None, insecure: bool = False):
    """
    Build the command centre's HTTP(S) server (call ``serve_forever`` to run it).

    Parameters
    ----------
    incident : Incident
        The model the page shows and writes to.
    host : str
        Address to listen on; a loopback one unless TLS or ``insecure``.
    port : int
        Port to listen on; 0 picks a free one (see ``server.server_address``).
    token : str
        The session token that writes need (at least ``MIN_TOKEN_CHARS`` characters).
    tls_context : ssl.SSLContext or None
        Serve HTTPS with it (``tls_context_from_files``).
    insecure : bool
        Allow plain HTTP on a host other than the loopback.

    Raises
    ------
    ValueError : a short token, or a non-loopback host without TLS nor ``insecure``.
    OSError : the address cannot be bound.

    """
    if not isinstance(token, str) or len(token) < MIN_TOKEN_CHARS:
        raise ValueError(f'the session token must have at least {MIN_TOKEN_CHARS} characters')
    if not is_loopback(host) and tls_context is None and not insecure:
        raise ValueError(f'refusing to serve {host} over plain HTTP: the token and the '
                         "responders' positions would cross the network in clear; give a "
                         'certificate and key (TLS) or, on a closed network, --insecure')
    family = socket.AF_INET6 if ':' in host else socket.AF_INET
    server = CommandCentreServer((host, port), incident, token, family)
    if tls_context is not None:
        server.socket = tls_context.wrap_socket(server.socket, server_side=True)
    return server


class Handler(BaseHTTPRequestHandler):
    """One request to the command centre."""

    server_version = 'anfis-command-centre'
    protocol_version = 'HTTP/1.1'
    timeout = REQUEST_TIMEOUT_S
    _body_read = False

    def log_message(self, format, *args):  # noqa: A002 (the base class's name)
        """Log requests at debug level only (a push stream per page, many reads)."""
        log.debug('%s %s', self.address_string(), format % args)

    # -- GET ------------------------------------------------------------------------------

    def do_GET(self):  # noqa: N802 (http.server's name)
        """Serve the page, its files, the state, the log or the push stream."""
        url = urlsplit(self.path)
        path = url.path
        if path in ('/', '/index.html'):
            return self._send_file(STATIC_DIR / 'index.html')
        if path.startswith('/static/leaflet/'):
            return self._send_file(_inside(leaflet_dir(), path[len('/static/leaflet/'):]))
        if path.startswith('/static/'):
            return self._send_file(_inside(STATIC_DIR, path[len('/static/'):]))
        if path == '/api/state':
            return self._send_json(HTTPStatus.OK, self.server.incident.snapshot())
        if path == '/api/log.csv':
            return self._send(HTTPStatus.OK, self.server.incident.log_csv().encode(),
                              'text/csv; charset=utf-8',
                              {'Content-Disposition': 'attachment; filename="incident_log.csv"'})
        if path == '/api/events':
            return self._stream(url.query)
        return self._refuse(HTTPStatus.NOT_FOUND, 'no such page')

    def _stream(self, query: str):
        # A reconnecting EventSource sends the last id it got: it wins over the first ?since.
        since = self.headers.get('Last-Event-ID', '') or parse_qs(query).get('since', [''])[0]
        try:
            seq = max(0, int(since))
        except ValueError:
            return self._refuse(HTTPStatus.BAD_REQUEST, 'since must be a whole number')
        if not self.server.streams.acquire(blocking=False):
            return self._refuse(HTTPStatus.SERVICE_UNAVAILABLE, 'too many open pages')
        try:
            self.send_response(HTTPStatus.OK)
            self.send_header('Content-Type', 'text/event-stream')
            self.send_header('X-Accel-Buffering', 'no')
            for name, value in SECURITY_HEADERS.items():
                self.send_header(name, value)
            self.end_headers()
            self.close_connection = True
            self._push(seq)
        except (OSError, ssl.SSLError):
            pass        # the page went away
        finally:
            self.server.streams.release()

    def _push(self, seq: int):
        incident = self.server.incident
        closing = self.server.closing
        self.wfile.write(b'retry: 1000\n\n')
        self.wfile.flush()
        quiet_since = time.monotonic()
        while not closing.is_set():
            if incident.wait_for_change(seq, CLOSING_POLL_S) <= seq:
                if time.monotonic() - quiet_since >= KEEPALIVE_S:
                    self.wfile.write(b': keepalive\n\n')
                    self.wfile.flush()
                    quiet_since = time.monotonic()
                continue
            quiet_since = time.monotonic()
            seq, events = incident.events_since(seq)
            data = json.dumps({'seq': seq, 'events': events}, separators=(',', ':'))
            self.wfile.write(f'id: {seq}\nevent: batch\ndata: {data}\n\n'.encode())
            self.wfile.flush()
            closing.wait(PUSH_PERIOD_S)

    # -- POST -----------------------------------------------------------------------------

    def do_POST(self):  # noqa: N802 (http.server's name)
        """Acknowledge an alarm, order evacuation or take a roll call (token needed)."""
        self._body_read = False
        path = urlsplit(self.path).path
        if path not in ('/api/ack', '/api/evacuate', '/api/roll_call'):
            return self._refuse(HTTPStatus.NOT_FOUND, 'no such action')
        if not self._authorised():
            return self._refuse(HTTPStatus.UNAUTHORIZED, 'a valid session token is needed',
                                {'WWW-Authenticate': 'Bearer'})
        body = self._json_body()
        if body is None:
            return
        by = body.get('by', 'command')
        incident = self.server.incident
        if path == '/api/ack':
            alarm_id = body.get('alarm_id')
            if not isinstance(alarm_id, str):
                return self._refuse(HTTPStatus.BAD_REQUEST, 'alarm_id (text) is needed')
            if not incident.acknowledge(alarm_id, by):
                return self._refuse(HTTPStatus.NOT_FOUND, f'no active alarm {alarm_id:.40}')
        elif path == '/api/evacuate':
            incident.evacuate(by)
        else:
            incident.roll_call(by)
        return self._send_json(HTTPStatus.OK, {'ok': True})

    def _authorised(self) -> bool:
        scheme, _, token = self.headers.get('Authorization', '').partition(' ')
        return scheme.lower() == 'bearer' and \
            hmac.compare_digest(token.strip().encode(), self.server.token)

    def _json_body(self):
        """Return the request's JSON object, or None after refusing it (400, 411, 413)."""
        try:
            length = int(self.headers.get('Content-Length', ''))
        except ValueError:
            self._refuse(HTTPStatus.LENGTH_REQUIRED, 'Content-Length is needed')
            return None
        if length > MAX_BODY_BYTES or length < 0:
            self._refuse(HTTPStatus.REQUEST_ENTITY_TOO_LARGE,
                         f'the body is limited to {MAX_BODY_BYTES} bytes')
            return None
        raw = self.rfile.read(length) if length else b'{}'
        self._body_read = True
        try:
            body = json.loads(raw.decode('utf-8'))
        except (UnicodeDecodeError, json.JSONDecodeError):
            body = None
        if not isinstance(body, dict):
            self._refuse(HTTPStatus.BAD_REQUEST, 'the body must be a JSON object')
            return None
        return body

    # -- replies --------------------------------------------------------------------------

    def _send_file(self, path):
        if path is None or not path.is_file():
            return self._refuse(HTTPStatus.NOT_FOUND, 'no such file')
        content_type = CONTENT_TYPES.get(path.suffix, 'application/octet-stream')
        return self._send(HTTPStatus.OK, path.read_bytes(), content_type)

    def _send_json(self, status, value):
        return self._send(status, json.dumps(value, separators=(',', ':')).encode(),
                          'application/json')

    def _refuse(self, status, message: str, headers=None):
        self.server.count_refusal(int(status))
        if self.command == 'POST' and not self._body_read:
            self.close_connection = True      # the unread body must not be parsed as a request
        return self._send(status, json.dumps({'error': message}).encode(), 'application/json',
                          headers)

    def _send(self, status, body: bytes, content_type: str, headers=None):
        self.send_response(status)
        self.send_header('Content-Type', content_type)
        self.send_header('Content-Length', str(len(body)))
        for name, value in {**SECURITY_HEADERS, **(headers or {})}.items():
            self.send_header(name, value)
        if self.close_connection:
            self.send_header('Connection', 'close')
        self.end_headers()
        if self.command != 'HEAD':
            self.wfile.write(body)


def _inside(folder: Path, relative: str):
    """Return folder/relative if it names a file inside ``folder`` (no ``..``), else None."""
    if not relative or '\\' in relative or '\0' in relative:
        return None
    path = (folder / relative).resolve()
    return path if path.is_relative_to(folder.resolve()) else None


__all__ = ['CommandCentreServer', 'is_loopback', 'leaflet_dir', 'make_server',
           'MAX_BODY_BYTES', 'tls_context_from_files']
