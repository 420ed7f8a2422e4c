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
Stair classifiers behind one interface, chosen by the model file.

A stair classifier maps the features of gait cycles (all of ``FEATURE_NAMES``, in
``GaitCycle.features`` order) to the continuous output that eq. (13) compares with sigma_th:
near +1 up, 0 level, -1 down. Each backend reads the features its model was trained on, by
name:

- :class:`AnfisClassifier`: the patent's ANFIS (``core/anfis.py``) on eq. (8)-(12);
- :class:`~anfis_elevation_ros.core.forest.Forest`: seed 001's random forest on eleven motion
  features and the height change; its output is its majority vote, signed, with its share
  of the votes (``core/forest.py``, ``majority_vote_output``).

:func:`load_classifier` reads a model file and picks the backend by its ``format`` key. The
elevation tracker, the classifier node, ``replay`` and ``train`` all use it.
"""

import time
from typing import Optional, Protocol

import numpy as np

from .anfis import Anfis, FORMAT_NAME as ANFIS_FORMAT, MAX_MODEL_BYTES
from .errors import InputError
from .forest import Forest, FORMAT_NAME as FOREST_FORMAT, MAX_FOREST_BYTES
from .gait import feature_index, N_FEATURES, PATENT_FEATURE_NAMES
from .json_file import read_json_file

BACKENDS = {'anfis': ANFIS_FORMAT, 'forest': FOREST_FORMAT}
"""Backend name -> ``format`` key of its model files."""


class StairClassifier(Protocol):
    """
    What the elevation tracker needs of a classifier.

    Attributes
    ----------
    n_inputs : int, N_FEATURES: it takes a cycle's whole feature vector.
    feature_names : tuple of str, the features it reads.
    metadata_ : dict, the model file's metadata (``mode_threshold``, how it was trained).

    """

    n_inputs: int
    feature_names: tuple
    metadata_: dict

    def predict(self, features: np.ndarray) -> np.ndarray:
        """(N, N_FEATURES) cycle features -> (N,) eq. (13) input, about -1 ... +1."""


class AnfisClassifier:
    """
    The patent's ANFIS as a stair classifier: eq. (8)-(12) in, the ANFIS output out.

    Parameters
    ----------
    model : Anfis
        A fitted ANFIS whose inputs are ``feature_names``.
    feature_names : sequence of str or None
        Its inputs; default the model's metadata ``feature_names``, else the patent's five.

    """

    def __init__(self, model: Anfis, feature_names: Optional[tuple] = None):
        names = feature_names or model.metadata_.get('feature_names') or PATENT_FEATURE_NAMES
        if not isinstance(names, (list, tuple)) or len(names) != model.n_inputs:
            raise InputError(f'the ANFIS has {model.n_inputs} inputs but names {names!r}')
        self.model = model
        self.feature_names = tuple(names)
        self._columns = feature_index(self.feature_names)
        self.n_inputs = N_FEATURES

    @property
    def metadata_(self) -> dict:
        """Return the ANFIS model's metadata."""
        return self.model.metadata_

    def predict(self, features) -> np.ndarray:
        """ANFIS output of cycles given all their features, (N, N_FEATURES) -> (N,)."""
        x = np.asarray(features, dtype=float)
        if x.ndim != 2 or x.shape[1] != self.n_inputs:
            raise ValueError(f'features must be (N, {self.n_inputs}), got {x.shape}')
        return self.model.predict(x[:, self._columns])

    def save(self, path, metadata: Optional[dict] = None):
        """Write the ANFIS model file (its feature names in the metadata)."""
        self.model.save(path, metadata={'feature_names': list(self.feature_names),
                                        **(metadata or {})})


def as_classifier(model):
    """Wrap a bare :class:`Anfis` of eq. (8)-(12) as an :class:`AnfisClassifier`; others as is."""
    return AnfisClassifier(model) if isinstance(model, Anfis) else model


def backend_name(classifier) -> str:
    """Return 'forest' or 'anfis': the backend of a loaded classifier."""
    return 'forest' if isinstance(classifier, Forest) else 'anfis'


def warm_up(classifier) -> float:
    """
    Classify one cycle of zeros and throw the answer away; return the seconds it took.

    The forest's tree walk is numba code: its first call compiles it (about 10 s on a new
    machine) or loads it from numba's cache (about 1 s). A node calls this at start, so that
    its first gait cycle does not wait for that.
    """
    start = time.monotonic()
    classifier.predict(np.zeros((1, N_FEATURES)))
    return time.monotonic() - start


def load_classifier(path):
    """
    Read a stair-classifier model file; the backend follows its ``format`` key.

    Returns
    -------
    AnfisClassifier or Forest.

    Raises
    ------
    InputError : unreadable or invalid file, an unknown format, unknown feature names.

    """
    doc = read_json_file(path, max(MAX_MODEL_BYTES, MAX_FOREST_BYTES), 'stair-classifier model')
    kind = doc.get('format') if isinstance(doc, dict) else None
    if kind == FOREST_FORMAT:
        return Forest.from_document(doc, str(path))
    if kind == ANFIS_FORMAT:
        return AnfisClassifier(Anfis.load(path))
    raise InputError(f'{path}: format {kind!r} is not a stair-classifier model (expected one of '
                     f'{sorted(BACKENDS.values())}); train one with anfis_elevation_ros train')


__all__ = ['AnfisClassifier', 'as_classifier', 'backend_name', 'BACKENDS', 'load_classifier',
           'StairClassifier', 'warm_up']
