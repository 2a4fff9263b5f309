# SPDX-License-Identifier: Apache-2.0
"""The output stage's model (``halfpoint.spec.outputs``): the sequential unit against
the closed form ``effective_duty``, the schedule, the pins, ``off`` and ``load``."""

from __future__ import annotations

import random

import pytest

from halfpoint.spec.outputs import (OutputInputs, OutputStage, base_duty, effective_duty,
                                    speed_ratio)

TOP_SPEED = (1 << 38) - 1
TOP_CRUISE = (1 << 32) - 1


def settle(stage: OutputStage, settings: OutputInputs, s: int, c: int) -> None:
    """From reset: the settings and the cruise speed loaded, then clocks with speed s
    up to the wrap after the next sample: the duty register then holds that sample's
    duty.  Clocks where the unit is idle are skipped (the counter set forward, as
    the RTL tests do), so P = 16 takes about 4P clocks, not 2^17."""
    stage.reset()
    load = OutputInputs(**{**vars(settings), "load": 1, "take": 1, "take_v_cruise": c})
    stage.clock(load)                            # counter 0 -> 1: this sample missed it
    run_to_wrap(stage, s)
    assert stage.at_start
    run_to_wrap(stage, s)


def run_to_wrap(stage: OutputStage, s: int) -> None:
    """Clock with speed s through the wrap (counter 2^P - 1 -> 0), skipping the clocks
    where only the counter and pwm change: the counter is set forward to the last clock
    before at_end's decode (the flags are all clear on both sides)."""
    p = stage.pwm_bits
    last_idle = stage.period - 3
    while True:
        if 2 * p + 2 <= stage.counter < last_idle:
            assert not (stage.at_start or stage.dividing or stage.clearing
                        or stage.multiplying or stage.at_end)
            stage.counter = last_idle
        end = stage.at_end
        stage.clock(OutputInputs(speed=s))
        if end:
            return


def sequential_duty(pwm_bits, power, enable, laser, dynamic, s, c) -> int:
    stage = OutputStage(pwm_bits)
    settings = OutputInputs(load_power=power, load_enable=enable, load_laser=laser,
                            load_dynamic=dynamic)
    settle(stage, settings, s, c)
    return stage.duty


EDGE_SPEEDS = [lambda c: 0, lambda c: 1, lambda c: max((c << 6) - 1, 0),
               lambda c: min(c << 6, TOP_SPEED), lambda c: min((c << 6) + 1, TOP_SPEED),
               lambda c: (c << 5), lambda c: TOP_SPEED, lambda c: 63, lambda c: 64]
EDGE_CRUISES = [0, 1, 2, 3, 1000, (1 << 31) - 1, 1 << 31, TOP_CRUISE]


@pytest.mark.parametrize("pwm_bits", [4, 5, 6, 10, 16])
def test_sequential_unit_equals_closed_form_on_edge_cases(pwm_bits):
    for c in EDGE_CRUISES:
        for speed in EDGE_SPEEDS:
            s = speed(c)
            for power in (0, 1, 1 << (16 - pwm_bits), 32768, 65535, 65536, 65537,
                          (1 << 17) - 1):
                for enable, laser, dynamic in ((1, 1, 1), (1, 1, 0), (1, 0, 1), (0, 1, 1)):
                    want = effective_duty(power, enable, laser, dynamic, s, c, pwm_bits)
                    got = sequential_duty(pwm_bits, power, enable, laser, dynamic, s, c)
                    assert got == want, (pwm_bits, power, enable, laser, dynamic, s, c)


@pytest.mark.parametrize("pwm_bits", [4, 7, 10, 13, 16])
def test_sequential_unit_equals_closed_form_at_random(pwm_bits):
    rng = random.Random(pwm_bits)
    for _ in range(300):
        c = rng.choice([rng.randrange(1 << 32), rng.randrange(1, 1 << rng.randint(1, 32))])
        s = rng.choice([rng.randrange(1 << 38), rng.randrange(max(c << 6, 1)),
                        rng.randrange(1 << rng.randint(1, 38))])
        power = rng.randrange(1 << 17)
        want = effective_duty(power, 1, 1, 1, s, c, pwm_bits)
        assert sequential_duty(pwm_bits, power, 1, 1, 1, s, c) == want


