# SPDX-License-Identifier: Apache-2.0
"""Cutter radius compensation (seed 004): the seed's tests, the skip/strict
behaviour, lead-in errors, and properties on random contours."""

from __future__ import annotations

import math
import random
from pathlib import Path

import pytest

from halfpoint.cam.comp import compensate, to_gcode
from halfpoint.cam.gcode import GcodeError, parse
from halfpoint.cam.geom import Arc, Line, intersect

EX = Path(__file__).resolve().parents[2] / "examples"


def element(m):
    if m.kind == "arc":
        return Arc.from_points(m.center, m.start[:2], m.end[:2], m.cw)
    return Line(m.start[:2], m.end[:2])


def test_seed_test1_path_is_a_e_d():
    """Tool radius 0.03: offsets of A-B and of the arc C-D meet at E'; the tool
    goes A' -> E' -> D' and block N2 (B -> C) is skipped."""
    prog = parse((EX / "seed004_test1.ngc").read_text(), radius_override=0.03)
    res = compensate(prog.moves)
    feed = [m for m in res.moves if m.kind != "rapid"]
    contour = feed[1:-1]
    ab = [m for m in contour if m.lineno == 5 and m.kind == "line"]
    arc = [m for m in contour if m.lineno == 7 and m.kind == "arc"]
    assert len(ab) == 1 and ab[0].kind == "line" and len(arc) == 1 and arc[0].kind == "arc"
    assert not any(m.lineno == 6 for m in contour)
    assert res.skipped == [6]
    e_prime = ab[0].end
    assert e_prime == arc[0].start
    # E' is one tool radius from A-B and from the programmed arc
    a, b = (-33.458, -67.263), (-33.508, -67.296)
    c = (-33.504 + 5.962, -67.312 + 2.244)
    r_arc = math.hypot(-5.962, -2.244)
    assert abs(Line(a, b).distance(e_prime[:2]) - 0.03) < 1e-9
    assert abs(abs(math.hypot(e_prime[0] - c[0], e_prime[1] - c[1]) - r_arc) - 0.03) < 1e-9
    # A' is A offset to the left of A-B; D' is D offset from the arc
    t = ((b[0] - a[0]), (b[1] - a[1]))
    n = math.hypot(*t)
    a_prime = (a[0] - 0.03 * t[1] / n, a[1] + 0.03 * t[0] / n)
    assert math.hypot(ab[0].start[0] - a_prime[0], ab[0].start[1] - a_prime[1]) < 1e-9
    d = (-33.007, -68.341)
    assert abs(math.hypot(arc[0].end[0] - c[0], arc[0].end[1] - c[1]) - (r_arc - 0.03)) < 1e-9
    # ... the arc's offset runs on towards D' until it meets the G40 move's offset
    assert arc[0].end[1] < e_prime[1] and math.dist(arc[0].end[:2], d) < 0.1


def test_seed_test2_far_blocks_removed():
    """Tool radius 1 in a notch whose mouth is 2 mm: the neighbours' offsets do
    not cross, the corner arcs at the mouth do; the notch blocks go."""
    prog = parse((EX / "seed004_test2.ngc").read_text(), radius_override=1.0)
    res = compensate(prog.moves)
    assert res.skipped == [5, 6, 7]
    feed = [m for m in res.moves if m.kind != "rapid"]
    assert [m.kind for m in feed] == ["line", "arc", "arc", "line"]
    assert math.dist(feed[1].end, feed[2].start) < 1e-9
    assert math.hypot(feed[1].end[0] - 11, feed[1].end[1]) < 1e-6     # tangent circles
    assert all(min(element(m).distance(p) for m in prog.moves[1:])
               >= 1 - 1e-9 for p in [feed[1].end[:2], feed[1].start[:2]])


def test_strict_turns_the_skip_into_an_error_naming_the_line():
    prog = parse((EX / "seed004_test2.ngc").read_text(), radius_override=1.0)
    with pytest.raises(GcodeError, match="line 5: the tool"):
        compensate(prog.moves, strict=True)


