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
Grow the random-forest stair classifier (``train --backend forest``) with scikit-learn.

Seed 001's scene classifier: ``sklearn.ensemble.RandomForestClassifier`` -- bootstrap samples
of the training cycles, each split on the best of a random subset of the features -- on every
gait-cycle feature (:data:`FOREST_FEATURE_NAMES`: the seed's eleven motion features and height
change, and the patent's other four, eq. 8, 9, 11, 12), labels down / level / up (-1 / 0 / +1).
With the patent's four, leave-one-subject-out on HuGaDB 1-9 went from 0.925 to 0.939
(doc/classifier_notebook.md, "features: seed 001's twelve").
The fitted forest is converted to arrays (:class:`~..core.forest.Forest`) and
stored as JSON; inference needs no scikit-learn. scikit-learn is only needed here: install the
``train`` extra (``pip install .[train]``).
"""

from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..core.forest import Forest
from ..core.gait import feature_index, FEATURE_NAMES
from ..core.validation import check_range

FOREST_FEATURE_NAMES = FEATURE_NAMES
"""Every gait-cycle feature: seed 001's twelve and eq. (8), (9), (11), (12)."""


@dataclass(frozen=True)
class ForestOptions:
    """
    Random-forest settings (``RandomForestClassifier`` arguments of the same name).

    ``max_features``: features tried at each split, as a share of the sixteen; ``train``
    chooses it by cross-validation among ``train.MAX_FEATURES_CANDIDATES``: 1/8 (two features)
    on the data of the default model (README, "Stair classifier for a new wearer").
    ``class_weight``: 'balanced' weights each mode by the inverse of its share of the cycles;
    'none' leaves the (level-heavy) mix as it is. ``seed``: of the bootstrap and the subsets.
    """

    n_trees: int = 100
    max_features: float = 0.125
    min_samples_leaf: int = 2
    class_weight: str = 'balanced'
    seed: int = 0

    def __post_init__(self):
        check_range('forest n_trees', self.n_trees, 1, 1000)
        check_range('forest max_features', self.max_features, 0.0, 1.0, open_low=True)
        check_range('forest min_samples_leaf', self.min_samples_leaf, 1, 1000)
        if self.class_weight not in ('balanced', 'none'):
            raise InputError(f"forest class_weight = {self.class_weight!r} is not 'balanced' or "
                             "'none'")


def fit_forest(features: np.ndarray, labels: np.ndarray, options: ForestOptions) -> Forest:
    """
    Fit the forest on whole cycle feature vectors (N, N_FEATURES) and modes -1 / 0 / +1.

    Raises
    ------
    InputError : scikit-learn is not installed, or the labels hold a single mode.

    """
    try:
        from sklearn.ensemble import RandomForestClassifier
    except ImportError:
        raise InputError('training a forest needs scikit-learn: pip install '
                         '"anfis_elevation_ros[train]" (scikit-learn==1.9.1)') from None
    if len(np.unique(labels)) < 2:
        raise InputError(f'the forest needs cycles of two modes or more, got only '
                         f'{np.unique(labels).tolist()}')
    estimator = RandomForestClassifier(
        n_estimators=options.n_trees, max_features=options.max_features,
        min_samples_leaf=options.min_samples_leaf,
        class_weight=None if options.class_weight == 'none' else options.class_weight,
        random_state=options.seed, n_jobs=1)
    estimator.fit(features[:, feature_index(FOREST_FEATURE_NAMES)], labels)
    return Forest.from_sklearn(estimator, FOREST_FEATURE_NAMES)


__all__ = ['FOREST_FEATURE_NAMES', 'ForestOptions', 'fit_forest']
