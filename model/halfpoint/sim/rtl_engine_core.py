# SPDX-License-Identifier: Apache-2.0
"""cocotb module behind ``--engine rtl`` of ``halfpoint run`` and ``halfpoint segments``.

Reads the command stream (commands and pauses), the hold intervals and the STEP/DIR
timing from the JSON file HP_CMDS, drives the Verilator-built ``halfpoint_core``
clock by clock with ``halfpoint.cam.motion.Feeder`` (the same policy as the model
executor: tvalid and tdata straight on the AXI4-Stream pins, hold on its pin), and
writes to HP_OUT every move with its cycle, the error codes, the final ``dry`` and
``underrun`` flags and the cycles run, as the RTL's outputs showed them.  The model is
not consulted.  Cycle 0 is the first cycle after reset, as in ``spec.core.run_program``.
"""

from __future__ import annotations

import json
import os
from types import SimpleNamespace

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge

from ..cam.motion import Feeder, Pause
from ..spec.rules import wrap
from .design import read_parameters


def _pack(values, width: int) -> int:
    out = 0
    for k, v in enumerate(values):
        out |= v << (k * width)
    return out


@cocotb.test()
async def run_stream(dut):
    with open(os.environ["HP_CMDS"], encoding="utf-8") as fh:
        job = json.load(fh)
    items = [Pause(it["pause"], it["seconds"], it["lineno"]) if isinstance(it, dict)
             else int(it) for it in job["items"]]
    axes, width, tw = read_parameters(dut, "NA", "W", "TW")
    cfg = job["cfg"]
    dut.cfg_steplen.value = _pack([c["steplen"] for c in cfg], tw)
    dut.cfg_stepspace.value = _pack([c["stepspace"] for c in cfg], tw)
    dut.cfg_dirsetup.value = _pack([c["dirsetup"] for c in cfg], tw)
    dut.cfg_dirhold.value = _pack([c["dirhold"] for c in cfg], tw)
    dut.cfg_step_inv.value = sum(c["step_inv"] << k for k, c in enumerate(cfg))
    dut.cfg_dir_inv.value = sum(c["dir_inv"] << k for k, c in enumerate(cfg))
    dut.feed_override.value = 128
    dut.abort_now.value = 0
    dut.hold.value = 0
    dut.stop.value = 0
    dut.s_axis_tvalid.value = 0
    dut.s_axis_tdata.value = 0
    if hasattr(dut, "s_axis_tlast"):
        dut.s_axis_tlast.value = 1
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    dut.rst.value = 1
    for _ in range(3):
        await RisingEdge(dut.clk)
    await FallingEdge(dut.clk)
    dut.rst.value = 0
    feeder = Feeder(items, job["holds"])
    limit = job["max_clocks"]
    cycle = 0
    failure = None
    while not feeder.done:
        if cycle >= limit:
            failure = f"the core is still busy after {limit} clocks"
            break
        raw = int(dut.pos.value)
        out = SimpleNamespace(
            tready=int(dut.s_axis_tready.value), busy=int(dut.busy.value),
            level=int(dut.queue_level.value), move=int(dut.move.value),
            pos=tuple(wrap(raw >> (k * width), width) for k in range(axes)),
            err=int(dut.err.value), err_code=int(dut.err_code.value),
            underrun=int(dut.underrun.value), dry=int(dut.dry.value))
        tvalid, tdata, hold = feeder.step(cycle, out)
        dut.s_axis_tvalid.value = tvalid
        dut.s_axis_tdata.value = tdata
        dut.hold.value = hold
        cycle += 1
        await FallingEdge(dut.clk)
    run = feeder.run
    result = {"moves": [[c, list(p)] for c, p in run.moves], "errors": run.errors,
              "dry": run.dry, "underrun": run.underrun, "cycles": run.cycles}
    if failure:
        result["failure"] = failure
    with open(os.environ["HP_OUT"], "w", encoding="utf-8") as fh:
        json.dump(result, fh)
