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
The colcon path: `colcon build` of the package in a temporary workspace, then its install.

colcon-core and colcon-ros come from PyPI (the [test] extra), so this runs with or without ROS:
the ament_python build task needs no ROS install and no AMENT_PREFIX_PATH; it runs
`setup.py install --single-version-externally-managed`, which installs no dependencies. The
test then checks what `ros2 run` and ament_index look for, and runs the installed command with
only the install's own paths (no `source install/setup.bash`).
"""

import os
from pathlib import Path
import shutil
import subprocess
import sys
from types import SimpleNamespace

import pytest

PACKAGE = 'anfis_elevation_ros'
PACKAGE_ROOT = Path(__file__).resolve().parents[1]
EXECUTABLES = ('anfis_elevation_ros', 'classifier_node', 'imu_node')
# What the build copies into the workspace: the files setup.py reads, not tests or caches.
SOURCE_ENTRIES = ('package.xml', 'setup.py', 'setup.cfg', 'resource', 'config', PACKAGE)
IGNORED = shutil.ignore_patterns('__pycache__', '*.pyc', '*.egg-info', '.*')


def find_colcon():
    """Return the colcon command beside this interpreter, else the one on PATH, else None."""
    beside = Path(sys.executable).parent / 'colcon'
    if beside.is_file():
        return str(beside)
    return shutil.which('colcon')


def files_under(root):
    """Return the relative paths of all files under root (empty if root is missing)."""
    if not root.is_dir():
        return set()
    return {p.relative_to(root).as_posix() for p in root.rglob('*')
            if p.is_file() and '__pycache__' not in p.parts}


@pytest.fixture(scope='module')
def colcon_ws(tmp_path_factory):
    """Build a copy of the package with colcon; yield the paths and the output, then clean up."""
    colcon = find_colcon()
    if colcon is None:
        pytest.fail("colcon not found: install the test tools with pip install -e '.[test]'")
    ws = tmp_path_factory.mktemp('colcon_ws')
    src = ws / 'src' / PACKAGE
    src.mkdir(parents=True)
    for entry in SOURCE_ENTRIES:
        source = PACKAGE_ROOT / entry
        if source.is_dir():
            shutil.copytree(source, src / entry, ignore=IGNORED)
        elif source.is_file():
            shutil.copy2(source, src / entry)
    env = {k: v for k, v in os.environ.items() if not k.startswith('COLCON_')}
    env['COLCON_HOME'] = str(ws / 'colcon_home')          # no user defaults.yaml
    result = subprocess.run(
        [colcon, '--log-base', str(ws / 'log'), 'build',
         '--base-paths', str(ws / 'src'),
         '--build-base', str(ws / 'build'),
         '--install-base', str(ws / 'install'),
         '--event-handlers', 'console_direct+'],
        cwd=ws, env=env, capture_output=True, text=True, timeout=300)
    prefix = ws / 'install' / PACKAGE
    inits = sorted(prefix.glob(f'lib/python3*/*-packages/{PACKAGE}/__init__.py'))
    yield SimpleNamespace(
        src=src, prefix=prefix, result=result,
        output=result.stdout + result.stderr,
        site_packages=inits[0].parents[1] if inits else None)
    shutil.rmtree(ws, ignore_errors=True)


def install_env(ws):
    """Environment that finds the installed package first, as install/setup.bash would."""
    env = dict(os.environ)
    for name, value in (('PYTHONPATH', ws.site_packages), ('AMENT_PREFIX_PATH', ws.prefix)):
        env[name] = os.pathsep.join([str(value)] + [p for p in env.get(name, '').split(os.pathsep)
                                                    if p])
    return env


def test_colcon_build_succeeds(colcon_ws):
    """Colcon build exits 0 and installs the ament index marker and package.xml itself."""
    assert colcon_ws.result.returncode == 0, colcon_ws.output[-5000:]
    # colcon-ros would add a missing marker or manifest on its own, with this warning
    assert "doesn't explicitly install" not in colcon_ws.output, colcon_ws.output[-5000:]
    assert colcon_ws.site_packages is not None, 'no installed anfis_elevation_ros package'


def test_executables_where_ros2_run_looks(colcon_ws):
    """Every console script is in lib/anfis_elevation_ros and is executable."""
    lib = colcon_ws.prefix / 'lib' / PACKAGE
    for name in EXECUTABLES:
        path = lib / name
        assert path.is_file(), f'{path} missing; found {sorted(files_under(lib))}'
        assert os.access(path, os.X_OK), f'{path} is not executable'


def test_share_holds_index_marker_manifest_and_config(colcon_ws):
    """The ament index marker, package.xml and every config/*.yaml|json are in share/."""
    share = colcon_ws.prefix / 'share'
    assert (share / 'ament_index' / 'resource_index' / 'packages' / PACKAGE).is_file()
    manifest = share / PACKAGE / 'package.xml'
    assert manifest.read_bytes() == (PACKAGE_ROOT / 'package.xml').read_bytes()
    source_config = {p.name for p in colcon_ws.src.glob('config/*')
                     if p.suffix in ('.yaml', '.json')}
    assert files_under(share / PACKAGE / 'config') == source_config


def test_package_data_installed(colcon_ws):
    """Every file under anfis_elevation_ros/data (the sample bag) is installed with the code."""
    source = files_under(colcon_ws.src / PACKAGE / 'data')
    installed = files_under(colcon_ws.site_packages / PACKAGE / 'data')
    assert installed == source


def test_install_ships_default_config_and_sample_bag(colcon_ws):
    """The install has config/params.yaml, both default models and a sample bag."""
    config = colcon_ws.prefix / 'share' / PACKAGE / 'config'
    for name in ('params.yaml', 'forest_default.json', 'anfis_default.json'):
        assert (config / name).is_file(), f'{name} not installed: is config/{name} missing?'
    bags = [p for p in files_under(colcon_ws.site_packages / PACKAGE / 'data')
            if p.endswith('metadata.yaml')]
    assert bags, 'no sample bag (a folder with metadata.yaml) in anfis_elevation_ros/data'


def test_installed_cli_runs(colcon_ws):
    """The installed command runs from lib/ with the install's paths; code comes from install."""
    env = install_env(colcon_ws)
    script = colcon_ws.prefix / 'lib' / PACKAGE / 'anfis_elevation_ros'
    result = subprocess.run([str(script), '--help'], cwd=colcon_ws.prefix, env=env,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'usage:' in result.stdout
    where = subprocess.run(
        [sys.executable, '-c', 'import anfis_elevation_ros; print(anfis_elevation_ros.__file__)'],
        cwd=colcon_ws.prefix, env=env, capture_output=True, text=True, timeout=120)
    assert where.returncode == 0, where.stderr
    assert Path(where.stdout.strip()).is_relative_to(colcon_ws.site_packages)


def test_ament_index_finds_installed_share(colcon_ws):
    """ament_index_python resolves the package's share directory from AMENT_PREFIX_PATH."""
    code = ('from ament_index_python.packages import get_package_share_directory; '
            f'print(get_package_share_directory({PACKAGE!r}))')
    result = subprocess.run([sys.executable, '-c', code], cwd=colcon_ws.prefix,
                            env=install_env(colcon_ws), capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    assert Path(result.stdout.strip()) == colcon_ws.prefix / 'share' / PACKAGE
