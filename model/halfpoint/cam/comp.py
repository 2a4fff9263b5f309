# SPDX-License-Identifier: Apache-2.0
"""Cutter radius compensation G41/G42/G40: offset, trim by distance, check.

A compensated stretch is the run of moves read while G41/G42 is on.  Its
first move with XY motion is the entry move, the rest is the contour; the
first move after G40 is the exit move.  For each stretch:

1. Raw offset path (LinuxCNC's rules).  The entry move goes from the
   uncompensated position to its programmed end offset by r perpendicular to
   the entry move (LinuxCNC's ``convert_straight_comp1``; an arc as entry
   move is reached by a straight move onto its offset start).  Every contour
   block is offset by r to the tool's side: lines sideways, arcs radially
   (R - r or R + r).  At each corner, a gap on the outside is joined by an
   arc of radius r about the programmed corner; on the inside two crossing
   offsets are trimmed to their crossing, and offsets that do not cross (tiny
   chords, a concave arc smaller than the tool, which has no offset) are
   joined by a straight connector through the tool's forbidden zone.  A
   contour that ends where it began (a closed contour, entered anywhere) gets
   the same join between its last and first block: its closing point is a
   join, not a crossing.  So does a closed loop with up to LEAD_BLOCKS blocks
   before it (a lead-in) and after it (a lead-out), CAM's lead arcs (``_loop``),
   and a contour that crosses its start instead of ending on it (an edge that
   overtravels the part's corner), cut where it crosses (``_crossing``).  Z-only
   moves keep their place between blocks; lines that move Z carry Z along their
   offset.
2. Interference as far as the tool reaches.  Every element of the raw path
   is split where any other element crosses it; the pairs are found through
   a uniform grid over the elements' boxes (``spatial.box_pairs``), so the
   search reaches every element within the tool's reach, however many blocks
   lie between.
3. Distance test.  A piece is kept only if its midpoint is at least
   ``r - 1e-7`` mm from every protected programmed block (connectors never
   are): the loop's of a closed stretch (its lead moves lie in the scrap),
   every block of an open one.  The entry move is exempt, except for the stretch behind its
   last crossing with the contour's offset when it meets the contour at an
   inside corner (LinuxCNC trims it there).
4. The path is followed from the entry through the kept pieces in program
   order; where a piece ends at a crossing and the next piece was removed,
   the path continues on the kept piece that leaves the crossing (the one
   furthest on where the path touches itself).  A closed contour is followed
   round until the point where the path joined it; its lead-out then goes
   back along the path to the loop's last block and leaves from there
   (``emit_lead_out``).  A kept stretch that
   the path cannot reach (the tool would have to pass a gap narrower than
   itself) is an error naming its lines.
5. Programmed blocks the path no longer visits are reported (a warning
   naming the lines; with ``strict`` an error naming the first one).
6. The independent check (``check.gouges``, ``check.self_crossings``) runs
   on the result: no point of the tool path between the entry and exit moves
   closer than ``r - 1e-6`` mm to the protected blocks, no self-crossing
   (the lead moves, which end and start where the loop is joined, left out);
   a violation is an error naming the programmed lines.

The exit move runs from the last point of the compensated path to its
programmed end (LinuxCNC); G40 without a move, or the end of the program
with compensation on, leaves the tool at the last point of the path.
``window`` (the old interference window) is accepted and ignored: the
search is no longer limited to a number of blocks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from . import check
from .gcode import GcodeError, Move
from .geom import TAU, Arc, Line, intersect
from .spatial import (A0, CX, CY, K, R, SW, X0, X1, Y0, Y1, box_pairs, boxes, element_distance,
                      pack, point_distance)

TOL = 1e-6              # the gouge check's tolerance (mm)
KEEP_TOL = 1e-7         # a piece is kept at distance >= r - KEEP_TOL
MIN_PIECE = 1e-9        # pieces shorter than this are points
CHORD_TOL = 1e-9        # a corner arc this close to its chord is run as the chord
REACH_TOL = 1e-3        # a kept stretch shorter than this may stay unreached
LEAD_BLOCKS = 2         # at most this many blocks before / after a closed loop are its
                        # lead-in / lead-out

ENTRY, CONTOUR, CORNER, CONNECTOR, EXIT = range(5)
# a closed loop's lead-in and lead-out (offset blocks and their corners): like
# CONTOUR pieces, kept only at r from the loop and checked for gouges, but, like
# the entry and exit moves, not in the self-crossing check: they end and start
# where the loop is joined, which the loop returns to
LEAD = 5


@dataclass
class CompResult:
    moves: list[Move]
    warnings: list[str]
    skipped: list[int]


@dataclass(eq=False, slots=True)
class Piece:
    el: object              # geom.Line or geom.Arc
    src: int                # programmed line
    role: int
    kind: str               # "line", "rapid" or "arc"
    feed: float
    z0: float
    z1: float
    raw: int = -1           # index of the raw element it was cut from
    t0: float = 0.0
    t1: float = 1.0
    valid: bool = True
    events: list | None = None      # Z-only moves after this piece


def _close(p, q, tol=TOL) -> bool:
    """Are the XY parts of p and q within tol of each other?"""
    dx, dy = p[0] - q[0], p[1] - q[1]
    return -tol <= dx <= tol and -tol <= dy <= tol and math.hypot(dx, dy) <= tol


def _offset(m: Move, side: str, r: float):
    """Offset element of a programmed block, or None if the tool cannot follow it."""
    if m.kind == "arc":
        a = Arc.from_points(m.center, m.start[:2], m.end[:2], m.cw, src=m.lineno)
        inward = (side == "left") != m.cw       # left of a CCW arc is towards the centre
        rr = a.r - r if inward else a.r + r
        if rr <= TOL:
            return None
        return Arc(a.c, rr, a.a0, a.sweep, m.lineno)
    dx, dy = m.end[0] - m.start[0], m.end[1] - m.start[1]
    n = math.hypot(dx, dy)
    nx, ny = (-dy / n, dx / n) if side == "left" else (dy / n, -dx / n)
    return Line((m.start[0] + r * nx, m.start[1] + r * ny),
                (m.end[0] + r * nx, m.end[1] + r * ny), m.lineno)


def _sub(el, t0: float, t1: float, p0, p1):
    """The part of element el between parameters t0 and t1 (end points given)."""
    if type(el) is Line:
        return Line(p0, p1, el.src, el.corner)
    a = math.atan2(p0[1] - el.c[1], p0[0] - el.c[0])
    return Arc(el.c, el.r, a, el.sweep * (t1 - t0), el.src, el.corner)


def _param(el, p) -> float:
    t = el.param(p)
    return 0.0 if t is None else t


def _full_turn(el) -> bool:
    """Is the arc element a whole circle?"""
    return abs(abs(el.sweep) - TAU) < 1e-9


def _programmed_element(m: Move):
    if m.kind == "arc":
        return Arc.from_points(m.center, m.start[:2], m.end[:2], m.cw, src=m.lineno)
    return Line(m.start[:2], m.end[:2], m.lineno)


def line_ranges(lines: list[int], most: int = 8) -> str:
    """'line 5' / 'lines 5, 6, 7' / 'lines 5-9, 12, ... (40 lines)'."""
    lines = sorted(set(lines))
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


def _encloses(blocks: list[Move]) -> bool:
    """Can these blocks, ending where they start, be a loop round a part: a full
    circle, two blocks with an arc, or three or more (a line out and back
    encloses nothing)?"""
    return len(blocks) >= 3 or any(m.kind == "arc" for m in blocks)


def _vertices(start_xy, xy: list[Move]) -> list:
    """The XY points a stretch passes: its start, then each block's end."""
    return [start_xy] + [m.end[:2] for m in xy]


