# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_core with Verilator and runs core_cocotb.py."""

import pytest

from halfpoint.sim.design import design_sources
from halfpoint.sim.env import BUILD, run_cocotb

# (NA, W, DEPTH, DIV, MOVE_DEPTH, PROFILE_DEPTH, PWM_BITS)
CASES = [(3, 32, 4, 3, 4, 2, 4), (2, 16, 8, 4, 2, 1, 6)]


@pytest.mark.parametrize("axes, width, depth, div, move_depth, profile_depth, pwm_bits", CASES,
                         ids=[f"NA{c[0]}-W{c[1]}-D{c[2]}-DIV{c[3]}" for c in CASES])
def test_core_rtl_matches_model(axes, width, depth, div, move_depth, profile_depth, pwm_bits):
    name = f"core_na{axes}_w{width}_d{depth}_div{div}"
    run_cocotb(
        toplevel="halfpoint_core",
        sources=design_sources("halfpoint_core"),
        test_module="core_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"NA": axes, "W": width, "DEPTH": depth, "TW": 16, "DIV": div,
                    "MOVE_DEPTH": move_depth, "PROFILE_DEPTH": profile_depth,
                    "PWM_BITS": pwm_bits},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