def test_closed_form_values():
    # P = 10: base = power >> 6
    assert base_duty(65536, 10) == 1024 and base_duty(65537, 10) == 1024
    assert base_duty(65535, 10) == 1023 and base_duty(63, 10) == 0
    assert base_duty(65535, 16) == 65535 and base_duty(65536, 16) == 65536
    c = 1000
    assert speed_ratio(0, c, 10) == 0
    assert speed_ratio(c << 6, c, 10) == 1024 and speed_ratio((c << 6) - 1, c, 10) == 1023
    assert speed_ratio(c << 5, c, 10) == 512
    assert speed_ratio(5, 0, 10) == 1024              # c = 0: full power while moving
    assert effective_duty(65536, 1, 1, 1, c << 5, c, 10) == 512
    assert effective_duty(32768, 1, 1, 1, c << 5, c, 10) == 256
    assert effective_duty(32768, 1, 1, 1, 3 * (c << 6), c, 10) == 512   # above cruise
    assert effective_duty(32768, 1, 1, 0, 1, c, 10) == 512            # M3: constant
    assert effective_duty(32768, 1, 1, 0, 0, c, 10) == 0              # at rest: off
    assert effective_duty(32768, 1, 0, 1, 0, c, 10) == 512            # spindle
    assert effective_duty(32768, 0, 0, 0, 5, c, 10) == 0
    with pytest.raises(ValueError):
        effective_duty(1, 1, 1, 1, 1 << 38, c, 10)
    with pytest.raises(ValueError):
        effective_duty(1, 1, 1, 1, 1, c, 3)
    with pytest.raises(ValueError):
        OutputStage(17)


def test_schedule_fits_the_period_at_four_bits():
    stage = OutputStage(4)
    seen = []
    for _ in range(16):
        seen.append((stage.counter, stage.at_start, stage.dividing, stage.clearing,
                     stage.multiplying, stage.at_end))
        stage.clock(OutputInputs())
    assert [k for k, *f in seen if f[1]] == [1, 2, 3, 4]
    assert [k for k, *f in seen if f[2]] == [5]
    assert [k for k, *f in seen if f[3]] == [6, 7, 8, 9]
    assert [k for k, *f in seen if f[0]] == [0] and [k for k, *f in seen if f[4]] == [15]


def test_pwm_is_high_for_duty_clocks_per_period_and_the_duty_lags():
    p = 4
    stage = OutputStage(p)
    # load at counter 3: the sample at counter 0 of the next period, the duty at its end
    for _ in range(3):
        stage.clock(OutputInputs())
    stage.clock(OutputInputs(load=1, load_power=5 << 12, load_enable=1))
    assert stage.enable and stage.duty == 0
    pins = [stage.step(OutputInputs()) for _ in range(12 + 16)]
    assert all(x.pwm == 0 for x in pins) and all(x.spindle_enable for x in pins)
    assert stage.duty == 5 and stage.counter == 0
    highs = [stage.step(OutputInputs()).pwm for _ in range(16)]
    # high during the clocks with counter 1..5
    assert highs == [0] + [1] * 5 + [0] * 10
    # full power: always on
    stage.clock(OutputInputs(load=1, load_power=65536, load_enable=1))
    for _ in range(2 * 16):
        stage.clock(OutputInputs())
    assert stage.duty == 16
    assert all(stage.step(OutputInputs()).pwm for _ in range(40))


