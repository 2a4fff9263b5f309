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
from ..spec.stepgen import StepCfg


@cocotb.test()
async def run_segments(dut):
    with open(os.environ["HP_CMDS"], encoding="utf-8") as fh:
        cmds = [int(c) for c in json.load(fh)]
    bench = CoreBench(dut, 3, 32, 16, 16, cfg=[StepCfg(1, 0, 0, 0)] * 3, check=False)
    await bench.start()
    await bench.send(cmds)
    await bench.drain()
    with open(os.environ["HP_OUT"], "w", encoding="utf-8") as fh:
        json.dump({"trace": bench.trace, "errors": [c for _, c in bench.errors]}, fh)
