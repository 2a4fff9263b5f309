# SPDX-License-Identifier: Apache-2.0
"""The formal flow (halfpoint.flows.formal): the quick proofs pass, with tools
from the venv only, and a broken step generator (steplen off by one, made
from the real RTL by a textual edit) fails the proof with a VCD trace, as
do a line unit that takes a command while it holds one (one is lost), a
profile stage whose speed rises by twice its acceleration, a core that
takes a beat while its queue is full and an arc unit that gives an end off
the circle the wrong reject code; a profile stage that pops at rest under
hold breaks the core's composed proof, and an arc squarer that adds a wrong
row breaks its link to the ghost rows at W = 8 and at W = 32.
The full set (all tasks, every mutant) is `make formal`."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

from halfpoint.flows import formal
from halfpoint.sim.env import BUILD, REPO


def test_tools_come_from_the_venv():
    sby = formal.setup_formal_env(BUILD / "test_formal")
    vbin = formal.venv_bin()
    assert sby == vbin / "yowasp-sby"
    for name in formal.TOOLS:
        found = Path(shutil.which(name))
        assert found.parent == BUILD / "test_formal" / "bin", found
    assert Path(shutil.which(formal.SOLVER)).parent == vbin
    out = subprocess.run(["yosys", "-V"], capture_output=True, text=True, env=os.environ)
    assert out.returncode == 0 and "Yosys" in out.stdout


def test_quick_tasks_are_tagged():
    tasks = formal.sby_tasks(formal.FORMAL / "halfpoint_stepgen.sby")
    quick = {t for t, tags in tasks.items() if "quick" in tags}
    assert {"stable_tw4", "live_tw4"} <= quick
    proofs, mutants = formal.plan(True, [])
    assert {name for _, _, name in proofs} >= {"halfpoint_stepgen:stable_tw4",
                                               "halfpoint_stepgen:live_tw4"}
    assert mutants == []
    # a design named with --quick: its quick tasks only; a task named: that task
    proofs, _ = formal.plan(True, ["halfpoint_stepgen", "halfpoint_arc:squarer_w32"])
    names = {name for _, _, name in proofs}
    assert "halfpoint_arc:squarer_w32" in names
    assert {n for n in names if n.startswith("halfpoint_stepgen:")} == \
        {f"halfpoint_stepgen:{t}" for t in quick}
    assert len(formal.plan(False, ["halfpoint_stepgen"])[0]) == len(tasks)
    # a mutants-only task (a bounded check the real design is proven by another
    # task) is not planned as a proof, but the mutants that name it run it
    assert "mutants_only" in formal.sby_tasks(formal.FORMAL / "halfpoint_core.sby")["steps_na2"]
    proofs, mutants = formal.plan(False, [])
    assert "halfpoint_core:steps_na2" not in {name for _, _, name in proofs}
    assert any("steps_na2" in m.tasks for m in mutants)


def test_quick_proofs_pass():
    out = BUILD / "test_formal"
    rc = formal.main(["--quick", "--jobs", "1", "--out", str(out)])
    assert rc == 0
    import json
    rows = json.loads((out / "report.json").read_text())
    for design in ("halfpoint_stepgen", "halfpoint_line", "halfpoint_arc", "halfpoint_profile",
                   "halfpoint_core"):
        mine = [r for r in rows if r["name"].startswith(f"{design}:")]
        assert mine and all(r["status"] == "PASS" and r["mode"] == "prove" for r in mine), \
            design


def test_mutant_edit_follows_the_rtl(tmp_path):
    for m in formal.MUTANTS:
        assert (REPO / m.path).read_text().count(m.old) == 1, m.name
        tasks = formal.sby_tasks(formal.FORMAL / f"{m.design}.sby")
        assert set(m.tasks) <= set(tasks), m.name
    rtl = (REPO / "rtl" / "halfpoint_stepgen.v").read_text()
    m = next(m for m in formal.MUTANTS if m.name == "stepgen_steplen_plus1")
    sby = formal.make_mutant(m, tmp_path / "mut")
    text = (tmp_path / "mut" / m.path).read_text()
    assert text == rtl.replace(m.old, m.new) and text != rtl
    assert sby.exists()


def test_steplen_off_by_one_fails_with_trace(tmp_path):
    m = next(m for m in formal.MUTANTS if m.name == "stepgen_steplen_plus1")
    results = formal.run_mutant(m, tmp_path / "mut")
    by_task = {r.name.rsplit(":", 1)[1]: r for r in results}
    for task in ("stable_tw4", "contract_tw4"):
        r = by_task[task]
        assert r.status == "FAIL", (task, r)
        assert r.traces and all(Path(t).exists() and Path(t).suffix == ".vcd"
                                for t in r.traces), r
        assert "$var" in Path(r.traces[0]).read_text()
    # the pin-level contract alone catches it at the steplen rule
    assert any(f.startswith(("a_steplen", "p_steplen")) for f in by_task["contract_tw4"].failed)


def test_line_lost_command_fails_with_trace(tmp_path):
    m = next(m for m in formal.MUTANTS if m.name == "line_ready_while_busy")
    (r,) = formal.run_mutant(m, tmp_path / "mut", tasks=("prove_na2_w8",))
    assert r.status == "FAIL", r
    assert r.traces and Path(r.traces[0]).exists()
    assert any(f.startswith("a_ready_idle") for f in r.failed), r.failed


def test_profile_double_acceleration_fails_with_trace(tmp_path):
    """A profile stage whose speed rises by twice accel breaks the acceleration limit."""
    m = next(m for m in formal.MUTANTS if m.name == "profile_double_accel")
    (r,) = formal.run_mutant(m, tmp_path / "mut")
    assert r.status == "FAIL", r
    assert r.traces and Path(r.traces[0]).exists()
    assert "a_rise_by_accel" in " ".join(r.failed), r.failed


def test_core_push_when_full_fails_with_trace(tmp_path):
    """A core whose tready ignores a full queue overwrites a queued command:
    the bounded check of the core finds the push without room."""
    m = next(m for m in formal.MUTANTS if m.name == "core_push_when_full")
    (r,) = formal.run_mutant(m, tmp_path / "mut")
    assert r.status == "FAIL", r
    assert r.traces and Path(r.traces[0]).exists()
    assert "a_push_room" in " ".join(r.failed), r.failed


def test_arc_square_lemmas_follow_the_rtl(tmp_path):
    """The free squares' lemmas (range_sq) restate the arc's u_n and v_n by cases:
    an RTL change they do not follow (v' = 1 after a crossing, the lemma still
    squaring 0) fails sqclaims_w8 on the claimed value, with a trace."""
    tasks = formal.sby_tasks(formal.FORMAL / "halfpoint_arc.sby")
    assert "quick" in tasks["sqclaims_w8"] and "quick" in tasks["sqclaims_w32"]
    m = next(m for m in formal.MUTANTS if m.name == "arc_crossing_v_one")
    (r,) = formal.run_mutant(m, tmp_path / "mut")
    assert r.status == "FAIL", r
    assert r.traces and Path(r.traces[0]).exists()
    assert "f_claim_v" in " ".join(r.failed), r.failed


def test_line_quick_task_is_the_induction_proof():
    """make test proves the line unit's properties, "ends" included, by induction."""
    tasks = formal.sby_tasks(formal.FORMAL / "halfpoint_line.sby")
    env = formal.setup_formal_env(BUILD / "test_formal")
    for task in ("prove_na2_w8", "endsp_na2_w8"):
        assert "quick" in tasks[task], task
        opts = formal.task_options(env, formal.FORMAL / "halfpoint_line.sby", task)
        assert opts["mode"] == "prove", task
    assert "endsp" in tasks["endsp_na2_w8"]
    assert "endsp: read -define F_ENDS" in (formal.FORMAL / "halfpoint_line.sby").read_text()


