# SPDX-License-Identifier: Apache-2.0
"""Laser G-code written by others, through the host in laser mode (grbl's ``$32``, the
machine file's ``[spindle] laser_mode``): the fixtures in tb/cam/public_laser/ (sources and
licences in its README.txt: MeerK40t's GRBL driver, a Python test-pattern generator,
image2gcode rasters, a hand-written file with '#' comments).

What grbl's laser mode promises (its doc/markdown/laser_mode.md) and these check on every
fixture: the motion stops only where grbl stops too (an M3/M4/M5 or M7/M8/M9 change, a
dwell, the end, or a corner the path cannot take at speed), never at an S word or a G0;
each segment's PROFILE carries the power of its line, S over the machine's S of 100 %
(grbl's ``$30``) on a cut and 0 on a G0 or with the laser off, read here independently of
the parser; M4 is dynamic power and M3 constant; and a raster with an S on every G1 runs
the same moves at the same cycles as without its S words.  All on the coarse simulation
machine, so the runs take well under a second each.
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest

from halfpoint.cam import machine as mc
from halfpoint.cam.gcode import GcodeError
from halfpoint.cam.motion import Pause, build_motion
from halfpoint.cam.planner import OutputChange
from halfpoint.cam.quant import quantise
from halfpoint.cam.run import load_program, plan_items_compensated, run_program
from halfpoint.spec import encoding as enc

HERE = Path(__file__).resolve().parent / "public_laser"
EX = Path(__file__).resolve().parents[2] / "examples"
SIM = mc.load(EX / "machine_sim.toml")
FULL = enc.OUTPUT_POWER_FULL
MOTION_OPS = (enc.OP_LINE, enc.OP_ARC_CW, enc.OP_ARC_CCW)

# each fixture that runs, with the S of a 100 % duty its generator was set up for
RUNNABLE = [
    ("meerk40t_rect.gcode", 1000.0),
    ("speed_power_excerpt.nc", 1000.0),
    ("image2gcode_m4.gc", 1000.0),
    ("image2gcode_m3_overscan.gc", 255.0),
]


def _laser(s_max: float) -> mc.Machine:
    return replace(SIM, laser_mode=True, spindle_max=s_max)


def _words(line: str) -> list[tuple[str, float]]:
    """The words of a line, comments ( ) and ';' dropped, upper case."""
    line = re.sub(r"\([^)]*\)", " ", line).split(";")[0].upper()
    return [(a, float(b)) for a, b in re.findall(r"([A-Z])\s*([-+]?[0-9]*\.?[0-9]+)", line)]


def _reading(text: str, s_max: float) -> dict:
    """An independent reading of a grbl-style laser program: for each line that moves,
    (kind, the power its segment should carry, the laser state M3 / M4 / M5).  The M words
    of a line act before its motion (LinuxCNC's and grbl's order of execution)."""
    out, motion, s, state = {}, 0, 0.0, "M5"
    for n, line in enumerate(text.splitlines(), 1):
        words = _words(line)
        moves = any(a in "XYZIJ" for a, _ in words)
        for a, v in words:
            if a == "G" and v in (0, 1, 2, 3):
                motion = int(v)
            elif a == "M" and v in (3, 4):
                state = f"M{int(v)}"
            elif a == "M" and v in (2, 5, 30):
                state = "M5"
            elif a == "S":
                s = v
            elif a == "G" and v in (4, 28, 30, 53, 92):
                moves = False
        if moves:
            on = motion != 0 and state != "M5" and s > 0
            power = round(FULL * min(s, s_max) / s_max) if on else 0
            out[n] = ("rapid" if motion == 0 else "cut", power, state)
    return out


def _plan(path: Path, machine: mc.Machine, events: bool = True):
    """The plan items and the motion plan of a program (without a machine for the items:
    the dwells only, no output or power change, the path's own stops)."""
    prog, comp, _ = load_program(str(path), machine=machine)
    items = plan_items_compensated(prog, comp.moves, machine if events else None)
    return items, build_motion(quantise(comp.moves, machine.blu), items, machine)


def _stream(mp) -> list:
    """The command stream: ("out", fields) for an OUTPUT, ("pause",) for a dwell, and
    ("move", line number, its PROFILE's fields, the command's fields) per motion command."""
    out, profile, k = [], None, 0
    for it in mp.items:
        if isinstance(it, Pause):
            out.append(("pause",))
            continue
        d = enc.decode(it)
        if d["opcode"] == enc.OP_PROFILE:
            profile = d
        elif d["opcode"] == enc.OP_OUTPUT:
            out.append(("out", d))
        elif d["opcode"] in MOTION_OPS:
            out.append(("move", mp.commands[k].move.lineno, profile, d))
            k += 1
    assert k == len(mp.commands)
    return out


def _stops(stream) -> list[tuple[int, str]]:
    """(line, cause) of every motion command that ends at rest: cause "out", "pause" or
    "end" by what follows it, else "corner" (a planned exit speed of 0)."""
    stops = []
    for i, x in enumerate(stream):
        if x[0] != "move" or (x[3]["cont"] and x[2]["v_exit"]):
            continue
        nxt = stream[i + 1][0] if i + 1 < len(stream) else "end"
        stops.append((x[1], "corner" if nxt == "move" else nxt))
    return stops


@pytest.mark.parametrize("name, s_max", RUNNABLE)
def test_the_motion_stops_only_where_grbl_stops(name, s_max):
    path = HERE / name
    lines = path.read_text().splitlines()
    machine = _laser(s_max)
    items, mp = _plan(path, machine)
    stream = _stream(mp)
    # every OUTPUT (a stop) comes from a line with an M3/M4/M5 or M7/M8/M9 word, never
    # from an S word or a G0
    outs = [it for it in items if isinstance(it, OutputChange)]
    assert [x[1]["enable"] for x in stream if x[0] == "out"] == [o.settings[1] for o in outs]
    for o in outs:
        ms = {int(v) for a, v in _words(lines[o.lineno - 1]) if a == "M"}
        assert ms & {3, 4, 5, 7, 8, 9}, (o.lineno, lines[o.lineno - 1])
    # the other stops are the path's own: the same program planned without its outputs
    # and powers stops there too
    own = {ln for ln, _ in _stops(_stream(_plan(path, machine, events=False)[1]))}
    for ln, cause in _stops(stream):
        assert cause in ("out", "pause", "end") or ln in own, (ln, cause, lines[ln - 1])


@pytest.mark.parametrize("name, s_max", RUNNABLE)
def test_each_segment_carries_the_power_of_its_line(name, s_max):
    # (on this coarse machine every cut reaches its F, so M4's scaling of the power by
    # the segment's cruise speed over F, tb/cam/test_outputs.py, leaves it as it is)
    path = HERE / name
    text = path.read_text()
    want = _reading(text, s_max)
    _, mp = _plan(path, _laser(s_max))
    stream = _stream(mp)
    moves = [x for x in stream if x[0] == "move"]
    assert moves and {x[1] for x in moves} <= set(want)
    for _, ln, profile, _ in moves:
        assert profile["set_power"] == 1, ln
        assert profile["power"] == want[ln][1], (ln, text.splitlines()[ln - 1])
    # somewhere a cut at power, and a segment at 0 (a G0, or an S0 overscan)
    assert any(p["power"] > 0 for _, _, p, _ in moves)
    assert any(p["power"] == 0 for _, _, p, _ in moves)
    # the OUTPUTs: laser mode always, dynamic power under M4, constant under M3
    outs = [x[1] for x in stream if x[0] == "out"]
    states = _states(text.splitlines(), set(want))
    assert len(outs) == len(states) > 0
    for out, state in zip(outs, states):
        assert out["laser"] == 1 and out["reverse"] == 0
        assert out["enable"] == (state != "M5")
        assert out["dynamic"] == (state == "M4")


def _states(lines: list[str], moving) -> list[str]:
    """The laser state (M3, M4 or M5) of each OUTPUT: the spindle and coolant state where
    it differs from the last one sent, at each line that moves (its M words act before its
    motion) and at the end; changes with no motion between them are one OUTPUT."""
    state, cool = "M5", frozenset()
    last, out = (state, cool), []
    for n, line in enumerate(lines, 1):
        for a, v in _words(line):
            if a == "M" and v in (3, 4, 5):
                state = f"M{int(v)}"
            elif a == "M" and v in (7, 8):
                cool = cool | {int(v)}
            elif a == "M" and v == 9:
                cool = frozenset()
        if n in moving and (state, cool) != last:
            out.append(state)
            last = (state, cool)
    if (state, cool) != last:
        out.append(state)
    return out


@pytest.mark.parametrize("name, s_max", [("image2gcode_m4.gc", 1000.0),
                                         ("image2gcode_m3_overscan.gc", 255.0)])
def test_a_raster_runs_as_without_its_s_words(name, s_max, tmp_path):
    text = (HERE / name).read_text()
    bare = tmp_path / name
    bare.write_text("\n".join(re.sub(r"S[0-9.]+", "", ln) if not ln.startswith(";") else ln
                              for ln in text.splitlines()) + "\n")
    runs = [run_program(str(p), machine=_laser(s_max)) for p in (HERE / name, bare)]
    for r in runs:
        assert not r.execution.errors
    assert len(runs[0].motion.commands) > 150
    assert runs[0].execution.moves == runs[1].execution.moves
    assert runs[0].execution.cycles == runs[1].execution.cycles


def test_hash_comments_are_refused_naming_the_line(tmp_path):
    path = HERE / "lfi_blue_square.gcode"
    lines = path.read_text().splitlines()
    first = next(n for n, ln in enumerate(lines, 1) if ln.startswith("#"))
    with pytest.raises(GcodeError) as e:
        load_program(str(path), machine=_laser(1000.0))
    assert e.value.lineno == first
    # with its comments written as ';' it reads up to the M6 P1 at its end (no tool
    # selected); without that line it runs, the S100 of its first cut not stopping the
    # motion after the G0 before it
    fixed = tmp_path / "square.gcode"
    fixed.write_text("\n".join(";" + ln[1:] if ln.startswith("#") else ln
                               for ln in lines) + "\n")
    m6 = next(n for n, ln in enumerate(lines, 1) if ln.startswith("M6"))
    with pytest.raises(GcodeError) as e:
        load_program(str(fixed), machine=_laser(1000.0))
    assert e.value.lineno == m6
    fixed.write_text("\n".join(";" + ln[1:] if ln.startswith("#") else ln
                               for ln in lines if not ln.startswith("M6")) + "\n")
    _, mp = _plan(fixed, _laser(1000.0))
    stream = _stream(mp)
    assert [c for _, c in _stops(stream)] == ["end"]
    powers = [(p["power"], lines[ln - 1].split()[0][:2]) for _, ln, p, _ in
              (x for x in stream if x[0] == "move")]
    s100 = round(FULL * 100 / 1000)
    # the G0 X0 Y0 from the origin makes no move; the G0 to the square's corner is at 0
    assert powers == [(0, "G0")] + [(s100, "G1")] * 4
    res = run_program(str(fixed), machine=_laser(1000.0))
    assert not res.execution.errors
    # what `halfpoint run` prints of it: one output change (the M4 at the top, at rest:
    # the file has no M5), two power changes (0 for the G0, S100 for the square)
    assert (res.motion.outputs, res.motion.power_changes) == (1, 2)
