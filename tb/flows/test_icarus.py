# SPDX-License-Identifier: Apache-2.0
"""The RTL on a second simulator: one representative cocotb test of every RTL
module on Icarus Verilog (compiled as Verilog-2005, ``-g2005``), so that the
RTL does not accidentally depend on Verilator.  Skipped, with the reason, when
Icarus is not installed.  Every cocotb test runs on Icarus with
``pytest --sim icarus`` (or HALFPOINT_SIM=icarus); this file is the lean part
that ``make test`` runs."""

from __future__ import annotations

import pytest

from halfpoint.sim.design import design_sources
from halfpoint.sim.env import BUILD, REPO, icarus_missing, run_cocotb

pytestmark = pytest.mark.skipif(icarus_missing() is not None,
                                reason=icarus_missing() or "")


# (module, its test directory, parameters, cocotb test module, the test(s) run, environment);
# the sources are the module's design (design_sources: read from the RTL's instantiations)
CASES = [
    ("halfpoint_stepgen", "halfpoint_stepgen", {"TW": 4}, "stepgen_cocotb",
     ["timing_and_model"], {}),
    ("halfpoint_line", "halfpoint_line", {"NA": 2, "W": 16}, "line_cocotb",
     ["seed_example", "back_to_back"], {}),
    ("halfpoint_arc", "halfpoint_arc", {"W": 16}, "arc_cocotb",
     ["quadrant_pairs"], {}),
    ("halfpoint_profile", "halfpoint_profile", {"W": 16, "DIV": 5}, "profile_cocotb",
     ["raw_profiles"], {}),
    ("halfpoint_core", "halfpoint_core",
     {"NA": 2, "W": 16, "DEPTH": 8, "TW": 16, "DIV": 4, "MOVE_DEPTH": 2, "PROFILE_DEPTH": 1},
     "core_cocotb", ["mixed_program"], {}),
    ("halfpoint_refloop", "halfpoint_refloop", {"WR": 34, "FOLD": 1}, "refloop_cocotb",
     ["recurrence"], {}),
    ("halfpoint_uart_cmd", "halfpoint_uart_cmd",
     {"CLK_HZ": 1_000_000, "BAUD": 125_000, "IDLE_BITS": 12}, "uart_cmd_cocotb",
     ["commands_and_replies"], {"HP_SKEW": 0.0}),
    ("halfpoint_outputs", "halfpoint_outputs", {"PWM_BITS": 4}, "outputs_cocotb",
     ["pins_and_registers_match_the_model"], {}),
    # the bench drives the Wishbone idle lines itself and makes cocotbext-wishbone's
    # master after time 0: Icarus 11 wedges a net put with Immediate at time 0
    # (see RegsBench.start); test_regs_tools.py compiles both slaves with -g2005
    ("halfpoint_wb", "halfpoint_regs",
     {"NA": 2, "W": 16, "DEPTH": 8, "TW": 4, "DIV": 4, "MOVE_DEPTH": 2, "PROFILE_DEPTH": 1},
     "regs_cocotb", ["every_register"], {}),
    # the pin monitor skips the STEP/DIR samples before the power-on reset's
    # first edge (X on Icarus) and fails on X or Z after it
    ("halfpoint_uart_top", "halfpoint_uart_top",
     {"CLK_HZ": 1_000_000, "BAUD": 125_000, "NA": 3, "W": 32, "DEPTH": 4, "STEPLEN": 2,
      "STEPSPACE": 2, "DIRSETUP": 1, "DIRHOLD": 1, "BTN_ACTIVE_LOW": 1, "DIV": 3},
     "uart_top_cocotb", ["abort_and_reset_buttons"], {}),
]


@pytest.mark.parametrize("module, tests, parameters, test_module, testcases, env", CASES,
                         ids=[(c.values if hasattr(c, "values") else c)[0]
                              .removeprefix("halfpoint_") for c in CASES])
def test_on_icarus(module, tests, parameters, test_module, testcases, env, monkeypatch):
    monkeypatch.syspath_prepend(str(REPO / "tb" / tests))      # the cocotb test module
    name = f"{module.removeprefix('halfpoint_')}_representative"
    run_cocotb(
        toplevel=module,
        sources=design_sources(module),
        test_module=test_module,
        test_dir=BUILD / "sim" / name / "run",      # run_cocotb moves it under icarus/
        parameters=parameters,
        build_name=name,
        extra_env={"HP_SEED": 1, **env},
        testcase=testcases,
        simulator="icarus",
    )
