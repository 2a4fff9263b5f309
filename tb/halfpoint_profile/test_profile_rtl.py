# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_profile with Verilator, runs profile_cocotb.py."""

import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb

CASES = [(32, 3), (16, 5)]


@pytest.mark.parametrize("width, div", CASES, ids=[f"W{w}-DIV{d}" for w, d in CASES])
def test_profile_rtl_matches_model(width, div):
    name = f"profile_w{width}_div{div}"
    run_cocotb(
        toplevel="halfpoint_profile",
        sources=rtl_sources("halfpoint_profile"),
        test_module="profile_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"W": width, "DIV": div},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
