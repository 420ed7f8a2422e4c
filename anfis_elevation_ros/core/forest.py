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
Random-forest stair classifier stored as data: JSON inference without scikit-learn.

Seed 001's scene classifier: bootstrap trees, each split on the best of a random subset of the
features, voting on level / up / down: the class most trees vote for is the cycle's mode
(:func:`majority_vote_output`). ``tools/train_forest.py`` grows it with scikit-learn
(``RandomForestClassifier``) and converts it with :meth:`Forest.from_sklearn`; here it is only
arrays, walked by one compiled loop (:func:`forest_probabilities`), so the nodes need nothing
beyond numpy and numba.

File (``format`` ``anfis_elevation_ros.forest``, ``version`` 2): ``feature_names`` (the gait-cycle
features it reads, in column order), ``classes`` ([-1, 0, 1]: down, level, up), ``trees`` with
the nodes of all trees end to end (``roots``, ``feature`` (-1 at a leaf), ``threshold``,
``left``, ``right``, ``value``: class fractions of the training cycles at the node),
``metadata``, and ``sha256``: the SHA-256 of the canonical JSON (sorted keys, no spaces) of
everything else, so a truncated, damaged or edited file is refused.

Decision rule of a node: x[feature] <= threshold goes left. scikit-learn compares the features
as float32 against float64 thresholds; :meth:`Forest.predict_proba` rounds them the same way, so
both give the same probabilities to the last bit.
"""

import hashlib
import json
import os
from typing import Optional

import numpy as np

from .errors import InputError
from .gait import feature_index, N_FEATURES
from .jit import jit
from .json_file import read_json_file, write_text_atomically

FORMAT_NAME = 'anfis_elevation_ros.forest'
"""Value of the ``format`` key of a forest file."""
FORMAT_VERSION = 2
"""Value of the ``version`` key; :meth:`Forest.load` reads only this version (1: the output
was P(up) - P(down), and the model's sigma_th was chosen for that output)."""
CLASSES = (-1, 0, 1)
"""Stair modes, in the column order of the probabilities: down, level, up."""
MAX_FOREST_BYTES = 20_000_000
"""Largest forest file read (500 trees of 2,000 nodes take about 15 MB)."""
MAX_NODES = 2_000_000
"""Largest total number of nodes."""


@jit
def forest_probabilities(x: np.ndarray, feature: np.ndarray, threshold: np.ndarray,
                         left: np.ndarray, right: np.ndarray, value: np.ndarray,
                         roots: np.ndarray) -> np.ndarray:
    """
    Mean class fractions of the leaves each sample reaches: p(c | x) = 1/T sum_t value[leaf_t(x)].

    Parameters
    ----------
    x : (N, F) float array
        Features, in the forest's column order.
    feature, left, right : (M,) int64 arrays
        Split feature (-1 at a leaf) and child indices of every node.
    threshold : (M,) float array
        Split thresholds: x[feature] <= threshold goes left.
    value : (M, C) float array
        Class fractions at each node.
    roots : (T,) int64 array
        Root node of each tree.

    Returns
    -------
    (N, C) array.

    """
    out = np.zeros((x.shape[0], value.shape[1]))
    for i in range(x.shape[0]):
        for t in range(roots.shape[0]):
            node = roots[t]
            while feature[node] >= 0:
                if x[i, feature[node]] <= threshold[node]:
                    node = left[node]
                else:
                    node = right[node]
            out[i] += value[node]
    return out / roots.shape[0]


def majority_vote_output(proba: np.ndarray) -> np.ndarray:
    """
    Eq. (13) input of a forest: the majority vote, signed, with its share of the votes.

        y = c* P(c*),   c* = argmax_c P(c),   c in (-1, 0, +1) (down, level, up)

    |y| is above 1/3 whenever c* is up or down, and 0 when it is level, so eq. (13) with any
    sigma_th below 1/3 is seed 001's majority vote; a larger sigma_th asks the vote for a
    margin. (P(up) - P(down), the output until 2026-12-03, is not the vote: at sigma_th 0.45,
    chosen for accuracy, it called 11 % of HuGaDB's new wearers' strides up level, against 8 %
    for the vote at the same accuracy.) Ties go to the first class, down, level, up.

    Parameters
    ----------
    proba : (N, 3) array
        Class probabilities (down, level, up), :meth:`Forest.predict_proba`.

    Returns
    -------
    (N,) array in [-1, 1].

    """
    winner = np.argmax(proba, axis=1)
    return np.asarray(CLASSES, dtype=float)[winner] * proba[np.arange(len(proba)), winner]


class Forest:
    """
    A random forest of stair-mode trees, as arrays.

    Attributes
    ----------
    feature_names : tuple of str, the gait-cycle features of its columns.
    n_inputs : int, the length of a cycle's feature vector it takes (all of FEATURE_NAMES).
    metadata_ : dict, how it was trained (command, data, cross-validation).

    """

    def __init__(self, feature_names, roots, feature, threshold, left, right, value,
                 metadata: Optional[dict] = None):
        self.feature_names = tuple(feature_names)
        self._columns = feature_index(self.feature_names)
        self.n_inputs = N_FEATURES
        self.roots = np.ascontiguousarray(roots, dtype=np.int64)
        self.feature = np.ascontiguousarray(feature, dtype=np.int64)
        self.threshold = np.ascontiguousarray(threshold, dtype=np.float64)
        self.left = np.ascontiguousarray(left, dtype=np.int64)
        self.right = np.ascontiguousarray(right, dtype=np.int64)
        self.value = np.ascontiguousarray(value, dtype=np.float64)
        self.metadata_ = dict(metadata or {})
        self._check()

    def _check(self):
        n_nodes = len(self.feature)
        if not 1 <= n_nodes <= MAX_NODES or len(self.roots) < 1:
            raise ValueError(f'a forest needs 1 to {MAX_NODES} nodes and a tree, got {n_nodes} '
                             f'nodes, {len(self.roots)} trees')
        if any(len(a) != n_nodes for a in (self.threshold, self.left, self.right, self.value)) \
                or self.value.shape != (n_nodes, len(CLASSES)):
            raise ValueError('feature, threshold, left, right and value must have one entry per '
                             f'node ({n_nodes}), value {len(CLASSES)} fractions each')
        split = self.feature >= 0
        if np.any(self.feature >= len(self.feature_names)) or np.any(self.feature < -1):
            raise ValueError(f'split features must be -1 (leaf) or < {len(self.feature_names)}')
        for name, children in (('left', self.left), ('right', self.right)):
            # Children come after their parent, so every walk down a tree ends at a leaf.
            if np.any((children[split] <= np.flatnonzero(split))
                      | (children[split] >= n_nodes)):
                raise ValueError(f'{name} child of a split must be a later node of the forest')
        if np.any((self.roots < 0) | (self.roots >= n_nodes)):
            raise ValueError('tree roots must be nodes of the forest')
        if not (np.all(np.isfinite(self.threshold[split])) and np.all(np.isfinite(self.value))
                and np.all(self.value >= 0.0)
                and np.allclose(self.value.sum(axis=1), 1.0, rtol=0.0, atol=1e-9)):
            raise ValueError('thresholds must be finite and node values class fractions '
                             '(>= 0, summing to 1)')

    # ----------------------------------------------------------------------------- inference

    def predict_proba(self, features) -> np.ndarray:
        """
        Class probabilities (down, level, up) of cycles, :func:`forest_probabilities`.

        Parameters
        ----------
        features : (N, n_inputs) array
            Gait-cycle features in ``FEATURE_NAMES`` order.

        """
        x = np.asarray(features, dtype=float)
        if x.ndim != 2 or x.shape[1] != self.n_inputs:
            raise ValueError(f'features must be (N, {self.n_inputs}), got {x.shape}')
        # float32 as scikit-learn compares them, then back to float64 for the thresholds.
        x = np.ascontiguousarray(x[:, self._columns].astype(np.float32), dtype=np.float64)
        return forest_probabilities(x, self.feature, self.threshold, self.left, self.right,
                                    self.value, self.roots)

    def predict(self, features) -> np.ndarray:
        """Eq. (13) input of cycles, :func:`majority_vote_output` of their probabilities."""
        return majority_vote_output(self.predict_proba(features))

    # ----------------------------------------------------------------------------- conversion

    @classmethod
    def from_sklearn(cls, estimator, feature_names, metadata: Optional[dict] = None):
        """
        Convert a fitted ``sklearn.ensemble.RandomForestClassifier`` (classes among -1, 0, 1).

        The estimator is only read (its ``estimators_[k].tree_`` arrays); scikit-learn is not
        imported here. A mode absent from the training data gets probability 0 everywhere.
        """
        classes = [int(c) for c in estimator.classes_]
        if not set(classes) <= set(CLASSES):
            raise ValueError(f'the forest must be trained on classes among {list(CLASSES)}, '
                             f'got {classes}')
        columns = [CLASSES.index(c) for c in classes]
        parts = {key: [] for key in ('feature', 'threshold', 'left', 'right', 'value')}
        roots, offset = [], 0
        for tree in (e.tree_ for e in estimator.estimators_):
            leaf = tree.children_left < 0
            roots.append(offset)
            parts['feature'].append(np.where(leaf, -1, tree.feature))
            parts['threshold'].append(np.where(leaf, 0.0, tree.threshold))
            parts['left'].append(np.where(leaf, -1, tree.children_left + offset))
            parts['right'].append(np.where(leaf, -1, tree.children_right + offset))
            value = np.zeros((tree.node_count, len(CLASSES)))
            value[:, columns] = tree.value[:, 0, :]
            parts['value'].append(value / value.sum(axis=1, keepdims=True))
            offset += tree.node_count
        return cls(feature_names, roots, *(np.concatenate(parts[k]) for k in parts),
                   metadata=metadata)

    # ----------------------------------------------------------------------------- files

    def to_dict(self) -> dict:
        """Return the JSON document of the forest, with its ``sha256``."""
        doc = {
            'format': FORMAT_NAME,
            'version': FORMAT_VERSION,
            'feature_names': list(self.feature_names),
            'classes': list(CLASSES),
            'trees': {'roots': self.roots.tolist(), 'feature': self.feature.tolist(),
                      'threshold': self.threshold.tolist(), 'left': self.left.tolist(),
                      'right': self.right.tolist(), 'value': self.value.tolist()},
            'metadata': self.metadata_,
        }
        doc['sha256'] = content_digest(doc)
        return doc

    def save(self, path, metadata: Optional[dict] = None):
        """Write the forest as JSON, atomically (``metadata`` is merged into ``metadata_``)."""
        if metadata:
            self.metadata_ = {**self.metadata_, **metadata}
        text = json.dumps(self.to_dict(), allow_nan=False, sort_keys=True,
                          separators=(',', ':'))
        write_text_atomically(path, text + '\n')

    @classmethod
    def load(cls, path) -> 'Forest':
        """
        Read a forest written by :meth:`save`, validating everything.

        Raises
        ------
        InputError : missing, unreadable, truncated or altered file (SHA-256), wrong format or
            version, bad arrays, unknown feature names.

        """
        doc = read_json_file(path, MAX_FOREST_BYTES, 'forest model')
        return cls.from_document(doc, os.fspath(path))

    @classmethod
    def from_document(cls, doc, path: str) -> 'Forest':
        """Build a forest from a parsed file (see :meth:`load`)."""
        def fail(message):
            raise InputError(f'{path}: {message}')

        if not isinstance(doc, dict) or doc.get('format') != FORMAT_NAME:
            fail(f'not a forest model file (expected "format": "{FORMAT_NAME}")')
        if type(doc.get('version')) is not int or doc['version'] != FORMAT_VERSION:
            fail(f'version {doc.get("version")!r} is not supported (this reader reads version '
                 f'{FORMAT_VERSION}); retrain the model with this version of the package')
        expected = {'format', 'version', 'feature_names', 'classes', 'trees', 'metadata',
                    'sha256'}
        if set(doc) != expected:
            fail(f'missing keys {sorted(expected - set(doc))} / unknown keys '
                 f'{sorted(set(doc) - expected)}')
        if doc['sha256'] != content_digest({k: v for k, v in doc.items() if k != 'sha256'}):
            fail('content does not match its sha256: the file was altered or damaged; '
                 'retrain or restore it')
        if doc['classes'] != list(CLASSES) or not isinstance(doc['metadata'], dict):
            fail(f'classes must be {list(CLASSES)} and metadata an object')
        names = doc['feature_names']
        if not (isinstance(names, list) and names and all(isinstance(n, str) for n in names)):
            fail('feature_names must be a list of feature names')
        trees = doc['trees']
        keys = ('roots', 'feature', 'threshold', 'left', 'right', 'value')
        if not isinstance(trees, dict) or set(trees) != set(keys):
            fail(f'trees must hold exactly {list(keys)}')
        arrays = []
        for key in keys:
            try:
                array = np.array(trees[key], dtype=float)
            except (TypeError, ValueError, OverflowError):
                fail(f'trees.{key} is not an array of numbers')
            if array.ndim != (2 if key == 'value' else 1):
                fail(f'trees.{key} has the wrong shape {array.shape}')
            if key in ('roots', 'feature', 'left', 'right') \
                    and not np.array_equal(array, np.round(array)):
                fail(f'trees.{key} must hold integers')
            arrays.append(array)
        try:
            return cls(names, *arrays, metadata=doc['metadata'])
        except (ValueError, InputError) as err:
            fail(str(err))


def content_digest(doc: dict) -> str:
    """SHA-256 (hex) of the canonical JSON of a document: sorted keys, no spaces, no NaN."""
    text = json.dumps(doc, allow_nan=False, sort_keys=True, separators=(',', ':'))
    return hashlib.sha256(text.encode('utf-8')).hexdigest()


__all__ = ['CLASSES', 'FORMAT_NAME', 'FORMAT_VERSION', 'Forest', 'content_digest',
           'forest_probabilities', 'majority_vote_output']
