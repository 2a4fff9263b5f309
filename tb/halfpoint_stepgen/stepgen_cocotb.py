# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_stepgen: pins and ready signals against the model
on every clock, and an independent timing checker on every STEP/DIR edge."""

from __future__ import annotations

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge

from halfpoint.spec.stepgen import StepCfg, StepGenModel, StepInputs
from halfpoint.sim.design import read_parameters
from halfpoint.sim.timing import StepDirChecker

TW = 0         # the design's timing width: bind() reads it


def bind(dut) -> None:
    """Take TW from the design under test (its parameters)."""
    global TW
    (TW,) = read_parameters(dut, "TW")

FIELDS = ("step_pin", "dir_pin", "ready_pos", "ready_neg", "busy", "direction",
          "next_ready_same", "next_ready_reverse")


def expected(model: StepGenModel, cfg: StepCfg) -> dict:
    """Every output of the model: the pins, readiness and the lookahead."""
    return {**vars(model.outputs(cfg)), **vars(model.lookahead(cfg))}

CONFIGS = [
    StepCfg(1, 1, 1, 1),
    StepCfg(3, 2, 5, 4),
    StepCfg(1, 0, 0, 0),
    StepCfg(0, 0, 0, 0),            # steplen 0 acts as 1
    StepCfg(5, 7, 0, 3, 1, 0),
    StepCfg(2, 9, 6, 0, 0, 1),
    StepCfg(4, 1, 2, 8, 1, 1),
    # one-clock pulses with a longer stepspace: the inactive time restarts at
    # the end of the pulse, not from the time before it (found by mutation
    # testing: no other setting tells them apart)
    StepCfg(1, 3, 0, 2),
    StepCfg(0, 4, 2, 5, 0, 1),
    # dirhold 2 or 3 above a stepspace of at most 1: a reversal waits for dirhold
    # after a pulse, a step in the same direction does not (found by mutation
    # testing: no other setting has the HIGH state's end decide by dirhold alone)
    StepCfg(2, 1, 0, 3, 0, 1),
    StepCfg(1, 0, 1, 2, 1, 0),
]


def apply_cfg(dut, cfg: StepCfg) -> None:
    dut.cfg_steplen.value = cfg.steplen
    dut.cfg_stepspace.value = cfg.stepspace
    dut.cfg_dirsetup.value = cfg.dirsetup
    dut.cfg_dirhold.value = cfg.dirhold
    dut.cfg_step_inv.value = cfg.step_inv
    dut.cfg_dir_inv.value = cfg.dir_inv


async def run_config(dut, cfg: StepCfg, rng: random.Random, nsteps: int, idle: float,
                     pushy: float = 0.0):
    """Request ``nsteps`` steps, each when its direction is ready (``idle``: chance
    of waiting a clock anyway); ``pushy``: chance that, in a clock without a
    request, req is raised for a direction that is NOT ready (must be ignored)."""
    model = StepGenModel(TW)
    checker = StepDirChecker(cfg)
    apply_cfg(dut, cfg)
    # reset both
    dut.rst.value, dut.req.value, dut.req_dir.value = 1, 0, 0
    model.clock(cfg, StepInputs(rst=1))
    # in reset: pins at their idle levels (the inversions), ready (found by
    # mutation testing: a wrong reset value shows for one clock only, and a pin
    # that ignored the reset would show the last configuration's DIR after the
    # first reset edge only)
    for edge in ("first", "second"):
        await FallingEdge(dut.clk)
        got = {k: int(getattr(dut, k).value) for k in FIELDS}
        assert got == {k: expected(model, cfg)[k] for k in FIELDS}, \
            f"in reset, after the {edge} edge: {got}"
    dut.rst.value = 0
    model.clock(cfg, StepInputs(rst=1))
    # a random step sequence with runs of equal direction
    want, d = [], rng.randint(0, 1)
    while len(want) < nsteps:
        if rng.random() < 0.3:
            d ^= 1
        want += [d] * rng.randint(1, 6)
    want = want[:nsteps]
    taken = 0
    cycles = 0
    while True:
        await FallingEdge(dut.clk)
        got = {k: int(getattr(dut, k).value) for k in FIELDS}
        exp = expected(model, cfg)
        bad = [k for k in FIELDS if got[k] != exp[k]]
        assert not bad, f"cycle {cycles}: " + ", ".join(f"{k}: rtl={got[k]} model={exp[k]}" for k in bad)
        checker.sample(got["step_pin"], got["dir_pin"])
        inp = StepInputs(req_dir=rng.randint(0, 1))
        ready = got["ready_pos"] if inp.req_dir else got["ready_neg"]
        ignored = bool(pushy) and not ready and rng.random() < pushy
        if taken < len(want) and rng.random() >= idle:
            dr = want[taken]
            if (got["ready_pos"] if dr else got["ready_neg"]):
                inp = StepInputs(req=1, req_dir=dr)
                taken += 1
                ignored = False
        if ignored:
            # req while not ready: the RTL must ignore it, so the model (for
            # which such a request is a requester's error) sees none
            dut.req.value, dut.req_dir.value = 1, inp.req_dir
        else:
            dut.req.value, dut.req_dir.value = inp.req, inp.req_dir
        model.clock(cfg, inp)
        cycles += 1
        if taken == len(want) and not got["busy"] and checker.idle and cycles > 3:
            # let the last pulse finish and be seen by the checker
            for _ in range(2 * max(cfg.steplen, 1) + cfg.dirsetup + 4):
                await FallingEdge(dut.clk)
                got = {k: int(getattr(dut, k).value) for k in FIELDS}
                exp = expected(model, cfg)
                assert got == {k: exp[k] for k in FIELDS}
                checker.sample(got["step_pin"], got["dir_pin"])
                dut.req.value = 0
                model.clock(cfg, StepInputs())
            break
    position = sum(1 if x else -1 for x in want)
    assert checker.steps == len(want), f"{checker.steps} pulses for {len(want)} requests"
    assert checker.position == position
    return cycles


@cocotb.test()
async def timing_and_model(dut):
    """Every configuration: pins equal the model on every clock, every edge
    meets the timing, every request becomes exactly one pulse."""
    bind(dut)
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    rng = random.Random(int(os.environ.get("HP_SEED", "1")))
    for cfg in CONFIGS:
        for idle in (0.0, 0.4):
            await run_config(dut, cfg, rng, 150, idle)


def wide_configs(tw: int) -> list[StepCfg]:
    """Settings that fill the timers' top bits: the largest value TW allows and
    values of 8..15 clocks (for TW = 4 the top bit; capped at 15 so that wide
    timers stay quick), in both polarities.  Found by mutation testing
    (python -m halfpoint.flows.mutate): with settings below 8 the top bit of
    the counters and the saturation of the inactive time were never used."""
    top = (1 << tw) - 1
    cap = min(top, 15)
    return [
        StepCfg(top, top, top, top) if tw <= 4 else StepCfg(cap, cap, cap, cap),
        StepCfg(8, min(12, cap), 9, min(14, cap), 1, 0),
        StepCfg(min(12, cap), 8, min(14, cap), 9, 0, 1),
        StepCfg(9, min(14, cap), 8, min(12, cap), 1, 1),
    ]


@cocotb.test()
async def wide_settings(dut):
    """Settings up to the timers' width: pins equal the model on every clock,
    every edge meets the timing, every request becomes exactly one pulse."""
    bind(dut)
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    rng = random.Random(int(os.environ.get("HP_SEED", "1")) + 101)
    for cfg in wide_configs(TW):
        for idle in (0.0, 0.5):
            await run_config(dut, cfg, rng, 40, idle)


@cocotb.test()
async def requests_while_not_ready(dut):
    """Requests raised while their direction is not ready are ignored: no
    pulse, no DIR change, pins equal the model.  Found by mutation testing: the
    other tests raise req only when ready."""
    bind(dut)
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    rng = random.Random(int(os.environ.get("HP_SEED", "1")) + 202)
    for cfg in CONFIGS + wide_configs(TW):
        await run_config(dut, cfg, rng, 30, 0.3, pushy=0.7)
