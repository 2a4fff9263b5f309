# SPDX-License-Identifier: Apache-2.0
"""The event-skipping core model (``spec.fastcore.run_fast``) against the clock-by-clock
model (``spec.core``): every move's cycle and position, the error codes, the final dry
and underrun flags and the run's length equal, on random programs (arcs and lines,
helices and arcs in the G18/G19 planes, some with a wrong move count, short and long
segments, slow and fast planned speeds, random accelerations and
junctions, random STEP/DIR timing, DIV small and large, hold intervals, override,
rejected commands); the closed forms of the STEP/DIR generators against the generator
clocked; and the skipping must actually skip on slow programs."""

from __future__ import annotations

import random

import pytest

from halfpoint.spec import encoding as enc
from halfpoint.spec import fastcore as fc
from halfpoint.spec import profile as pf
from halfpoint.spec.core import CoreInputs, CoreModel, run_program
from halfpoint.spec.program import profiled, random_arc, random_helix, random_line
from halfpoint.spec.stepgen import StepCfg, StepGenModel, StepInputs

ONE = 1 << 32                   # a speed field of 1 BLU per clock


def random_cfg(rng, axes, slow=False):
    hi = 40 if slow else 3
    return [StepCfg(rng.randint(1, hi), rng.randint(0, hi), rng.randint(0, hi),
                    rng.randint(0, hi), rng.randint(0, 1), rng.randint(0, 1))
            for _ in range(axes)]


