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
The numpy core never imports ROS: no rclpy, no message packages, no rosbags, no adapters.

Two checks: a static scan of every import statement in anfis_elevation_ros/core (also the ones
inside functions), and a fresh interpreter that imports every core module while an import hook
refuses the ROS packages (catching ROS pulled in through another module of the package).
"""

import ast
import json
import os
from pathlib import Path
import subprocess
import sys

import pytest

PACKAGE_ROOT = Path(__file__).resolve().parents[1]
CORE_DIR = PACKAGE_ROOT / 'anfis_elevation_ros' / 'core'

# Top-level names that only exist with ROS (or the bag library) installed.
FORBIDDEN_TOP_LEVEL = (
    'rclpy', 'rosbags', 'rosbag2_py', 'rosidl_runtime_py', 'rosidl_parser', 'rpyutils',
    'ament_index_python', 'builtin_interfaces', 'rcl_interfaces', 'launch', 'launch_ros',
    'message_filters', 'tf2_ros', 'diagnostic_updater',
)
# The package's own ROS-side modules.
FORBIDDEN_SUBPACKAGES = ('anfis_elevation_ros.nodes', 'anfis_elevation_ros.tools')


def forbidden_reason(name):
    """Return why importing the absolute module name is not allowed in the core, or None."""
    top = name.split('.')[0]
    if top in FORBIDDEN_TOP_LEVEL:
        return f'{top} is a ROS package'
    if top.endswith(('_msgs', '_srvs', '_interfaces')):
        return f'{top} is a ROS interface package'
    for sub in FORBIDDEN_SUBPACKAGES:
        if name == sub or name.startswith(sub + '.'):
            return f'{sub} is a ROS adapter, the core must not depend on it'
    return None


def module_name(path):
    """Return the dotted module name of a .py file under PACKAGE_ROOT."""
    parts = list(path.relative_to(PACKAGE_ROOT).with_suffix('').parts)
    if parts[-1] == '__init__':
        parts.pop()
    return '.'.join(parts)


def core_files():
    """Return every .py file of the core, sorted."""
    return sorted(p for p in CORE_DIR.rglob('*.py') if '__pycache__' not in p.parts)


def imported_names(path):
    """Return (line, absolute module name) for every import statement in the file."""
    tree = ast.parse(path.read_text(encoding='utf-8'), filename=str(path))
    package = module_name(path)
    if path.name != '__init__.py':
        package = package.rpartition('.')[0]
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.extend((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split('.')
                base = base[:len(base) - node.level + 1]
                module = '.'.join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            names.append((node.lineno, module))
            # 'from anfis_elevation_ros import nodes' imports a subpackage
            names.extend((node.lineno, f'{module}.{alias.name}') for alias in node.names)
    return names


def test_core_modules_exist():
    """The core package is where this test looks for it."""
    assert (CORE_DIR / '__init__.py').is_file()
    assert len(core_files()) >= 2, f'expected the core modules under {CORE_DIR}'


def test_core_source_has_no_ros_import():
    """No import statement of the core, at module level or in a function, names ROS."""
    problems = []
    for path in core_files():
        for line, name in imported_names(path):
            reason = forbidden_reason(name)
            if reason:
                problems.append(
                    f'{path.relative_to(PACKAGE_ROOT)}:{line}: imports {name} ({reason})')
    assert not problems, 'the core must stay numpy-only:\n' + '\n'.join(problems)


# Runs in a fresh interpreter: refuse the forbidden imports, import the modules named in argv.
BLOCKER_SCRIPT = r"""
import importlib
import json
import os
import sys

RULES = json.loads(os.environ['ANFIS_FORBIDDEN_IMPORTS'])


def forbidden(name):
    top = name.split('.')[0]
    return (top in RULES['top_level']
            or top.endswith(('_msgs', '_srvs', '_interfaces'))
            or any(name == s or name.startswith(s + '.') for s in RULES['subpackages']))


class Blocker:
    def find_spec(self, name, path=None, target=None):
        if forbidden(name):
            raise ImportError(f'the core imported {name}')
        return None


for name in [n for n in sys.modules if forbidden(n)]:
    del sys.modules[name]
sys.meta_path.insert(0, Blocker())
failures = []
for module in sys.argv[1:]:
    try:
        importlib.import_module(module)
    except Exception as err:
        failures.append(f'{module}: {type(err).__name__}: {err}')
leaked = sorted(n for n in sys.modules if forbidden(n))
if leaked:
    failures.append('ROS modules loaded anyway: ' + ', '.join(leaked))
print(chr(10).join(failures))
sys.exit(1 if failures else 0)
"""


def run_with_blocker(modules):
    """Import the modules in a fresh interpreter that refuses ROS imports."""
    env = dict(os.environ)
    env['ANFIS_FORBIDDEN_IMPORTS'] = json.dumps(
        {'top_level': FORBIDDEN_TOP_LEVEL, 'subpackages': FORBIDDEN_SUBPACKAGES})
    env['PYTHONPATH'] = os.pathsep.join(
        [str(PACKAGE_ROOT)] + [p for p in env.get('PYTHONPATH', '').split(os.pathsep) if p])
    return subprocess.run(
        [sys.executable, '-c', BLOCKER_SCRIPT, *modules], cwd=PACKAGE_ROOT, env=env,
        capture_output=True, text=True, timeout=120)


def test_core_imports_without_ros():
    """Every core module imports in an interpreter where ROS packages cannot be imported."""
    modules = [module_name(path) for path in core_files()]
    result = run_with_blocker(modules)
    assert result.returncode == 0, (
        'importing the core needed ROS or failed:\n' + result.stdout + result.stderr)


def test_blocker_catches_a_ros_import():
    """The import hook does refuse rclpy and message packages (so the check above can fail)."""
    result = run_with_blocker(['rclpy', 'sensor_msgs.msg', 'anfis_elevation_ros.nodes'])
    assert result.returncode == 1
    for name in ('rclpy', 'sensor_msgs', 'anfis_elevation_ros.nodes'):
        assert f'the core imported {name}' in result.stdout


@pytest.mark.parametrize(('name', 'expected'), [
    ('numpy', None),
    ('anfis_elevation_ros.core.errors', None),
    ('rclpy.node', 'ROS package'),
    ('sensor_msgs.msg', 'interface package'),
    ('anfis_elevation_ros.tools.bags', 'adapter'),
])
def test_forbidden_reason(name, expected):
    """The static rule names ROS packages and the adapters, and nothing else."""
    reason = forbidden_reason(name)
    if expected is None:
        assert reason is None
    else:
        assert expected in reason
