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

"""Tests of the forest backend: JSON inference equals scikit-learn, damaged files refused."""

import json
import math
import subprocess
import sys
import time

from anfis_elevation_ros.core.anfis import Anfis, grid_partition
from anfis_elevation_ros.core.classifier import AnfisClassifier, backend_name, load_classifier
from anfis_elevation_ros.core.classifier import warm_up
from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.forest import Forest, majority_vote_output
from anfis_elevation_ros.core.gait import feature_index, N_FEATURES, PATENT_FEATURE_NAMES
from anfis_elevation_ros.core.stair_steps import stair_mode
from anfis_elevation_ros.tools.train_forest import fit_forest, FOREST_FEATURE_NAMES, \
    ForestOptions
import numpy as np
import pytest


def three_modes(n, seed):
    """Cycles whose height change and gyro mean separate down / level / up, with noise."""
    rng = np.random.default_rng(seed)
    labels = rng.integers(-1, 2, n)
    features = rng.normal(size=(n, N_FEATURES))
    features[:, feature_index(['height_change_m'])[0]] += 2.0 * labels
    features[:, feature_index(['gyr_x_mean_rps'])[0]] += 1.5 * labels
    return features, labels


@pytest.fixture(scope='module')
def trained():
    """Grow a small forest with scikit-learn; return the estimator and its Forest."""
    sklearn_ensemble = pytest.importorskip('sklearn.ensemble')
    features, labels = three_modes(600, 1)
    estimator = sklearn_ensemble.RandomForestClassifier(n_estimators=15, max_features=0.5,
                                                        random_state=0)
    estimator.fit(features[:, feature_index(FOREST_FEATURE_NAMES)], labels)
    return estimator, Forest.from_sklearn(estimator, FOREST_FEATURE_NAMES)


def test_json_inference_equals_scikit_learn_on_every_sample(trained, tmp_path):
    estimator, forest = trained
    features, _ = three_modes(2000, 2)
    expected = estimator.predict_proba(features[:, feature_index(FOREST_FEATURE_NAMES)])
    path = tmp_path / 'forest.json'
    forest.save(path, metadata={'mode_threshold': 0.4})
    loaded = load_classifier(path)
    assert isinstance(loaded, Forest) and loaded.metadata_['mode_threshold'] == 0.4
    np.testing.assert_array_equal(loaded.predict_proba(features), expected)
    # Eq. 13 at sigma_th 0 on the output is scikit-learn's decision, the majority vote.
    output = loaded.predict(features)
    sklearn_modes = estimator.predict(features[:, feature_index(FOREST_FEATURE_NAMES)])
    np.testing.assert_array_equal(stair_mode(output, 0.0), sklearn_modes)
    np.testing.assert_array_equal(np.abs(output), np.where(sklearn_modes == 0, 0.0,
                                                           expected.max(axis=1)))


def test_the_output_is_the_vote_signed_with_its_share():
    proba = np.array([[0.5, 0.3, 0.2], [0.2, 0.45, 0.35], [0.1, 0.3, 0.6], [0.4, 0.2, 0.4],
                      [0.34, 0.33, 0.33]])
    np.testing.assert_allclose(majority_vote_output(proba), [-0.5, 0.0, 0.6, -0.4, -0.34])
    # Below 1/3, sigma_th changes nothing: a vote for up or down has over a third of the trees.
    for threshold in (0.0, 0.2, 0.33):
        assert stair_mode(majority_vote_output(proba), threshold).tolist() == [-1, 0, 1, -1, -1]


def test_fit_forest_learns_the_modes():
    pytest.importorskip('sklearn')
    features, labels = three_modes(1500, 3)
    forest = fit_forest(features, labels, ForestOptions(n_trees=20))
    test_features, test_labels = three_modes(1000, 4)
    proba = forest.predict_proba(test_features)
    assert np.mean(np.argmax(proba, axis=1) - 1 == test_labels) > 0.8   # chance: 1/3
    two_modes = fit_forest(features[labels >= 0], labels[labels >= 0], ForestOptions(n_trees=5))
    assert np.all(two_modes.predict_proba(test_features)[:, 0] == 0.0)   # never 'down'
    with pytest.raises(InputError, match='two modes'):
        fit_forest(features[labels == 0], labels[labels == 0], ForestOptions(n_trees=2))


