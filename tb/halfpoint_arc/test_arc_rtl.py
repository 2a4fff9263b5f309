# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_arc with Verilator and runs arc_cocotb.py."""

from pathlib import Path

import pytest

from halfpoint.sim import BUILD, rtl_sources, run_cocotb

HERE = Path(__file__).resolve().parent


@pytest.mark.parametrize("width", [16, 32])
def test_arc_rtl_matches_model(width):
    run_cocotb(
        toplevel="halfpoint_arc",
        sources=rtl_sources("halfpoint_arc"),
        test_module="arc_cocotb",
        test_dir=BUILD / "sim" / f"arc_w{width}" / "run",
        parameters={"W": width},
        build_name=f"arc_w{width}",
        extra_env={"HP_W": width, "HP_SEED": 1},
    )