@pytest.mark.parametrize(
    "text, lineno, reason",
    [
        ("F100\nG41.1 D4 G1 X1\nX10\nG40 X12\nM2", 2, "lead-in move (1 mm) is shorter than the tool radius"),
        # the seed refused arc entries, Z moves while compensating and the end of
        # the program with compensation on; LinuxCNC accepts them (issue 12)
        ("F100\nG41.1 D2 G3 X0 Y0 I0.5\nG1 X10\nG40 G1 X12\nM2", 2, "entry arc"),
        ("F100\nG41.1 D2 G1 X10\nG18 G2 X20 Z0 I5\nG40 G1 X30\nM2", 3, "in G17"),
        ("F100\nG41.1 D2 G1 X10\nG40 X20\nM2", 3, "lead-in move only"),
    ],
)
def test_comp_errors_name_the_line(text, lineno, reason):
    with pytest.raises(GcodeError) as exc:
        compensate(parse(text).moves)
    assert exc.value.lineno == lineno and reason in str(exc.value), str(exc.value)


def test_concave_arc_smaller_than_the_tool_is_skipped_or_strict_error():
    # a CCW pocket-like contour with a tiny concave round (R 0.5) and tool radius 2 (inside)
    prog = """F100
G0 X0 Y0
G41.1 D4 G1 X0 Y-10
X10 Y-10
G3 X10.5 Y-9.5 I0 J0.5
G1 X10.5 Y10
X-10 Y10
X-10 Y-10
X0 Y-10
G40 G1 X0 Y0
M2"""
    # G41 on a CCW contour keeps the tool inside; the round at line 5 is concave
    res = compensate(parse(prog).moves)
    assert 5 in res.skipped and res.warnings
    with pytest.raises(GcodeError, match="line 5"):
        compensate(parse(prog).moves, strict=True)


def test_compensated_gcode_reparses_to_the_same_path():
    prog = parse((EX / "seed004_test1.ngc").read_text(), radius_override=0.03)
    res = compensate(prog.moves)
    again = parse(to_gcode(res.moves)).moves
    assert len(again) == len(res.moves)
    for a, b in zip(again, res.moves):
        assert max(abs(x - y) for x, y in zip(a.end, b.end)) < 1e-4
        assert a.kind == b.kind


# --- properties on random contours ------------------------------------------------

def random_contour(rng):
    """A closed star-shaped contour (CCW) with random notches (some narrower
    than the tool) and arcs, as G-code blocks; starts and ends at the middle
    of its first edge.  Features are kept apart from each other by more than
    the tool diameter except inside the notches, which the tool may or may
    not fit."""
    n = rng.randint(7, 12)
    angles = sorted((k + rng.uniform(0.2, 0.8)) * 2 * math.pi / n for k in range(n))
    verts = []
    for a in angles:
        rr = rng.uniform(25, 40)
        verts.append((rr * math.cos(a), rr * math.sin(a)))
    blocks = []         # ("line", end) or ("arc", end, centre, cw)
    v0 = verts[0]
    mid = ((v0[0] + verts[1][0]) / 2, (v0[1] + verts[1][1]) / 2)
    pts = [mid] + verts[1:] + [v0, mid]
    for p, q in zip(pts, pts[1:]):
        dx, dy = q[0] - p[0], q[1] - p[1]
        length = math.hypot(dx, dy)
        u = (dx / length, dy / length)
        nrm = (-u[1], u[0])                 # inward for a CCW contour
        roll = rng.random()
        if roll < 0.25 and length > 16:
            # a rectangular notch into the part, some narrower than the tool
            w = rng.uniform(0.5, 6)
            dep = rng.uniform(0.5, 3)
            s = rng.uniform(4, length - w - 4)
            a = (p[0] + u[0] * s, p[1] + u[1] * s)
            b = (a[0] + nrm[0] * dep, a[1] + nrm[1] * dep)
            c = (b[0] + u[0] * w, b[1] + u[1] * w)
            d = (a[0] + u[0] * w, a[1] + u[1] * w)
            blocks += [("line", a), ("line", b), ("line", c), ("line", d), ("line", q)]
        elif roll < 0.5:
            # an arc bulging out or in, sagitta up to an eighth of the chord
            sag = rng.uniform(0.03, 0.12) * length * rng.choice((-1, 1))
            h = length / 2
            rad = (h * h + sag * sag) / (2 * abs(sag))
            m = ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2)
            off = rad - abs(sag)
            sgn = 1 if sag < 0 else -1       # sag > 0 bulges outward (to the right)
            centre = (m[0] + sgn * nrm[0] * off, m[1] + sgn * nrm[1] * off)
            cw = sag > 0
            blocks.append(("arc", q, centre, cw))
        else:
            blocks.append(("line", q))
    return mid, blocks


