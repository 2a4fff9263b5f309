# SPDX-License-Identifier: Apache-2.0
"""Integer lemmas of the formal monitors, proven by an SMT solver in integer
arithmetic where the bit-level solver of SymbiYosys does not finish.

One lemma so far, ``squares``: the arc unit's squarer ghosts (rtl/halfpoint_arc.v,
``F_SQUARER``) end as the sums of squares at every width the RTL runs at.

The monitor keeps one ghost accumulator per squaring register; from the
accepting edge (ghost 0) it adds, on the squaring clock of count k, the two rows
of binary multiplication a_k (a << k) + b_k (b << k), in F_PW = 2W + 4 bits,
where a, b < 2^W are the command's magnitudes (``GHOST_TEXT`` below, checked
against the RTL's text).  ``proto_wN`` proves the schedule at every width (the
count is k on the clock k after the accepting edge, k = 0 .. W - 1; SUM follows
at W), ``squarer_wN`` proves the registers equal to the ghosts and ``codes_wN``
the reject codes against them, up to W = 32.  What is left is arithmetic: that
the ghost after the W rows is a^2 + b^2.  As bit vectors that is a multiplier to
the solver (``square_w8`` and ``sqghost_w8`` prove it at W = 8 only); in
integers it is a polynomial identity.  :func:`squares_query` states, in
SMT-LIB's QF_NIA, for all bits a_i, b_i in {0, 1}: every partial sum of the
recurrence, after each of its two adds, and every row are in 0 .. 2^F_PW - 1
(so the monitor's F_PW-bit adds never wrap and its ghost is the integer sum),
and the sum after W rows is a^2 + b^2; ``yices-smt2`` (the flow's solver) must
answer unsat for the negation.  ``wrong_row`` states it with the row of bit k
shifted by k + 1 (the squarer's wrong-bit mutant, in the lemma): that must be
sat, with the values of a and b that break it.
"""

from __future__ import annotations

import re
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

from ..sim.env import REPO

ARC_RTL = REPO / "rtl" / "halfpoint_arc.v"
F_PW_EXTRA = 4                  # the monitor's F_PW = 2W + 4 (checked in GHOST_TEXT)
# the monitor's lines that the lemma restates (each must occur exactly once)
GHOST_TEXT = (
    f"localparam integer F_PW = 2 * W + {F_PW_EXTRA};",
    "wire [5:0]      f_sk = square_count_q;",
    "wire [F_PW-1:0] f_row_xs = f_axs[f_sk] ? (f_axs << f_sk) : {F_PW{1'b0}};",
    "wire [F_PW-1:0] f_row_ys = f_ays[f_sk] ? (f_ays << f_sk) : {F_PW{1'b0}};",
    "wire [F_PW-1:0] f_row_xe = f_axe[f_sk] ? (f_axe << f_sk) : {F_PW{1'b0}};",
    "wire [F_PW-1:0] f_row_ye = f_aye[f_sk] ? (f_aye << f_sk) : {F_PW{1'b0}};",
    "f_gr2 <= {F_PW{1'b0}};",
    "f_ge2 <= {F_PW{1'b0}};",
    "f_gr2 <= f_gr2 + f_row_xs + f_row_ys;",
    "f_ge2 <= f_ge2 + f_row_xe + f_row_ye;",
)
WIDTHS = range(8, 33)           # the arc unit's legal W


def ghost_text_follows(rtl: Path = ARC_RTL) -> list[str]:
    """The restated lines the RTL no longer has exactly once (empty: it follows)."""
    text = rtl.read_text()
    return [line for line in GHOST_TEXT if text.count(line) != 1]


