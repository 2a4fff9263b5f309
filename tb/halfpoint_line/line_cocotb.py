# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_line: the RTL against the model on every clock.

Run by ``test_line_rtl.py``; the axis count and width are read from the design (NA, W).
"""

from __future__ import annotations

import os
import random

import cocotb

from halfpoint.sim.design import read_parameters
from halfpoint.sim.linebench import LineBench
from halfpoint.spec.line import ERR_EMPTY, line_latency, line_steps

NA = W = 0     # the design's axis count and width: bind() reads them
SEED = int(os.environ.get("HP_SEED", "1"))


def bind(dut) -> None:
    """Take NA, W from the design under test (its parameters)."""
    global NA, W
    NA, W = read_parameters(dut, "NA", "W")


def fit(deltas):
    """The first NA deltas, padded with zeros."""
    return tuple(list(deltas)[:NA] + [0] * max(0, NA - len(deltas)))


def check_results(results, cmds):
    assert [r.cmd for r in results] == [tuple(c) for c in cmds]
    for r in results:
        if r.rejected:
            assert r.moves == []
            continue
        assert r.finished, f"{r.cmd} did not finish"
        assert r.moves == line_steps(r.cmd), f"steps of {r.cmd}"
        ends = [sum(m[k] for m in r.moves) for k in range(NA)]
        assert ends == list(r.cmd)


def random_segment(rng, scale=40):
    seg = [rng.randint(-scale, scale) for _ in range(NA)]
    if rng.random() < 0.2:
        seg[rng.randrange(NA)] = 0
    return tuple(seg)


@cocotb.test()
async def seed_example(dut):
    """Seed 001's worked example O(0,0,0) -> E(6,5,3), and its mirror image."""
    bind(dut)
    bench = LineBench(dut, NA, W, seed=SEED)
    await bench.start()
    cmds = [fit((6, 5, 3)), fit((-6, 5, -3))]
    results, _ = await bench.run(cmds)
    check_results(results, cmds)


@cocotb.test()
async def random_program(dut):
    """Hundreds of random segments with random en and s_valid gaps,
    including empty segments (rejected) in between."""
    bind(dut)
    rng = random.Random(SEED * 3 + 1)
    bench = LineBench(dut, NA, W, seed=SEED + 5)
    await bench.start()
    cmds = []
    for k in range(300):
        if k % 37 == 5:
            cmds.append(tuple([0] * NA))
        else:
            cmds.append(random_segment(rng, rng.choice((3, 40, 200))))
    results, stats = await bench.run(cmds, valid_idle=0.3, en_idle=0.3)
    check_results(results, cmds)
    assert sum(1 for r in results if r.rejected == ERR_EMPTY) == sum(1 for c in cmds if not any(c))
    dut._log.info("random program: %d segments, %d moves, %d cycles", len(cmds), stats.moves, stats.cycles)