def random_program(rng, axes, width, div, count, slow):
    """A planned program of ``count`` motion commands: arcs and lines, short or long,
    the speeds slow (0.0005 .. 0.01 BLU per clock) or fast (0.02 .. 0.45), ramps of 1
    to 30 ticks, random junction speeds; now and then a rejected command."""
    cmds = []
    for _ in range(count):
        short = rng.random() < 0.4
        if rng.random() < 0.25:
            cmds.append(random_arc(rng, True, 1, 3) if short else random_arc(rng, True, 2, 12))
        elif rng.random() < 1 / 3:      # helices and arcs in any plane, now and then a wrong
            miss = rng.choice((-1, 1)) if rng.random() < 0.1 else 0     # count
            cmds.append(random_helix(rng, axes, True, 1, 3 if short else 12, miss))
        else:
            cmds.append(random_line(rng, axes, True, 2 if short else 12))
        if rng.random() < 0.05:         # an unknown opcode: rejected (E_OPCODE)
            cmds.append(enc.pack([0xF] + [0] * (enc.CMD_WORDS - 1)))
    lo, hi = (0.0005, 0.01) if slow else (0.02, 0.45)
    speeds = [int(rng.uniform(lo, hi) * ONE) for _ in range(count)]

    def accel(k):
        return max(1, min((1 << 34) - 1, (speeds[k] << 6) // rng.randint(1, 30)))

    prog = profiled(cmds, axes, width, div, v_cruise=lambda k: speeds[k], accel=accel,
                    rng=rng)
    if rng.random() < 0.1:              # a motion command with no profile in force
        prog.insert(0, random_line(rng, axes, True, 3))
    return prog


def random_holds(rng, length, count):
    out = []
    for _ in range(count):
        a = rng.randint(0, max(1, length))
        out.append((a, a + rng.randint(1, max(2, length // 4))))
    return out


def check_equal(cmds, params, holds=(), override=128, gaps=()):
    ref = fc.run_clocked(cmds, *params, holds=holds, override=override, max_clocks=400_000,
                         gaps=gaps)
    got = fc.run_fast(cmds, *params, holds=holds, override=override, max_clocks=400_000,
                      gaps=gaps)
    assert got.trace == ref.trace, "positions differ"
    for k, (a, b) in enumerate(zip(got.times, ref.times)):
        assert a == b, f"move {k}: fast model at cycle {a}, clock-by-clock at {b}"
    assert len(got.times) == len(ref.times)
    assert got.errors == ref.errors
    assert (got.dry, got.underrun, got.clocks) == (ref.dry, ref.underrun, ref.clocks)
    return ref, got


def test_reference_driver_is_run_program():
    """``run_clocked`` without holds is ``spec.core.run_program`` (the cycle numbering)."""
    rng = random.Random(5)
    cfg = random_cfg(rng, 3)
    cmds = random_program(rng, 3, 32, 4, 8, slow=False)
    ref = fc.run_clocked(cmds, 3, 32, 4, 16, 4, 3, 2, cfg)
    model = CoreModel(3, 32, 4, 16, 4, 3, 2, [StepCfg(**vars(c)) for c in cfg])
    base = run_program(model, cmds)
    assert (ref.times, ref.trace, ref.errors) == (base.times, base.trace, base.errors)
    assert len(ref.times) > 50


# (axes, width, depth, div, move_depth, profile_depth, slow, motion commands)
CASES = [
    (3, 32, 4, 3, 4, 2, False, 10),
    (2, 16, 2, 1, 2, 1, False, 10),
    (3, 32, 16, 6, 3, 2, True, 3),
    (4, 32, 4, 10, 4, 2, True, 3),
    (2, 32, 8, 12, 2, 1, True, 3),
    (3, 16, 4, 2, 4, 3, True, 4),
]


@pytest.mark.parametrize("case", range(len(CASES)))
@pytest.mark.parametrize("seed", range(3))
def test_fast_equals_clocked(case, seed):
    axes, width, depth, div, move_depth, profile_depth, slow, count = CASES[case]
    rng = random.Random(1000 * case + seed)
    cfg = random_cfg(rng, axes, slow)
    cmds = random_program(rng, axes, width, div, count, slow)
    params = (axes, width, depth, 16, div, move_depth, profile_depth, cfg)
    ref, got = check_equal(cmds, params)
    assert len(ref.times) > 0
    if slow:        # the point of the model: most clocks are not clocked one by one
        assert got.exact + got.lean < ref.clocks / 4, (got.exact, got.lean, ref.clocks)
    # the same program with feed holds (and sometimes a reduced override)
    holds = random_holds(rng, ref.clocks, rng.randint(1, 4))
    override = rng.choice((128, 128, 96, 37))
    check_equal(cmds, params, holds, override)
    # and with gaps in the stream while the core moves (tvalid low), with and
    # without the holds
    gaps = random_holds(rng, ref.clocks, rng.randint(1, 6))
    check_equal(cmds, params, (), 128, gaps)
    check_equal(cmds, params, holds, override, gaps)


def test_stream_gaps_delay_and_starve():
    """A gap in the stream delays what follows it and, long enough, starves the
    core, in both models alike."""
    rng = random.Random(41)
    cfg = random_cfg(rng, 3)
    cmds = random_program(rng, 3, 32, 4, 8, slow=False)
    params = (3, 32, 4, 16, 4, 3, 2, cfg)
    ref, _ = check_equal(cmds, params)
    late, _ = check_equal(cmds, params, gaps=[(0, 500)])
    assert late.times[0] == ref.times[0] + 500
    starved, _ = check_equal(cmds, params, gaps=[(ref.times[len(ref.times) // 3], ref.clocks)])
    assert starved.times != ref.times and starved.clocks > ref.clocks


def test_hold_at_start_and_across_the_end():
    """Hold from cycle 0, and a hold that outlasts a short program's motion."""
    rng = random.Random(77)
    cfg = random_cfg(rng, 3)
    cmds = random_program(rng, 3, 32, 5, 3, slow=True)
    params = (3, 32, 4, 16, 5, 4, 2, cfg)
    check_equal(cmds, params, [(0, 3000)])
    ref, _ = check_equal(cmds, params)
    check_equal(cmds, params, [(ref.clocks // 2, ref.clocks * 2)] + [(ref.clocks * 3, 1 << 40)])


def test_dry_queue_and_underrun():
    """Short fast segments after slowly validated arcs: the queue runs dry (the profile
    stage's dry path and the underrun flag) in both models alike."""
    rng = random.Random(3)
    cmds = []
    for _ in range(6):
        cmds.append(random_line(rng, 3, True, 2))
        cmds.append(random_arc(rng, True, 1, 2))
    prog = profiled(cmds, 3, 32, 2, v_cruise=ONE // 2 - 1, accel=1 << 33,
                    junction=ONE // 3)
    ref, _ = check_equal(prog, (3, 32, 2, 16, 2, 2, 1, [StepCfg()] * 3))
    assert ref.dry or ref.underrun


def test_stepgen_closed_forms():
    """``_sg_advance`` and ``_sg_ready_at`` against the STEP/DIR generator clocked."""
    rng = random.Random(11)
    for _ in range(300):
        c = StepCfg(rng.randint(0, 6), rng.randint(0, 6), rng.randint(0, 6), rng.randint(0, 6))
        ref = StepGenModel(rng.choice((4, 16)))
        for _ in range(rng.randint(0, 3)):          # a few steps in random directions
            d = rng.randint(0, 1)
            while not ref._ready(c, d):
                ref.clock(c, StepInputs())
            ref.clock(c, StepInputs(req=1, req_dir=d))
            for _ in range(rng.randint(0, 8)):
                ref.clock(c, StepInputs())
        fast = StepGenModel(ref.tw)
        fast.__dict__.update(vars(ref))
        ready = [fc._sg_ready_at(fast, c, d) for d in (0, 1)]
        k = rng.randint(0, 30)
        for j in range(k):
            for d in (0, 1):
                assert bool(ref._ready(c, d)) == (j >= ready[d]), (j, d, ready)
            ref.clock(c, StepInputs())
        fc._sg_advance(fast, c, k)
        assert vars(fast) == vars(ref)


def owed_hold_case(seed: int = 1):
    """A fast program with slow STEP/DIR timing and many short holds (seed 1: the core
    reaches rest under hold with the head move's axes ready and the credit covering it
    at cycle 427, DIV 2, where the profile stage popped it before 2026-11-25)."""
    rng = random.Random(seed)
    axes, width, div = 3, 32, rng.choice((2, 3, 5))
    cfg = random_cfg(rng, axes, slow=rng.random() < 0.7)
    cmds = random_program(rng, axes, width, div, rng.randint(3, 8), slow=False)
    holds, t = [], 0
    for _ in range(40):
        t += rng.randint(5, 400)
        holds.append((t, t + rng.randint(5, 600)))
        t = holds[-1][1]
    return cmds, (axes, width, 4, 16, div, 4, 2, cfg), holds


def test_no_move_at_rest_under_hold_even_when_owed():
    """In the core: from a hold's second clock at rest (speed 0) no move pops while the
    hold stays high, even on clocks where the head move is ready and the credit covers
    it (owed by the deceleration; the case occurs in this program); the event-skipping
    model agrees with the clock-by-clock one on it."""
    cmds, params, holds = owed_hold_case()
    axes, width, depth, tw, div, move_depth, profile_depth, cfg = params
    m = CoreModel(axes, width, depth, tw, div, move_depth, profile_depth,
                  [StepCfg(**vars(c)) for c in cfg])
    m.clock(CoreInputs(rst=1))
    idx = cyc = idle = owed = held = 0
    hold_before = 0
    while idx < len(cmds) or idle < 4:
        assert cyc < 400_000
        hold = int(any(a <= cyc < b for a, b in holds))
        o = m.outputs()
        inp = CoreInputs(hold=hold)
        if idx < len(cmds):
            inp = CoreInputs(tvalid=1, tdata=cmds[idx], hold=hold)
            idx += o.tready
        idle = 0 if (o.busy or idx < len(cmds)) else idle + 1
        st, si = m.stage, m.stage_inputs(inp)
        at_rest = bool(hold and hold_before and st.v == 0 and st.cur is not None)
        if at_rest and si.head_valid and si.ready:
            held += 1
            owed += int(st.covers(pf.move_cost(si.head_class, st.cur)))
        w = m.clock(inp)
        assert not (at_rest and w is not None and w.pop), f"a move at rest under hold, {cyc}"
        hold_before, cyc = hold, cyc + 1
    assert owed >= 1 and held >= owed, (owed, held)
    check_equal(cmds, params, holds)
