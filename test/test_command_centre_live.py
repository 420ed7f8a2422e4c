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
The command centre live: three namespaced responders replayed over DDS, a real browser.

The incident of ``sim/responders.py`` (``/ff1`` climbs to floor 1, ``/ff2`` to floor 2,
``/ff3`` walks a few strides on the ground floor and stands still), each responder its own
``run --namespace`` and ``play`` process, the ``command-centre`` process with short alarm
timers (real time), and chromium driven by Selenium:

- the page shows each responder on its true floor and the floor counts add up;
- ``/ff3`` standing still raises the man-down pre-alarm and then the alarm at the parameter
  times after its last gait cycle (received by this test's own listener);
- ``/ff1``'s bag ends (its nodes still report diagnostics, but no tracking message comes)
  and lost contact is raised ``lost_contact_s`` after its last tracking message; acknowledged
  on the page with the session token, it clears when ``/ff1``'s nodes restart and publish
  again; the log has every step.

A screenshot of the page is kept in test_artifacts/.
"""


from anfis_elevation_ros.sim.responders import RESPONDERS
from anfis_elevation_ros.tools.incident_demo import write_incident
from browser_support import ARTIFACTS, start_chromium, stop_chromium, wait_on_page, \
    why_no_browser
from incident_support import Processes, responders, START_TIMEOUT_S, wait_state
from live_support import listening
import pytest
from selenium.common.exceptions import NoSuchElementException, \
    StaleElementReferenceException

pytestmark = pytest.mark.skipif(why_no_browser() is not None, reason=str(why_no_browser()))

PREALARM_S, ALARM_S, LOST_CONTACT_S = 6.0, 10.0, 4.0
TICK_S = 0.25                                 # tick_rate_hz 4
FLOOR_NAMES = {0: 'Ground', 1: 'Floor 1', 2: 'Floor 2'}
PAGE_WAIT_S = 15.0


@pytest.fixture()
def ff3_listener():
    """Listen to /ff3's elevation in this process (the time of its last gait cycle)."""
    with listening(namespace='/ff3') as listener:
        yield listener


@pytest.fixture()
def browser():
    driver, profile = start_chromium()
    driver.set_page_load_timeout(30)
    yield driver
    stop_chromium(driver, profile)


def page_wait(driver, condition, what, timeout_s=PAGE_WAIT_S):
    """Wait for ``condition`` on the page; a failure says what the roster showed."""
    return wait_on_page(driver, condition, what, timeout_s, shown=roster)


def click(driver, selector) -> bool:
    """Click the element; False while it is absent or the roster redraws it under us."""
    try:
        driver.find_element('css selector', selector).click()
        return True
    except (NoSuchElementException, StaleElementReferenceException):
        return False


def roster(driver) -> dict:
    return driver.execute_script("""
        const rows = {};
        document.querySelectorAll('#roster tbody tr').forEach(function (row) {
          rows[row.dataset.id] = {floor: row.querySelector('.floor').textContent,
                                  alarms: row.querySelector('.alarms').textContent};
        });
        return rows;""")


def floor_counts(driver) -> dict:
    return driver.execute_script("""
        const counts = {};
        document.querySelectorAll('#floors button[data-floor]').forEach(function (b) {
          counts[b.dataset.floor] = Number(b.querySelector('.count').textContent); });
        return counts;""")


def raised(state, rid, kind, severity):
    """Return the unix time the log says an alarm of ``rid`` was raised at, or None."""
    for entry in state['log']:
        if entry['responder'] == rid and entry['event'] == 'raised' and \
                entry.get('kind') == kind and entry.get('severity') == severity:
            return entry['time_unix_s']
    return None


def test_three_responders_live_in_the_browser(tmp_path, ff3_listener, browser):
    building, bags = write_incident(tmp_path)
    state_dir = tmp_path / 'state'
    alarms = [f'alarm.no_motion_prealarm_s:={PREALARM_S}', f'alarm.no_motion_alarm_s:={ALARM_S}',
              f'alarm.lost_contact_s:={LOST_CONTACT_S}']
    with Processes(tmp_path) as procs:
        procs.start('command_centre', 'command-centre', '--building', building, '--port', 0,
                    '--ros-args', *(a for p in alarms for a in ('-p', p)))
        url, token = procs.url_and_token()
        for plan in RESPONDERS:
            name = plan.namespace.strip('/')
            procs.start(name, 'run', '--namespace', plan.namespace, '--building', building,
                        '--ros-args', '-p', f'state_dir:={state_dir}')
            procs.start(f'play_{name}', 'play', bags[plan.namespace], '--topic',
                        f'{plan.namespace}/imu/data', '--rate', 2, '--wait-s', START_TIMEOUT_S)
        browser.get(url)
        page_wait(browser, lambda d: len(roster(d)) == 3, 'three responders', START_TIMEOUT_S)

        # Man down: /ff3's last gait cycle, then the pre-alarm and the alarm on time.
        state = wait_state(url, lambda s: raised(s, '/ff3', 'no_motion', 'alarm'),
                           START_TIMEOUT_S + 60, "/ff3's man-down alarm")
        last_cycle_s = ff3_listener.elevations[-1][-1] * 1e-9
        pre_s = raised(state, '/ff3', 'no_motion', 'pre-alarm') - last_cycle_s
        alarm_s = raised(state, '/ff3', 'no_motion', 'alarm') - last_cycle_s
        assert PREALARM_S - 0.5 <= pre_s <= PREALARM_S + 1.0 + TICK_S, pre_s
        assert ALARM_S - 0.5 <= alarm_s <= ALARM_S + 1.0 + TICK_S, alarm_s
        page_wait(browser, lambda d: 'ALARM \u2014 /ff3' in d.find_element(
            'id', 'alarm-banner').text, "/ff3's alarm on the banner")

        # The walks end: each responder on its true floor, the floor counts add up.
        for plan in RESPONDERS:
            assert procs.wait(f'play_{plan.namespace.strip("/")}', START_TIMEOUT_S + 60) == 0
        truth = {p.namespace: FLOOR_NAMES[p.final_floor] for p in RESPONDERS}
        page_wait(browser, lambda d: {k: v['floor'] for k, v in roster(d).items()} == truth,
                  f'the true floors {truth}')
        counts = floor_counts(browser)
        assert counts == {'2': 1, '1': 1, '0': 1} and sum(counts.values()) == len(RESPONDERS)
        ARTIFACTS.mkdir(exist_ok=True)
        browser.save_screenshot(str(ARTIFACTS / 'command_centre_live.png'))

        # The bags have ended: the nodes still report diagnostics every second, but no
        # tracking message comes: the age of /ff1's data grows past lost_contact_s (it would
        # stay under 1 s if diagnostics counted) and its lost contact is then active. (Under
        # load a start-up gap may have raised it earlier and it waits for an ack, so the time
        # of its first raise is not the bag's end.)
        wait_state(url, lambda s: responders(url)['/ff1']['last_update_age_s'] >=
                   LOST_CONTACT_S + TICK_S + 0.5, LOST_CONTACT_S + 10,
                   "/ff1's tracking silent after its bag ended")
        assert any(a['kind'] == 'lost_contact' and a['cause_active']
                   for a in responders(url)['/ff1']['alarms']), responders(url)['/ff1']
        lost = next(a for a in responders(url)['/ff1']['alarms'] if a['kind'] == 'lost_contact')
        ack = f'#roster button.ack[data-alarm="{lost["id"]}"]'
        page_wait(browser, lambda d: click(d, ack), "/ff1's lost contact's Ack in the roster")
        page_wait(browser, lambda d: d.find_element('id', 'token-input').is_displayed(),
                  'the token dialog')
        browser.find_element('id', 'token-input').send_keys(token)
        browser.find_element('id', 'name-input').send_keys('IC Live')
        browser.find_element('id', 'token-ok').click()
        wait_state(url, lambda s: any(e['event'] == 'acknowledged' and e['responder'] == '/ff1'
                                      for e in s['log']), 10.0, 'the acknowledgement')
        assert procs.stop('ff1') == 0, procs.log('ff1')
        procs.start('ff1_back', 'run', '--namespace', '/ff1', '--building', building,
                    '--ros-args', '-p', f'state_dir:={state_dir}')
        wait_state(url, lambda s: not any(a['kind'] == 'lost_contact'
                                          for a in responders(url)['/ff1']['alarms']),
                   START_TIMEOUT_S, '/ff1 back and its lost contact cleared')
        log_text = page_wait(browser, lambda d: 'Lost contact cleared' in d.find_element(
            'id', 'log').text and d.find_element('id', 'log').text, 'the clearing in the log')
        for line in ('No motion (man down) pre-alarm', 'No motion (man down) alarm',
                     'Lost contact alarm', 'Lost contact alarm acknowledged by IC Live'):
            assert line in log_text, line
        assert procs.stop('command_centre') == 0, procs.log('command_centre')
