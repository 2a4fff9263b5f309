# SPDX-License-Identifier: Apache-2.0
"""End to end: G-code -> compensation -> quantisation -> core (model and RTL)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from halfpoint.cam.gcode import GcodeError, parse
from halfpoint.cam.quant import quantise
from halfpoint.cam.run import run_program
from halfpoint.sim.engines import core_runner

EX = Path(__file__).resolve().parents[2] / "examples"


def hp(*args):
    return subprocess.run([sys.executable, "-m", "halfpoint", *args], capture_output=True, text=True)


def test_quantised_segments_chain_exactly_on_the_lattice():
    prog = parse("G21 F100\nG1 X1.0004 Y2.0006\nG2 X3.0004 Y2.0006 I1 J0\nG1 X0.12345 Y-0.0004 Z0.3\nM2")
    q = quantise(prog.moves, (0.001,) * 3)
    # the last point is the programmed end rounded to the lattice, whatever the arc did
    assert q.end == (123, 0, 300)
    assert sum(q.moves_per_cmd) > 0
    from halfpoint.spec import encoding as enc
    first = enc.decode(q.cmds[0])
    assert first["opcode"] == enc.OP_LINE and first["deltas"][:3] == [1000, 2001, 0]
    arc = enc.decode(q.cmds[1])
    assert arc["opcode"] == enc.OP_ARC_CW and (arc["i"], arc["j"]) == (1000, 0)


def test_arc_with_tiny_sagitta_runs_as_its_chord():
    # R 1 mm, chord 0.02 mm: sagitta 0.05 um, under a quarter BLU
    prog = parse("F100\nG1 X1\nG3 X0.99980 Y0.02 I-1 J0\nM2")
    q = quantise(prog.moves, (0.001,) * 3)
    from halfpoint.spec import encoding as enc
    assert [enc.decode(c)["opcode"] for c in q.cmds] == [enc.OP_LINE, enc.OP_LINE]
    assert q.end == (1000, 20, 0)


def test_quantise_range_and_plane_errors_name_the_line():
    prog = parse("F100\nG1 X3000\nM2")
    with pytest.raises(GcodeError, match="line 2: end point outside the core's 32-bit range"):
        quantise(prog.moves, (1e-6,) * 3)
    prog = parse("F100\nG18 G2 X2 Z0 I1 K0\nM2")
    with pytest.raises(GcodeError, match="line 2: the core interpolates arcs in the XY plane"):
        quantise(prog.moves)


@pytest.mark.parametrize("prog, radius", [("seed004_test1.ngc", 0.03), ("seed004_test2.ngc", 1.0),
                                          ("plate.ngc", None)])
def test_programs_end_to_end_model_and_rtl_agree(prog, radius):
    kw = dict(radius=radius, tools_path=None if radius else str(EX / "tools.tbl"),
              blu=(0.005,) * 3 if prog == "plate.ngc" else (0.001,) * 3)
    m = run_program(str(EX / prog), core_runner("model"), **kw)
    r = run_program(str(EX / prog), core_runner("rtl"), **kw)
    assert m.lattice == r.lattice
    assert m.max_dev_mm == r.max_dev_mm
    blu = kw["blu"][0]
    # lattice path within about one BLU of the compensated path everywhere
    assert m.max_dev_mm <= 1.0 * blu, m.max_dev_mm / blu


def test_run_and_compensate_commands(tmp_path):
    png, csv = tmp_path / "p.png", tmp_path / "t.csv"
    p = hp("run", str(EX / "seed004_test2.ngc"), "--radius", "1", "--engine", "rtl",
           "--plot", str(png), "--trace", str(csv))
    assert p.returncode == 0, p.stderr
    assert "max deviation of the lattice path from the compensated path" in p.stdout
    assert "lines 5-7: skipped" in p.stderr
    assert png.stat().st_size > 1000 and csv.read_text().startswith("move,x_blu")
    c = hp("compensate", str(EX / "seed004_test2.ngc"), "--radius", "1")
    assert c.returncode == 0 and c.stdout.startswith("G21 G90 G91.1")
    assert "G41" not in c.stdout and "G42" not in c.stdout
    s = hp("compensate", str(EX / "seed004_test2.ngc"), "--radius", "1", "--strict")
    assert s.returncode != 0 and s.stdout == ""
    assert s.stderr.strip().count("\n") == 0 and "line 5:" in s.stderr


@pytest.mark.parametrize(
    "text, needle",
    [
        ("G1 X1\nM2", "line 1: no feed rate set"),
        ("F10\nG41 D3 G1 X10\nX20\nG40 X30\nM2", "line 2: tool 3 is not in the tool table"),
        ("F10\nG1 X1 Q4\nM2", "line 2: unsupported word Q4"),
    ],
)
def test_run_bad_program_one_line_naming_the_line(tmp_path, text, needle):
    f = tmp_path / "bad.ngc"
    f.write_text(text + "\n")
    p = hp("run", str(f))
    assert p.returncode != 0 and p.stdout == ""
    assert p.stderr.strip().count("\n") == 0 and needle in p.stderr, p.stderr


def test_the_tool_table_beside_the_program_is_the_default(tmp_path):
    """Without --tools or --radius, a tools.tbl beside the program is read (and said);
    --tools names another; with neither, G41 D1 is an error naming the line."""
    prog = tmp_path / "p.ngc"
    prog.write_text("G21 F100\nG0 X-5\nG41 D1 G1 X0 Y0\nX10\nG40 X15\nM2\n")
    r = hp("compensate", str(prog))
    assert r.returncode == 3 and "line 3" in r.stderr
    (tmp_path / "tools.tbl").write_text("T1 P1 D2.0\n")
    r = hp("compensate", str(prog))
    assert r.returncode == 0, r.stderr
    assert f"note: tool table {tmp_path / 'tools.tbl'} (beside the program" in r.stderr
    assert "Y1" in r.stdout                      # the 1 mm radius, left of +X
    other = tmp_path / "other.tbl"
    other.write_text("T1 P1 D4.0\n")
    r = hp("compensate", str(prog), "--tools", str(other))
    assert r.returncode == 0 and "Y2" in r.stdout and "beside the program" not in r.stderr
