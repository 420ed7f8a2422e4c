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

"""Debian's chromium driven by Selenium, for the command-centre page's tests and benchmark."""

from pathlib import Path
import shutil
import tempfile
import time

CHROMIUM_FLAGS = ('--headless', '--no-sandbox', '--disable-gpu', '--disable-quic',
                  '--no-first-run', '--disable-background-networking',
                  '--disable-component-update', '--disable-sync', '--disable-dev-shm-usage',
                  '--window-size=1600,1000', '--autoplay-policy=no-user-gesture-required')
ARTIFACTS = Path(__file__).resolve().parents[1] / 'test_artifacts'


def why_no_browser():
    """Return why the browser cannot run here (a reason to skip), or None if it can."""
    missing = [name for name in ('chromium', 'chromedriver') if shutil.which(name) is None]
    if missing:
        return (f'{" and ".join(missing)} not found: apt-get install -y chromium '
                'chromium-driver (.ci/run installs them)')
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium not installed: pip install -e '.[test]'"
    return None


def start_chromium():
    """Start headless chromium under chromedriver; return (driver, profile folder to remove)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    profile = tempfile.mkdtemp(prefix='anfis_chromium_')
    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which('chromium')
    for flag in CHROMIUM_FLAGS:
        options.add_argument(flag)
    options.add_argument(f'--user-data-dir={profile}')
    service = Service(executable_path=shutil.which('chromedriver'))
    try:
        return webdriver.Chrome(service=service, options=options), profile
    except Exception:
        shutil.rmtree(profile, ignore_errors=True)
        raise


def wait_on_page(driver, condition, what, timeout_s, shown=None):
    """
    Poll ``condition(driver)`` until truthy and return it; fail saying ``what`` otherwise.

    ``shown(driver)``, when given, is added to the failure: what the page showed instead.
    """
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        value = condition(driver)
        if value:
            return value
        time.sleep(0.05)
    seen = f'; the page showed {shown(driver)}' if shown is not None else ''
    raise AssertionError(f'the page did not show {what} within {timeout_s} s{seen}')


def stop_chromium(driver, profile) -> None:
    """Quit the browser and remove its profile."""
    try:
        driver.quit()
    finally:
        shutil.rmtree(profile, ignore_errors=True)
