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

"""The command-centre web server: reads, the push stream, token-guarded writes, refusals, TLS."""

import http.client
import json
import ssl
import subprocess
import time

from anfis_elevation_ros.command_centre import web
from anfis_elevation_ros.command_centre.alarms import AlarmParams
from anfis_elevation_ros.command_centre.incident import Incident
from command_centre_support import FakeClock, running_server, TOKEN
import pytest


def request(server, method, path, body=None, headers=None, context=None):
    host, port = server.server_address[:2]
    if context is None:
        connection = http.client.HTTPConnection(host, port, timeout=10)
    else:
        connection = http.client.HTTPSConnection(host, port, timeout=10, context=context)
    try:
        connection.request(method, path, body, headers or {})
        response = connection.getresponse()
        return response.status, response.read(), response
    finally:
        connection.close()


def post(server, path, value, token=TOKEN):
    headers = {'Content-Type': 'application/json'}
    if token is not None:
        headers['Authorization'] = f'Bearer {token}'
    return request(server, 'POST', path, json.dumps(value), headers)


def incident_with_alarm():
    clock = FakeClock()
    incident = Incident(clock=clock, params=AlarmParams(lost_contact_s=5.0))
    incident.update_pose('/ff1', 1, 1.0, 2.0, 0.0, 0.0, 0.5)
    incident.update_pose('/ff2', 1, 4.0, 2.0, 0.0, 0.0, 0.5)
    clock.t = 6.0
    incident.update_pose('/ff2', 2, 4.0, 2.0, 0.0, 0.0, 0.5)
    incident.tick()
    (alarm,) = incident.snapshot()['responders'][0]['alarms']
    return incident, alarm['id']


def test_state_is_the_snapshot_as_json():
    incident, _ = incident_with_alarm()
    with running_server(incident) as server:
        status, body, response = request(server, 'GET', '/api/state')
    assert status == 200 and response.getheader('Content-Type') == 'application/json'
    state = json.loads(body)
    assert [r['id'] for r in state['responders']] == ['/ff1', '/ff2']
    assert state['responders'][0]['alarms'][0]['kind'] == 'lost_contact'
    assert response.getheader('Content-Security-Policy').startswith("default-src 'self'")


def test_ack_needs_the_token_and_clears_nothing_without_it():
    incident, alarm_id = incident_with_alarm()
    with running_server(incident) as server:
        for token in (None, 'wrong-token-0123456789', TOKEN + 'x', ''):
            status, _, response = post(server, '/api/ack', {'alarm_id': alarm_id}, token)
            assert status == 401
            assert response.getheader('WWW-Authenticate') == 'Bearer'
        assert not incident.snapshot()['responders'][0]['alarms'][0]['acknowledged']
        status, body, _ = post(server, '/api/ack', {'alarm_id': alarm_id, 'by': 'IC Smith'})
        assert (status, json.loads(body)) == (200, {'ok': True})
        alarm = incident.snapshot()['responders'][0]['alarms'][0]
        assert alarm['acknowledged_by'] == 'IC Smith'
        status, _, _ = post(server, '/api/ack', {'alarm_id': 'A999'})
        assert status == 404
        assert server.refused == {401: 4, 404: 1}


def test_a_refused_write_does_not_spoil_the_next_request_on_the_connection():
    incident, alarm_id = incident_with_alarm()
    with running_server(incident) as server:
        host, port = server.server_address[:2]
        connection = http.client.HTTPConnection(host, port, timeout=10)
        body = json.dumps({'alarm_id': alarm_id})
        statuses = []
        for token in ('wrong-token-0123456789', TOKEN):
            try:
                connection.request('POST', '/api/ack', body, {'Authorization': f'Bearer {token}'})
            except (http.client.HTTPException, OSError):    # the server closed it: reconnect
                connection.close()
                connection.request('POST', '/api/ack', body, {'Authorization': f'Bearer {token}'})
            response = connection.getresponse()
            response.read()
            statuses.append(response.status)
            if response.getheader('Connection') == 'close':
                connection.close()
        connection.close()
    assert statuses == [401, 200]


def test_evacuation_and_roll_call_with_the_token():
    incident, _ = incident_with_alarm()
    with running_server(incident) as server:
        assert post(server, '/api/evacuate', {'by': 'IC'})[0] == 200
        assert post(server, '/api/roll_call', {})[0] == 200
        assert post(server, '/api/evacuate', {}, token=None)[0] == 401
    state = incident.snapshot()
    assert state['evacuation']['by'] == 'IC' and state['roll_call']['by'] == 'command'