def contour_program(mid, blocks, side, r):
    """The contour with a lead-in from the tool's side, perpendicular to the
    first edge at its middle, and a G40 move back out the same way."""
    q = blocks[0][1]
    ex, ey = q[0] - mid[0], q[1] - mid[1]
    n = math.hypot(ex, ey)
    inward = (-ey / n, ex / n)
    sgn = 1 if side == "left" else -1         # left of a CCW contour is inside
    lead = 4 + 2 * r
    st = (mid[0] + sgn * inward[0] * lead, mid[1] + sgn * inward[1] * lead)
    out = ["G21 G90 G91.1 F600", f"G0 X{st[0]:.6f} Y{st[1]:.6f}"]
    g = "G41.1" if side == "left" else "G42.1"
    out.append(f"{g} D{2 * r:.6f} G1 X{mid[0]:.6f} Y{mid[1]:.6f}")
    cur = mid
    for b in blocks:
        if b[0] == "line":
            out.append(f"G1 X{b[1][0]:.6f} Y{b[1][1]:.6f}")
        else:
            _, q, c, cw = b
            out.append(f"{'G2' if cw else 'G3'} X{q[0]:.6f} Y{q[1]:.6f} "
                       f"I{c[0] - cur[0]:.6f} J{c[1] - cur[1]:.6f}")
        cur = b[1]
    out.append(f"G40 G1 X{st[0]:.6f} Y{st[1]:.6f}")
    out.append("M2")
    return "\n".join(out)


@pytest.mark.parametrize("seed", range(int(__import__("os").environ.get("HP_COMP_SEEDS", "60"))))
def test_random_contours_no_gouge_no_self_intersection(seed):
    rng = random.Random(seed)
    mid, blocks = random_contour(rng)
    side = rng.choice(("left", "right"))
    r = rng.uniform(0.3, 2.5)
    prog = parse(contour_program(mid, blocks, side, r))
    programmed = [element(m) for m in prog.moves[2:-1]]
    res = compensate(prog.moves, window=8)
    feed = [m for m in res.moves if m.kind != "rapid"]
    path = [element(m) for m in feed[1:-1]]          # between entry and exit moves
    # no gouge: every point of the tool path is at least r from the contour
    for el in path:
        for k in range(21):
            p = el.point(k / 20)
            d = min(pe.distance(p) for pe in programmed)
            assert d >= r - 1e-5, f"gouge of {r - d:.3g} mm near {p} (seed {seed}, {side})"
    # no self-intersection left
    for i, a in enumerate(path):
        for j in range(i + 1, len(path)):
            for _, _, p in intersect(a, path[j]):
                shared = (j == i + 1 and math.dist(p, a.end) < 1e-6) or \
                         (i == 0 and j == len(path) - 1 and math.dist(p, a.start) < 1e-6)
                assert shared, f"elements {i} and {j} cross at {p} (seed {seed}, {side})"


