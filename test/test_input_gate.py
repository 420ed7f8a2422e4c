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

"""The input gate: each reason on hand-made samples, the counters, the latch and the resync."""

import math

from anfis_elevation_ros.core.errors import InputError
from anfis_elevation_ros.core.input_gate import DUPLICATE, GateParams, InputGate, NON_FINITE
from anfis_elevation_ros.core.input_gate import OUT_OF_ORDER, REJECT_REASONS, SATURATED
from anfis_elevation_ros.core.input_gate import UNITS_LATCH_COUNT, WRONG_FRAME, WRONG_UNITS
import pytest

REST_ACC = (0.0, 0.0, 9.81)
REST_GYR = (0.001, -0.002, 0.0005)
MS = 1_000_000


def feed(gate, stamps_ms, acc=REST_ACC, gyr=REST_GYR, frame_id='imu_link'):
    """Check one sample per stamp (ms); return the reasons."""
    return [gate.check(t * MS, acc, gyr, frame_id) for t in stamps_ms]


def test_defaults_are_16_g_and_2000_deg_per_s():
    """The default full scales are the ones of common foot IMUs."""
    params = GateParams()
    assert params.acc_range_mps2 == pytest.approx(16 * 9.80665)
    assert params.gyr_range_rps == pytest.approx(math.radians(2000.0))
    assert params.reject_saturated is False and params.frame_id == ''


def test_clean_samples_pass_and_are_counted():
    """Increasing stamps and plausible values are accepted; every counter starts at 0."""
    gate = InputGate()
    assert feed(gate, [0, 5, 10]) == [None, None, None]
    assert gate.accepted == 3 and gate.last_stamp_ns == 10 * MS
    assert dict(gate.rejected) == dict.fromkeys(REJECT_REASONS, 0)
    assert gate.rejected_total == 0


@pytest.mark.parametrize('index', range(6))
@pytest.mark.parametrize('value', [math.nan, math.inf, -math.inf])
def test_non_finite_in_any_value_is_refused(index, value):
    """A NaN or Inf in any of the six numbers is refused, and the stamp does not advance."""
    gate = InputGate()
    feed(gate, [0])
    values = list(REST_ACC + REST_GYR)
    values[index] = value
    assert gate.check(5 * MS, values[:3], values[3:]) == NON_FINITE
    assert gate.rejected[NON_FINITE] == 1 and gate.last_stamp_ns == 0


def test_out_of_order_and_duplicate_are_refused_against_the_last_accepted():
    """Earlier than the last accepted stamp: out_of_order; equal: duplicate."""
    gate = InputGate()
    assert feed(gate, [10, 5, 10, 11]) == [None, OUT_OF_ORDER, DUPLICATE, None]
    assert gate.rejected[OUT_OF_ORDER] == 1 and gate.rejected[DUPLICATE] == 1
    # Refused samples do not move the reference: 11 was accepted after 10.
    assert gate.last_stamp_ns == 11 * MS


def test_gap_is_flagged_not_refused():
    """An interval above max_gap_s (50 ms) passes and counts as a gap; exactly 50 ms does not."""
    gate = InputGate(GateParams(max_gap_s=0.05))
    assert feed(gate, [0, 50, 101, 105]) == [None] * 4
    assert gate.flagged['gap'] == 1


def test_gyro_beyond_40_rps_is_wrong_units():
    """40 rad/s is above any MEMS gyro (2000 deg/s = 34.9 rad/s): deg/s data."""
    gate = InputGate()
    assert gate.check(0, REST_ACC, (0.0, 40.5, 0.0)) == WRONG_UNITS
    assert gate.check(MS, REST_ACC, (0.0, 34.0, 0.0)) is None         # saturated, accepted
    assert gate.check(2 * MS, (1001.0, 0.0, 0.0), REST_GYR) == WRONG_UNITS   # mg or cm/s^2


def test_saturation_is_accepted_and_flagged_by_default():
    """A component at 0.999 of the full scale or above is flagged and passed on."""
    gate = InputGate(GateParams(acc_range_mps2=100.0, gyr_range_rps=10.0))
    assert gate.check(0, (99.8, 0.0, 9.8), REST_GYR) is None
    assert gate.check(MS, (99.9, 0.0, 9.8), REST_GYR) is None
    assert gate.check(2 * MS, REST_ACC, (0.0, 0.0, -10.0)) is None
    assert gate.flagged[SATURATED] == 2 and gate.accepted == 3