@pytest.mark.parametrize('damage', ['truncate', 'threshold', 'metadata', 'sha256', 'version'])
def test_a_damaged_forest_file_is_refused(trained, tmp_path, damage):
    path = tmp_path / 'forest.json'
    trained[1].save(path)
    text = path.read_text()
    if damage == 'truncate':
        path.write_text(text[:len(text) // 2])
        match = 'not valid JSON'
    else:
        doc = json.loads(text)
        if damage == 'threshold':
            split = next(i for i, f in enumerate(doc['trees']['feature']) if f >= 0)
            doc['trees']['threshold'][split] += 0.25
        elif damage == 'metadata':
            doc['metadata']['mode_threshold'] = 0.1
        elif damage == 'sha256':
            doc['sha256'] = '0' * 64
        else:
            doc['version'] = 1          # P(up) - P(down) with its own sigma_th: retrain
        path.write_text(json.dumps(doc))
        match = 'version 1' if damage == 'version' else 'sha256'
    with pytest.raises(InputError, match=match):
        load_classifier(path)


def test_forest_arrays_that_loop_or_point_outside_are_refused():
    leaf = {'feature': [0, -1, -1], 'threshold': [0.5, 0.0, 0.0],
            'value': [[0.2, 0.6, 0.2], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]}
    Forest(['height_change_m'], [0], left=[1, -1, -1], right=[2, -1, -1], **leaf)
    for left in ([0, -1, -1], [3, -1, -1]):              # a cycle, a node past the end
        with pytest.raises(ValueError, match='later node'):
            Forest(['height_change_m'], [0], left=left, right=[2, -1, -1], **leaf)
    with pytest.raises(InputError, match='unknown gait-cycle feature'):
        Forest(['no_such_feature'], [0], left=[1, -1, -1], right=[2, -1, -1], **leaf)


def test_load_classifier_picks_the_backend_by_format(tmp_path):
    universe = np.array([[-1.0, 1.0]] * len(PATENT_FEATURE_NAMES))
    anfis = Anfis.from_params(grid_partition(universe, 2, 'triangle'),
                              np.zeros((2 ** len(PATENT_FEATURE_NAMES), 6)), universe)
    path = tmp_path / 'anfis.json'
    AnfisClassifier(anfis).save(path, metadata={'mode_threshold': 0.5})
    loaded = load_classifier(path)
    assert isinstance(loaded, AnfisClassifier)
    assert loaded.feature_names == PATENT_FEATURE_NAMES and loaded.n_inputs == N_FEATURES
    np.testing.assert_array_equal(loaded.predict(np.ones((3, N_FEATURES))), np.zeros(3))
    other = tmp_path / 'other.json'
    other.write_text(json.dumps({'format': 'something.else', 'version': 1}))
    with pytest.raises(InputError, match='not a stair-classifier model'):
        load_classifier(other)


def test_warm_up_classifies_one_cycle_of_every_feature(trained):
    """
    A node warms its classifier at start (the forest's numba code): one whole feature row.

    Warm-up classifies one cycle of zeros and returns the seconds that took, a finite float.
    """
    calls = []
    predict_s = 0.05

    class Recording:
        def predict(self, features):
            calls.append(np.array(features))
            time.sleep(predict_s)
            return np.zeros(len(features))

    took_s = warm_up(Recording())
    assert isinstance(took_s, float) and predict_s <= took_s < 5.0
    assert len(calls) == 1 and calls[0].shape == (1, N_FEATURES) and not calls[0].any()
    _, forest = trained
    took_s = warm_up(forest)
    assert isinstance(took_s, float) and math.isfinite(took_s) and took_s >= 0.0
    assert backend_name(forest) == 'forest'
    universe = np.array([[-1.0, 1.0]] * len(PATENT_FEATURE_NAMES))
    anfis = Anfis.from_params(grid_partition(universe, 2, 'triangle'),
                              np.zeros((2 ** len(PATENT_FEATURE_NAMES), 6)), universe)
    assert backend_name(AnfisClassifier(anfis)) == 'anfis'


def test_inference_does_not_import_scikit_learn(trained, tmp_path):
    path = tmp_path / 'forest.json'
    trained[1].save(path)
    code = ('import sys, numpy as np\n'
            'from anfis_elevation_ros.core.classifier import load_classifier\n'
            'from anfis_elevation_ros.core.gait import N_FEATURES\n'
            f'load_classifier({str(path)!r}).predict(np.zeros((1, N_FEATURES)))\n'
            'assert "sklearn" not in sys.modules, "inference imported scikit-learn"\n')
    subprocess.run([sys.executable, '-c', code], check=True, timeout=120)
