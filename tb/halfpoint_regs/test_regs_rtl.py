# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds the SoC register interface (halfpoint_wb and
halfpoint_axil, each over halfpoint_regs and halfpoint_core) with Verilator and
runs regs_cocotb.py through cocotbext-wishbone and cocotbext-axi."""

import pytest

from halfpoint.sim.design import design_sources
from halfpoint.sim.env import BUILD, run_cocotb
# (top, NA, W, DEPTH, TW, DIV, MOVE_DEPTH, PROFILE_DEPTH)
CASES = [("halfpoint_wb", 3, 32, 4, 16, 3, 4, 2),
         ("halfpoint_axil", 2, 16, 8, 4, 4, 2, 1)]


@pytest.mark.parametrize("case", CASES, ids=[f"{c[0]}-NA{c[1]}-W{c[2]}" for c in CASES])
def test_regs_rtl_matches_model(case):
    top, axes, width, depth, tw, div, move_depth, profile_depth = case
    name = f"{top}_na{axes}_w{width}"
    run_cocotb(
        toplevel=top,
        sources=design_sources(top),
        test_module="regs_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"NA": axes, "W": width, "DEPTH": depth, "TW": tw, "DIV": div,
                    "MOVE_DEPTH": move_depth, "PROFILE_DEPTH": profile_depth},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
