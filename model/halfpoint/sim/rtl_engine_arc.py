# SPDX-License-Identifier: Apache-2.0
"""cocotb module behind ``--engine rtl``: runs commands through the RTL.

The command line starts the Verilator-built ``halfpoint_arc`` with this module;
the commands come in as JSON in HP_CMDS and what the RTL did goes out as JSON
to the file HP_OUT.  Nothing here consults the model: the RTL's own outputs
are reported.
"""

from __future__ import annotations

import json
import os

import cocotb

from .arcbench import ArcBench
from .design import read_parameters


@cocotb.test()
async def run_commands(dut):
    (width,) = read_parameters(dut, "W")
    cmds = [tuple(c) for c in json.loads(os.environ["HP_CMDS"])]
    bench = ArcBench(dut, width, check=False)
    await bench.start()
    results, stats = await bench.run(cmds)
    out = [
        {"cmd": list(r.cmd), "points": ArcBench.points(r), "rejected": r.rejected, "finished": r.finished}
        for r in results
    ]
    with open(os.environ["HP_OUT"], "w", encoding="utf-8") as fh:
        json.dump({"results": out, "cycles": stats.cycles, "moves": stats.moves}, fh)
