# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_core with Verilator and runs core_cocotb.py."""

import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb

CASES = [(3, 32, 4), (2, 16, 8)]


@pytest.mark.parametrize("axes, width, depth", CASES, ids=[f"NA{a}-W{w}-D{d}" for a, w, d in CASES])
def test_core_rtl_matches_model(axes, width, depth):
    name = f"core_na{axes}_w{width}_d{depth}"
    run_cocotb(
        toplevel="halfpoint_core",
        sources=rtl_sources("halfpoint_core", "halfpoint_arc", "halfpoint_line", "halfpoint_stepgen"),
        test_module="core_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"NA": axes, "W": width, "DEPTH": depth, "TW": 16},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