def _second_pass(start_xy, xy: list[Move], loop) -> int | None:
    """Where the closed loop ``xy[a:b]`` (``loop``) is followed round again: the
    block c (a < c < b) at which the path is back at the loop's start having gone
    round once (depth passes round one contour), or None."""
    a, b = loop
    verts = _vertices(start_xy, xy)
    for c in range(a + 1, b):
        if _close(verts[c], verts[a], 1e-6) and _encloses(xy[a:c]) and _encloses(xy[c:b]):
            return c
    return None


def _loop(start_xy, xy: list[Move]):
    """The closed loop of a stretch, as (a, b): its blocks ``xy[a:b]`` (the
    blocks with XY motion, after the entry move; an arc entry counts as the
    first) return to the point where block a starts.  ``(0, len(xy))`` for a
    stretch that ends where it began.  Otherwise the loop may have up to
    LEAD_BLOCKS blocks before it, a lead-in, and up to LEAD_BLOCKS after it, a
    lead-out (CAM's tangent lead-in and lead-out arcs and lines, programmed
    with compensation on: LinuxCNC's handbook calls them entry moves); the
    shortest lead-in and then the shortest lead-out are taken (the loop as
    ``_encloses`` has it).  None for an open stretch."""
    n = len(xy)
    if n == 0:
        return None
    verts = _vertices(start_xy, xy)
    if _close(verts[n], verts[0], 1e-6):
        return 0, n
    for a in range(0, min(LEAD_BLOCKS, n - 1) + 1):
        for b in range(n, a, -1):
            if n - b > LEAD_BLOCKS:
                break
            if _close(verts[b], verts[a], 1e-6) and _encloses(xy[a:b]):
                return a, b
    return None


def _crossing(xy: list[Move]):
    """Where a stretch that overruns its start closes: a point X where one of its
    first LEAD_BLOCKS blocks (with XY motion) and one of its last LEAD_BLOCKS
    meet away from their shared vertex, as (i, ti, j, tj, X) with ti, tj the
    blocks' parameters of X; the earliest block i, then the latest j.  A
    contour that runs on past its start corner (the handbook way: the last edge
    overtravels the corner, or the first edge starts before it) closes there;
    the parts of the two blocks outside the loop are its lead-in and lead-out.
    None when no such pair meets."""
    n = len(xy)
    els = [_programmed_element(m) for m in xy]
    for i in range(min(LEAD_BLOCKS, n)):
        for j in range(n - 1, max(i, n - 1 - LEAD_BLOCKS), -1):
            hits = []
            for ti, tj, pt in intersect(els[i], els[j]):
                if j == i + 1 and ti > 1 - 1e-9 and tj < 1e-9:
                    continue                    # their shared vertex
                hits.append((ti, -tj, pt))
            if not hits:
                continue
            ti, tj, pt = min(hits)
            tj = -tj
            a = i + 1 if ti > 1 - 1e-9 else i   # the loop's first block ...
            b = j - 1 if tj < 1e-9 else j       # ... and its last
            if b < a or not _encloses(xy[a:b + 1]):
                continue
            return i, ti, j, tj, pt
    return None


def _split(m: Move, t: float, point) -> tuple[Move, Move]:
    """The move cut at ``point`` (its parameter t): the part before and after."""
    x = (point[0], point[1], m.start[2] + t * (m.end[2] - m.start[2]))
    return replace(m, end=x), replace(m, start=x)