def test_off_clears_at_once_and_wins_over_load():
    p = 4
    stage = OutputStage(p)
    full = OutputInputs(load=1, load_power=65536, load_enable=1, load_reverse=1,
                        load_laser=1, load_dynamic=1, load_mist=1, load_flood=1,
                        speed=123, take=1, take_v_cruise=1)
    stage.clock(full)
    for _ in range(40):
        stage.clock(OutputInputs(speed=123))
    assert stage.duty == 16 and stage.pwm
    # off while the unit computes (counter 3): pwm and everything low from the next clock,
    # and the computation under way delivers 0
    while stage.counter != 3:
        stage.clock(OutputInputs(speed=123))
    stage.clock(OutputInputs(**{**vars(full), "off": 1}))
    pins = stage.outputs()
    assert (pins.spindle_enable, pins.spindle_reverse, pins.coolant_mist, pins.coolant_flood,
            pins.pwm, pins.duty) == (0, 0, 0, 0, 0, 0)
    assert (stage.laser, stage.dynamic, stage.power, stage.sample_enable) == (0, 0, 0, 0)
    assert stage.cruise == 1
    # enabled again in the same period: the duty stays 0 up to the next sample's result
    stage.clock(OutputInputs(load=1, load_power=65536, load_enable=1, speed=123))
    while not stage.at_end:
        assert stage.step(OutputInputs(speed=123)).pwm == 0
    stage.clock(OutputInputs(speed=123))
    assert stage.duty == 0
    for _ in range(16):
        stage.clock(OutputInputs(speed=123))
    assert stage.duty == 16


def test_laser_at_rest_is_off_and_follows_the_speed():
    p = 10
    c = 1 << 20
    stage = OutputStage(p)
    stage.clock(OutputInputs(load=1, load_power=65536, load_enable=1, load_laser=1,
                             load_dynamic=1, take=1, take_v_cruise=c))
    for s, want in ((0, 0), (c << 5, 512), (c << 6, 1024), (c << 7, 1024), (c << 4, 256)):
        for _ in range(2 << p):
            stage.clock(OutputInputs(speed=s))
        assert stage.duty == want


def test_a_segments_power_is_taken_with_it_and_a_load_wins():
    """A take with take_set_power loads the power register as a load would (clamped at
    65536, its low bits dropped); without the flag, or without the take, the power is
    kept; a load at the same edge wins; off wins over both."""
    p = 10
    c = 1 << 20
    stage = OutputStage(p)
    stage.clock(OutputInputs(load=1, load_power=65536, load_enable=1, load_laser=1,
                             take=1, take_v_cruise=c))
    assert stage.power == 1 << p
    stage.clock(OutputInputs(take=1, take_v_cruise=c, take_set_power=1, take_power=16384))
    assert stage.power == 256 and stage.enable and stage.laser     # the settings kept
    stage.clock(OutputInputs(take=1, take_v_cruise=c, take_power=65536))    # no flag
    stage.clock(OutputInputs(take_set_power=1, take_power=65536))           # no take
    assert stage.power == 256
    stage.clock(OutputInputs(take=1, take_set_power=1, take_power=(1 << 17) - 1))
    assert stage.power == 1 << p                                    # above 65536: full
    stage.clock(OutputInputs(take=1, take_set_power=1, take_power=63))
    assert stage.power == 0                                         # below 2^(16 - P)
    stage.clock(OutputInputs(load=1, load_power=32768, load_enable=1, take=1,
                             take_set_power=1, take_power=65536))
    assert stage.power == 512                                       # the load wins
    stage.clock(OutputInputs(off=1, take=1, take_set_power=1, take_power=65536))
    assert stage.power == 0
    # the duty follows at the next sample (laser constant power, moving)
    stage.clock(OutputInputs(load=1, load_power=65536, load_enable=1, load_laser=1))
    stage.clock(OutputInputs(take=1, take_v_cruise=c, take_set_power=1, take_power=8192,
                             speed=c << 6))
    for _ in range(2 << p):
        stage.clock(OutputInputs(speed=c << 6))
    assert stage.duty == 128


def test_bad_inputs_are_refused():
    stage = OutputStage(4)
    with pytest.raises(ValueError):
        stage.clock(OutputInputs(load=1, load_power=1 << 17))
    with pytest.raises(ValueError):
        stage.clock(OutputInputs(take=1, take_v_cruise=1 << 32))
    with pytest.raises(ValueError):
        stage.clock(OutputInputs(speed=-1))
    with pytest.raises(ValueError):
        stage.clock(OutputInputs(take=1, take_set_power=1, take_power=1 << 17))