def test_a_yosys_warning_fails_the_proof(tmp_path):
    """A design that Yosys reads with a warning (here an implicitly declared net in a
    file without `default_nettype none`) is an ERROR, though its property holds."""
    (tmp_path / "warned.v").write_text(
        "module warned(input wire clk, input wire a, output wire b);\n"
        "    assign implicit = a;\n"
        "    assign b = implicit;\n"
        "`ifdef FORMAL\n"
        "    always @(*) assert (b == a);\n"
        "`endif\n"
        "endmodule\n")
    sby = tmp_path / "warned.sby"
    sby.write_text("[tasks]\nprove\n\n[options]\nmode prove\ndepth 2\n\n"
                   f"[engines]\nsmtbmc {formal.SOLVER.removesuffix('-smt2')}\n\n"
                   "[script]\nread -formal warned.v\nprep -top warned\n\n"
                   "[files]\nwarned.v\n")
    sbyexe = formal.setup_formal_env(BUILD / "test_formal")
    res = formal.run_task(sbyexe, sby, "prove", tmp_path / "work" / "warned", "warned:prove")
    assert (tmp_path / "work" / "warned_prove" / "PASS").exists(), res   # sby: it holds
    assert res.status == "ERROR" and "implicitly declared" in res.note, res
    assert not res.ok