SQUARE_WITH_PLUNGE = """G21 G17 G90 G94 F600
G0 Z1
G0 X10 Y10
G41.1 D4 G1 X10 Y0
G1 Z-1
G1 X20 Y0
G1 X20 Y20
G1 X0 Y20
G1 X0 Y0
G1 X10 Y0
G0 Z1
G40 G0 X10 Y10
M2
"""


def _same_xy(p, q):
    return math.dist(p[:2], q[:2]) <= 1e-12


def test_z_moves_round_a_closed_loop_keep_their_place_in_program_order():
    """A plunge after the entry and a retract after the loop's last block (a public
    program's pattern, found by a G-code trial): the plunge was made after the loop
    (the first edge ramped down from the safe height instead), and the loop closed on
    the first edge's part before the entry's join after the retract, so the tool fed
    back down to depth and left by a rapid at depth."""
    res = compensate(parse(SQUARE_WITH_PLUNGE).moves)
    assert not res.warnings and not res.skipped
    moves = res.moves
    xy = [k for k, m in enumerate(moves) if not _same_xy(m.start, m.end)]
    plunge = next(k for k, m in enumerate(moves) if m.lineno == 5)
    retract = next(k for k, m in enumerate(moves) if m.lineno == 11)
    # XY moves before the plunge and after the retract at the safe height
    for k in xy:
        m = moves[k]
        if k < plunge or k > retract:
            assert m.end[2] == 1.0, (k, m)
        else:
            # the whole loop at depth, no ramp
            assert m.start[2] == m.end[2] == -1.0, (k, m)
    # the loop's offset cut whole at depth: 4 x 16 mm inside the 20 mm square
    depth = sum(math.dist(moves[k].start[:2], moves[k].end[:2]) for k in xy
                if plunge < k < retract)
    assert depth == pytest.approx(64.0, abs=1e-9)
    # the exit rapid leaves from where the retract ended, at the safe height
    assert moves[-1].kind == "rapid" and moves[-1].start[2] == 1.0


def test_depth_passes_round_one_closed_contour_are_refused_naming_the_line():
    """A closed contour followed round twice with compensation on (a ramp to each
    depth, as LinuxCNC's useful-subroutines o200 does): the passes' offsets coincide
    and the first pass was skipped with a warning that the tool could not follow it,
    while the second ramped to its depth from the safe height.  Refused, naming the
    block where the second pass starts."""
    text = SQUARE_WITH_PLUNGE.replace("G1 Z-1\nG1 X20 Y0\n", "G1 X20 Y0 Z-1\n").replace(
        "G1 X10 Y0\nG0 Z1\n",
        "G1 X10 Y0\nG1 X20 Y0 Z-2\nG1 X20 Y20\nG1 X0 Y20\nG1 X0 Y0\nG1 X10 Y0\nG0 Z1\n")
    with pytest.raises(GcodeError) as exc:
        compensate(parse(text).moves)
    assert exc.value.lineno == 10 and "followed round again" in str(exc.value)


def test_compensated_moves_keep_their_blocks_path_mode():
    """G61.1 (exact stop) acts on the planner through each move's path mode: the moves
    compensation makes of a block carry the block's mode (they were all G64)."""
    text = ("G21 G90 G17 F600\nG0 X-5 Y-5\nG61.1\nG42.1 D2 G1 X0 Y0\nG1 X10\nG64 G1 X20\n"
            "G1 X20 Y10\nG1 X0 Y10\nG61.1 G1 X0 Y0\nG40 G1 X-5 Y-5\nM2\n")
    prog = parse(text)
    want = {m.lineno: m.path_mode for m in prog.moves}
    res = compensate(prog.moves)
    assert {m.lineno for m in res.moves} <= set(want)
    for m in res.moves:
        assert m.path_mode == want[m.lineno], (m.lineno, m.path_mode)
    assert {m.path_mode for m in res.moves} == {"G61.1", "G64"}
