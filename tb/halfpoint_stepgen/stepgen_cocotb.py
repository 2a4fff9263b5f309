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

FIELDS = ("step_pin", "dir_pin", "ready_pos", "ready_neg", "busy")

CONFIGS = [
    StepCfg(1, 1, 1, 1),
    StepCfg(3, 2, 5, 4),
    StepCfg(1, 0, 0, 0),
    StepCfg(0, 0, 0, 0),            # steplen 0 acts as 1
    StepCfg(5, 7, 0, 3, 1, 0),
    StepCfg(2, 9, 6, 0, 0, 1),
    StepCfg(4, 1, 2, 8, 1, 1),
]


def apply_cfg(dut, cfg: StepCfg) -> None:
    dut.cfg_steplen.value = cfg.steplen
    dut.cfg_stepspace.value = cfg.stepspace
    dut.cfg_dirsetup.value = cfg.dirsetup
    dut.cfg_dirhold.value = cfg.dirhold
    dut.cfg_step_inv.value = cfg.step_inv
    dut.cfg_dir_inv.value = cfg.dir_inv


async def run_config(dut, cfg: StepCfg, rng: random.Random, nsteps: int, idle: float):
    model = StepGenModel(TW)
    checker = StepDirChecker(cfg)
    apply_cfg(dut, cfg)
    # reset both
    dut.rst.value, dut.req.value, dut.req_dir.value = 1, 0, 0
    model.clock(cfg, StepInputs(rst=1))
    await FallingEdge(dut.clk)
    await FallingEdge(dut.clk)
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
        exp = vars(model.outputs(cfg))
        bad = [k for k in FIELDS if got[k] != exp[k]]
        assert not bad, f"cycle {cycles}: " + ", ".join(f"{k}: rtl={got[k]} model={exp[k]}" for k in bad)
        checker.sample(got["step_pin"], got["dir_pin"])
        inp = StepInputs(req_dir=rng.randint(0, 1))
        if taken < len(want) and rng.random() >= idle:
            dr = want[taken]
            if (got["ready_pos"] if dr else got["ready_neg"]):
                inp = StepInputs(req=1, req_dir=dr)
                taken += 1
        dut.req.value, dut.req_dir.value = inp.req, inp.req_dir
        model.clock(cfg, inp)
        cycles += 1
        if taken == len(want) and not got["busy"] and checker.idle and cycles > 3:
            # let the last pulse finish and be seen by the checker
            for _ in range(2 * max(cfg.steplen, 1) + cfg.dirsetup + 4):
                await FallingEdge(dut.clk)
                got = {k: int(getattr(dut, k).value) for k in FIELDS}
                exp = vars(model.outputs(cfg))
                assert got == {k: exp[k] for k in FIELDS}
                checker.sample(got["step_pin"], got["dir_pin"])
                dut.req.value = 0
                model.clock(cfg, StepInputs())
            break
    expected = sum(1 if x else -1 for x in want)
    assert checker.steps == len(want), f"{checker.steps} pulses for {len(want)} requests"
    assert checker.position == expected
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