def test_arc_termination_mutant_breaks_the_proof(tmp_path):
    """An arc that a crossing does not arm could circle for ever: the termination
    proof (ends_w8) no longer closes, on the invariant that ties armed to the
    crossings; a NOPROOF mutant is as expected only when its proof does not pass."""
    m = next(m for m in formal.MUTANTS if m.name == "arc_never_armed")
    assert m.expect == "NOPROOF"
    (r,) = formal.run_mutant(m, tmp_path / "mut")
    assert r.status in ("FAIL", "UNKNOWN") and r.ok, r
    assert any(f.startswith("i_e_armed") for f in r.failed), r.failed
    assert not formal.Result("x", status="PASS", expect="NOPROOF").ok
    assert not formal.Result("x", status="UNKNOWN", expect="FAIL").ok


def test_arc_wrong_reject_code_fails_with_trace(tmp_path):
    """An end off the circle rejected with code 2 instead of 3: the bounded
    check of the reject codes (codesbmc_w8, the codes against the squarer's
    sums) fails with a trace on a_reject_code."""
    m = next(m for m in formal.MUTANTS if m.name == "arc_code_for_too_big")
    (r,) = formal.run_mutant(m, tmp_path / "mut")
    assert r.status == "FAIL" and r.ok and r.traces, r
    assert any(f.startswith("a_reject_code") for f in r.failed), r.failed


def test_core_pop_held_at_rest_breaks_the_composed_proof(tmp_path):
    """The profile stage popping a move the credit covers at rest under hold (its
    behaviour before 2026-11-25): the core's composed proof (compose_na2, the profile
    stage read with its properties) no longer closes, on the profile stage's
    a_hold_rest_no_pop or the core's a_rest_kept."""
    m = next(m for m in formal.MUTANTS if m.name == "core_pops_held_at_rest")
    assert m.expect == "NOPROOF" and m.tasks == ("compose_na2",)
    (r,) = formal.run_mutant(m, tmp_path / "mut")
    assert r.status in ("FAIL", "UNKNOWN") and r.ok, r
    assert any(f.startswith(("a_hold_rest_no_pop", "a_rest_kept")) for f in r.failed), r.failed


def test_core_arc_not_flushed_breaks_the_composed_proof(tmp_path):
    """A core that does not flush the arc unit (its abort_now tied low) leaves the
    arc's command to run after the queue was dropped.  With the arc unit's contract
    assumed, compose_na2 passed on it; read with its properties (since 2026-11-25)
    the arc unit's contract is an obligation, and the proof no longer closes, on
    the invariant that ties the arc unit's slot to the command in flight."""
    m = next(m for m in formal.MUTANTS if m.name == "core_arc_not_flushed")
    assert m.expect == "NOPROOF" and m.tasks == ("compose_na2",)
    (r,) = formal.run_mutant(m, tmp_path / "mut")
    assert r.status in ("FAIL", "UNKNOWN") and r.ok, r
    assert any(f.startswith(("i_arc_in_flight", "arc_handed", "arc_reject_unvalidated"))
               for f in r.failed), r.failed


