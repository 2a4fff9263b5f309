# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_helix with Verilator and runs helix_cocotb.py."""

import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb

# NA 6: both helix slots and every plane (NA 3 runs inside the core's own test)
CASES = [(6, 16)]


@pytest.mark.parametrize("axes, width", CASES, ids=[f"NA{a}-W{w}" for a, w in CASES])
def test_helix_rtl_matches_model(axes, width):
    name = f"helix_na{axes}_w{width}"
    run_cocotb(
        toplevel="halfpoint_helix",
        sources=rtl_sources("halfpoint_helix"),
        test_module="helix_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"NA": axes, "W": width},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
