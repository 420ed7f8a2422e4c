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
The package's JSON data files (models): read bounded and strict, written atomically.

A model file is data: it is read with a size bound (a bag passed by mistake is refused
unread), non-finite numbers are refused, and every failure is an InputError that names the
file. A writer replaces the file in one step, so a reader never sees half of it.
"""

import json
import os

from .errors import InputError


def read_json_file(path, max_bytes: int, what: str, hint: str = ''):
    """
    Parse a JSON file of at most ``max_bytes``; non-finite numbers are refused.

    ``what`` names the kind of file in the messages ('forest model'); ``hint``, when given,
    ends each message with what to do about it.

    Raises
    ------
    InputError : missing, unreadable, too large, not UTF-8 or not valid JSON.

    """
    path = os.fspath(path)
    tail = f'; {hint}' if hint else ''
    try:
        with open(path, 'rb') as stream:
            data = stream.read(max_bytes + 1)
    except FileNotFoundError:
        raise InputError(f'{what} file not found: {path}{tail}') from None
    except OSError as err:
        raise InputError(f'cannot read {what} file {path}: {err}{tail}') from None
    if len(data) > max_bytes:
        raise InputError(f'{path} is larger than {max_bytes} bytes: not a {what} file{tail}')
    try:
        text = data.decode('utf-8')
    except UnicodeDecodeError as err:
        raise InputError(f'cannot read {what} file {path}: {err}{tail}') from None

    def reject_constant(name):
        raise InputError(f'{path}: non-finite number {name} in the {what}{tail}')

    try:
        return json.loads(text, parse_constant=reject_constant)
    except InputError:
        raise
    # JSONDecodeError, and the ValueError of an integer of more than 4300 digits and the
    # RecursionError of arrays nested too deep that json.loads also raises.
    except (ValueError, RecursionError) as err:
        raise InputError(f'{path} is not valid JSON ({err}): the {what} file is corrupt or '
                         f'truncated{tail}') from None


def write_text_atomically(path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and ``os.replace``."""
    path = os.fspath(path)
    tmp_path = f'{path}.tmp{os.getpid()}'
    try:
        with open(tmp_path, 'w', encoding='utf-8') as stream:
            stream.write(text)
        os.replace(tmp_path, path)
    finally:
        if os.path.exists(tmp_path):
            os.remove(tmp_path)


__all__ = ['read_json_file', 'write_text_atomically']
