# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds halfpoint_uart_cmd with Verilator, runs uart_cmd_cocotb.py."""

import pytest

from halfpoint.sim.env import BUILD, rtl_sources, run_cocotb


# (clocks per bit, host baud error in percent)
@pytest.mark.parametrize("cpb, skew", [(8, 0.0), (10, 2.0), (104, -2.5)])
def test_uart_cmd_rtl(cpb, skew):
    name = f"uart_cmd_cpb{cpb}"
    run_cocotb(
        toplevel="halfpoint_uart_cmd",
        sources=rtl_sources("halfpoint_uart_cmd"),
        test_module="uart_cmd_cocotb",
        test_dir=BUILD / "sim" / f"{name}_{skew}" / "run",
        parameters={"CLK_HZ": 1_000_000, "BAUD": 1_000_000 // cpb, "IDLE_BITS": 12},
        build_name=name,
        extra_env={"HP_SKEW": skew, "HP_SEED": 1},
    )