class _Stretch:
    """One compensated stretch: builds, cuts, keeps and follows its pieces."""

    def __init__(self, entry: Move, contour: list[Move], side: str, r: float, exit_move=None):
        self.entry, self.contour, self.side, self.r = entry, contour, side, r
        self.exit_move = exit_move
        self.exit_outside = True
        self.has_exit = False
        self.slack = 0.0
        self.cut_keys: set = set()
        self.left = side == "left"
        self.pieces: list[Piece] = []
        self.cycle0 = 0
        self.closed = False
        self.lead_out: list[Move] = []  # moves after the closed loop, before G40
        self.closing_from = -1          # raw index of the closing join's first piece
        self.entry_outside = True
        self.feed = entry.feed or next((m.feed for m in contour if m.feed), 0.0) or 1.0
        self.trim_entry = False

    # -- 1. raw offset path ----------------------------------------------------------
    def _corner(self, prev: Piece, el, corner, src: int, feed: float, trim: bool,
                gap: float = 0.0):
        """Join prev's end to el's start about the programmed corner point;
        returns (pieces to insert, el possibly trimmed at its start, outside?)."""
        pel = prev.el
        if type(pel) is Line and type(el) is Line:
            a, b = pel.p1, el.p0
            if _close(a, b, 1e-9):
                return [], el, True
            # the two unit directions, without the generic tangent calls
            ta = (pel.p1[0] - pel.p0[0], pel.p1[1] - pel.p0[1])
            tb = (el.p1[0] - el.p0[0], el.p1[1] - el.p0[1])
            na, nb = math.hypot(*ta) or 1.0, math.hypot(*tb) or 1.0
            ta, tb = (ta[0] / na, ta[1] / na), (tb[0] / nb, tb[1] / nb)
        else:
            a, b = pel.end, el.start
            if _close(a, b, 1e-9):
                return [], el, True
            ta, tb = pel.tangent(1.0), el.tangent(0.0)
        cross = ta[0] * tb[1] - ta[1] * tb[0]
        dot = ta[0] * tb[0] + ta[1] * tb[1]
        outside = (cross < 0) if self.left else (cross > 0)
        if abs(cross) < 1e-12 and dot < 0:
            outside = True
        z = prev.z1
        if outside:
            # radius exactly r about the programmed corner (an arc block's
            # offset may end a rounding error away from it)
            a0 = math.atan2(a[1] - corner[1], a[0] - corner[0])
            a1 = math.atan2(b[1] - corner[1], b[0] - corner[0])
            sweep = -((a0 - a1) % TAU) if self.left else (a1 - a0) % TAU
            rho = self.r + gap
            if rho * (1 - math.cos(sweep / 2)) < CHORD_TOL:
                # a turn so small that its chord is within CHORD_TOL of the arc
                return [Piece(Line(a, b, src, True), src, CORNER, "line", feed, z, z)], el, True
            arc = Arc(corner, rho, a0, sweep, src, True)
            return [Piece(arc, src, CORNER, "arc", feed, z, z)], el, True
        if trim and type(prev.el) is Line and type(el) is Line:
            (x1, y1), (x2, y2) = prev.el.p0, prev.el.p1
            (x3, y3), (x4, y4) = el.p0, el.p1
            den = (x1 - x2) * (y3 - y4) - (y1 - y2) * (x3 - x4)
            if den != 0.0:
                t = ((x1 - x3) * (y3 - y4) - (y1 - y3) * (x3 - x4)) / den
                u = -((x1 - x2) * (y1 - y3) - (y1 - y2) * (x1 - x3)) / den
                if 1e-12 < t <= 1.0 and 0.0 <= u < 1 - 1e-12:
                    p = (x1 + t * (x2 - x1), y1 + t * (y2 - y1))
                    prev.el = Line(prev.el.p0, p, prev.el.src)
                    prev.z1 = prev.z0 + t * (prev.z1 - prev.z0)
                    return [], Line(p, el.p1, el.src), False
            trim = False
        if trim:
            best = None
            la, lb = prev.el.length(), el.length()
            for ta_, tb_, p in intersect(prev.el, el):
                key = (1 - ta_) * la + tb_ * lb
                if best is None or key < best[0]:
                    best = (key, ta_, tb_, p)
            if best is not None and best[1] > 1e-12 and best[2] < 1 - 1e-12:
                _, ta_, tb_, p = best
                prev.el = prev.el.with_end(p)
                prev.z1 = prev.z0 + ta_ * (prev.z1 - prev.z0)
                return [], el.with_start(p), False
        return [Piece(Line(a, b, src, True), src, CONNECTOR, "line", feed, z, z)], el, False

    def build(self):
        e, r = self.entry, self.r
        c = e.start[:2]
        p0 = e.end[:2]
        if e.kind == "arc":
            # an arc as entry move: straight onto its offset start, then the
            # arc's offset like any contour block
            el = _offset(e, self.side, r)
            if el is None:
                raise GcodeError(e.lineno, "the tool cannot follow the entry arc "
                                           "(concave, smaller than the tool)")
            self.pieces.append(Piece(Line(c, el.start, e.lineno), e.lineno, ENTRY, "line",
                                     e.feed, e.start[2], e.start[2]))
            self.contour = [e] + self.contour
        else:
            d = math.dist(c, p0)
            if d < r - TOL:
                raise GcodeError(e.lineno, f"lead-in move ({d:g} mm) is shorter than "
                                           f"the tool radius ({r:g} mm)")
            ux, uy = (p0[0] - c[0]) / d, (p0[1] - c[1]) / d
            nx, ny = (-uy, ux) if self.left else (uy, -ux)
            end = (p0[0] + r * nx, p0[1] + r * ny)
            self.pieces.append(Piece(Line(c, end, e.lineno), e.lineno, ENTRY, e.kind,
                                     e.feed, e.start[2], e.end[2]))
        moving = [m.kind == "arc" or not _close(m.start, m.end, 1e-12) for m in self.contour]
        xy = [m for m, f in zip(self.contour, moving) if f]
        start_xy = e.start[:2] if e.kind == "arc" else p0
        loop = _loop(start_xy, xy)
        cross = _crossing(xy) if loop is None else None
        if cross is not None:
            # it overruns its start: the blocks that meet are cut where they do, so
            # that the loop closes on a vertex (its lead-in and lead-out keep the rest)
            i, ti, j, tj, pt = cross
            cut = {}
            if 1e-9 < ti < 1 - 1e-9:
                cut[id(xy[i])] = _split(xy[i], ti, pt)
            if 1e-9 < tj < 1 - 1e-9:
                cut[id(xy[j])] = _split(xy[j], tj, pt)
            if cut:
                self.contour = [q for m in self.contour for q in cut.get(id(m), (m,))]
                moving = [m.kind == "arc" or not _close(m.start, m.end, 1e-12)
                          for m in self.contour]
                xy = [m for m, f in zip(self.contour, moving) if f]
            loop = _loop(start_xy, xy)
        self.closed = loop is not None
        again = _second_pass(start_xy, xy, loop) if loop is not None else None
        if again is not None:
            # followed round more than once (depth passes): every pass would be a
            # loop of its own, and the interference check would read the passes'
            # offsets as crossing each other
            raise GcodeError(xy[again].lineno,
                             f"the closed contour of lines {xy[loop[0]].lineno}-"
                             f"{xy[again - 1].lineno} is followed round again from "
                             "here with cutter compensation on (depth passes): "
                             "not supported; turn compensation off (G40) after "
                             "each pass and on again (G41/G42) for the next")
        loop_first = None
        if loop is not None:
            a, b = loop
            loop_first = xy[a]
            if b < len(xy):
                # the lead-out: its moves (from its first block on) are offset after
                # the loop has been followed round (emit_lead_out)
                cut = next(k for k, m in enumerate(self.contour) if m is xy[b])
                self.lead_out = self.contour[cut:]
                self.contour = self.contour[:cut]
                moving = moving[:cut]
            xy = xy[:b]
        # the programmed element of each block, by the block (a block cut where the
        # stretch overruns its start is two, with one line number)
        self.prog_of = {id(m): _programmed_element(m) for m in xy}
        # what the tool must keep its radius from: the loop of a closed stretch (its
        # lead-in, like the entry move, and its lead-out lie in the scrap), every block
        # of an open one
        self.protected = {id(m): self.prog_of[id(m)]
                          for m in xy[0 if loop is None else loop[0]:]}
        first_piece = None
        loop_piece = None
        prog_end = self.entry.end[:2]
        pending_gap = False         # a block without offset since the last piece
        for idx, m in enumerate(self.contour):
            if not moving[idx]:
                last = self.pieces[-1]
                if last.events is None:
                    last.events = []
                last.events.append(m)
                continue
            el = _offset(m, self.side, r)
            if el is None:
                pending_gap = True
                prog_end = self.prog_of[id(m)].end
                continue
            prev = self.pieces[-1]
            is_first = first_piece is None
            if is_first and self.trim_entry:
                el = self._trim_entry(prev, el)
            if pending_gap:
                # over a concave arc smaller than the tool: a straight bridge,
                # kept or removed by the distance test like any piece
                extra = [Piece(Line(prev.el.end, el.start, m.lineno, True), m.lineno,
                               CORNER, "line", m.feed or self.feed, prev.z1, prev.z1)]
                outside = False
            else:
                extra, el, outside = self._corner(prev, el, m.start[:2], m.lineno,
                                                  m.feed or self.feed,
                                                  trim=not is_first and prev.role != ENTRY,
                                                  gap=math.dist(prog_end, m.start[:2]))
            if is_first:
                self.entry_outside = outside and not pending_gap
            pending_gap = False
            prog_end = self.prog_of[id(m)].end
            self.pieces += extra
            z0, z1 = m.start[2], m.end[2]
            piece = Piece(el, m.lineno, CONTOUR, m.kind, m.feed or self.feed, z0, z1)
            if is_first:
                first_piece = piece
                if not self.closed:
                    self.cycle0 = len(self.pieces)
            if loop_piece is None and self.closed and id(m) in self.protected:
                # the loop's first block with an offset: the loop closes onto it
                loop_piece, loop_move = piece, m
                self.cycle0 = len(self.pieces)
            self.pieces.append(piece)
        if first_piece is None:
            raise GcodeError(self.contour[0].lineno, "the tool cannot follow this contour at all")
        if self.closed and loop_piece is None:
            raise GcodeError(loop_first.lineno, "the tool cannot follow this contour at all")
        if self.closed:
            first_piece = loop_piece
            last = self.pieces[-1]
            m_first = loop_move
            start0 = _offset(m_first, self.side, r).start
            if pending_gap:
                extra = [Piece(Line(last.el.end, start0, first_piece.src, True), first_piece.src,
                               CONNECTOR, "line", self.feed, last.z1, last.z1)]
            else:
                tmp = _offset(m_first, self.side, r)
                extra, _, _ = self._corner(last, tmp, m_first.start[:2], first_piece.src,
                                           first_piece.feed, trim=False,
                                           gap=math.dist(prog_end, m_first.start[:2]))
            for p in extra:
                p.z0 = p.z1 = last.z1
            self.closing_from = len(self.pieces)    # the closing join's raw pieces
            self.pieces += extra
            for p in self.pieces[:self.cycle0]:
                if p.role in (CONTOUR, CORNER):
                    p.role = LEAD
        x = self.exit_move
        if not self.closed and x is not None and x.kind != "arc" and \
                math.dist(x.start[:2], x.end[:2]) > TOL:
            # the G40 move starts from its own start point offset to the
            # tool's side and joins the contour like any block (seed 004)
            q0, q1 = x.start[:2], x.end[:2]
            d = math.dist(q0, q1)
            ux, uy = (q1[0] - q0[0]) / d, (q1[1] - q0[1]) / d
            nx, ny = (-uy, ux) if self.left else (uy, -ux)
            el = Line((q0[0] + r * nx, q0[1] + r * ny), q1, x.lineno)
            prev = self.pieces[-1]
            extra, el, self.exit_outside = self._corner(prev, el, q0, x.lineno,
                                                        x.feed or self.feed, trim=False)
            self.pieces += extra
            self.pieces.append(Piece(el, x.lineno, EXIT, x.kind, x.feed, prev.z1, x.end[2]))
            self.has_exit = True

    def _trim_entry(self, prev: Piece, el):
        """LinuxCNC's inside corner after the entry move (interp_convert.cc,
        convert_straight_comp2 / convert_arc_comp2): the entry's end moves
        back along the entry's offset line (through its end, parallel to the
        programmed entry) to where it meets the first block's offset, and the
        block starts there.  A reversal onto an arc the tool runs outside
        counts as an inside corner too (LinuxCNC's "h" shape).  When that
        point lies behind the entry's start, LinuxCNC refuses the program
        (interp_queue.cc, move_endpoint_and_flush: "Straight feed in concave
        corner cannot be reached by the tool without gouging"): so does this.
        Returns el trimmed; raises _NoTrim where the rule does not apply."""
        e = self.entry
        if e.kind == "arc" or prev.role != ENTRY:
            raise _NoTrim
        c, p0 = e.start[:2], e.end[:2]
        d = math.dist(c, p0)
        ux, uy = (p0[0] - c[0]) / d, (p0[1] - c[1]) / d
        tb = el.tangent(0.0)
        cross = ux * tb[1] - uy * tb[0]
        dot = ux * tb[0] + uy * tb[1]
        inside = (cross > 1e-12) if self.left else (cross < -1e-12)
        if abs(cross) <= 1e-12 and dot < 0 and type(el) is Arc:
            inside = (el.sweep > 0) != self.left        # the tool outside the arc
        if not inside:
            raise _NoTrim
        end = prev.el.end
        far = Line(end, (end[0] - ux * (d + 4 * self.r), end[1] - uy * (d + 4 * self.r)))
        hits = [(ta, tb_, pt) for ta, tb_, pt in intersect(far, el) if tb_ < 1 - 1e-12]
        if not hits:
            raise _NoTrim
        ta, tb_, mid = min(hits)
        back = ta * far.length()
        if back >= d - TOL:
            raise GcodeError(e.lineno, f"the tool (radius {self.r:g} mm) cannot join the "
                                       "contour from this entry move without gouging: the "
                                       "inside corner lies behind the entry's start (LinuxCNC "
                                       "refuses it too)")
        prev.el = Line(prev.el.p0, mid, prev.el.src)
        if type(el) is Line:
            return Line(mid, el.p1, el.src)
        return el.with_start(mid)

    # -- 2. cut at every crossing ------------------------------------------------------
    def cut(self):
        pieces = self.pieces
        n = len(pieces)
        for k, p in enumerate(pieces):
            p.raw = k
        arr = self.arr = pack([p.el for p in pieces])
        if n < 3:
            return
        bx = boxes(arr)
        ii, jj = box_pairs(bx, bx, 1e-9)
        keep = ii < jj
        ii, jj = ii[keep], jj[keep]
        keep = jj != ii + 1
        if self.closed:
            keep &= ~((ii == self.cycle0) & (jj == n - 1))
        ii, jj = ii[keep], jj[keep]
        # only pairs that touch somewhere can cross (vectorised pre-test)
        if len(ii):
            touch = element_distance(arr[ii], arr[jj]) <= 1e-9
            ii, jj = ii[touch], jj[touch]
        cuts: dict[int, list] = {}
        if not self.closed:
            # an open contour exposes what a closed one keeps inside the part:
            # the far side of each block and the ends.  Their offsets bound
            # the forbidden zone too; they cut pieces but are never followed.
            bars = self._barriers()
            if bars:
                barr = pack(bars)
                bi, bj = box_pairs(bx, boxes(barr), 1e-9)
                if len(bi):
                    touch = element_distance(arr[bi], barr[bj]) <= 1e-9
                    for i, j in zip(bi[touch].tolist(), bj[touch].tolist()):
                        for ta, _, pt in intersect(pieces[i].el, bars[j]):
                            length = pieces[i].el.length()
                            # (a piece that merely touches a barrier at its
                            # end, as offsets of the first block do, is not cut)
                            if 1e-6 < ta * length and (1 - ta) * length > 1e-6:
                                cuts.setdefault(i, []).append((ta, pt))
        for i, j in zip(ii.tolist(), jj.tolist()):
            for ta, tb, pt in intersect(pieces[i].el, pieces[j].el):
                if MIN_PIECE < ta * pieces[i].el.length() and \
                        (1 - ta) * pieces[i].el.length() > MIN_PIECE:
                    cuts.setdefault(i, []).append((ta, pt))
                if MIN_PIECE < tb * pieces[j].el.length() and \
                        (1 - tb) * pieces[j].el.length() > MIN_PIECE:
                    cuts.setdefault(j, []).append((tb, pt))
        self.cut_keys = set()
        self.cut_points = [pt for cs in cuts.values() for _, pt in cs]
        for cs in cuts.values():
            for _, pt in cs:
                kx, ky = round(pt[0] * 1e6), round(pt[1] * 1e6)
                for dx in (-1, 0, 1):
                    for dy in (-1, 0, 1):
                        self.cut_keys.add((kx + dx, ky + dy))
        if not cuts:
            return
        out = []
        cycle0 = self.cycle0
        for k, p in enumerate(pieces):
            if k == self.cycle0:
                cycle0 = len(out)
            cs = cuts.get(k)
            if not cs:
                out.append(p)
                continue
            cs.sort(key=lambda c: c[0])
            ts = [0.0] + [c[0] for c in cs] + [1.0]
            ps = [p.el.start] + [c[1] for c in cs] + [p.el.end]
            events = p.events
            for a in range(len(ts) - 1):
                if ts[a + 1] - ts[a] <= 0 and math.dist(ps[a], ps[a + 1]) <= MIN_PIECE:
                    continue
                zz0 = p.z0 + ts[a] * (p.z1 - p.z0)
                zz1 = p.z0 + ts[a + 1] * (p.z1 - p.z0)
                out.append(Piece(_sub(p.el, ts[a], ts[a + 1], ps[a], ps[a + 1]), p.src, p.role,
                                 p.kind, p.feed, zz0, zz1, k, ts[a], ts[a + 1]))
            out[-1].events = events
        self.pieces = out
        self.cycle0 = cycle0
        self.arr = pack([p.el for p in out])

    def _barriers(self):
        """Far-side offsets of the contour's blocks and circles of radius r
        round its two ends (an open contour's forbidden zone boundary)."""
        r, out = self.r, []
        far = "right" if self.left else "left"
        for m in self.contour:
            if id(m) not in self.prog_of:
                continue
            el = _offset(m, far, r)
            if el is not None:
                out.append(el)
        progs = list(self.prog_of.values())
        if progs:
            for p in (progs[0].start, progs[-1].end):
                out.append(Arc(p, r, 0.0, math.pi))
                out.append(Arc(p, r, math.pi, math.pi))
        return out

    # -- 3. distance test ------------------------------------------------------------------
    def classify(self, programmed, prog_arr):
        pieces = self.pieces
        if self.closed and not self.cut_keys and not self.has_exit and \
                not any(p.role == CONNECTOR for p in pieces):
            # nothing crosses and nothing was bridged: the raw path of a
            # closed or open contour is its own offset (the gouge check on
            # the result stands behind this shortcut)
            for p in pieces:
                p.valid = p.el.length() > MIN_PIECE or p.role in (ENTRY, EXIT)
            return
        r = self.r
        a = self.arr
        arc = a[:, K] == 1
        length = np.where(arc, np.abs(a[:, SW]) * a[:, R], np.hypot(a[:, X1] - a[:, X0],
                                                                     a[:, Y1] - a[:, Y0]))
        pb = boxes(prog_arr)
        ccx, ccy = (pb[:, 0] + pb[:, 2]) / 2, (pb[:, 1] + pb[:, 3]) / 2
        hh = np.hypot(pb[:, 2] - pb[:, 0], pb[:, 3] - pb[:, 1]) / 2
        limit = r - KEEP_TOL - self.slack

        def too_close(idx):
            """Is the midpoint of each piece idx[k] closer than r to the contour?"""
            idx = np.asarray(idx, dtype=np.int64)
            half = a[idx, A0] + a[idx, SW] / 2
            qx = np.where(arc[idx], a[idx, CX] + a[idx, R] * np.cos(half),
                          (a[idx, X0] + a[idx, X1]) / 2)
            qy = np.where(arc[idx], a[idx, CY] + a[idx, R] * np.sin(half),
                          (a[idx, Y0] + a[idx, Y1]) / 2)
            i, j = box_pairs(np.stack([qx, qy, qx, qy], axis=1), pb, r)
            near = np.hypot(qx[i] - ccx[j], qy[i] - ccy[j]) - hh[j] < r
            i, j = i[near], j[near]
            d = point_distance(qx[i], qy[i], prog_arr[j])
            out = np.zeros(len(idx), bool)
            out[i[d < limit]] = True
            return out

        # runs of pieces between crossings, connectors and role changes keep
        # one side of every other block's offset: test the first, longest and
        # last piece of each run, and every piece of a run where they differ
        cut_keys = self.cut_keys
        runs, cur = [], []
        prev_role = None
        for k, p in enumerate(pieces):
            role = p.role if p.role in (ENTRY, EXIT, CONNECTOR) else CONTOUR
            st = p.el.start
            if cur and (role != prev_role or role == CONNECTOR or
                        (cut_keys and (round(st[0] * 1e6), round(st[1] * 1e6)) in cut_keys)):
                runs.append(cur)
                cur = []
            cur.append(k)
            prev_role = role
        if cur:
            runs.append(cur)
        probe, owner = [], []
        for n_run, run in enumerate(runs):
            best = max(run, key=lambda q: length[q])
            for q in dict.fromkeys((run[0], best, run[-1])):
                probe.append(q)
                owner.append(n_run)
        res = too_close(probe)
        verdict: dict[int, set] = {}
        for q, o, v in zip(probe, owner, res.tolist()):
            verdict.setdefault(o, set()).add(v)
        close = np.zeros(len(pieces), bool)
        mixed = []
        for n_run, run in enumerate(runs):
            v = verdict[n_run]
            if len(v) > 1:
                mixed += run
            elif True in v:
                close[run] = True
        if mixed:
            close[mixed] = too_close(mixed)
        close |= length <= MIN_PIECE
        close = close.tolist()
        for k, p in enumerate(pieces):
            if p.role == CONNECTOR:
                p.valid = False
            else:
                p.valid = not close[k]
        # the entry: exempt, except what lies behind its last crossing at an inside corner
        entry = [k for k, p in enumerate(pieces) if p.role == ENTRY]
        if self.entry_outside and entry:
            pieces[entry[-1]].valid = True
        trailing = True
        for k in reversed(entry):
            if trailing and not pieces[k].valid:
                continue
            trailing = False
            pieces[k].valid = True
        if entry and not pieces[entry[0]].valid:
            pieces[entry[0]].valid = True       # the entry move always starts
        # the exit: exempt, except what lies before its first crossing with
        # the contour's offset when it leaves at an inside corner
        exits = [k for k, p in enumerate(pieces) if p.role == EXIT]
        if self.exit_outside and exits:
            pieces[exits[0]].valid = True
        leading = True
        for k in exits:
            if leading and not pieces[k].valid:
                continue
            leading = False
            pieces[k].valid = True
        if exits:
            pieces[exits[-1]].valid = True

    # -- 4. follow --------------------------------------------------------------------------
    def follow(self):
        pieces = self.pieces
        n = len(pieces)
        closed = self.closed
        c0 = self.cycle0
        ncyc = n - c0

        def key(p):
            return (round(p[0] * 1e6), round(p[1] * 1e6))

        cut_keys = self.cut_keys
        starts: dict = {}
        end_at_cut: set = set()
        if cut_keys:
            # pieces that start or end at a crossing (found for all at once)
            a = self.arr
            cp = np.array(self.cut_points)
            cb = np.concatenate([cp, cp], axis=1)
            ends = np.stack([a[:, X1], a[:, Y1], a[:, X1], a[:, Y1]], axis=1)
            end_at_cut = set(box_pairs(ends, cb, 2e-6)[0].tolist())
            begs = np.stack([a[:, X0], a[:, Y0], a[:, X0], a[:, Y0]], axis=1)
            for k in sorted(set(box_pairs(begs, cb, 2e-6)[0].tolist())):
                p = pieces[k]
                if p.valid and p.role != ENTRY:
                    starts.setdefault(key(p.el.start), []).append(k)

        def at(point):
            kx, ky = key(point)
            out = []
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for q in starts.get((kx + dx, ky + dy), ()):
                        if math.dist(pieces[q].el.start, point) <= 2e-6:
                            out.append(q)
            return out

        def ahead(k, q):
            if closed:
                if k < c0:
                    return q - c0 if q >= c0 else -1
                return (q - k) % ncyc if q >= c0 else -1
            return q - k

        if not cut_keys:
            # nothing crosses: the path is the raw path up to the first removed piece
            chain = [0]
            k = 0
            while True:
                nxt = k + 1 if k + 1 < n else (c0 if closed else None)
                if nxt is None or (closed and nxt == c0 and k >= c0) or not pieces[nxt].valid \
                        or (pieces[nxt].role == ENTRY and pieces[k].role != ENTRY):
                    break
                chain.append(nxt)
                k = nxt
            self._finish(chain, set(chain))
            return
        used = [False] * n
        chain = [0]
        used[0] = True
        passed = {0}
        attach = None
        k = 0
        while True:
            end = pieces[k].el.end
            nxt = k + 1 if k + 1 < n else (c0 if closed else None)
            if nxt is not None and nxt != attach and not used[nxt] and pieces[nxt].valid and \
                    pieces[nxt].role != ENTRY and k not in end_at_cut:
                if attach is None and nxt >= c0:
                    attach = nxt
                used[nxt] = True
                chain.append(nxt)
                passed.add(nxt)
                k = nxt
                if closed and attach != nxt and \
                        _close(pieces[k].el.end, pieces[attach].el.start, 2e-6):
                    self._pass_to(k, attach, passed)
                    break
                continue
            cands = []
            if nxt is not None and not used[nxt] and pieces[nxt].valid and \
                    (pieces[nxt].role != ENTRY or pieces[k].role == ENTRY):
                cands.append((ahead(k, nxt), nxt))
            for q in (at(end) if k in end_at_cut else ()):
                if not used[q] and q != nxt and ahead(k, q) > 0:
                    cands.append((ahead(k, q), q))
            if not cands:
                break
            _, q = max(cands)
            if closed and attach is not None and q == attach:
                break
            # everything between k and q is passed by
            step = k
            while step != q:
                step = step + 1 if step + 1 < n else c0
                passed.add(step)
            if attach is None and q >= c0:
                attach = q
            used[q] = True
            chain.append(q)
            k = q
            if closed and attach is not None and attach != q and \
                    _close(pieces[k].el.end, pieces[attach].el.start, 2e-6):
                # passed the pieces between here and the attach point too
                self._pass_to(k, attach, passed)
                break
        self._finish(chain, passed)

    def _pass_to(self, k, attach, passed):
        """Mark the pieces after k up to the attach point (cyclically) passed by."""
        n, c0 = len(self.pieces), self.cycle0
        step = k
        while True:
            step = step + 1 if step + 1 < n else c0
            if step == attach:
                return
            passed.add(step)

    def _finish(self, chain, passed):
        pieces = self.pieces
        k = chain[-1]
        self.chain = chain
        self.passed = passed
        if self.has_exit and pieces[k].role != EXIT:
            raise GcodeError(self.exit_move.lineno, f"the tool (radius {self.r:g} mm) cannot "
                                                    "reach the G40 move without gouging")
        unreached = [p for k, p in enumerate(pieces) if p.valid and k not in passed
                     and p.role not in (ENTRY, EXIT)]
        lost = {}
        for p in unreached:
            lost[p.src] = lost.get(p.src, 0.0) + p.el.length()
        lost = sorted(s for s, v in lost.items() if v > REACH_TOL)
        if lost:
            raise GcodeError(lost[0], f"the tool (radius {self.r:g} mm) cannot reach "
                                      f"{line_ranges(lost)} without gouging: the way there is "
                                      "narrower than the tool")

    def emit(self):
        """Moves of the chain; consecutive parts of one raw element are merged.

        Z-only moves keep their place in program order: the pieces are in program
        order (the parts of a cut element in a row), and a Z-only move that follows
        piece i is made where the path first goes on past piece i (before the first
        move of a later piece), or at the path's end.  So a plunge after the entry
        comes before the contour even where the entry was cut short, and a retract
        after a closed loop's last block comes after the loop has closed, even where
        the path closes on the first block's part before the entry's join."""
        pieces = self.pieces
        groups: list[list[int]] = []
        if not self.cut_keys:
            groups = [[k] for k in self.chain]
        else:
            for k in self.chain:
                p = pieces[k]
                g = groups[-1] if groups else None
                q = pieces[g[-1]] if g else None
                if q is not None and q.raw == p.raw and abs(q.t1 - p.t0) < 1e-12 and \
                        _close(q.el.end, p.el.start, 1e-9):
                    g.append(k)
                else:
                    groups.append([k])
        out: list[Move] = []
        self.path, self.path_roles, self.path_out = [], [], []
        if len(groups) == len(self.chain):
            self.path_arr = self.arr[self.chain]
        else:
            self.path_arr = None
        # the Z-only moves in program order: (the piece they follow, their order)
        pending = [(i, j, ev) for i, p in enumerate(pieces) if p.events
                   for j, ev in enumerate(p.events)]
        done = 0
        reached = -1
        t = None

        def z_moves(before: int):
            nonlocal done
            while done < len(pending) and pending[done][0] < before:
                ev = pending[done][2]
                out.append(Move(ev.kind, (t[0], t[1], ev.start[2]), (t[0], t[1], ev.end[2]),
                                ev.lineno, ev.feed))
                done += 1

        for g in groups:
            first, last = pieces[g[0]], pieces[g[-1]]
            reached = max(reached, g[-1])
            if t is not None:
                z_moves(reached)
            if first is last:
                el = first.el
            elif type(first.el) is Line:
                el = Line(first.el.start, last.el.end, first.src, first.el.corner)
            else:
                el = Arc(first.el.c, first.el.r, first.el.a0,
                         sum(pieces[k].el.sweep for k in g), first.src, first.el.corner)
            self.path.append(el)
            self.path_roles.append(first.role)
            self.path_out.append(len(out))
            if type(el) is Line:
                (sx, sy), t = el.p0, el.p1
                kind = first.kind if first.kind != "arc" else "line"
                out.append(Move(kind, (sx, sy, first.z0), (t[0], t[1], last.z1), first.src,
                                0.0 if kind == "rapid" else first.feed))
            else:
                sx, sy = first.el.start
                # a full circle ends exactly where it starts (its end from the angle
                # is a rounding error off, which read as a zero sweep downstream)
                t = (sx, sy) if _full_turn(el) else last.el.end
                out.append(Move("arc", (sx, sy, first.z0), (t[0], t[1], last.z1), first.src,
                                first.feed, el.c, el.sweep < 0, 17))
        # the rest at the path's end, in program order
        if t is not None:
            z_moves(len(pieces))
        self.stray = [ev for _, _, ev in pending[done:]]
        return out

    def emit_lead_out(self, out: list[Move]) -> list[Move]:
        """The closed loop's lead-out after the loop's moves ``out``: the Z-only
        moves left at the path's end first, then back along the path to the end of
        the loop's last block (below), then each lead-out block offset to the tool's
        side and joined like any corner (role LEAD: checked with the rest against
        the loop, left out of the self-crossing check)."""
        r = self.r
        last = self.path[-1]
        z = out[-1].end[2]
        end = last.end
        for ev in self.stray:
            out.append(Move(ev.kind, (end[0], end[1], z), (end[0], end[1], ev.end[2]),
                            ev.lineno, ev.feed))
            z = ev.end[2]
        self.stray = []
        pieces: list[Piece] = []
        # the loop was cut all round, to where the path joined it: past its last
        # block's end come the closing join and, when the path joined the loop past
        # its start, the first block's stretch up to there.  The lead-out leaves from
        # the last block's end, as the program goes: back along that tail of the path
        # (the same tool path, reversed), then the corner between the last block and
        # the lead-out
        last_raw = self.closing_from - 1
        ends = [k for k, q in enumerate(self.chain)
                if self.pieces[q].raw == last_raw and self.pieces[q].t1 == 1.0]
        if ends and ends[-1] < len(self.chain) - 1:
            for q in reversed(self.chain[ends[-1] + 1:]):
                el = self.pieces[q].el
                back = Line(el.p1, el.p0, el.src, True) if type(el) is Line else \
                    Arc(el.c, el.r, el.a0 + el.sweep, -el.sweep, el.src, True)
                pieces.append(Piece(back, self.pieces[q].src, LEAD,
                                    "line" if type(el) is Line else "arc", self.feed, z, z))
            last = self.pieces[self.chain[ends[-1]]].el
            end = last.end
        # the loop's last element, as the piece the first corner joins (not trimmed)
        prev = Piece(last, last.src, CONTOUR, "line", self.feed, z, z)
        retraced = len(pieces)
        prog_end = None             # the loop closes where the lead-out starts
        for m in self.lead_out:
            if m.kind != "arc" and _close(m.start[:2], m.end[:2], 1e-12):
                holder = pieces[-1] if pieces else None
                if holder is None:
                    out.append(Move(m.kind, (end[0], end[1], z), (end[0], end[1], m.end[2]),
                                    m.lineno, m.feed))
                    z = m.end[2]
                else:
                    holder.events = (holder.events or []) + [m]
                continue
            el = _offset(m, self.side, r)
            if el is None:
                raise GcodeError(m.lineno, "the tool cannot follow the lead-out arc "
                                           "(concave, smaller than the tool)")
            gap = 0.0 if prog_end is None else math.dist(prog_end, m.start[:2])
            extra, el, _ = self._corner(prev, el, m.start[:2], m.lineno, m.feed or self.feed,
                                        trim=len(pieces) > retraced, gap=gap)
            if len(pieces) == retraced and \
                    math.dist((extra[0].el if extra else el).start, end) > 1e-9:
                # the path was joined past the loop's closing point (an entry trimmed
                # onto the loop's first block): straight back to the lead-out, which
                # the check tests like every piece
                extra = [Piece(Line(end, el.start, m.lineno, True), m.lineno, LEAD, "line",
                               m.feed or self.feed, z, z)]
            for q in extra:
                q.role = LEAD
                q.z0 = q.z1 = prev.z1
            piece = Piece(el, m.lineno, LEAD, m.kind, m.feed or self.feed, m.start[2], m.end[2])
            pieces += extra + [piece]
            prev = piece
            prog_end = _programmed_element(m).end
        if self.path_arr is not None and pieces:
            self.path_arr = None
        for p in pieces:
            el = p.el
            self.path.append(el)
            self.path_roles.append(LEAD)
            self.path_out.append(len(out))
            (sx, sy), (tx, ty) = el.start, el.end
            if type(el) is not Line and _full_turn(el):
                tx, ty = sx, sy
            if type(el) is Line:
                kind = p.kind if p.kind != "arc" else "line"
                out.append(Move(kind, (sx, sy, p.z0), (tx, ty, p.z1), p.src,
                                0.0 if kind == "rapid" else p.feed))
            else:
                out.append(Move("arc", (sx, sy, p.z0), (tx, ty, p.z1), p.src, p.feed, el.c,
                                el.sweep < 0, 17))
            for ev in p.events or ():
                out.append(Move(ev.kind, (tx, ty, ev.start[2]), (tx, ty, ev.end[2]),
                                ev.lineno, ev.feed))
        return out