@cocotb.test()
async def extreme_deltas(dut):
    """The most negative and most positive delta the width allows."""
    bind(dut)
    bench = LineBench(dut, NA, W, seed=SEED + 9)
    await bench.start()
    half = 1 << (W - 1)
    big = min(half, 1 << 15)     # keep the move count simulable at W = 32
    cmds = [fit((-big, big - 1, big // 3, -1, 1, 0))]
    if W <= 16:
        cmds.append(fit((-half, half - 1, -half, half - 1, 7, -7)))
    # each axis in turn one short of the longest, every bit below the top set:
    # its no-step increment 2|d| uses every bit of the register that keeps it
    for k in range(NA):
        d = [0] * NA
        d[k] = -(big - 1) if k % 2 else big - 1
        if NA > 1:
            d[(k + 1) % NA] = -big
        cmds.append(tuple(d))
    results, _ = await bench.run(cmds)
    check_results(results, cmds)


@cocotb.test()
async def close_magnitudes(dut):
    """The validator's running maximum where it is decided by little: magnitudes
    within 8 of one another in every order (a later axis one to eight above or below
    an earlier one), and, at W <= 13, the most negative delta (|d| = 2^(W-1)) on two
    axes and on all.  (Written for the line unit's mutation run on the stable
    sample: a bit of the maximum's compare inverted, and a bit of the second axis's
    magnitude inverted while the first's top bit is set, survived every other test.)"""
    bind(dut)
    rng = random.Random(SEED * 17 + 3)
    bench = LineBench(dut, NA, W, seed=SEED + 17)
    await bench.start()
    half = 1 << (W - 1)
    top = min(half - 1, 1 << 12)        # keep the move count simulable at W = 32
    cmds = []
    if half <= 1 << 12:                 # 2^(W-1) moves each
        cmds += [fit((-half, -half, 0)), fit((-half, -half, -half)), fit((-half, 0, -half))]
    for _ in range(40):
        base = rng.randint(9, top - 8)
        cmds.append(fit([rng.choice((-1, 1)) * (base + rng.randint(-8, 8))
                         for _ in range(NA)]))
    results, _ = await bench.run(cmds)
    check_results(results, cmds)


@cocotb.test()
async def back_to_back(dut):
    """Queued segments run with no idle clock between them."""
    bind(dut)
    rng = random.Random(SEED * 11 + 7)
    bench = LineBench(dut, NA, W, seed=SEED + 13)
    await bench.start()
    lat = line_latency(NA)
    cmds = []
    while len(cmds) < 20:
        seg = random_segment(rng, 30)
        if max(abs(d) for d in seg) > lat + 2:
            cmds.append(seg)
    results, stats = await bench.run(cmds)
    check_results(results, cmds)
    span = stats.last_done - stats.first_move + 1
    assert stats.moves == span, f"{span - stats.moves} idle clocks between segments"


@cocotb.test()
async def control_and_sequencing(dut):
    """rst, abort_now, start_en, en and s_valid at random on every clock, with
    short segments (empty ones included): every output equals the model on
    every clock, and so do the sequencing outputs the motion core uses
    (running, pending, loading, ending, and nx_step / nx_dir while running).
    Found by mutation testing (python -m halfpoint.flows.mutate): the other
    tests hold start_en high and abort_now low and read no sequencing output."""
    from cocotb.triggers import FallingEdge, ReadOnly
    from halfpoint.spec.line import L_HOLD, LineInputs

    bind(dut)
    rng = random.Random(SEED * 17 + 3)
    bench = LineBench(dut, NA, W, seed=SEED + 21)
    await bench.start()
    model = bench.model
    fields = LineBench.FIELDS
    half = 1 << (W - 1)
    counts = {"abort": 0, "reject": 0, "done": 0, "loading": 0, "stalled": 0}
    for cycle in range(2500):
        await FallingEdge(dut.clk)
        r = rng.random()
        deltas = tuple(rng.choice((0, 0, rng.randint(-5, 5), rng.randrange(-half, half)
                                   if rng.random() < 0.2 else rng.randint(-9, 9)))
                       for _ in range(NA))
        inp = LineInputs(s_valid=int(rng.random() < 0.6), s_delta=deltas,
                         en=int(rng.random() < 0.8), rst=int(r < 0.004),
                         start_en=int(rng.random() < 0.7), abort=int(0.004 <= r < 0.02))
        bench.drive(inp)
        await ReadOnly()
        got = {k: int(getattr(dut, k).value) for k in fields}
        exp = vars(model.outputs(abort=inp.abort))
        bad = [k for k in fields if got[k] != exp[k]]
        assert not bad, f"cycle {cycle}: " + ", ".join(
            f"{k}: rtl={got[k]} model={exp[k]}" for k in bad)
        run = model.run
        running = run is not None
        pending = model.vstate == L_HOLD
        ending = running and bool(inp.en) and not inp.abort and run.left == 1
        loading = (pending and bool(inp.start_en) and not inp.abort
                   and (not running or ending))
        seq = {"running": int(running), "pending": int(pending),
               "ending": int(ending), "loading": int(loading)}
        if running:
            seq["nx_step"] = sum(1 << k for k, s in enumerate(run.peek()) if s)
            seq["nx_dir"] = sum(1 << k for k, d in enumerate(run.dirs) if d >= 0)
        for k, want in seq.items():
            assert int(getattr(dut, k).value) == want, \
                f"cycle {cycle}: {k}: rtl={int(getattr(dut, k).value)} model={want}"
        counts["abort"] += inp.abort
        counts["reject"] += got["reject"]
        counts["done"] += got["done"]
        counts["loading"] += int(loading)
        counts["stalled"] += int(pending and not inp.start_en)
        model.clock(inp)
    dut._log.info("control mix: %s", counts)
    assert all(counts.values()), f"a case never happened: {counts}"
