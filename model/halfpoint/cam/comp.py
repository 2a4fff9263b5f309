# SPDX-License-Identifier: Apache-2.0
"""Cutter radius compensation G41/G42/G40 with interference avoidance (seed 004).

For each compensated stretch (from the move that switches G41/G42 on to the
G40 move):

1. Every block of the contour is offset by the tool radius r to the tool's
   side: lines sideways, arcs radially (R - r or R + r).  A concave arc whose
   radius is smaller than the tool has no offset: it is skipped.
2. Where two consecutive offsets leave a gap (an outside corner), an arc of
   radius r about the programmed corner joins them: the tool rolls round the
   corner (LinuxCNC's choice too), turning clockwise under G41 and
   counter-clockwise under G42.  Where they cross (an inside corner), step 3
   trims both to the crossing.
3. Interference avoidance: the offset elements are scanned with a buffer of
   the next `window` blocks.  If element i intersects a later element j in
   the buffer (bounding boxes first, arcs by their quadrant-split pieces),
   element i ends and element j starts at their intersection, and everything
   between them is deleted; of all intersections of i with the buffer, the
   one nearest the start of i is taken (the furthest j on a tie), so the
   path leaves i where the first later element crosses it.
   This removes the loops that tiny CAM segments produce, notches narrower
   than the tool, and arcs smaller than the tool, without gouging.
4. Whole programmed blocks that vanished in 2 or 3 are reported: a warning
   naming the lines, or with ``strict`` an error naming the first one.

The entry move (the straight move that switches compensation on, at least r
long, else an error naming the line) goes from the uncompensated position to
its own offset end point, and the G40 move from its own offset start point to
its uncompensated end; both take part in steps 2 and 3 like any block, so a
notch right behind the entry is handled too (seed 004's test 2).  Within a compensated stretch Z
must stay constant (2.5-D contouring) and arcs must be in G17.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .gcode import GcodeError, Move
from .geom import Arc, Line, intersect

TOL = 1e-6


@dataclass
class CompResult:
    moves: list[Move]
    warnings: list[str]
    skipped: list[int]


def _offset(m: Move, side: str, r: float):
    """Offset element of a programmed block, or None if the tool cannot follow it."""
    if m.kind == "arc":
        a = Arc.from_points(m.center, m.start[:2], m.end[:2], m.cw, src=m.lineno)
        inward = (side == "left") != m.cw       # left of a CCW arc is towards the centre
        rr = a.r - r if inward else a.r + r
        if rr <= TOL:
            return None
        return Arc(a.c, rr, a.a0, a.sweep, m.lineno)
    t = Line(m.start[:2], m.end[:2]).tangent(0.0)
    n = (-t[1], t[0]) if side == "left" else (t[1], -t[0])
    return Line((m.start[0] + r * n[0], m.start[1] + r * n[1]),
                (m.end[0] + r * n[0], m.end[1] + r * n[1]), m.lineno)


def _close(p, q, tol=TOL) -> bool:
    return math.hypot(p[0] - q[0], p[1] - q[1]) <= tol


def _crossing(a, b) -> bool:
    """Do two consecutive offset elements cross (other than end to start)?"""
    return any(not (_close(p, a.end) and _close(p, b.start)) for _, _, p in intersect(a, b))


def offset_contour(contour: list[Move], side: str, r: float, window: int = 5,
                   pin_start=None, pin_end=None):
    """Offset elements of a contour after corner joins and interference removal.

    ``pin_start`` / ``pin_end``: the first element starts / the last element
    ends at this uncompensated point instead (the entry and G40 moves).
    Returns (elements, skipped source lines of the inner blocks)."""
    elems = []
    prev_kept = None
    for idx, m in enumerate(contour):
        e = _offset(m, side, r)
        if e is not None and idx == 0 and pin_start is not None:
            e = Line(pin_start, e.end, m.lineno)
        if e is not None and idx == len(contour) - 1 and pin_end is not None:
            e = Line(e.start, pin_end, m.lineno)
        if e is None:
            prev_kept = None
            continue
        if prev_kept is not None:
            pm, pe = prev_kept
            # a gap between the offsets (the tool goes round the corner) gets
            # an arc about the programmed corner; crossing offsets (an inside
            # corner) are trimmed in the interference pass below
            if not _close(pe.end, e.start) and not _crossing(pe, e):
                elems.append(Arc.from_points(pm.end[:2], pe.end, e.start, side == "left",
                                             src=m.lineno, corner=True, full_if_closed=False))
        elems.append(e)
        prev_kept = (m, e)

    span = 2 * window               # corner joins travel with their block
    boxes = [e.bbox() for e in elems]
    out = []
    i = 0
    n_el = len(elems)
    while i < n_el:
        e = elems[i]
        e_line = type(e) is Line or e.corner
        found = None
        ex0, ey0, ex1, ey1 = boxes[i]
        ex0 -= 1e-9
        ey0 -= 1e-9
        ex1 += 1e-9
        ey1 += 1e-9
        for j in range(i + 1, min(n_el - 1, i + span) + 1):
            fx0, fy0, fx1, fy1 = boxes[j]
            if fx0 > ex1 or ex0 > fx1 or fy0 > ey1 or ey0 > fy1:
                continue            # bounding boxes apart: no intersection
            f = elems[j]
            if j == i + 1 and (e_line or f.corner or type(f) is Line) and _close(e.end, f.start):
                # joined neighbours: two lines meet once, and a corner arc is
                # tangent to its neighbours, so the joint is their only contact
                continue
            for ta, tb, p in intersect(e, f):
                if ta <= TOL and _close(p, e.start):
                    continue        # the joint with the element before e
                if j == i + 1 and _close(p, e.end) and _close(p, f.start):
                    continue        # the ordinary joint with the next element
                key = (ta, -j)
                if found is None or key < found[0]:
                    found = (key, j, p)
        if found is not None:
            _, j, p = found
            out.append(e.with_end(p))
            elems[j] = elems[j].with_start(p)
            boxes[j] = elems[j].bbox()
            i = j
            continue
        out.append(e)
        i += 1
    out = [e for e in out if e.length() > TOL]
    # A trim at an element's start can move it past the crossing with its
    # successor; the two then end/start a hair apart.  Such a small gap
    # (below r/20) is bridged by a straight move: its points dip below the
    # offset distance by at most gap^2 / (8 r), i.e. r / 3200.
    bridged = []
    for a in out:
        if bridged and not _close(bridged[-1].end, a.start) and \
                math.dist(bridged[-1].end, a.start) < r / 20:
            bridged.append(Line(bridged[-1].end, a.start, a.src, corner=True))
        bridged.append(a)
    out = bridged
    present = {e.src for e in out if not e.corner}
    inner = contour[1 if pin_start is not None else 0:len(contour) - (1 if pin_end is not None else 0)]
    skipped = sorted({m.lineno for m in inner} - present)
    return out, skipped


def _line_ranges(lines: list[int], most: int = 8) -> str:
    """'line 5' / 'lines 5, 6, 7' / 'lines 5-9, 12, ... (40 lines)'."""
    if len(lines) == 1:
        return f"line {lines[0]}"
    runs = []
    for n in lines:
        if runs and n == runs[-1][1] + 1:
            runs[-1][1] = n
        else:
            runs.append([n, n])
    if all(a == b for a, b in runs) and len(runs) <= most:
        return "lines " + ", ".join(str(a) for a, _ in runs)
    parts = [f"{a}-{b}" if b > a else str(a) for a, b in runs[:most]]
    more = f", ... ({len(lines)} lines)" if len(runs) > most else ""
    return "lines " + ", ".join(parts) + more


def compensate(moves: list[Move], window: int = 5, strict: bool = False) -> CompResult:
    """Apply cutter compensation to parsed moves; see the module docstring."""
    result: list[Move] = []
    warnings: list[str] = []
    skipped_all: list[int] = []
    k = 0
    while k < len(moves):
        m = moves[k]
        if m.comp == "off":
            result.append(m)
            k += 1
            continue
        entry = m
        side, r = m.comp, m.radius
        if entry.kind == "arc":
            raise GcodeError(entry.lineno, "the move that starts cutter compensation must be straight")
        lead = math.hypot(entry.end[0] - entry.start[0], entry.end[1] - entry.start[1])
        if lead < r - TOL:
            raise GcodeError(entry.lineno, f"lead-in move ({lead:g} mm) is shorter than the tool radius ({r:g} mm)")
        k += 1
        contour = []
        while k < len(moves) and moves[k].comp != "off":
            c = moves[k]
            if c.kind == "arc" and c.plane != 17:
                raise GcodeError(c.lineno, "compensated arcs must be in G17")
            if abs(c.start[2] - entry.end[2]) > TOL or abs(c.end[2] - entry.end[2]) > TOL:
                raise GcodeError(c.lineno, "Z must stay constant while cutter compensation is on")
            if c.kind != "arc" and _close(c.start[:2], c.end[:2]):
                raise GcodeError(c.lineno, "a move without XY motion while cutter compensation is on")
            contour.append(c)
            k += 1
        if k >= len(moves):
            raise GcodeError(moves[-1].lineno, "the program ends with cutter compensation on (no G40 move)")
        exit_move = moves[k]
        if exit_move.kind == "arc":
            raise GcodeError(exit_move.lineno, "the G40 move must be straight")
        if not contour:
            raise GcodeError(exit_move.lineno, "cutter compensation on for the lead-in move only")
        elems, skipped = offset_contour([entry] + contour + [exit_move], side, r, window,
                                        pin_start=entry.start[:2], pin_end=exit_move.end[:2])
        if len(elems) < 2 or elems[0].src != entry.lineno or elems[-1].src != exit_move.lineno:
            raise GcodeError(contour[0].lineno, "the tool cannot follow this contour at all")
        for a, b in zip(elems, elems[1:]):
            if not _close(a.end, b.start, 1e-5):
                raise GcodeError(b.src, f"cannot resolve the inside corner within a window of {window} blocks")
        if skipped:
            if strict:
                raise GcodeError(skipped[0], f"the tool (radius {r:g} mm) cannot follow the contour here")
            which = _line_ranges(skipped)
            warnings.append(f"{which}: skipped, the tool (radius {r:g} mm) cannot follow the contour there")
            skipped_all += skipped
        z = entry.end[2]
        first = elems[0].end
        result.append(Move(entry.kind, entry.start, (first[0], first[1], z), entry.lineno, entry.feed))
        feeds = {c.lineno: c.feed for c in contour}
        for e in elems[1:-1]:
            s, t = e.start, e.end
            f = feeds.get(e.src, entry.feed or exit_move.feed)
            if isinstance(e, Line):
                result.append(Move("line", (s[0], s[1], z), (t[0], t[1], z), e.src, f))
            else:
                result.append(Move("arc", (s[0], s[1], z), (t[0], t[1], z), e.src, f,
                                   center=e.c, cw=e.cw, plane=17))
        last = elems[-1].start
        result.append(Move(exit_move.kind, (last[0], last[1], z), exit_move.end, exit_move.lineno,
                           exit_move.feed))
        k += 1
    return CompResult(result, warnings, skipped_all)


def _num(v: float) -> str:
    return f"{v + 0.0:.4f}".replace("-0.0000", "0.0000")


def to_gcode(moves: list[Move]) -> str:
    """Plain G-code of moves: G21 G90 G91.1, G0/G1/G2/G3 only."""
    out = ["G21 G90 G91.1 G17"]
    feed = None
    for m in moves:
        x, y, z = m.end
        if m.kind == "rapid":
            out.append(f"G0 X{_num(x)} Y{_num(y)} Z{_num(z)}")
            continue
        fw = ""
        if m.feed and m.feed != feed:
            fw = f" F{m.feed:.1f}"
            feed = m.feed
        if m.kind == "line":
            out.append(f"G1 X{_num(x)} Y{_num(y)} Z{_num(z)}{fw}")
        else:
            i, j = m.center[0] - m.start[0], m.center[1] - m.start[1]
            out.append(f"{'G2' if m.cw else 'G3'} X{_num(x)} Y{_num(y)} I{_num(i)} J{_num(j)}{fw}")
    out.append("M2")
    return "\n".join(out) + "\n"