def test_saturation_can_be_refused():
    """With reject_saturated the same samples are refused as saturated."""
    gate = InputGate(GateParams(acc_range_mps2=100.0, reject_saturated=True))
    assert gate.check(0, (-100.0, 0.0, 9.8), REST_GYR) == SATURATED
    assert gate.rejected[SATURATED] == 1 and gate.accepted == 0


def test_wrong_frame_only_when_configured():
    """frame_id '' accepts any frame; a configured one refuses the others; None skips."""
    assert InputGate().check(0, REST_ACC, REST_GYR, 'anything') is None
    gate = InputGate(GateParams(frame_id='imu_link'))
    assert gate.check(0, REST_ACC, REST_GYR, 'camera') == WRONG_FRAME
    assert gate.check(MS, REST_ACC, REST_GYR, 'imu_link') is None
    assert gate.check(2 * MS, REST_ACC, REST_GYR, None) is None


def test_deg_per_s_stream_latches():
    """UNITS_LATCH_COUNT wrong-units samples within 5 s latch: plausible ones are refused too."""
    gate = InputGate()
    fast = (0.0, 300.0, 0.0)                                            # deg/s in a swing
    for k in range(UNITS_LATCH_COUNT - 1):
        assert gate.check(k * 10 * MS, REST_ACC, fast) == WRONG_UNITS
    assert not gate.units_latched
    assert gate.check(1000 * MS, REST_ACC, REST_GYR) is None          # still plausible
    assert gate.check(1010 * MS, REST_ACC, fast) == WRONG_UNITS
    assert gate.units_latched
    assert gate.check(1020 * MS, REST_ACC, REST_GYR) == WRONG_UNITS   # latched
    gate.reset_units()
    assert gate.check(1030 * MS, REST_ACC, REST_GYR) is None


def test_isolated_spikes_do_not_latch():
    """Wrong-units samples spread over more than 5 s do not latch."""
    gate = InputGate()
    for k in range(3 * UNITS_LATCH_COUNT):
        assert gate.check(k * 1000 * MS, REST_ACC, (100.0, 0.0, 0.0)) == WRONG_UNITS
        assert gate.check((k * 1000 + 1) * MS, REST_ACC, REST_GYR) is None
    assert not gate.units_latched


def test_one_wild_future_stamp_does_not_block_the_stream():
    """A stamp far ahead is refused; the stream after it goes on being accepted."""
    gate = InputGate(GateParams(max_future_jump_s=1.0))
    assert feed(gate, [0, 5]) == [None, None]
    assert gate.check(3_600_000 * MS, REST_ACC, REST_GYR) == OUT_OF_ORDER
    assert feed(gate, [10, 15]) == [None, None]


def test_a_real_clock_jump_is_accepted_after_three_samples():
    """Three consecutive samples agreeing on a jump are a real one: accepted from the third."""
    gate = InputGate(GateParams(max_future_jump_s=1.0))
    feed(gate, [0])
    assert feed(gate, [5000, 5005, 5010, 5015]) == [OUT_OF_ORDER, OUT_OF_ORDER, None, None]
    assert gate.flagged['gap'] == 1


def test_set_params_keeps_counters_and_stamp():
    """New parameters apply from the next sample; counts and the last stamp stay."""
    gate = InputGate()
    feed(gate, [0, 0])
    gate.set_params(GateParams(frame_id='imu_link'))
    assert gate.rejected[DUPLICATE] == 1 and gate.last_stamp_ns == 0
    assert gate.check(MS, REST_ACC, REST_GYR, 'other') == WRONG_FRAME


@pytest.mark.parametrize(('field', 'value'), [
    ('acc_range_mps2', 5.0), ('acc_range_mps2', 5000.0), ('gyr_range_rps', 50.0),
    ('max_gap_s', 0.0), ('max_future_jump_s', 0.001), ('reject_saturated', 1),
    ('frame_id', None)])
def test_bad_gate_params_raise_naming_the_field(field, value):
    """Out-of-range or mistyped parameters raise InputError naming the field."""
    with pytest.raises(InputError, match=field):
        GateParams(**{field: value})
