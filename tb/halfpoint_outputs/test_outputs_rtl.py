# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_outputs with Verilator, runs outputs_cocotb.py."""

import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb


@pytest.mark.parametrize("pwm_bits", [4, 10, 16])
def test_outputs_rtl_matches_model(pwm_bits):
    name = f"outputs_p{pwm_bits}"
    run_cocotb(
        toplevel="halfpoint_outputs",
        sources=rtl_sources("halfpoint_outputs"),
        test_module="outputs_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"PWM_BITS": pwm_bits},
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