class _NoTrim(Exception):
    """The LinuxCNC entry trim does not apply to this entry."""


def _stretch(entry, contour, side, r, exit_move, trim_entry):
    """Build, cut, classify and follow one stretch; (stretch, programmed
    elements, their array, the arc-end slack)."""
    st = _Stretch(entry, contour, side, r, exit_move)
    st.trim_entry = trim_entry
    st.build()
    st.cut()
    programmed = list(st.protected.values())
    prog_arr = pack(programmed)
    # an arc runs about its centre with its start radius; its end may be
    # a rounding error (at most LinuxCNC's arc tolerance) away from where
    # the next block starts: the checks allow that much on top of TOL
    slack = float(np.hypot(prog_arr[:-1, X1] - prog_arr[1:, X0],
                           prog_arr[:-1, Y1] - prog_arr[1:, Y0]).max()) \
        if len(programmed) > 1 else 0.0
    st.slack = slack
    st.classify(programmed, prog_arr)
    st.follow()
    return st, programmed, prog_arr, slack


def _violations(path, roles, programmed, prog_arr, r, tol, arr=None):
    """(gouges, self-crossings) of the path between the entry and exit moves,
    as path indices: gouges as (path index, programmed index, distance),
    crossings as (path index, path index)."""
    keep = [k for k, role in enumerate(roles) if role not in (ENTRY, EXIT)]
    body = [path[k] for k in keep]
    body_arr = arr[keep] if arr is not None else pack(body)
    bad = check.gouges(body, programmed, r, tol, arrays=(body_arr, prog_arr))
    if bad:
        return [(keep[i], j, d) for i, j, d in bad], []
    # the self-crossing check leaves out a closed loop's lead-in and lead-out too
    loop = [k for k, role in enumerate(roles) if role not in (ENTRY, EXIT, LEAD)]
    crossings = check.self_crossings([path[k] for k in loop],
                                     arr=arr[loop] if arr is not None else None)
    return [], [(loop[i], loop[j]) for i, j in crossings]


