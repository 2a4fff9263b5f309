# SPDX-License-Identifier: Apache-2.0
"""The mutation flow (halfpoint.flows.mutate) on a handful of mutants: all
mutants in one netlist selected by +mutsel, the unmutated design passes, a
known-bad mutant (the STEP pin's flip-flop stuck) is killed, a mutant the
checked-in list proves equivalent survives, and the list is well formed.  The full run
is `make mutate`."""

from __future__ import annotations

import dataclasses
import re

import pytest

from halfpoint.flows import mutate
from halfpoint.sim.env import BUILD

STEPGEN = mutate.TARGETS["halfpoint_stepgen"]


def find(mutations, pattern: str) -> int:
    hits = [m.index for m in mutations if re.search(pattern, m.command)]
    assert hits, f"no mutation matches {pattern!r}: update this test"
    return hits[0]


def test_every_module_has_a_target_and_tests():
    from halfpoint.sim.env import REPO
    for name, t in mutate.TARGETS.items():
        assert (REPO / "rtl" / f"{name}.v").exists()
        assert (REPO / "tb" / name / f"{t.test_module}.py").exists(), name
    assert mutate.DEFAULT_COUNT >= 200


def test_equivalent_list_is_well_formed():
    entries = mutate.load_equivalent()
    for e in entries:
        assert e["module"] in mutate.TARGETS
        assert e["mutation"].startswith("mutate ")
        assert len(e["reason"]) > 20


def test_equivalent_entry_without_reason_is_refused(tmp_path):
    bad = tmp_path / "eq.toml"
    bad.write_text('[[equivalent]]\nmodule = "halfpoint_line"\nparameters = {}\n'
                   'seed = 1\nmutation = "mutate -mode inv"\nreason = " "\n')
    with pytest.raises(ValueError, match="no reason"):
        mutate.load_equivalent(bad)


def test_known_bad_killed_and_equivalent_survives():
    out = BUILD / "test_mutate"
    target = dataclasses.replace(STEPGEN, testcases=("timing_and_model",))
    mutations = mutate.generate(target, mutate.DEFAULT_COUNT, 1, out / target.module)
    assert len(mutations) == mutate.DEFAULT_COUNT
    stuck = find(mutations, r"-mode const[01] .*-port Q .*-wire step_pin ")
    # the first mutant of this run that the checked-in list proves equivalent
    proven = {cmd for cmd, reason in
              mutate.equivalent_for(target, 1, mutate.load_equivalent()).items()
              if reason.startswith("proven")}
    # (one that Yosys's equivalence passes prove too, for --equiv below)
    workdir = out / target.module
    equivalent = next((m.index for m in mutations if m.command in proven
                       and mutate.equiv_check(target, workdir, m.index)[0] == "PASS"), None)
    assert equivalent is not None, "no proven-equivalent stepgen mutant: update the list"
    report = mutate.run_module(target, mutate.DEFAULT_COUNT, 1, "verilator", 1,
                               only=[stuck, equivalent], out=out, entries=[],
                               log=lambda *_: None, equiv=True)
    status = {m["index"]: m for m in report["mutations"]}
    assert status[stuck]["status"] == "KILLED", status[stuck]
    assert "failed" in status[stuck]["detail"]
    assert status[equivalent]["status"] == "SURVIVED", status[equivalent]
    # the same mutant, listed as equivalent, is reported so (and not stale)
    entry = {"module": target.module, "parameters": target.parameters, "seed": 1,
             "mutation": next(m.command for m in mutations if m.index == equivalent),
             "reason": "listed as proven equivalent"}
    known = mutate.equivalent_for(target, 1, [entry])
    assert list(known) == [entry["mutation"]]
    assert report["killed"] == 1 and report["survived"] == 1
    assert 0 < report["seconds_per_mutant"]
    # --equiv proposed the survivor for the list, and only it
    assert status[equivalent]["equivalence_proof"] == "equiv PASS"
    assert status[stuck]["equivalence_proof"] == ""
    proposed = mutate.tomllib.loads((workdir / "equivalent-proposed.toml").read_text())
    assert [e["mutation"] for e in proposed["equivalent"]] == [entry["mutation"]]
    assert proposed["equivalent"][0]["key"] == next(m.key for m in mutations
                                                     if m.index == equivalent)


