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

"""Tests of tools.metrics against hand-computed values."""

import math

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.tools.metrics import (
    accuracy, confusion_matrix, pyshoe_align, pyshoe_position_error)
import numpy as np
import pytest


def rot_z(angle):
    """Return the 3x3 rotation about z by ``angle`` rad."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def square_walk(n=400, seed=0):
    """Return an (n, 3) wandering track that leaves the start by more than 0.8 m."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 4.0 * np.pi, n)
    pos = np.column_stack([1.5 * np.sin(t), 1.2 * (1 - np.cos(0.5 * t)), 0.1 * np.sin(3 * t)])
    return pos + 0.01 * rng.standard_normal(pos.shape)


def test_identical_tracks_give_zero():
    gt = square_walk()
    assert pyshoe_position_error(gt, gt) == 0.0


def test_rotated_and_shifted_copy_gives_zero_after_alignment():
    gt = square_walk()
    est = (gt - gt[0]) @ rot_z(2.0).T + np.array([5.0, -3.0, 1.0])
    assert pyshoe_position_error(est, gt) == pytest.approx(0.0, abs=1e-12)
    # 2D estimates work the same way.
    assert pyshoe_position_error(est[:, :2], gt) == pytest.approx(0.0, abs=1e-12)


def test_constant_offset_everywhere_vanishes_with_the_start_shift():
    # Both tracks are shifted to start at 0, so a constant offset is no error at all.
    gt = square_walk()
    assert pyshoe_position_error(gt + np.array([1.0, 0.0, 0.0]), gt) == pytest.approx(0.0)


def test_offset_appearing_mid_track_gives_hand_computed_value():
    # Truth along +x in steps of 0.125 m. The estimate equals it up to sample 19, then is
    # 1 m further along x. Alignment: |e_7| = 0.875 m is the first >= 0.8 m, so sample 6 is
    # used: e_6 = t_6 = (0.75, 0) -> no rotation. Per sample error sqrt((1^2 + 0^2) / 2) on
    # samples 20..49: ARMSE = 30/50 * sqrt(1/2).
    n, m = 50, 20
    gt = np.column_stack([0.125 * np.arange(n), np.zeros(n), np.zeros(n)])
    est = gt.copy()
    est[m:, 0] += 1.0
    assert pyshoe_position_error(est, gt) == pytest.approx((n - m) / n * math.sqrt(0.5), rel=1e-12)


def test_alignment_uses_the_sample_before_the_estimate_crosses_the_distance():
    # est: (0, 0), (0, 0.5), (0.9, 0); gt: (0, 0), (0.5, 0), (1, 0). |e_1| = 0.5, |e_2| = 0.9,
    # so pyshoe aligns on sample 1: e_1 = +y onto t_1 = +x, a rotation of -90 deg taking
    # (x, y) to (y, -x). Aligned est: (0, 0), (0.5, 0), (0, -0.9); errors 0, 0,
    # sqrt((1^2 + 0.9^2) / 2).
    est = np.array([[0.0, 0.0], [0.0, 0.5], [0.9, 0.0]])
    gt = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0]])
    est_aligned, gt_shifted = pyshoe_align(est, gt)
    np.testing.assert_allclose(est_aligned, [[0, 0], [0.5, 0], [0, -0.9]], atol=1e-12)
    np.testing.assert_allclose(gt_shifted, gt[:, :2])
    expected = math.sqrt((1.0 + 0.81) / 2) / 3
    assert pyshoe_position_error(est, gt) == pytest.approx(expected, rel=1e-12)


def test_distance_test_is_on_the_estimate_not_the_truth():
    # The truth never gets 0.8 m from its start (0.4 m along +x) but the estimate (twice as
    # long, along +y) does: aligned on the estimate's sample, the error is computed normally.
    # Rotated onto +x the estimate is 2 t_k, so the per-sample error is sqrt(t_k^2 / 2).
    n = 41
    x = np.linspace(0.0, 0.4, n)
    gt = np.column_stack([x, np.zeros(n)])
    est = np.column_stack([np.zeros(n), 2.0 * x])
    expected = float(np.mean(x / math.sqrt(2.0)))
    assert pyshoe_position_error(est, gt) == pytest.approx(expected, rel=1e-12)


