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
Where the HuGaDB leave-one-subject-out errors come from (a script, not a test).

Run from the repository root: ``PYTHONPATH=. python test/benchmarks/bench_hugadb_errors.py``
(``--clipped-gyro`` adds the +-250 deg/s feet, subjects 1-9; ``--parts`` to choose; ``--help``).
The cross-validation is the ``train`` one (simulated seeds 1-40 + HuGaDB, one fold per subject,
default training options), scored with sigma_th chosen inside the training folds
(``cross_validation.nested_cv``). Parts:

- ``loso``: accuracy and confusion per subject; errors by distance of the cycle to the nearest
  change of the human label, by cycle duration (merged cycles: a stance the detector missed),
  by two-foot agreement (the other foot's overlapping cycles predicted the same wrong mode:
  label or ambiguity; predicted otherwise: this foot's features), and runs of at least 3
  consecutive errors of one label on one foot (suspect label stretches).
- ``nav``: what the navigator makes of the +-2 g accelerometer: per swing, the velocity left at
  its end (what the ZUPT removes; from the track's last two swing samples) against the number
  of saturated accelerometer samples in it; the EKF's accelerometer-bias estimate; horizontal
  stride length per mode (true: about 1.3 m level, 0.6 m on stairs).
- ``gyro``: the feet whose gyro ``file_index.csv`` flags, read as +-2000 and as +-250 deg/s,
  classified by a model of the unflagged feet and the simulated runs.
- ``gate``: the cycles the stride gate (``stride_gate.enabled``) adds and removes, per foot:
  an added cycle is one whose end is more than 0.2 s from every end without the gate; its
  duration (from the previous end), its ratio to the neighbouring cycles' (a split stride:
  about 0.5; a recovered one: about 1), where its end falls in the cycle without the gate
  that holds it (0-1), and whether its relaxed stance sits on the +-2 g rail (+-2 samples);
  the two feet of a file should cut as many cycles.
- ``gate_loso``: leave-one-subject-out of the used cycles, gate off and on (every simulated run
  in every training set, sigma_th 0.45: a quick check, not the ``train`` folds): accuracy of
  the cycles both detectors cut (start and end within 0.2 s) and of those only one cuts.
- ``pipeline``: the forest out of fold in the ``train`` folds (the shipped settings, not
  nested), each held-out HuGaDB foot replayed through the whole pipeline (``replay``): the
  classifier's mode against the mode after the stride's geometry check
  (``height_checked_mode``, which uses the INS stride's length), and what the check changed.
- ``decision``: the forest's out-of-fold class probabilities in the ``train`` folds (simulated
  seeds 1-40 + HuGaDB, then HuGaDB alone), HuGaDB accuracy and recall per mode when the mode is
  the largest probability and when it is eq. (13) on P(up) - P(down) at several sigma_th.

Navigator outputs are cached as in ``train`` (``--cache-dir``).
"""

import argparse
from collections import Counter, defaultdict
import dataclasses
from pathlib import Path
import sys

from anfis_elevation_ros.core.forest import majority_vote_output
from anfis_elevation_ros.core.height import stair_mode
from anfis_elevation_ros.core.input_gate import InputGate
from anfis_elevation_ros.core.navigator import FootNavigator
from anfis_elevation_ros.core.params import load_pipeline_params
from anfis_elevation_ros.tools import labels as lab
from anfis_elevation_ros.tools.cross_validation import assign_folds, cross_validate, fit_model
from anfis_elevation_ros.tools.cross_validation import nested_cv, stack, TrainOptions
from anfis_elevation_ros.tools.datasets import load_hugadb, shared_data_dir, STANDARD_GRAVITY_MPS2
from anfis_elevation_ros.tools.metrics import confusion_matrix
from anfis_elevation_ros.tools.replay import CYCLE_COLUMNS, navigated_samples, replay_recording
from anfis_elevation_ros.tools.training_data import collect, DEFAULT_MIN_STRIDE_S, hugadb_specs
from anfis_elevation_ros.tools.training_data import LabelRules, Progress
from anfis_elevation_ros.tools.training_recordings import default_cache_dir, HugadbSpec, navigated
from anfis_elevation_ros.tools.training_recordings import Pipeline, sim_spec
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
HUGADB_ACC_SATURATION_MPS2 = 0.999 * 2.0 * STANDARD_GRAVITY_MPS2
RUN_LENGTH = 3


def cycle_table(spec, cycle_set, rules, cache_dir) -> dict:
    """Stamps, duration and label-change distance of the used cycles of one HuGaDB foot."""
    nav = navigated(spec, Pipeline(), cache_dir)[0]
    labels, labelled = lab.majority_labels(nav.start_ns, nav.stamp_ns, nav.truth_stamp_ns,
                                           nav.truth_label, rules.min_majority)
    non_stride = lab.non_stride_cycles(nav.start_ns, nav.stamp_ns, rules.min_stride_s)
    used = nav.valid & (labelled | non_stride)
    assert int(used.sum()) == len(cycle_set.labels)
    change_ns = nav.truth_stamp_ns[1:][np.diff(nav.truth_label) != 0]
    start, stop = nav.start_ns[used], nav.stamp_ns[used]
    before = np.searchsorted(change_ns, start, side='right') - 1
    after = np.searchsorted(change_ns, stop, side='left')
    gap_before = np.where(before >= 0, start - change_ns[np.maximum(before, 0)], np.inf)
    gap_after = np.where(after < len(change_ns),
                         change_ns[np.minimum(after, len(change_ns) - 1)] - stop, np.inf)
    inside = after - before > 1
    distance_s = np.where(inside, 0.0, np.minimum(gap_before, gap_after) * 1e-9)
    return {'start_s': start * 1e-9, 'stop_s': stop * 1e-9, 'distance_s': distance_s,
            'non_stride': non_stride[used], 'invalid': int(np.sum(~nav.valid)),
            'cycles': len(nav.valid)}


def loso(args):
    """Run the cross-validation; return per-cycle arrays of the HuGaDB cycles."""
    rules = LabelRules()
    hugadb = hugadb_specs(args.hugadb, clipped_gyro=args.clipped_gyro)
    specs = [sim_spec(seed) for seed in range(1, 41)] + hugadb
    progress = Progress(args.quiet)
    everything = collect(specs, Pipeline(), rules, args.cache_dir, args.jobs, progress)
    keep = [i for i, s in enumerate(everything) if len(s.labels)]
    sets = [everything[i] for i in keep]
    folds, _ = assign_folds(sets, 'subject', 0, 0)
    options = TrainOptions()
    output = cross_validate(sets, folds, options, progress)
    _, thresholds, predicted = nested_cv(sets, folds, [options], [output], progress)
    _, labels, owner = stack(sets)
    rows = defaultdict(list)
    for i, cycle_set in zip(keep, sets):
        spec = specs[i]
        mask = owner == keep.index(i)
        if cycle_set.source != 'hugadb':
            continue
        table = cycle_table(spec, cycle_set, rules, args.cache_dir)
        n = len(cycle_set.labels)
        rows['file'] += [Path(spec.path).stem] * n
        rows['foot'] += [spec.foot] * n
        rows['subject'] += [spec.subject] * n
        rows['gyro_range_dps'] += [spec.gyro_range_dps] * n
        for key in ('start_s', 'stop_s', 'distance_s', 'non_stride'):
            rows[key].append(table[key])
        rows['label'].append(labels[mask])
        rows['predicted'].append(predicted[mask])
        rows['output'].append(output[mask])
        rows['features'].append(cycle_set.features)
    table = {key: (np.concatenate(value) if isinstance(value[0], np.ndarray)
                   else np.array(value)) for key, value in rows.items()}
    print(f'\nHuGaDB leave-one-subject-out, {len(hugadb)} feet, sigma_th per fold '
          f'{"/".join(f"{t:g}" for t in thresholds)} (chosen inside the training folds)')
    return table


def print_loso(t):
    """Accuracy, confusion and the error breakdowns of the cross-validation."""
    ok = t['label'] == t['predicted']
    print(f'  accuracy {ok.mean():.4f} on {len(ok)} cycles, {int(np.sum(~ok))} errors; '
          f'confusion (rows true -1/0/+1) {confusion_matrix(t["label"], t["predicted"]).tolist()}')
    for subject in sorted(set(t['subject'].tolist())):
        m = t['subject'] == subject
        print(f'    s{subject}: {ok[m].mean():.4f} on {m.sum():4d}, confusion '
              f'{confusion_matrix(t["label"][m], t["predicted"][m]).tolist()}')
    print('  by distance of the cycle to the nearest label change:')
    for lo, hi in ((0.0, 1e-9), (1e-9, 0.5), (0.5, 1.0), (1.0, 2.0), (2.0, 4.0), (4.0, np.inf)):
        m = (t['distance_s'] >= lo) & (t['distance_s'] < hi)
        name = 'spans one' if hi < 1e-6 else f'[{lo:g}, {hi:g}) s'
        if m.any():
            print(f'    {name:12s} {m.sum():5d} cycles, accuracy {ok[m].mean():.4f}, '
                  f'{int(np.sum(~ok[m]))} errors')
    duration = t['stop_s'] - t['start_s']
    print('  by cycle duration (swing; a stride takes 0.6-1.1 s):')
    for lo, hi in ((0.0, 0.3), (0.3, 0.6), (0.6, 1.2), (1.2, 1.5), (1.5, 2.6)):
        m = (duration >= lo) & (duration < hi)
        if m.any():
            print(f'    [{lo:g}, {hi:g}) s {m.sum():5d} cycles, accuracy {ok[m].mean():.4f}, '
                  f'{int(np.sum(~ok[m]))} errors')
    agreement = Counter()
    keys = list(zip(t['file'], t['foot']))
    by_foot = defaultdict(list)
    for i, key in enumerate(keys):
        by_foot[key].append(i)
    for i in np.flatnonzero(~ok):
        other = by_foot.get((t['file'][i], 'left' if t['foot'][i] == 'right' else 'right'), [])
        near = [j for j in other if t['stop_s'][j] > t['start_s'][i] - 0.3
                and t['start_s'][j] < t['stop_s'][i] + 0.3 and not t['non_stride'][j]]
        if not other:
            agreement['one foot only'] += 1
        elif not near:
            agreement['no overlapping cycle'] += 1
        elif all(t['predicted'][j] == t['predicted'][i] for j in near):
            agreement['other foot predicts the same'] += 1
        else:
            agreement['other foot predicts otherwise'] += 1
    print(f'  errors by two-foot agreement: {dict(agreement)}')
    runs = []
    for key, index in by_foot.items():
        index = [i for i in index if not t['non_stride'][i]]
        k = 0
        while k < len(index):
            j = k
            while j < len(index) and not ok[index[j]] and \
                    t['label'][index[j]] == t['label'][index[k]]:
                j += 1
            if j - k >= RUN_LENGTH:
                runs.append((key, t['start_s'][index[k]], t['stop_s'][index[j - 1]], j - k,
                             int(t['label'][index[k]]),
                             dict(Counter(t['predicted'][index[k:j]].tolist()))))
            k = max(j, k + 1)
    print(f'  runs of >= {RUN_LENGTH} consecutive errors of one label on one foot '
          f'({sum(r[3] for r in runs)} cycles):')
    for (name, foot), start, stop, n, label, predicted in sorted(runs):
        print(f'    {name} {foot:5s} {start:6.1f}-{stop:6.1f} s: {n} cycles labelled {label:+d}, '
              f'predicted {predicted}')
    f = t['features']
    print('  medians of dh (m) and max pitch (rad), right | wrong, per true mode:')
    for mode in lab.MODES:
        parts = []
        mine = t['label'] == mode
        for name, m in (('right', mine & ok), ('wrong', mine & ~ok)):
            parts.append(f'{name} n={m.sum():4d} dh {np.median(f[m, 2]):+.3f} pitch '
                         f'{np.median(f[m, 4]):+.3f}')
        print(f'    {mode:+d}: ' + ' | '.join(parts))


def swing_diagnostics(spec):
    """Per swing: end velocity (m/s), saturated samples; acc-bias estimate; cycle strides."""
    recording, activity = load_hugadb(spec.path, spec.foot, gyro_range_dps=spec.gyro_range_dps)
    saturated = np.any(np.abs(recording.acc_b) >= HUGADB_ACC_SATURATION_MPS2, axis=1)
    navigator = FootNavigator(Pipeline().navigator)
    swings, biases, strides = [], [], []
    previous, n_saturated, n_swing, last_pos = None, 0, 0, None
    min_swing = int(round(DEFAULT_MIN_STRIDE_S * recording.rate_hz))
    for k, point, cycle in navigated_samples(recording, InputGate(Pipeline().gate),
                                             navigator):
        if not point.stance:
            n_saturated += saturated[k]
            n_swing += 1
        elif previous is not None and not previous[0].stance and previous[1] is not None:
            dt_s = (previous[0].stamp_ns - previous[1].stamp_ns) * 1e-9
            velocity = (previous[0].pos_n - previous[1].pos_n) / dt_s
            if n_swing >= min_swing:       # a stride, not the detector flickering at rest
                swings.append((n_saturated, np.hypot(*velocity[:2]), abs(velocity[2])))
            n_saturated = n_swing = 0
            biases.append(float(np.linalg.norm(getattr(navigator, '_acc_bias', np.zeros(3)))))
        if cycle is not None and cycle.valid:
            if last_pos is not None:
                strides.append((cycle.start_stamp_ns, cycle.stamp_ns,
                                float(np.hypot(*(cycle.pos_n[:2] - last_pos[:2])))))
            last_pos = cycle.pos_n
        previous = (point, previous[0] if previous else None)
    return np.array(swings).reshape(-1, 3), np.array(biases), strides, recording, activity


def print_nav(args):
    """Swing-end velocity against saturation, bias estimates, stride lengths."""
    swings, biases, lengths = [], [], defaultdict(list)
    for spec in hugadb_specs(args.hugadb):
        s, b, strides, recording, activity = swing_diagnostics(spec)
        swings.append(s)
        biases.append(b)
        modes = lab.hugadb_activity_labels(activity)
        start = np.array([a for a, _, _ in strides], dtype=np.int64)
        stop = np.array([z for _, z, _ in strides], dtype=np.int64)
        label, labelled = lab.majority_labels(start, stop, recording.stamp_ns, modes)
        for length, mode, known in zip([x for _, _, x in strides], label, labelled):
            if known:
                lengths[int(mode)].append(length)
    swings = np.vstack(swings)
    biases = np.concatenate(biases)
    print(f'\nNavigation of the unflagged feet: {len(swings)} swings of at least '
          f'{DEFAULT_MIN_STRIDE_S:g} s')
    print('  velocity left at the end of the swing (removed by the ZUPT) by saturated '
          'accelerometer samples in the swing:')
    for lo, hi in ((0, 1), (1, 3), (3, 6), (6, 10), (10, 1000)):
        m = (swings[:, 0] >= lo) & (swings[:, 0] < hi)
        print(f'    [{lo}, {hi}) saturated: {m.sum():5d} swings, median |v_h| '
              f'{np.median(swings[m, 1]):.3f} m/s, |v_z| {np.median(swings[m, 2]):.3f} m/s')
    print(f'  saturated samples per swing: median {np.median(swings[:, 0]):.0f}; EKF |acc bias| '
          f'estimate at the stances: median {np.median(biases):.2f} m/s^2, 95 % '
          f'{np.percentile(biases, 95):.2f} (start-up sigma 0.1)')
    print('  horizontal stride length per labelled mode (median, m): ' + ', '.join(
        f'{m:+d}: {np.median(v):.2f} ({len(v)})' for m, v in sorted(lengths.items())))


def print_gyro(args):
    """Classify the flagged gyros, read at either full scale, by a model of the others."""
    rules = LabelRules()
    specs = [sim_spec(seed) for seed in range(1, 41)] + hugadb_specs(args.hugadb)
    sets = [s for s in collect(specs, Pipeline(), rules, args.cache_dir, args.jobs,
                               Progress(args.quiet)) if len(s.labels)]
    features, labels, _ = stack(sets)
    model = fit_model(features, labels, TrainOptions())
    threshold = 0.45                                    # the default model's sigma_th
    flagged = [s for s in hugadb_specs(args.hugadb, clipped_gyro=True)
               if s.gyro_range_dps != 2000]
    print(f'\nFlagged gyros ({len(flagged)} feet), model of the {len(specs) - 40} unflagged feet '
          f'and seeds 1-40, sigma_th {threshold}:')
    for range_dps in (2000, 250):
        specs_r = [HugadbSpec(s.path, s.foot, s.subject, range_dps) for s in flagged]
        found = [s for s in collect(specs_r, Pipeline(), rules, args.cache_dir,
                                    args.jobs, Progress(True)) if len(s.labels)]
        f, y, owner = stack(found)
        p = stair_mode(model.predict(f), threshold)
        subject = np.array([found[i].subject for i in owner])
        counts = {key: sum(s.counts[key] for s in found) for key in ('cycles', 'invalid')}
        per = ', '.join(f'{name[-3:]} {np.mean(p[subject == name] == y[subject == name]):.3f}'
                        for name in sorted(set(subject.tolist())))
        print(f'  read as +-{range_dps} deg/s: accuracy {np.mean(p == y):.4f} on {len(y)} '
              f'cycles ({counts["cycles"]} cycles, {counts["invalid"]} invalid); {per}')


def gated_pipeline(enabled: bool):
    """Return the default pipeline with the stride gate off or on."""
    defaults = Pipeline()
    return Pipeline(dataclasses.replace(defaults.navigator, stride_gate=dataclasses.replace(
        defaults.navigator.stride_gate, enabled=enabled)), defaults.gate)


def gated_run(recording, enabled: bool):
    """Per sample stance flags and the end stamps of the cycles, gate off or on."""
    defaults = gated_pipeline(enabled)
    params = defaults.navigator
    stance = np.zeros(len(recording.stamp_ns), bool)
    ends = []
    for k, point, cycle in navigated_samples(recording, InputGate(defaults.gate),
                                             FootNavigator(params)):
        stance[k] = point.stance
        if cycle is not None:
            ends.append(cycle.stamp_ns)
    return stance, np.array(ends, dtype=np.int64)


def print_gate(args):
    """Print the cycles the stride gate adds and removes on HuGaDB, and what they are."""
    tolerance_ns = 200_000_000
    added, removed, counts, per_file = [], [], np.zeros(2, int), defaultdict(dict)
    for spec in hugadb_specs(args.hugadb):
        recording, _ = load_hugadb(spec.path, spec.foot, gyro_range_dps=spec.gyro_range_dps)
        stance_off, off = gated_run(recording, False)
        stance_on, on = gated_run(recording, True)
        saturated = np.any(np.abs(recording.acc_b) >= HUGADB_ACC_SATURATION_MPS2, axis=1)
        stamps = np.asarray(recording.stamp_ns)
        per_file[spec.path][spec.foot] = (len(off), len(on))
        counts += len(off), len(on)
        removed += [(t - off[i - 1]) * 1e-9 for i, t in enumerate(off)
                    if i and _distance_ns(on, t) >= tolerance_ns]
        for i, end in enumerate(on):
            if i == 0 or _distance_ns(off, end) < tolerance_ns:
                continue
            duration = (end - on[i - 1]) * 1e-9
            neighbours = [(on[j] - on[j - 1]) * 1e-9 for j in (i - 1, i + 1, i + 2)
                          if 0 < j < len(on) and j != i]
            k = int(np.searchsorted(stamps, end))
            j = int(np.searchsorted(off, end))
            phase = (end - off[j - 1]) / (off[j] - off[j - 1]) if 0 < j < len(off) else np.nan
            added.append((duration, duration / np.median(neighbours) if neighbours else np.nan,
                          phase, stance_on[k] and not stance_off[k],
                          saturated[max(0, k - 2):k + 3].any()))
    added = np.array(added, dtype=float).reshape(-1, 5)
    print(f'\nStride gate on HuGaDB ({len(per_file)} files): {counts[0]} cycles without, '
          f'{counts[1]} with; {len(added)} added, {len(removed)} removed (not first of a foot)')
    edges = (0, .4, .8, 1.2, 2, 100)
    print('  removed cycles by duration (s): ' + ', '.join(
        f'[{lo:g}, {hi:g}) {n}' for lo, hi, n in _histogram(np.array(removed), edges)))
    for title, column, edges in (('duration (s)', 0, (0, .6, .8, 1.2, 1.5, 2, 100)),
                                 ('ratio to the neighbouring cycles', 1, (0, .6, .8, 1.2, 1.6,
                                                                          100)),
                                 ('end within the cycle without the gate', 2,
                                  (0, .2, .4, .6, .8, 1))):
        print(f'  added cycles by {title}: ' + ', '.join(
            f'[{lo:g}, {hi:g}) {n}' for lo, hi, n in _histogram(added[:, column], edges)))
    print(f'  ended by a relaxed stance: {int(added[:, 3].sum())}; on the +-2 g rail: '
          f'{int(added[:, 4].sum())}')
    both = [feet for feet in per_file.values() if len(feet) == 2]
    for index, name in ((0, 'without'), (1, 'with')):
        print(f'  |left - right| cycles {name} the gate, summed over the {len(both)} files '
              f'with both feet: {sum(abs(f["left"][index] - f["right"][index]) for f in both)}')


def gate_loso(args, enabled: bool) -> dict:
    """Leave-one-subject-out of the used HuGaDB cycles: {name: (label, predicted, start, end)}."""
    pipeline, rules = gated_pipeline(enabled), LabelRules()
    sims = [sim_spec(seed) for seed in range(1, 41)]
    hugadb = hugadb_specs(args.hugadb)
    sets = collect(sims + hugadb, pipeline, rules, args.cache_dir, args.jobs, Progress(args.quiet))
    stamps = {}
    for spec, cycle_set in zip(hugadb, sets[len(sims):]):
        nav = navigated(spec, pipeline, args.cache_dir)[0]
        _, labelled = lab.majority_labels(nav.start_ns, nav.stamp_ns, nav.truth_stamp_ns,
                                          nav.truth_label, rules.min_majority)
        used = nav.valid & (labelled | lab.non_stride_cycles(nav.start_ns, nav.stamp_ns,
                                                             rules.min_stride_s))
        stamps[cycle_set.name] = nav.start_ns[used], nav.stamp_ns[used]
    simulated = [s for s in sets[:len(sims)] if len(s.labels)]
    found = [s for s in sets[len(sims):] if len(s.labels)]
    out = {}
    for subject in sorted({s.subject for s in found}):
        features, labels, _ = stack(simulated + [s for s in found if s.subject != subject])
        model = fit_model(features, labels, TrainOptions())
        for s in found:
            if s.subject == subject:
                out[s.name] = (s.labels, stair_mode(model.predict(s.features), 0.45),
                               *stamps[s.name])
    return out


def print_gate_loso(args):
    """Print the accuracy of the cycles both detectors cut and of those only one cuts."""
    tolerance_ns = 200_000_000
    runs = {'without': gate_loso(args, False), 'with': gate_loso(args, True)}
    for name, other in (('with', 'without'), ('without', 'with')):
        both, alone, alone_confusion = [], [], np.zeros((3, 3), int)
        for key, (label, predicted, start, end) in runs[name].items():
            _, _, other_start, other_end = runs[other].get(key, (None, None, [], []))
            for i in range(len(label)):
                same = (_distance_ns(np.asarray(other_end), end[i]) < tolerance_ns
                        and _distance_ns(np.asarray(other_start), start[i]) < tolerance_ns)
                (both if same else alone).append(label[i] == predicted[i])
                if not same:
                    alone_confusion[label[i] + 1, predicted[i] + 1] += 1
        print(f'  {name} the gate: {len(both)} cycles also cut {other} it, accuracy '
              f'{np.mean(both):.3f}; {len(alone)} only {name} it, accuracy {np.mean(alone):.3f}, '
              f'confusion (rows true -1/0/+1) {alone_confusion.tolist()}')


def print_decision(args):
    """Print the forest's HuGaDB accuracy and recalls by largest probability and by eq. 13."""
    rules, options = LabelRules(), TrainOptions(backend='forest')
    specs = [sim_spec(seed) for seed in range(1, 41)] + hugadb_specs(args.hugadb)
    every = [s for s in collect(specs, Pipeline(), rules, args.cache_dir, args.jobs,
                                Progress(args.quiet)) if len(s.labels)]
    print('\nForest decision rule, leave-one-subject-out in the train folds, HuGaDB cycles '
          '(accuracy, recall down / level / up, confusion rows true -1/0/+1):')
    for title, sets in (('simulated + HuGaDB', every),
                        ('HuGaDB alone', [s for s in every if s.source == 'hugadb'])):
        folds, _ = assign_folds(sets, 'subject', 0, 0)
        features, labels, owner = stack(sets)
        cycle_fold = folds[owner]
        proba = np.empty((len(labels), 3))
        for k in range(int(folds.max()) + 1):
            test = cycle_fold == k
            model = fit_model(features[~test], labels[~test], options)
            proba[test] = model.predict_proba(features[test])
        hugadb = np.array([sets[i].source == 'hugadb' for i in owner])
        decisions = [('largest probability', stair_mode(majority_vote_output(proba), 0.0))]
        decisions += [(f'sigma_th {t:g}', stair_mode(proba[:, 2] - proba[:, 0], t))
                      for t in (0.3, 0.4, 0.45, 0.5)]
        for name, predicted in decisions:
            matrix = confusion_matrix(labels[hugadb], predicted[hugadb])
            recall = np.diag(matrix) / matrix.sum(axis=1)
            print(f'  {title:18s} {name:20s} {np.mean(labels[hugadb] == predicted[hugadb]):.4f}  '
                  f'{"/".join(f"{r:.3f}" for r in recall)}  {matrix.tolist()}')


def print_pipeline(args):
    """Print the forest's mode and the whole pipeline's, out of fold, on the HuGaDB cycles."""
    rules, options = LabelRules(), TrainOptions(backend='forest')
    specs = [sim_spec(seed) for seed in range(1, 41)] + hugadb_specs(args.hugadb)
    every = collect(specs, Pipeline(), rules, args.cache_dir, args.jobs, Progress(args.quiet))
    keep = [i for i, s in enumerate(every) if len(s.labels)]
    sets = [every[i] for i in keep]
    folds, _ = assign_folds(sets, 'subject', 0, 0)
    features, labels, owner = stack(sets)
    defaults = load_pipeline_params()
    pipeline = dataclasses.replace(defaults, elevation=dataclasses.replace(
        defaults.elevation, mode_threshold=0.0))            # the vote, as the shipped forest
    column = {name: k for k, name in enumerate(CYCLE_COLUMNS)}
    label, classified, checked = [], [], []
    for k in range(int(folds.max()) + 1):
        held_out = [keep[i] for i in range(len(sets))
                    if folds[i] == k and sets[i].source == 'hugadb']
        if not held_out:
            continue
        model = fit_model(features[folds[owner] != k], labels[folds[owner] != k], options)
        for i in held_out:
            nav = navigated(specs[i], Pipeline(), args.cache_dir)[0]
            modes, labelled = lab.majority_labels(nav.start_ns, nav.stamp_ns,
                                                  nav.truth_stamp_ns, nav.truth_label,
                                                  rules.min_majority)
            non_stride = lab.non_stride_cycles(nav.start_ns, nav.stamp_ns, rules.min_stride_s)
            used = nav.valid & (labelled | non_stride)
            recording, _ = load_hugadb(specs[i].path, specs[i].foot,
                                       gyro_range_dps=specs[i].gyro_range_dps)
            rows = np.array([[float(v) for v in row] for row in
                             replay_recording(recording, pipeline, model).cycles])
            label.append(np.where(non_stride, 0, modes)[used])
            classified.append(stair_mode(np.nan_to_num(rows[used, column['anfis_output']]),
                                         0.0))
            checked.append(rows[used, column['mode']].astype(int))
    label, classified, checked = (np.concatenate(v) for v in (label, classified, checked))
    print('\nForest out of fold (the train folds, the shipped settings, not nested), each '
          "held-out HuGaDB foot replayed through the pipeline: the classifier's mode and the "
          "mode after the stride's geometry check (accuracy, recall down / level / up, "
          'confusion rows true -1/0/+1):')
    for name, predicted in (('classifier', classified), ('pipeline', checked)):
        matrix = confusion_matrix(label, predicted)
        recall = np.diag(matrix) / matrix.sum(axis=1)
        print(f'  {name:10s} {np.mean(label == predicted):.4f}  '
              f'{"/".join(f"{r:.3f}" for r in recall)}  {matrix.tolist()}')
    changes = Counter(zip(classified[classified != checked].tolist(),
                          checked[classified != checked].tolist(),
                          label[classified != checked].tolist()))
    print('  changed by the check (classifier -> pipeline, true: cycles): ' + ', '.join(
        f'{a:+d} -> {b:+d}, true {t:+d}: {n}' for (a, b, t), n in sorted(changes.items())))


def _distance_ns(stamps_ns, stamp_ns) -> float:
    """Return the distance of a stamp to the nearest of others (inf when none), ns."""
    return float(np.min(np.abs(stamps_ns - stamp_ns))) if len(stamps_ns) else np.inf


def _histogram(values, edges):
    """Return (low, high, count) of the finite values per bin."""
    counts = np.histogram(values[np.isfinite(values)], edges)[0]
    return zip(edges[:-1], edges[1:], counts)


def main(argv=None) -> int:
    """Print the analysis."""
    parser = argparse.ArgumentParser(description=__doc__.strip().split('\n\n')[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--parts', default='loso,nav,gyro')
    parser.add_argument('--clipped-gyro', action='store_true',
                        help='loso: add the +-250 deg/s feet (subjects 4 and 5 have no other)')
    parser.add_argument('--hugadb', type=Path, default=None,
                        help='HuGaDB folder (default: hugadb of the shared data)')
    parser.add_argument('--cache-dir', type=Path, default=default_cache_dir())
    parser.add_argument('--jobs', type=int, default=1)
    parser.add_argument('--quiet', action='store_true')
    args = parser.parse_args(argv)
    parts = args.parts.split(',')
    if args.hugadb is None:
        args.hugadb = shared_data_dir() / 'hugadb'
    if 'loso' in parts:
        print_loso(loso(args))
    if 'nav' in parts:
        print_nav(args)
    if 'gyro' in parts:
        print_gyro(args)
    if 'gate' in parts:
        print_gate(args)
    if 'gate_loso' in parts:
        print_gate_loso(args)
    if 'decision' in parts:
        print_decision(args)
    if 'pipeline' in parts:
        print_pipeline(args)
    return 0


if __name__ == '__main__':
    sys.exit(main())