def test_oversized_and_malformed_bodies_are_refused_and_the_server_keeps_serving():
    incident, alarm_id = incident_with_alarm()
    auth = {'Authorization': f'Bearer {TOKEN}'}
    with running_server(incident) as server:
        big = b'{"alarm_id": "' + b'x' * (web.MAX_BODY_BYTES + 10) + b'"}'
        assert request(server, 'POST', '/api/ack', big, auth)[0] == 413
        for body in (b'{not json', b'[1, 2]', b'\xff\xfe', b'"text"'):
            assert request(server, 'POST', '/api/ack', body, auth)[0] == 400
        assert post(server, '/api/ack', {'alarm_id': 7})[0] == 400
        assert request(server, 'POST', '/api/ack', None, auth)[0] == 400      # no alarm_id
        assert request(server, 'POST', '/api/nothing', b'{}', auth)[0] == 404
        assert request(server, 'GET', '/api/state')[0] == 200
        assert post(server, '/api/ack', {'alarm_id': alarm_id})[0] == 200


def test_files_outside_the_static_folders_are_not_served():
    with running_server(Incident(clock=FakeClock())) as server:
        for path in ('/static/../web.py', '/static/%2e%2e/web.py', '/static/leaflet/../../x',
                     '/static/', '/nothing'):
            assert request(server, 'GET', path)[0] == 404, path
        status, body, response = request(server, 'GET', '/static/leaflet/leaflet.js')
        assert status == 200 and b'Leaflet' in body[:400]
        assert response.getheader('Content-Type').startswith('text/javascript')


def test_log_csv_is_a_download():
    incident, _ = incident_with_alarm()
    with running_server(incident) as server:
        status, body, response = request(server, 'GET', '/api/log.csv')
    assert status == 200 and 'attachment' in response.getheader('Content-Disposition')
    assert body.decode().splitlines()[0].startswith('seq,time_utc')
    assert b'Lost contact' in body


def read_event(response):
    """Read one SSE event (up to its blank line); return (id, event, data)."""
    fields = {}
    while True:
        line = response.fp.readline().decode().rstrip('\n')
        if not line:
            if fields:
                return fields.get('id'), fields.get('event'), fields.get('data')
            continue
        if line.startswith(':') or line.startswith('retry:'):
            continue
        key, _, value = line.partition(': ')
        fields[key] = value


def test_push_stream_sends_a_change_within_a_second():
    incident = Incident()
    incident.update_floor('/ff1', 0)
    with running_server(incident) as server:
        host, port = server.server_address[:2]
        connection = http.client.HTTPConnection(host, port, timeout=10)
        connection.request('GET', '/api/events?since=0')
        response = connection.getresponse()
        assert response.status == 200
        assert response.getheader('Content-Type') == 'text/event-stream'
        seq, event, data = read_event(response)
        assert event == 'batch' and json.loads(data)['seq'] == int(seq)
        start = time.monotonic()
        incident.update_floor('/ff1', 3)
        seq2, _, data = read_event(response)
        latency = time.monotonic() - start
        connection.close()
    assert int(seq2) > int(seq)
    (changed,) = [e for e in json.loads(data)['events'] if e['type'] == 'responder']
    assert changed['responder']['floor'] == 3
    assert latency < 1.0


def test_push_stream_ends_soon_after_the_server_stops():
    incident = Incident()
    incident.update_floor('/ff1', 0)
    with running_server(incident) as server:
        host, port = server.server_address[:2]
        connection = http.client.HTTPConnection(host, port, timeout=10)
        connection.request('GET', '/api/events?since=0')
        response = connection.getresponse()
        read_event(response)
        stopped = time.monotonic()
    while response.fp.readline():       # until the server closes the stream
        pass
    connection.close()
    assert time.monotonic() - stopped < 1.0 + web.CLOSING_POLL_S


def test_push_stream_refuses_a_bad_since():
    with running_server(Incident()) as server:
        assert request(server, 'GET', '/api/events?since=abc')[0] == 400


@pytest.mark.parametrize('host', ['0.0.0.0', '192.168.1.10', '::'])
def test_lan_host_refused_without_tls_or_insecure(host):
    with pytest.raises(ValueError, match='plain HTTP'):
        web.make_server(Incident(), host, 0, TOKEN)


def test_short_token_refused():
    with pytest.raises(ValueError, match='token'):
        web.make_server(Incident(), '127.0.0.1', 0, 'short')


def test_lan_host_with_insecure_serves():
    server = web.make_server(Incident(), '0.0.0.0', 0, TOKEN, insecure=True)
    server.server_close()
    assert server.url.startswith('http://0.0.0.0:')


def test_tls_from_cert_and_key_files(tmp_path):
    cert, key = tmp_path / 'cert.pem', tmp_path / 'key.pem'
    subprocess.run(['openssl', 'req', '-x509', '-newkey', 'rsa:2048', '-nodes', '-days', '1',
                    '-subj', '/CN=localhost', '-keyout', str(key), '-out', str(cert)],
                   check=True, capture_output=True)
    context = web.tls_context_from_files(cert, key)
    with running_server(Incident(), tls_context=context) as server:
        assert server.url.startswith('https://127.0.0.1:')
        client = ssl.create_default_context(cafile=str(cert))
        client.check_hostname = False
        assert request(server, 'GET', '/api/state', context=client)[0] == 200