def test_equiv_check_refuses_what_it_cannot_prove():
    """Yosys's equivalence check (--equiv) leaves a mutant that changes an output
    unproven, naming the signal, and does not judge a mutation of a clock port."""
    target = STEPGEN
    workdir = BUILD / "test_mutate" / "equiv" / target.module
    mutations = mutate.generate(target, mutate.DEFAULT_COUNT, 1, workdir)
    stuck = find(mutations, r"-mode const[01] .*-port Q .*-wire step_pin ")
    status, _, unproven = mutate.equiv_check(target, workdir, stuck)
    assert status == "UNPROVEN" and "step_pin" in unproven, (status, unproven)
    clock = find(mutations, r"-port CLK ")
    assert mutate.equiv_check(target, workdir, clock)[0] == "CLOCK"


def test_core_mutants_come_from_its_own_file():
    """The core target draws its mutants only from the cells of halfpoint_core.v
    (the units have their own targets), on the whole flattened netlist; a list
    drawn from another file is refused as foreign (the gen step alone)."""
    core = mutate.TARGETS["halfpoint_core"]
    assert core.mutate_sources == ("halfpoint_core",)
    out = BUILD / "test_mutate" / "core_sources"
    mutations = mutate.generate(core, mutate.DEFAULT_COUNT, 1, out / core.module)
    assert len(mutations) == mutate.DEFAULT_COUNT
    cells = mutate.cell_sources(out / core.module, core.module)
    assert any(files[0] != "rtl/halfpoint_core.v" for files in cells.values()), \
        "the netlist should hold the units' cells too"
    for m in mutations:
        assert cells[m.option("cell")][0] == "rtl/halfpoint_core.v", m.command
        assert "-src rtl/halfpoint_core.v:" in m.command, m.command
    arc = dataclasses.replace(core, mutate_sources=("halfpoint_arc",))
    drawn = mutate.generate(arc, 20, 1, out / "arc_cells")
    assert all(cells[m.option("cell")][0] == "rtl/halfpoint_arc.v" for m in drawn)
    assert len(mutate.foreign_mutations(core, drawn, out / "arc_cells")) == len(drawn)
    with pytest.raises(ValueError, match="not among its sources"):
        dataclasses.replace(core, mutate_sources=("halfpoint_uart_cmd",)).selection()


def test_tests_option_needs_only():
    """--tests (a subset of the tests) is for re-running survivors (--only) only."""
    with pytest.raises(SystemExit):
        mutate.main(["--tests", "decode_every_field_bit", "halfpoint_core"])


def test_listed_mutations_match_up_to_yosys_numbers():
    """An entry matches its mutation when only Yosys's automatic cell numbers moved
    (another module of the netlist changed), but not when two mutations share the
    key."""
    listed = {"mutate -mode inv -cell $ne$rtl/a.v:3$17 -port A -portbit 2": "r1",
              "mutate -mode inv -cell $procmux$40 -port Y -portbit 0 -src rtl/a.v:9": "r2",
              "mutate -mode inv -cell $procmux$41 -port Y -portbit 0 -src rtl/a.v:9": "r3"}
    generated = ["mutate -mode inv -cell $ne$rtl/a.v:3$19 -port A -portbit 2",
                 "mutate -mode inv -cell $procmux$52 -port Y -portbit 0 -src rtl/a.v:9",
                 "mutate -mode inv -cell $procmux$53 -port Y -portbit 0 -src rtl/a.v:9",
                 "mutate -mode inv -cell $ne$rtl/a.v:3$19 -port A -portbit 3"]
    found = mutate.match_listed(listed, generated)
    assert found == {generated[0]: "r1"}
    exact = mutate.match_listed(listed, list(listed))
    assert exact == listed


