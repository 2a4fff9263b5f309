# SPDX-License-Identifier: Apache-2.0
"""The ``halfpoint`` command line: output format, errors, engine equality."""

from __future__ import annotations

import subprocess
import sys

import pytest

from halfpoint.spec.arc import arc_points


def hp(*args):
    return subprocess.run([sys.executable, "-m", "halfpoint", *args], capture_output=True, text=True)


def test_arc_prints_points_with_header():
    p = hp("arc", "5", "0", "0", "5", "--ccw")
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0] == "x,y"
    pts = [tuple(map(int, ln.split(","))) for ln in lines[1:]]
    assert pts == arc_points(5, 0, 0, 5, 0)
    assert pts[0] == (5, 0) and pts[-1] == (0, 5)


def test_arc_no_header_and_cw():
    p = hp("arc", "--no-header", "0", "7", "7", "0", "--cw")
    assert p.returncode == 0
    assert p.stdout.splitlines()[0] == "0,7"
    assert p.stdout.splitlines()[-1] == "7,0"


@pytest.mark.parametrize(
    "args, needle",
    [
        (["arc", "0", "0", "1", "1", "--cw"], "radius is zero"),
        (["arc", "10", "0", "0", "13", "--cw"], "off the circle"),
        (["arc", "40000", "0", "40000", "0", "--cw", "--width", "16"], "does not fit"),
        (["arc", "32767", "0", "32767", "0", "--cw", "--width", "16"], "does not fit the coordinate width"),
        (["arc", "1", "2", "3", "--cw"], "arguments"),
        (["arc", "1", "0", "1", "0"], "--cw"),
        (["arc", "1", "0", "x", "0", "--ccw"], "not an integer"),
        (["arc", "1", "0", "1", "0", "--ccw", "--engine", "spice"], "engine"),
        (["arc", "1", "0", "1", "0", "--ccw", "--width", "64"], "width"),
        (["send", "examples/boardsim_part.ngc"], "--port"),
        (["send", "examples/boardsim_part.ngc", "--port", "loop://", "--baud", "0"],
         "--baud and --timeout must be positive"),
        (["send", "examples/boardsim_part.ngc", "--port", "/dev/ttyHALFPOINT_NONE", "--quiet"],
         "cannot open /dev/ttyHALFPOINT_NONE"),
        (["board-sim", "--listen", "10.0.0.1:7000"], "serves 127.0.0.1 only"),
        (["board-sim", "--listen", "127.0.0.1:x"], "needs [127.0.0.1:]PORT"),
    ],
)
def test_bad_input_one_line_reason_nonzero_exit(args, needle):
    p = hp(*args)
    assert p.returncode != 0
    assert p.stdout == ""
    err = p.stderr.strip().splitlines()
    assert len(err) == 1 and needle in err[0], p.stderr


@pytest.mark.parametrize(
    "args",
    [
        ["arc", "5", "0", "5", "0", "--ccw"],
        ["arc", "17", "-9", "-18", "-6", "--cw", "--width", "16"],
        ["arc", "0", "0", "1", "1", "--cw"],
    ],
)
def test_rtl_engine_prints_exactly_what_the_model_prints(args):
    m = hp(*args, "--engine", "model")
    r = hp(*args, "--engine", "rtl")
    assert (m.returncode, m.stdout, m.stderr) == (r.returncode, r.stdout, r.stderr)


# --- halfpoint segments ---------------------------------------------------

EXAMPLE = "examples/square_with_arcs.jsonl"


def test_segments_example_model_and_rtl_identical(tmp_path):
    # the shipped example still says "rate" (the lead updates it): run it with "speed"
    f = tmp_path / "square.jsonl"
    f.write_text(open(EXAMPLE, encoding="utf-8").read().replace('"rate"', '"speed"'))
    m = hp("segments", str(f))
    r = hp("segments", str(f), "--engine", "rtl")
    assert m.returncode == 0 and r.returncode == 0, m.stderr + r.stderr
    assert m.stdout == r.stdout
    rows = [tuple(map(int, ln.split(","))) for ln in m.stdout.splitlines()]
    assert rows[0] == (0, 0, 0) and rows[-1] == (0, 0, 0)     # the program is closed
    # every move changes each axis by at most one BLU
    assert all(max(abs(a - b) for a, b in zip(p, q)) == 1 for p, q in zip(rows, rows[1:]))


def test_segments_random_file_model_and_rtl_identical(tmp_path):
    import json
    import math
    import random

    from halfpoint.spec.arc import lattice_point_near

    rng = random.Random(4)
    lines = []
    for _ in range(40):
        if rng.random() < 0.5:
            lines.append({"op": "line", "delta": [rng.randint(-9, 9) for _ in range(3)],
                          "speed": round(rng.uniform(0.05, 0.6), 3),
                          "accel": rng.choice((1e-4, 2e-4))})
        else:
            i, j = rng.randint(-12, 12), rng.randint(-12, 12)
            if i == 0 and j == 0:
                i = 5
            xe, ye = lattice_point_near(i * i + j * j, rng.uniform(0, 2 * math.pi))
            lines.append({"op": "arc", "dir": rng.choice(("cw", "ccw")),
                          "center": [i, j], "end": [xe + i, ye + j]})
    f = tmp_path / "prog.jsonl"
    f.write_text("\n".join(json.dumps(x) for x in lines) + "\n")
    m = hp("segments", str(f))
    r = hp("segments", str(f), "--engine", "rtl")
    assert m.returncode == 0 and m.stdout == r.stdout


