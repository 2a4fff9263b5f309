# SPDX-License-Identifier: Apache-2.0
"""Helical arcs and G18/G19 arcs through the host pipeline (issue 14, item 2): a helix
ends exactly on its programmed Z and steps Z in proportion to the arc's moves; the G18
and G19 arcs of a public program run to their expected end on the right side of their
centres, and the bore runs the same on the RTL engine; the planner plans a helix along its 3-D path with every axis's limits; and
each error (plane axes with different BLUs, cutter compensation outside G17) names its
line or machine-file key; a helix too steep for the core's helix mapper runs as short lines
along it."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import pytest

from halfpoint.cam import machine as mc
from halfpoint.cam.gcode import GcodeError, parse
from halfpoint.cam.geom import Arc
from halfpoint.cam.planner import plan, plane_share
from halfpoint.cam.quant import quantise
from halfpoint.cam.run import run_program
from halfpoint.cam.segments import run_segments_model
from halfpoint.sim.engines import executor
from halfpoint.spec import encoding as enc

EX = Path(__file__).resolve().parents[2] / "examples"
SIM = mc.load(EX / "machine_sim.toml")

# the helical bore of examples/cam_style.ngc (three turns down, then a flat turn),
# scaled to a 0.07 mm radius so that the coarse simulation machine runs it in a few
# thousand moves
BORE = """G21 G90 G17
G0 X0.37 Y0.3 Z0.05
G1 Z0 F30000
G2 X0.37 Y0.3 Z-0.1 I-0.07 J0 P3
X0.37 Y0.3 I-0.07 J0
G1 X0.3 Y0.3
G0 Z0.05
M2
"""

# the G18 and G19 arcs at the end of the demo program of nraynaud/webgcode (a G-code
# simulator, https://nraynaud.github.io/webgcode/), with G21 and a feed added
WEBGCODE_PLANES = """G21 G90 F600
G0 X30 Y30 Z30
G18 (X-Z plane)
G3 Z40 I0 K5
G19 (Y-Z plane)
G3 Z50 J0 K5
G17 (back to X-Y plane)
M2
"""


def _write(tmp_path, text, name="p.ngc"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def _segments(res):
    """(first trace index, moves, programmed move) of every motion command."""
    out, k = [], 0
    for pc in res.motion.commands:
        out.append((k, pc.moves, pc.move, pc.kind, pc.cmd))
        k += pc.moves
    return out


def test_helix_ends_exactly_on_its_z_and_steps_z_with_the_arc(tmp_path):
    res = run_program(_write(tmp_path, BORE), machine=SIM)
    trace = res.lattice
    assert trace[-1] == (30, 30, 5)
    helix_cmds = 0
    for start, n, move, kind, cmd in _segments(res):
        before = trace[start - 1] if start else (0, 0, 0)
        points = trace[start:start + n]
        if move.kind == "arc" and move.start[2] != move.end[2]:
            # every command of the helix: Z monotonic, in proportion to the moves
            d = enc.decode(cmd)
            if kind == "arc":
                helix_cmds += 1
                assert (d["u_axis"], d["v_axis"]) == (0, 1) and d["count"] == n
                dz = d["helix"][0]
                for k, p in enumerate(points, start=1):
                    assert abs((p[2] - before[2]) - dz * k / n) <= 0.5
            assert all(b[2] <= a[2] for a, b in zip([before] + points, points))
        if move.kind == "arc" and move.start[2] == move.end[2] == -0.1:
            assert all(p[2] == -10 for p in points)     # the flat turn: exactly on Z-0.1
    assert helix_cmds >= 3
    # every lattice point within a BLU of its block in the plane
    assert res.max_dev_mm <= res.blu[0] + 1e-12


def test_webgcode_g18_and_g19_arcs_run_to_their_end(tmp_path):
    res = run_program(_write(tmp_path, WEBGCODE_PLANES), machine=SIM)
    trace = res.lattice
    assert trace[-1] == (3000, 3000, 5000)
    planes = {}
    for start, n, move, kind, cmd in _segments(res):
        if kind == "arc":
            d = enc.decode(cmd)
            planes.setdefault(move.plane, []).extend(trace[start:start + n])
            assert (d["u_axis"], d["v_axis"]) == enc.PLANES[move.plane]
            assert d["helix"] == (0, 0) and d["count"] == n
    # G18 CCW seen from +Y, Z30 -> Z40 about X30 Z35: through X25, Y still
    g18 = planes[18]
    assert min(p[0] for p in g18) == 2500 and {p[1] for p in g18} == {3000}
    # G19 CCW seen from +X, Z40 -> Z50 about Y30 Z45: through Y35, X still
    g19 = planes[19]
    assert max(p[1] for p in g19) == 3500 and {p[0] for p in g19} == {3000}
    for pts, (cu, cv), (u, v) in ((g18, (3500, 3000), (2, 0)), (g19, (3000, 4500), (1, 2))):
        assert all(abs(math.hypot(p[u] - cu, p[v] - cv) - 500) <= 1.0 for p in pts)


def test_planner_plans_a_helix_along_its_path_with_every_axis_limit():
    slow_z = replace(SIM, axes=(SIM.axes[0], SIM.axes[1],
                                replace(SIM.axes[2], max_velocity_mm_s=50.0,
                                        max_accel_mm_s2=1000.0)))
    prog = parse("G21 G90 F60000\nG0 X10 Y0 Z0\nG2 X10 Y0 Z-20 I-10 J0\nM2\n")
    seg = plan(prog.moves, slow_z)[-1]
    flat = 2 * math.pi * 10
    assert seg.length == pytest.approx(math.hypot(flat, 20))
    h = 20 / seg.length
    # the Z axis limits the helix: its share of the path speed within Z's limit
    assert seg.v_limit * h <= 50.0 + 1e-9 and seg.v_limit * h == pytest.approx(50.0)
    assert seg.accel * h <= 1000.0 + 1e-9
    assert plane_share(seg) == pytest.approx(flat / seg.length)
    # the same arc flat: the Z limits do not apply (the feed, 1000 mm/s, does)
    flat_seg = plan(parse("G21 G90 F60000\nG0 X10\nG2 X10 Y0 I-10 J0\nM2\n").moves, slow_z)[-1]
    assert flat_seg.v_limit == pytest.approx(1000.0) and plane_share(flat_seg) == 1.0


def test_plane_axes_need_the_same_blu(tmp_path):
    path = _write(tmp_path, WEBGCODE_PLANES)
    with pytest.raises(mc.MachineError) as err:
        run_program(path, blu=(0.01, 0.01, 0.02))
    assert err.value.key == "axis.x.blu_mm" and "G18" in str(err.value) \
        and "line 4" in str(err.value)
    # the quantiser checks it too, naming the line
    prog = parse("G21 F100\nG19 G2 Y2 Z0 J1 K0\nM2")
    with pytest.raises(GcodeError, match="line 2: an arc in G19 needs axes Y and Z"):
        quantise(prog.moves, (0.01, 0.01, 0.02))


def test_a_helix_too_steep_for_the_core_runs_as_lines_along_it():
    """0.05 mm radius, 1 mm down in a half turn: 100 BLU of Z over about 20 arc
    moves, more than the helix mapper's one step per arc move (Inkscape gcodetools
    plunges so in its first arc; LinuxCNC and grbl run it).  It runs as short
    lines through the lattice points nearest the arc, Z where the helix is there,
    noted by the line; until 2026-11-27 it was an error."""
    prog = parse("G21 G90 F100\nG0 X0.1\nG2 X0 Y0 Z-1 I-0.05 J0\nM2")
    q = quantise(prog.moves, (0.01,) * 3)
    assert q.steep == [3] and q.arcs == 0 and q.fallback > 0
    trace = run_segments_model(q.cmds)
    assert trace[-1] == (0, 0, -100)
    arc = prog.moves[1]
    el = Arc.from_points(arc.center, arc.start[:2], arc.end[:2], arc.cw)
    k, points = 0, []
    for m, n in zip(q.src, q.moves_per_cmd):
        if m is arc:
            points += trace[k:k + n]
        k += n
    zs = [p[2] for p in points]
    assert zs == sorted(zs, reverse=True) and len(points) >= 100   # Z only goes down
    for p in points:
        assert el.distance((p[0] * 0.01, p[1] * 0.01)) <= 0.01 + 1e-12
        # Z within one line's share of the helix's 100 BLU (and a BLU) of where the
        # helix is at the point's angle (CW from 0)
        t = min(max(-math.atan2(p[1], p[0] - 5) / math.pi % 2, 0.0), 1.0)
        assert abs(p[2] - (-100 * t)) <= 100 / (q.fallback - 1) + 1 + 1e-9


@pytest.mark.parametrize("plane", ["G18", "G19"])
def test_cutter_compensation_stays_g17_only(plane):
    with pytest.raises(GcodeError, match="line 2: cutter compensation is supported in G17"):
        parse(f"G21 F100\n{plane} G41.1 D2 G1 X5\nM2")


def test_the_bore_runs_the_same_on_the_rtl(tmp_path):
    """The helical bore through the Verilator-built core: every move on the same clock
    as the model's."""
    path = _write(tmp_path, BORE)
    model = run_program(path, machine=SIM)
    rtl = run_program(path, executor("rtl"), machine=SIM)
    assert rtl.execution.moves == model.execution.moves
    assert rtl.lattice[-1] == (30, 30, 5)
