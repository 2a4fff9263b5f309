# SPDX-License-Identifier: Apache-2.0
"""End to end: G-code -> compensation -> quantisation -> planned PROFILEs -> core
(model and RTL)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from halfpoint.cam.gcode import GcodeError, parse
from halfpoint.cam.quant import quantise
from halfpoint.cam import machine as mc
from halfpoint.cam.planner import estimate_time
from halfpoint.cam.run import run_program, write_trace
from halfpoint.sim.engines import executor

EX = Path(__file__).resolve().parents[2] / "examples"
SIM = mc.load(EX / "machine_sim.toml")


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
    with pytest.raises(GcodeError, match="line 2: an arc in G18 needs axes Z and X to share"):
        quantise(prog.moves, (0.001, 0.001, 0.002))


@pytest.mark.parametrize("prog, radius, machine", [
    ("seed004_test1.ngc", 0.03, None), ("seed004_test2.ngc", 1.0, None),
    ("plate.ngc", None, SIM)])
def test_programs_end_to_end_on_the_model(prog, radius, machine):
    """The shipped programs at their programmed feeds (seconds of machine time: the
    fast model), on the default machine (1 um) and the plate on the coarse one."""
    kw = dict(radius=radius, tools_path=None if radius else str(EX / "tools.tbl"),
              machine=machine)
    m = run_program(str(EX / prog), **kw)
    blu = m.blu[0]
    # lattice path within about one BLU of the compensated path everywhere
    assert m.max_dev_mm <= 1.0 * blu, m.max_dev_mm / blu
    assert m.execution.dry == 0 and m.execution.underrun == 0
    # no faster than the planner's estimate of the compensated path allows (arcs run a
    # little slower), and not much slower
    planned = estimate_time(m.motion.planned)
    assert 0.99 * planned <= m.seconds <= 1.15 * planned


PROGRAM = ("G21 G90 G17 F600000\nG1 X4\nG2 X8 Y0 I2 J0\nG4 P0.0002\nG3 X8 Y4 I0 J2\n"
           "G1 X0 Y4\nG0 X0 Y0\nM2\n")


def test_model_and_rtl_executors_agree_with_a_dwell_and_a_hold(tmp_path):
    f = tmp_path / "p.ngc"
    f.write_text(PROGRAM)
    holds = [(9000, 15000)]
    m = run_program(str(f), executor("model"), machine=SIM, holds=holds)
    r = run_program(str(f), executor("rtl"), machine=SIM, holds=holds)
    assert m.execution == r.execution
    assert m.execution.moves and m.motion.pauses
    write_trace(m, str(tmp_path / "m.csv"))
    write_trace(r, str(tmp_path / "r.csv"))
    assert (tmp_path / "m.csv").read_bytes() == (tmp_path / "r.csv").read_bytes()


def test_trace_format(tmp_path):
    f = tmp_path / "p.ngc"
    f.write_text("G21 G90 F600000\nG1 X0.05 Y0.02 Z-0.03\nM2\n")
    res = run_program(str(f), machine=SIM)
    out = tmp_path / "t.csv"
    write_trace(res, str(out))
    rows = out.read_text().splitlines()
    assert rows[0] == "cycle,x,y,z" and rows[1] == "0,0,0,0"
    body = [[int(v) for v in r.split(",")] for r in rows[2:]]
    assert len(body) == 5 and body[-1][1:] == [5, 2, -3]
    cycles = [r[0] for r in body]
    assert cycles == sorted(cycles) and len(set(cycles)) == len(cycles) and cycles[0] > 0
    # every row one lattice move from the one before: at most 1 BLU per axis
    prev = [0, 0, 0]
    for r in body:
        assert max(abs(a - b) for a, b in zip(r[1:], prev)) == 1
        prev = r[1:]
    assert cycles == res.cycles


def test_run_and_compensate_commands(tmp_path):
    png, csv, prof = tmp_path / "p.png", tmp_path / "t.csv", tmp_path / "s.png"
    p = hp("run", str(EX / "seed004_test2.ngc"), "--radius", "1", "--machine",
           str(EX / "machine_sim.toml"), "--plot", str(png), "--trace", str(csv),
           "--profile", str(prof), "--hold", "100000:200000")
    assert p.returncode == 0, p.stderr
    assert "max deviation of the lattice path from the compensated path" in p.stdout
    assert "estimated run time" in p.stdout and "simulated time:" in p.stdout
    assert "holds 100000:200000" in p.stdout
    assert "lines 5-7: skipped" in p.stderr
    assert png.stat().st_size > 1000 and prof.stat().st_size > 1000
    assert csv.read_text().startswith("cycle,x,y,z\n0,0,0,0\n")
    c = hp("compensate", str(EX / "seed004_test2.ngc"), "--radius", "1")
    assert c.returncode == 0 and c.stdout.startswith("G21 G90 G91.1")
    assert "G41" not in c.stdout and "G42" not in c.stdout
    s = hp("compensate", str(EX / "seed004_test2.ngc"), "--radius", "1", "--strict")
    assert s.returncode != 0 and s.stdout == ""
    assert s.stderr.strip().count("\n") == 0 and "line 5:" in s.stderr


@pytest.mark.parametrize("args, needle", [
    (["--hold", "5"], "--hold 5: needs A:B"),
    (["--hold", "9:3"], "--hold 9:3: needs 0 <= A < B"),
    (["--blu", "0.01"], "--blu and --blu-z are gone"),
    (["--machine", "no/such.toml"], "cannot read"),
])
def test_run_bad_options_one_line(args, needle):
    p = hp("run", str(EX / "plate.ngc"), *args)
    assert p.returncode in (2, 3) and p.stdout == ""
    assert p.stderr.strip().count("\n") == 0 and needle in p.stderr, p.stderr


def test_bad_machine_file_names_the_key(tmp_path):
    bad = tmp_path / "m.toml"
    bad.write_text((EX / "machine_sim.toml").read_text().replace(
        "max_accel_mm_s2 = 10000000.0", "max_accel_mm_s2 = -1"))
    p = hp("run", str(EX / "plate.ngc"), "--machine", str(bad))
    assert p.returncode == 3 and "axis.z.max_accel_mm_s2: must be > 0" in p.stderr


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


@pytest.mark.parametrize("failure, needle", [
    ("busy", "the core is still busy after 7 clocks (the run's bound"),
    ("reject", "rejected a command the host planned: code 7 (profile fields break"),
    ("moves", "the core made 0 moves, the host predicted"),
])
def test_an_engine_failure_is_one_line_not_a_traceback(tmp_path, monkeypatch, capsys,
                                                         failure, needle):
    """The core not running a planned program as planned (still busy past the run's
    bound, a rejected command, another number of moves) is an error naming the program
    and the engine, exit 4, not a traceback (until 2026-11-28 a RuntimeError escaped)."""
    from halfpoint import cli
    from halfpoint.cam.motion import Execution
    from halfpoint.sim import engines

    def broken(items, config, holds, max_clocks):
        if failure == "busy":
            raise RuntimeError("the core is still busy after 7 clocks")
        return Execution(errors=[7] if failure == "reject" else [])

    monkeypatch.setattr(engines, "executor", lambda name: broken)
    prog = tmp_path / "p.ngc"
    prog.write_text("G21 F100\nG1 X1 Y1\nM2\n")
    assert cli.main(["run", str(prog), "--machine", str(EX / "machine_sim.toml")]) == 4
    err = capsys.readouterr().err
    assert err.strip().count("\n") == 0 and needle in err and str(prog) in err, err
    assert "the model engine" in err
