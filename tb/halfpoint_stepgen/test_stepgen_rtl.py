# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_stepgen with Verilator, runs stepgen_cocotb.py."""

import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb


@pytest.mark.parametrize("tw", [16, 4])
def test_stepgen_rtl(tw):
    name = f"stepgen_tw{tw}"
    run_cocotb(
        toplevel="halfpoint_stepgen",
        sources=rtl_sources("halfpoint_stepgen"),
        test_module="stepgen_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"TW": tw},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