def _checked(st, out, programmed, prog_arr, r, tol, strict):
    """Run the independent check on a stretch's result: (moves, warning).

    A gouge or self-crossing is an error naming the programmed lines; without
    ``strict``, the offending stretch of the path (from the first element
    involved to the last) is removed and bridged by a straight move where
    the result passes the same check again (the warning names the lines)."""
    path, roles = st.path, st.path_roles
    bad, crossings = _violations(path, roles, programmed, prog_arr, r, tol, st.path_arr)
    if not bad and not crossings:
        return out, None

    def error():
        if bad:
            worst = min(bad, key=lambda b: b[2])
            lines = sorted({programmed[b[1]].src for b in bad} | {path[b[0]].src for b in bad})
            return GcodeError(lines[0], f"the compensated path comes {r - worst[2]:.3g} mm too "
                                        f"close to the contour near {line_ranges(lines)} "
                                        f"(tool radius {r:g} mm)")
        lines = sorted({path[i].src for i, _ in crossings} | {path[j].src for _, j in crossings})
        return GcodeError(lines[0], f"the compensated path crosses itself near "
                                    f"{line_ranges(lines)}")

    if strict:
        raise error()
    ks = [b[0] for b in bad] + [k for c in crossings for k in c]
    a, b = min(ks), max(ks)
    if any(role in (ENTRY, EXIT) for role in roles[a:b + 1]):
        raise error()
    p0, p1 = path[a].start, path[b].end
    bridge = [Line(p0, p1, path[a].src)] if not _close(p0, p1, 1e-9) else []
    new_path = path[:a] + bridge + path[b + 1:]
    new_roles = roles[:a] + [CONNECTOR] * len(bridge) + roles[b + 1:]
    bad2, cross2 = _violations(new_path, new_roles, programmed, prog_arr, r, tol)
    if bad2 or cross2:
        raise error()
    i0, i1 = st.path_out[a], st.path_out[b + 1] if b + 1 < len(path) else len(out)
    removed = out[i0:i1]
    lines = sorted({m.lineno for m in removed})
    # Z-only moves inside the stretch keep their order after the bridge
    events = [m for m in removed if m.kind != "arc" and _close(m.start[:2], m.end[:2], 1e-12)]
    z, z_end = out[i0].start[2], out[i1 - 1].end[2]
    mid = []
    if bridge:
        m0 = out[i0]
        z1 = z if events else z_end
        mid.append(Move("line", (p0[0], p0[1], z), (p1[0], p1[1], z1), m0.lineno,
                        m0.feed or st.feed))
        z = z1
    for ev in events + ([out[i1 - 1]] if events else []):
        if ev.end[2] != z:
            mid.append(Move("line" if ev.kind == "arc" else ev.kind, (p1[0], p1[1], z),
                            (p1[0], p1[1], ev.end[2]), ev.lineno, ev.feed or st.feed))
            z = ev.end[2]
    what = "too close to the contour" if bad else "crossing itself"
    note = (f"{line_ranges(lines)}: path removed (it came {what}) and bridged by a straight "
            f"move that the tool (radius {r:g} mm) can follow")
    return out[:i0] + mid + out[i1:], note