@pytest.mark.parametrize(
    "text, needle",
    [
        ('{"op": "line", "delta": [1, 2, 3]}\n{"op": "line", "delta": [1, 2}', "line 2: not valid JSON"),
        ('{"op": "move", "delta": [1]}', 'line 1: "op" must be'),
        ('\n# comment\n{"op": "line"}', 'line 3: "delta" must be a list'),
        ('{"op": "line", "delta": [1, 2, 3, 4]}', "line 1: \"delta\" must be a list of 1..3"),
        ('{"op": "line", "delta": [1.5, 2, 3]}', "line 1: \"delta\" must hold integers"),
        ('{"op": "line", "delta": [1], "feed": 3}', "line 1: unknown key 'feed'"),
        ('{"op": "line", "delta": [1], "speed": 3}', 'line 1: "speed" must be a number of BLU'),
        ('{"op": "line", "delta": [1], "accel": 0.1}', 'line 1: "accel" must be a number'),
        ('{"op": "line", "delta": [1], "speed": 1e-12}', 'line 1: "speed" 1e-12 is below'),
        ('{"op": "line", "delta": [0, 0]}', "line 1: a line must move"),
        ('{"op": "arc", "dir": "cw", "center": [10, 0], "end": [13, 0]}', "line 1: arc rejected: end point is off the circle"),
        ('{"op": "arc", "dir": "up", "center": [10, 0], "end": [20, 0]}', 'line 1: "dir" must be'),
        ('{"op": "arc", "dir": "cw", "center": [0, 0], "end": [1, 1]}', "line 1: arc rejected: radius is zero"),
        ('{"op": "line", "delta": [1], "rate": 1}', 'line 1: "rate" is gone: give "speed"'),
        ('[1, 2]', "line 1: a segment must be a JSON object"),
    ],
)
def test_segments_bad_file_names_the_line(tmp_path, text, needle):
    f = tmp_path / "bad.jsonl"
    f.write_text(text + "\n")
    p = hp("segments", str(f))
    assert p.returncode != 0 and p.stdout == ""
    err = p.stderr.strip().splitlines()
    assert len(err) == 1 and needle in err[0], p.stderr


def test_segments_ramp_at_the_files_speed_and_acceleration(tmp_path):
    """A long line at speed 0.5: the core's pace starts slow, reaches 0.5 BLU per clock
    and slows down again (the trace's cycles, through the model executor)."""
    from halfpoint.cam.motion import run_model
    from halfpoint.cam.segments import CONFIG, parse_segments, segment_items

    segs = parse_segments('{"op": "line", "delta": [3000, 0, 0], "speed": 0.5}\n')
    run = run_model(segment_items(segs), CONFIG)
    t = [c for c, _ in run.moves]
    assert len(t) == 3000
    first, middle, last = t[10] - t[0], t[1510] - t[1500], t[-1] - t[-11]
    assert middle == pytest.approx(20, abs=1)       # 10 moves at 0.5 BLU per clock
    assert first > 3 * middle and last > 3 * middle


def test_segments_missing_file():
    p = hp("segments", "no/such/file.jsonl")
    assert p.returncode == 2 and "cannot read" in p.stderr


def test_program_messages_are_printed_with_their_line(tmp_path):
    """(DEBUG, and (MSG, of the executed program reach stderr in order, naming the line;
    the expressions behind them reach the output."""
    f = tmp_path / "p.ngc"
    f.write_text("#<r> = [2 * 3]\n(DEBUG, r is #<r>)\nF100 G1 X#<r>\n(MSG, done)\nM2\n")
    r = hp("compensate", str(f))
    assert r.returncode == 0, r.stderr
    assert f"{f}: line 2: DEBUG: r is 6" in r.stderr
    assert r.stderr.index("DEBUG") < r.stderr.index("line 4: MSG: done")
    assert "X6" in r.stdout


# --- halfpoint run: model and RTL --------------------------------------------

RUN_PROGRAM = ("G21 G90 G17 F600000\nG1 X3\nG2 X7 Y0 I2 J0\nG4 P0.0002\n"
               "G3 X7 Y4 I0 J2\nG1 X0 Y4\nG0 X0 Y0\nM2\n")


def test_run_model_and_rtl_print_and_write_exactly_the_same(tmp_path):
    """A short program with lines, arcs, a dwell and a hold on the coarse simulation
    machine: both engines print the same text and write the same trace file."""
    import os

    prog = tmp_path / "p.ngc"
    prog.write_text(RUN_PROGRAM)
    machine = os.path.abspath("examples/machine_sim.toml")
    outs = {}
    for engine in ("model", "rtl"):
        d = tmp_path / engine
        d.mkdir()
        p = subprocess.run([sys.executable, "-m", "halfpoint", "run", str(prog), "--machine",
                            machine, "--engine", engine, "--trace", "trace.csv", "--hold",
                            "8000:14000"], capture_output=True, text=True, cwd=d)
        assert p.returncode == 0, p.stderr
        outs[engine] = (p.stdout, p.stderr, (d / "trace.csv").read_text())
    assert outs["model"] == outs["rtl"]
    text, _, trace = outs["model"]
    assert "dwells: 1" in text and "holds 8000:14000" in text
    rows = trace.splitlines()
    assert rows[0] == "cycle,x,y,z" and rows[1] == "0,0,0,0"
    cycles = [int(r.split(",")[0]) for r in rows[2:]]
    # no move while held (the hold starts while moving: the core ramps down first)
    held = [c for c in cycles if 8000 + 4096 <= c < 14000]
    assert held == [], held[:5]