def test_estimate_never_reaching_the_distance_uses_sample_300_or_raises():
    # The estimate (0.1 of the truth, turned by +90 deg) stays within 0.4 m: pyshoe aligns on
    # sample 300. Turned back it is 0.1 t_k, so the error is sqrt((0.9 x_k)^2 / 2).
    n = 400
    x = np.linspace(0.0, 4.0, n)
    gt = np.column_stack([x, np.zeros(n), np.zeros(n)])
    est = np.column_stack([np.zeros(n), 0.1 * x])
    expected = float(np.mean(0.9 * x / math.sqrt(2.0)))
    assert pyshoe_position_error(est, gt) == pytest.approx(expected, rel=1e-12)
    with pytest.raises(InputError, match='never gets 0.8 m'):
        pyshoe_position_error(est, gt, fallback_index=None)
    with pytest.raises(InputError, match='outside'):
        pyshoe_position_error(est[:300], gt[:300])


def test_degenerate_alignment_raises():
    # First step already beyond 0.8 m: the alignment sample is sample 0, the start itself.
    est = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    with pytest.raises(InputError, match='no heading'):
        pyshoe_position_error(est, est)


def test_bad_shapes_raise():
    gt = square_walk(50)
    with pytest.raises(InputError, match='samples'):
        pyshoe_position_error(gt[:40], gt)
    with pytest.raises(InputError, match='shape'):
        pyshoe_position_error(gt[:, 0], gt)
    with pytest.raises(InputError, match='finite'):
        pyshoe_position_error(np.full_like(gt, np.nan), gt)


def test_agrees_with_arccos_form_of_the_angle():
    # Independent form of the alignment angle: sign(cross) * arccos(cos), on random tracks.
    rng = np.random.default_rng(7)
    for _ in range(20):
        gt = np.cumsum(0.05 * rng.standard_normal((300, 2)), axis=0) + [0.0, 0.0]
        gt[:, 0] += np.linspace(0.0, 3.0, 300)
        est = gt @ rot_z(rng.uniform(-3, 3))[:2, :2].T + 0.05 * rng.standard_normal(gt.shape)
        e, t = est - est[0], gt - gt[0]
        i = int(np.flatnonzero(np.linalg.norm(e[1:], axis=1) >= 0.8)[0])
        cos_a = min(e[i] @ t[i] / (np.linalg.norm(e[i]) * np.linalg.norm(t[i])), 1.0)
        angle = np.sign(e[i, 0] * t[i, 1] - e[i, 1] * t[i, 0]) * math.acos(cos_a)
        aligned = e @ rot_z(angle)[:2, :2].T
        expected = np.mean(np.sqrt(np.sum((aligned - t) ** 2, axis=1) / 2))
        assert pyshoe_position_error(est, gt) == pytest.approx(expected, rel=1e-9)


def test_confusion_matrix_counts_pairs():
    true = [-1, -1, 0, 0, 0, 1, 1, 1, 1]
    pred = [-1, 0, 0, 0, 1, 1, 1, 1, -1]
    expected = np.array([[1, 1, 0], [0, 2, 1], [1, 0, 3]])
    np.testing.assert_array_equal(confusion_matrix(true, pred), expected)
    np.testing.assert_array_equal(
        confusion_matrix(true, pred, labels=(1, 0, -1)), expected[::-1, ::-1])
    assert confusion_matrix(true, pred).sum() == len(true)
    assert accuracy(true, pred) == pytest.approx(6 / 9)


def test_classification_helpers_reject_bad_input():
    with pytest.raises(InputError, match=r'\[2\]'):
        confusion_matrix([0, 2], [0, 0])
    with pytest.raises(InputError, match='labels'):
        confusion_matrix([0, 1], [0])
    with pytest.raises(InputError, match='undefined'):
        accuracy([], [])
