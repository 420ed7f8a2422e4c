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
A screenshot of a web page with the machine's headless chromium, driven by Selenium.

Only the system's ``chromium`` and ``chromedriver`` are used (Debian: ``apt-get install
chromium chromium-driver``); nothing is downloaded. Where they or Selenium are missing,
``why_no_browser`` says so and the caller skips the screenshot.
"""

import shutil
import tempfile
import time

CHROMIUM_FLAGS = ('--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
                  '--disable-background-networking', '--disable-component-update',
                  '--disable-sync', '--disable-dev-shm-usage')


def why_no_browser():
    """Return why no screenshot can be taken here, or None if it can."""
    missing = [name for name in ('chromium', 'chromedriver') if shutil.which(name) is None]
    if missing:
        return f'{" and ".join(missing)} not found (apt-get install -y chromium chromium-driver)'
    try:
        import selenium  # noqa: F401
    except ImportError:
        return 'selenium is not installed (pip install selenium)'
    return None


def screenshot(url: str, png, ready_js: str = 'return true', width: int = 1600,
               height: int = 1000, timeout_s: float = 30.0) -> None:
    """
    Open ``url`` in headless chromium, wait until ``ready_js`` returns true, save a PNG.

    Raises
    ------
    RuntimeError : the page did not become ready within ``timeout_s``.

    """
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    profile = tempfile.mkdtemp(prefix='anfis_chromium_')
    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which('chromium')
    for flag in CHROMIUM_FLAGS + (f'--window-size={width},{height}',
                                  f'--user-data-dir={profile}'):
        options.add_argument(flag)
    driver = None
    try:
        driver = webdriver.Chrome(service=Service(executable_path=shutil.which('chromedriver')),
                                  options=options)
        driver.set_page_load_timeout(timeout_s)
        driver.get(url)
        deadline = time.monotonic() + timeout_s
        while not driver.execute_script(ready_js):
            if time.monotonic() > deadline:
                raise RuntimeError(f'{url} was not ready within {timeout_s:g} s')
            time.sleep(0.2)
        time.sleep(1.0)                   # the map's tiles and the last push settle
        driver.save_screenshot(str(png))
    finally:
        if driver is not None:
            driver.quit()
        shutil.rmtree(profile, ignore_errors=True)