def squares_query(w: int, wrong_row: bool = False) -> str:
    """The negated lemma at width w, SMT-LIB 2 (QF_NIA): unsat proves it."""
    top = 1 << (2 * w + F_PW_EXTRA)
    out = ["(set-option :produce-models true)", "(set-logic QF_NIA)"]
    for v in "ab":
        for i in range(w):
            out.append(f"(declare-fun {v}{i} () Int)")
            # a bit: 0 <= x <= 1 (as (or (= x 0) (= x 1)) yices had not
            # answered W = 8 in 10 minutes; as bounds it answers W = 32 in 0.3 s)
            out.append(f"(assert (and (<= 0 {v}{i}) (<= {v}{i} 1)))")
        terms = " ".join(f"(* {1 << i} {v}{i})" for i in range(w))
        out.append(f"(define-fun {v} () Int (+ {terms}))")
    goals = []

    def fits(term: str) -> str:
        return f"(and (<= 0 {term}) (< {term} {top}))"

    out.append("(define-fun g0 () Int 0)")
    for k in range(w):
        shift = 1 << (k + 1 if wrong_row else k)
        # the two rows of count k and the ghost after each of the two adds
        out.append(f"(define-fun ra{k} () Int (* a{k} {shift} a))")
        out.append(f"(define-fun rb{k} () Int (* b{k} {shift} b))")
        out.append(f"(define-fun h{k} () Int (+ g{k} ra{k}))")
        out.append(f"(define-fun g{k + 1} () Int (+ h{k} rb{k}))")
        # a row is (a << k) or 0 in F_PW bits: a 2^k must not lose bits there
        goals += [fits(f"(* {shift} a)"), fits(f"(* {shift} b)"), fits(f"h{k}"),
                  fits(f"g{k + 1}")]
    goals.append(f"(= g{w} (+ (* a a) (* b b)))")
    out.append(f"(assert (not (and {' '.join(goals)})))")
    out.append("(check-sat)")
    out.append("(get-value (a b))")
    return "\n".join(out) + "\n"


@dataclass
class LemmaRun:
    status: str                 # PASS (unsat), FAIL (sat), ERROR
    seconds: float
    note: str = ""
    trace: str = ""             # FAIL: the solver's answer with the values of a and b
    width: int = 0              # FAIL: the width that is sat ...
    values: dict = field(default_factory=dict)      # ... and the solver's a and b there


def run_squares(solver: Path, workdir: Path, wrong_row: bool = False,
                widths=WIDTHS) -> LemmaRun:
    """The lemma at each width, the queries kept in workdir; PASS when every
    width is unsat, FAIL (with the width and the values of a and b) when one is
    sat, ERROR when the RTL's ghost no longer reads as restated or the solver
    answers anything else."""
    t0 = time.monotonic()
    stale = ghost_text_follows()
    if stale:
        return LemmaRun("ERROR", 0.0, "the RTL's squarer ghost changed; restate the lemma "
                        f"(halfpoint.flows.lemmas.GHOST_TEXT): {stale[0]}")
    workdir.mkdir(parents=True, exist_ok=True)
    for w in widths:
        query = workdir / f"squares_w{w}.smt2"
        query.write_text(squares_query(w, wrong_row))
        proc = subprocess.run([str(solver), str(query)], capture_output=True, text=True)
        (workdir / f"squares_w{w}.out").write_text(proc.stdout + proc.stderr)
        lines = proc.stdout.split("\n")
        answer = lines[0].strip()
        if answer == "sat":
            found = re.findall(r"\((\w) (\d+)\)", " ".join(lines[1:]))
            values = {k: int(v) for k, v in found}
            return LemmaRun("FAIL", time.monotonic() - t0,
                            f"W = {w}: " + ", ".join(f"{k} = {v}" for k, v in values.items()),
                            str(workdir / f"squares_w{w}.out"), w, values)
        if answer != "unsat":
            return LemmaRun("ERROR", time.monotonic() - t0,
                            f"W = {w}: {(proc.stdout + proc.stderr).strip()[:160]}")
    return LemmaRun("PASS", time.monotonic() - t0,
                    f"W = {min(widths)}..{max(widths)}, QF_NIA")


# the formal flow's integer lemmas by task name (halfpoint.flows.formal.LEMMAS)
RUNNERS = {"squares_int": run_squares}
