# SPDX-License-Identifier: Apache-2.0
"""pytest runner: builds the example board top (serial port + motion core)
with Verilator and runs uart_top_cocotb.py."""

from halfpoint.sim.design import design_sources
from halfpoint.sim.env import BUILD, run_cocotb

PARAMS = {"CLK_HZ": 1_000_000, "BAUD": 125_000, "NA": 3, "W": 32, "DEPTH": 4,
          "STEPLEN": 2, "STEPSPACE": 2, "DIRSETUP": 1, "DIRHOLD": 1, "BTN_ACTIVE_LOW": 1,
          "DIV": 3}


def test_uart_top_rtl():
    name = "uart_top"
    run_cocotb(
        toplevel="halfpoint_uart_top",
        sources=design_sources("halfpoint_uart_top"),
        test_module="uart_top_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters=PARAMS,
        build_name=name,
        extra_env={"HP_SEED": 1},
    )
