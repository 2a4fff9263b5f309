# SPDX-License-Identifier: Apache-2.0
"""Step generator model against the independent timing checker (no simulator)."""

from __future__ import annotations

import random

import pytest

from halfpoint.spec.stepgen import StepCfg, StepGenModel, StepInputs
from halfpoint.sim.timing import StepDirChecker, TimingViolation


def drive(cfg: StepCfg, want, rng, idle=0.0, tw=16):
    m = StepGenModel(tw)
    chk = StepDirChecker(cfg)
    taken, cycles = 0, 0
    while taken < len(want) or m.outputs(cfg).busy or not chk.idle or cycles < 3:
        o = m.outputs(cfg)
        chk.sample(o.step_pin, o.dir_pin)
        inp = StepInputs()
        if taken < len(want) and rng.random() >= idle:
            d = want[taken]
            if o.ready_pos if d else o.ready_neg:
                inp = StepInputs(req=1, req_dir=d)
                taken += 1
        m.clock(cfg, inp)
        cycles += 1
    for _ in range(4):
        o = m.outputs(cfg)
        chk.sample(o.step_pin, o.dir_pin)
        m.clock(cfg, StepInputs())
    return chk, cycles


def test_random_configs_never_violate_timing_and_lose_no_step():
    rng = random.Random(2)
    for _ in range(300):
        cfg = StepCfg(rng.randint(0, 6), rng.randint(0, 6), rng.randint(0, 6),
                      rng.randint(0, 6), rng.randint(0, 1), rng.randint(0, 1))
        want = [rng.randint(0, 1) for _ in range(rng.randint(1, 40))]
        chk, _ = drive(cfg, want, rng, idle=rng.choice((0.0, 0.5)))
        assert chk.steps == len(want)
        assert chk.position == sum(1 if d else -1 for d in want)


def test_fastest_rates_are_the_timing_limits():
    """Same direction: one step per max(steplen, 1) + max(stepspace, 1)
    clocks (STEP is inactive for at least one clock between pulses)."""
    rng = random.Random(0)
    for steplen, space in [(1, 1), (2, 3), (5, 0), (1, 0), (0, 0)]:
        cfg = StepCfg(steplen, space, 0, 0)
        _, cycles = drive(cfg, [1] * 100, rng)
        period = max(steplen, 1) + max(space, 1)
        # 100 periods, plus the few clocks of set-up and tail drive() adds
        assert 100 * period <= cycles + period <= 100 * period + 12


def test_request_while_not_ready_is_an_error():
    m = StepGenModel()
    cfg = StepCfg(3, 3, 0, 0)
    m.clock(cfg, StepInputs(req=1, req_dir=1))
    with pytest.raises(AssertionError):
        m.clock(cfg, StepInputs(req=1, req_dir=1))


@pytest.mark.parametrize(
    "rule, trace",
    [
        ("steplen", [(0, 0), (1, 0), (0, 0), (0, 0), (0, 0)]),
        ("stepspace", [(0, 0), (1, 0), (1, 0), (0, 0), (1, 0), (1, 0), (0, 0)]),
        ("dirsetup", [(0, 0), (0, 1), (1, 1), (1, 1), (0, 1)]),
        ("dirhold", [(0, 0), (1, 0), (1, 0), (0, 0), (0, 1), (0, 1)]),
        ("DIR changed while STEP", [(0, 0), (0, 0), (0, 0), (1, 0), (1, 1), (0, 1)]),
    ],
)
def test_checker_catches_each_violation(rule, trace):
    chk = StepDirChecker(StepCfg(2, 3, 2, 2))
    with pytest.raises(TimingViolation, match=rule):
        for s, d in trace:
            chk.sample(s, d)
