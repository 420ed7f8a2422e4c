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
Licence header of every Python file: a plain check here, ament_copyright where it is installed.

ament_copyright (ROS 2 Jazzy) has no wheel on PyPI, so the standalone install cannot run it. The
plain check below runs everywhere: every .py file starts with the project's 13-line Apache-2.0
header, then its module docstring. On a ROS machine (rosdep installs ament_copyright as a
test_depend) ament_copyright runs as well.
"""

import ast
import importlib.util
import os
from pathlib import Path

import pytest

PACKAGE_ROOT = Path(__file__).resolve().parents[1]

HEADER_LINES = (
    '# Copyright 2026 The anfis_elevation_ros Authors',
    '#',
    '# Licensed under the Apache License, Version 2.0 (the "License");',
    '# you may not use this file except in compliance with the License.',
    '# You may obtain a copy of the License at',
    '#',
    '#     http://www.apache.org/licenses/LICENSE-2.0',
    '#',
    '# Unless required by applicable law or agreed to in writing, software',
    '# distributed under the License is distributed on an "AS IS" BASIS,',
    '# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.',
    '# See the License for the specific language governing permissions and',
    '# limitations under the License.',
)

IGNORE_MARKERS = ('AMENT_IGNORE', 'COLCON_IGNORE')


def python_files(root):
    """
    Return the .py files under root that the ament linters check, sorted.

    Like ament_flake8, skip folders whose name starts with '.' or '_' (virtual environments,
    caches) and folders holding an AMENT_IGNORE or COLCON_IGNORE file (colcon's build, install
    and log folders).
    """
    found = []
    for dirpath, dirnames, filenames in os.walk(root):
        if any(marker in filenames for marker in IGNORE_MARKERS):
            dirnames[:] = []
            continue
        dirnames[:] = sorted(d for d in dirnames if d[0] not in '._')
        found.extend(Path(dirpath) / name for name in filenames if name.endswith('.py'))
    return sorted(found)


def header_problem(path):
    """Return why path does not start with the licence header and a docstring, or None."""
    text = path.read_text(encoding='utf-8')
    lines = text.splitlines()
    if lines and lines[0].startswith('#!'):
        lines = lines[1:]
    for number, expected in enumerate(HEADER_LINES, start=1):
        if number > len(lines):
            return f'has {len(lines)} lines, the licence header needs {len(HEADER_LINES)}'
        if lines[number - 1].rstrip() != expected:
            return f'line {number} is {lines[number - 1]!r}, expected {expected!r}'
    try:
        docstring = ast.get_docstring(ast.parse(text, filename=str(path)))
    except SyntaxError as err:
        return f'does not parse: {err}'
    if not docstring:
        return 'has no module docstring after the licence header'
    return None


@pytest.mark.copyright
@pytest.mark.linter
def test_licence_header_in_every_python_file():
    """Every .py file starts with the exact header of /tmp/header.txt, then a module docstring."""
    files = python_files(PACKAGE_ROOT)
    assert files, f'no .py file found under {PACKAGE_ROOT}'
    problems = [f'{path.relative_to(PACKAGE_ROOT)}: {problem}'
                for path in files
                if (problem := header_problem(path)) is not None]
    assert not problems, (
        f'{len(problems)} of {len(files)} files lack the licence header (copy it from an '
        'existing file):\n' + '\n'.join(problems))


def test_header_check_rejects_a_wrong_header(tmp_path):
    """The plain check fails on a file whose header differs in one word or lacks a docstring."""
    good = tmp_path / 'good.py'
    good.write_text('\n'.join(HEADER_LINES) + '\n\n"""Docstring."""\n', encoding='utf-8')
    assert header_problem(good) is None
    wrong_year = tmp_path / 'wrong_year.py'
    wrong_year.write_text(good.read_text().replace('2026', '2025'), encoding='utf-8')
    assert 'line 1' in header_problem(wrong_year)
    no_docstring = tmp_path / 'no_docstring.py'
    no_docstring.write_text('\n'.join(HEADER_LINES) + '\n\nimport os\n', encoding='utf-8')
    assert 'docstring' in header_problem(no_docstring)


@pytest.mark.copyright
@pytest.mark.linter
@pytest.mark.skipif(importlib.util.find_spec('ament_copyright') is None,
                    reason='ament_copyright is not installed (no PyPI wheel); '
                           'the plain licence check above still ran')
def test_ament_copyright(monkeypatch):
    """ament_copyright finds a copyright notice and the Apache-2.0 licence in every file."""
    from ament_copyright.main import main
    monkeypatch.chdir(PACKAGE_ROOT)
    rc = main(argv=['.', 'test'])
    assert rc == 0, 'Found errors'
