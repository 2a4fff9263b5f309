# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_line with Verilator and runs line_cocotb.py."""

import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb

CASES = [(3, 32), (1, 16), (6, 16), (2, 24)]


@pytest.mark.parametrize("axes, width", CASES, ids=[f"NA{a}-W{w}" for a, w in CASES])
def test_line_rtl_matches_model(axes, width):
    name = f"line_na{axes}_w{width}"
    run_cocotb(
        toplevel="halfpoint_line",
        sources=rtl_sources("halfpoint_line"),
        test_module="line_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"NA": axes, "W": width},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