def test_assertion_label_through_a_macro():
    """A failed assertion written through a macro (`arc_handed: `F_ARC_CONTRACT(...)`)
    is reported by its label, as a plain `label: assert` is."""
    src = REPO / "rtl" / "halfpoint_core.v"
    lines = src.read_text().splitlines()
    for label in ("arc_handed", "arc_reject_unvalidated", "i_arc_in_flight"):
        line = next(k for k, text in enumerate(lines, 1) if f"{label}:" in text)
        assert formal.assertion_label(src, line) == label


def test_arc_squarer_link_breaks_at_every_width(tmp_path):
    """The squarer's link to the ghost rows (squarer_w*, in make test at W = 8 and
    16, at W = 32 in make formal) cannot close on a squarer that adds |xs| where
    |ys| is due, at W = 8 nor at the core's W = 32: it fails on the link's own
    assertions (sq_sum, or the per-count invariant of g_f_link)."""
    tasks = formal.sby_tasks(formal.FORMAL / "halfpoint_arc.sby")
    assert "quick" in tasks["squarer_w8"] and "quick" in tasks["squarer_w16"]
    assert "wide" in tasks["squarer_w32"]
    rtl = (REPO / "rtl" / "halfpoint_arc.v").read_text().splitlines()
    link = [i + 1 for i, line in enumerate(rtl)
            if "assert({3'b000, radius_square_q} == (f_axs >> f_lk)" in line]
    assert len(link) == 1
    m = next(m for m in formal.MUTANTS if m.name == "arc_square_wrong_row")
    assert m.expect == "NOPROOF" and m.tasks == ("squarer_w8", "squarer_w32")
    results = formal.run_mutant(m, tmp_path / "mut")
    assert len(results) == 2
    for r in results:
        assert r.status in ("FAIL", "UNKNOWN") and r.ok, r
        assert r.failed and all(f.startswith("sq_") or f"halfpoint_arc.v:{link[0]}" in f
                                for f in r.failed), r.failed


def test_arc_squares_integer_lemma(tmp_path):
    """The squarer ghosts' arithmetic at every width the arc runs at (8..32): the
    rows of binary multiplication, added as the monitor adds them in F_PW bits,
    never wrap and end as a^2 + b^2 (unsat in QF_NIA); the lemma with the row of
    bit k shifted by k + 1 is sat, and the solver's a and b do break it; a ghost
    in the RTL that no longer reads as the lemma restates it is an ERROR."""
    from halfpoint.flows import lemmas
    solver = formal.venv_bin() / formal.SOLVER
    assert lemmas.ghost_text_follows() == []
    good = lemmas.run_squares(solver, tmp_path / "good")
    assert good.status == "PASS", good
    assert sorted(p.name for p in (tmp_path / "good").glob("*.smt2")) == \
        sorted(f"squares_w{w}.smt2" for w in range(8, 33))
    bad = lemmas.run_squares(solver, tmp_path / "bad", wrong_row=True, widths=[8, 32])
    assert bad.status == "FAIL" and Path(bad.trace).exists(), bad
    w, a, b = bad.width, bad.values["a"], bad.values["b"]
    assert a < 2 ** w and b < 2 ** w

    def rows(x, shift):
        return sum(((x >> k) & 1) * (x << (k + shift)) for k in range(w))

    assert rows(a, 0) + rows(b, 0) == a * a + b * b           # the true recurrence
    assert rows(a, 1) + rows(b, 1) != a * a + b * b           # broken for these values
    # the restatement is checked against the RTL's text
    rtl = tmp_path / "halfpoint_arc.v"
    rtl.write_text(lemmas.ARC_RTL.read_text().replace(
        "f_gr2 <= f_gr2 + f_row_xs + f_row_ys;", "f_gr2 <= f_gr2 + f_row_ys + f_row_xs;"))
    assert lemmas.ghost_text_follows(rtl) == ["f_gr2 <= f_gr2 + f_row_xs + f_row_ys;"]
    proofs, mutants = formal.plan(True, [])
    assert "halfpoint_arc:squares_int" in {name for _, _, name in proofs}
    assert "arc_squares_int_wrong_row" in {m.name for m in formal.plan(False, [])[1]}
    assert {lemma.task for lemma in formal.LEMMAS} <= set(lemmas.RUNNERS)
