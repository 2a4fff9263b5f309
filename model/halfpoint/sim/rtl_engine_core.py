# SPDX-License-Identifier: Apache-2.0
"""cocotb module behind ``halfpoint segments --engine rtl``.

Sends the encoded commands (JSON file HP_CMDS) through cocotbext-axi into the
Verilator-built ``halfpoint_core`` and writes the positions the core's
outputs showed after every move to HP_OUT.  The model is not consulted.
"""

from __future__ import annotations

import json
import os

import cocotb

from .corebench import CoreBench
from .design import read_parameters
from ..spec.stepgen import StepCfg


@cocotb.test()
async def run_segments(dut):
    with open(os.environ["HP_CMDS"], encoding="utf-8") as fh:
        cmds = [int(c) for c in json.load(fh)]
    axes, width, depth, tw = read_parameters(dut, "NA", "W", "DEPTH", "TW")
    bench = CoreBench(dut, axes, width, depth, tw, cfg=[StepCfg(1, 0, 0, 0)] * axes, check=False)
    await bench.start()
    await bench.send(cmds)
    await bench.drain()
    with open(os.environ["HP_OUT"], "w", encoding="utf-8") as fh:
        json.dump({"trace": bench.trace, "errors": [c for _, c in bench.errors]}, fh)
