# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_arc with Verilator and runs arc_cocotb.py."""


import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb


# every cocotb test at the two widths the issue names; an odd width in
# between runs the circle and quadrant tests
CASES = [
    (16, None),
    (32, None),
    (23, ["full_circles", "quadrant_pairs", "rejects_then_valid", "tolerance_edges"]),
]


@pytest.mark.parametrize("width, testcases", CASES, ids=[f"W{w}" for w, _ in CASES])
def test_arc_rtl_matches_model(width, testcases):
    run_cocotb(
        toplevel="halfpoint_arc",
        sources=rtl_sources("halfpoint_arc"),
        test_module="arc_cocotb",
        test_dir=BUILD / "sim" / f"arc_w{width}" / "run",
        parameters={"W": width},
        build_name=f"arc_w{width}",
        extra_env={"HP_SEED": 1},
        testcase=testcases,
    )
