# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_refloop (the synthesis timing reference)
with Verilator and runs refloop_cocotb.py for both loop forms."""

import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb


@pytest.mark.parametrize("fold", [0, 1])
def test_refloop_rtl(fold):
    name = f"refloop_fold{fold}"
    run_cocotb(
        toplevel="halfpoint_refloop",
        sources=rtl_sources("halfpoint_refloop"),
        test_module="refloop_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"WR": 34, "FOLD": fold},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
