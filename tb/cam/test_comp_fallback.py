# SPDX-License-Identifier: Apache-2.0
"""Issue 12, item 3: what the gouge check does with a violation.

The compensation never builds a gouge on purpose, so the check is exercised
here on a path made wrong after the fact: the path ``compensate`` emits is
bent into the part (a bulge towards the contour, or a whole element moved
onto it), as a construction bug would.  Without ``strict`` the offending
stretch is removed and bridged with a warning naming its lines when the
bridged path passes the check again; otherwise, and always with ``strict``,
it is an error naming the programmed lines."""

from __future__ import annotations

import pytest

from halfpoint.cam import comp
from halfpoint.cam.gcode import GcodeError, Move, parse
from halfpoint.cam.geom import Line

SQUARE = """G21 G90 F600
G0 X-5 Y-10
G42.1 D2 G1 X0 Y-10
X40
Y40
X0
Y-10
G40 G1 X-5 Y-10
M2"""


def bend(monkeypatch, mode):
    """Make the emitted path gouge at the contour line 4 (X40, y = -10)."""
    orig = comp._Stretch.emit

    def emit(self):
        out = orig(self)
        k = next(i for i, el in enumerate(self.path)
                 if el.src == 4 and type(el) is Line and self.path_roles[i] == comp.CONTOUR)
        el, i = self.path[k], self.path_out[k]
        (x0, y0), (x1, y1) = el.p0, el.p1
        m = out[i]
        if mode == "bulge":
            # a tent 0.6 mm into the part in the middle of the line
            mid = ((x0 + x1) / 2, (y0 + y1) / 2 + 0.6)
            parts = [Line(el.p0, mid, 4), Line(mid, el.p1, 4)]
            moves = [Move("line", m.start, (mid[0], mid[1], m.start[2]), 4, m.feed),
                     Move("line", (mid[0], mid[1], m.start[2]), m.end, 4, m.feed)]
            self.path[k:k + 1] = parts
            self.path_roles[k:k + 1] = [comp.CONTOUR, comp.CONTOUR]
            self.path_out[k + 1:] = [j + 1 for j in self.path_out[k + 1:]]
            self.path_out.insert(k + 1, i + 1)
            out[i:i + 1] = moves
        else:
            # the whole line moved 0.5 mm towards the contour
            self.path[k] = Line((x0, y0 + 0.5), (x1, y1 + 0.5), 4)
        self.path_arr = None
        return out

    monkeypatch.setattr(comp._Stretch, "emit", emit)


def test_a_clean_path_passes():
    res = comp.compensate(parse(SQUARE).moves)
    assert res.warnings == []


def test_bulge_is_removed_with_a_warning_naming_its_line(monkeypatch):
    bend(monkeypatch, "bulge")
    res = comp.compensate(parse(SQUARE).moves)
    assert len(res.warnings) == 1 and res.warnings[0].startswith("line 4: path removed")
    # the bridge is the line as it should have been: y = -11 from x = 0 to 40
    line4 = [m for m in res.moves if m.lineno == 4 and m.kind == "line"]
    assert len(line4) == 1, line4
    assert abs(line4[0].start[1] + 11) < 1e-9 and abs(line4[0].end[1] + 11) < 1e-9
    assert abs(line4[0].start[0]) < 1e-9 and abs(line4[0].end[0] - 40) < 1e-9


def test_bulge_is_an_error_with_strict(monkeypatch):
    bend(monkeypatch, "bulge")
    with pytest.raises(GcodeError, match=r"line 4: the compensated path comes 0\.6 mm too close"):
        comp.compensate(parse(SQUARE).moves, strict=True)


def test_no_gouge_free_bridge_is_an_error(monkeypatch):
    bend(monkeypatch, "shift")
    with pytest.raises(GcodeError, match=r"line 4: the compensated path comes 0\.5 mm too close"):
        comp.compensate(parse(SQUARE).moves)