def compensate(moves: list[Move], window: int = 5, strict: bool = False) -> CompResult:
    """Apply cutter compensation to parsed moves; see the module docstring."""
    result: list[Move] = []
    warnings: list[str] = []
    skipped_all: list[int] = []
    k = 0
    n_moves = len(moves)
    while k < n_moves:
        m = moves[k]
        if m.comp == "off":
            result.append(m)
            k += 1
            continue
        side, r = m.comp, m.radius
        # moves without XY motion before the entry move run as they are
        while k < n_moves and moves[k].comp != "off" and moves[k].kind != "arc" and \
                _close(moves[k].start[:2], moves[k].end[:2], 1e-12):
            result.append(moves[k])
            k += 1
        if k >= n_moves or moves[k].comp == "off":
            continue
        entry = moves[k]
        if r <= 0:
            # D0 / a zero diameter: the path is the programmed one
            while k < n_moves and moves[k].comp != "off":
                result.append(moves[k])
                k += 1
            continue
        k += 1
        contour = []
        while k < n_moves and moves[k].comp != "off":
            c = moves[k]
            if c.kind == "arc" and c.plane != 17:
                raise GcodeError(c.lineno, "compensated arcs must be in G17")
            contour.append(c)
            k += 1
        if not any(c.kind == "arc" or not _close(c.start[:2], c.end[:2], 1e-12) for c in contour) \
                and entry.kind != "arc":
            if k < n_moves:
                raise GcodeError(moves[k].lineno,
                                 "cutter compensation on for the lead-in move only")
            raise GcodeError(entry.lineno, "cutter compensation on for the lead-in move only")
        exit_move = moves[k] if k < n_moves else None
        try:
            st, programmed, prog_arr, slack = _stretch(entry, contour, side, r, exit_move, False)
        except GcodeError as first_error:
            # the path stopped at an inside corner behind the entry: the
            # entry's end moved back along its offset onto the contour's
            # offset, as LinuxCNC moves it (an error naming the entry move
            # when that lies behind the entry's start)
            try:
                st, programmed, prog_arr, slack = _stretch(entry, contour, side, r, exit_move,
                                                           True)
            except _NoTrim:
                raise first_error from None
        out = st.emit()
        if st.lead_out:
            out = st.emit_lead_out(out)
        # the independent check of the result (entry excluded)
        out, note = _checked(st, out, programmed, prog_arr, r, TOL + slack, strict)
        if note:
            warnings.append(note)
        present = {p.src for kk in st.chain for p in [st.pieces[kk]]
                   if p.role in (CONTOUR, LEAD)}
        skipped = sorted({c.lineno for c in st.contour if c.kind == "arc" or
                          not _close(c.start[:2], c.end[:2], 1e-12)} - present - {entry.lineno})
        if skipped:
            if strict:
                raise GcodeError(skipped[0], f"the tool (radius {r:g} mm) cannot follow "
                                             "the contour here")
            warnings.append(f"{line_ranges(skipped)}: skipped, the tool (radius {r:g} mm) "
                            "cannot follow the contour there")
            skipped_all += skipped
        first = len(result)
        result += out
        last = out[-1].end
        for ev in st.stray:
            result.append(Move(ev.kind, last, (last[0], last[1], ev.end[2]), ev.lineno, ev.feed))
            last = result[-1].end
        # the exit move: from the last point of the path to its programmed end
        if st.has_exit:
            k += 1
        elif k < n_moves:
            x = moves[k]
            if x.kind == "arc":
                if not _close(last[:2], x.start[:2], 1e-12):
                    result.append(Move("line", last, x.start, x.lineno, x.feed or st.feed))
                result.append(x)
            else:
                result.append(Move(x.kind, last, x.end, x.lineno, x.feed))
            k += 1
        # the moves made of a block keep its path mode (G61.1 stops after each)
        modes = {m.lineno: (m.path_mode, m.path_tolerance, m.naive_tolerance)
                 for m in (entry, *contour, exit_move) if m is not None}
        for mv in result[first:]:
            if mv.lineno in modes:
                mv.path_mode, mv.path_tolerance, mv.naive_tolerance = modes[mv.lineno]
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
            zw = f" Z{_num(z)}" if m.end[2] != m.start[2] else ""
            out.append(f"{'G2' if m.cw else 'G3'} X{_num(x)} Y{_num(y)}{zw} I{_num(i)} J{_num(j)}"
                       f"{fw}")
    out.append("M2")
    return "\n".join(out) + "\n"