@pytest.mark.parametrize("module", sorted(mutate.TARGETS))
def test_equivalents_match_the_current_netlist(module):
    """Every listed equivalent of a target names one of the mutations it draws today
    (the list is keyed by command, up to Yosys's numbers, which shift when another
    module changes): a change of the RTL that leaves an entry stale fails here, not
    only in the next `make mutate`."""
    target = mutate.TARGETS[module]
    mutations = mutate.generate(target, mutate.DEFAULT_COUNT, 1,
                                BUILD / "test_mutate" / "equivalents" / module)
    _, stale = mutate.match_target(target, 1, mutate.load_equivalent(), mutations)
    assert not stale, module


def test_stable_sample_moves_only_where_the_rtl_changes():
    """The stable sample (the core's and the stepgen's) names each mutation by the
    text of its source lines, so lines added elsewhere leave it unchanged; a changed
    line redraws only its own mutants, each replaced by exactly one other."""
    texts = {"a.v": ["module a;", "assign x = p & q;", "assign y = r | s;", "endmodule"]}
    shifted = {"a.v": ["module a;", "// a new comment", "assign x = p & q;",
                       "assign y = r | s;", "endmodule"]}
    changed = {"a.v": ["module a;", "assign x = p ^ q;", "assign y = r | s;", "endmodule"]}

    def commands(first: int, cell: int) -> list[str]:
        out = []
        for line, name in ((first, "and"), (first + 1, "or")):
            for mode in ("inv", "const0", "const1"):
                for bit in range(4):
                    out.append(f"mutate -mode {mode} -module a -cell ${name}$rtl/a.v:{line}"
                               f"${cell + line} -port Y -portbit {bit} "
                               f"-src rtl/a.v:{line}.8-{line}.17")
        return out

    base = mutate.select_stable(commands(2, 10), 4, 1, texts)
    assert len(base) == 4 and len(set(base)) == 4
    # other line numbers and other automatic numbers: the same mutations
    moved = mutate.select_stable(commands(3, 50), 4, 1, shifted)
    assert [mutate.stable_key(c, shifted) for c in moved] == \
        [mutate.stable_key(c, texts) for c in base]
    # one bit per group (mode, cell, port): spread over the cells, not the bits
    groups = {re.sub(r" -portbit \d+", "", c) for c in mutate.select_stable(
        commands(2, 10), 6, 1, texts)}
    assert len(groups) == 6
    # the changed line's mutants are drawn anew; the other line's stay
    again = mutate.select_stable(commands(2, 10), 4, 1, changed)
    kept = [c for c in base if "$or$" in c]
    assert all(c in again for c in kept)
    assert {mutate.stable_key(c, changed) for c in again if "$and$" in c}.isdisjoint(
        {mutate.stable_key(c, texts) for c in base if "$and$" in c})


def test_stable_entries_match_by_key():
    """A stable target's entry matches by its key, wherever its lines now sit, and an
    entry without a key is refused."""
    target = mutate.TARGETS["halfpoint_core"]
    assert target.stable
    texts = {"halfpoint_core.v": ["x", "assign y = a & b;"]}
    cmd = "mutate -mode inv -module m -cell $and$rtl/halfpoint_core.v:2$7 -port Y -portbit 0"
    moved = "mutate -mode inv -module m -cell $and$rtl/halfpoint_core.v:3$9 -port Y -portbit 0"
    key = mutate.stable_key(cmd, texts)
    entry = {"module": target.module, "parameters": target.parameters, "seed": 1,
             "mutation": cmd, "key": key, "reason": "r"}
    now = [mutate.Mutation(1, moved, key=mutate.stable_key(
        moved, {"halfpoint_core.v": ["x", "// new", "assign y = a & b;"]}))]
    assert mutate.match_target(target, 1, [entry], now) == ({moved: "r"}, [])
    gone = [mutate.Mutation(1, moved, key="other")]
    assert mutate.match_target(target, 1, [entry], gone) == ({}, [cmd])
    with pytest.raises(ValueError):
        mutate.match_target(target, 1, [{**entry, "key": ""}], now)
