# SPDX-License-Identifier: Apache-2.0
"""The arc-to-axes mapper (``spec.helix``) and the core's arc decode (issue 14, item 2):
every helix axis ends exactly on its delta after exactly N moves, at most one step per
move and on the closed form floor((k |d| + floor(N/2)) / N) after every move; the arc's
own steps land on the plane's axes (G17 X Y, G18 Z X, G19 Y Z); a count other than the
arc's moves drops the helix steps beyond N or leaves them short and flags the last move;
the decode's errors (E_OPCODE, E_FIELD, E_HELIX) and the encoding's round trip."""

from __future__ import annotations

import random

import pytest

from halfpoint.spec import encoding as enc
from halfpoint.spec.arc import arc_points, arc_stop
from halfpoint.spec.core import decode_for_core
from halfpoint.spec.helix import HelixCommand, HelixMapper, map_arc, steps_after
from halfpoint.spec.program import expect, profiled, random_helix


def _plane_moves(rng, n):
    """n random in-plane moves (axis or diagonal)."""
    return [rng.choice(((1, 0), (0, -1), (1, 1), (-1, 1))) for _ in range(n)]


@pytest.mark.parametrize("axes", [3, 4, 6])
def test_helix_axes_end_exactly_after_n_moves(axes):
    rng = random.Random(axes)
    for _ in range(300):
        n = rng.choice((1, 2, 3, rng.randint(4, 50), rng.randint(51, 3000)))
        u, v = rng.choice([p for p in enc.PLANES.values()])
        slots = enc.helix_axes(u, v, axes)
        deltas = tuple(rng.randint(-n, n) for _ in slots)
        cmd = HelixCommand(u, v, n, deltas + (0,) * (enc.HELIX_SLOTS - len(deltas)))
        plane = _plane_moves(rng, n)
        steps = map_arc(plane, cmd, axes)
        total = [0] * axes
        for k, (st, (du, dv)) in enumerate(zip(steps, plane), start=1):
            assert st[u] == du and st[v] == dv
            assert all(abs(s) <= 1 for s in st)
            total = [t + s for t, s in zip(total, st)]
            for axis, d in zip(slots, deltas):
                assert total[axis] == steps_after(k, n, d), (n, d, k)
        for axis, d in zip(slots, deltas):
            assert total[axis] == d
        others = set(range(axes)) - {u, v} - set(slots)
        assert all(total[a] == 0 for a in others)


def test_closed_form_is_the_nearest_with_halves_down():
    # floor((k d + floor(N/2)) / N) is within 1/2 of k d / N at every move
    for n in range(1, 60):
        for d in range(0, n + 1):
            for k in range(n + 1):
                assert abs(steps_after(k, n, d) - k * d / n) <= 0.5


@pytest.mark.parametrize("miss", [-3, -1, 1, 4])
def test_a_wrong_count_never_runs_away(miss):
    rng = random.Random(miss)
    n = 40
    cmd = HelixCommand(0, 1, n + miss, (n + miss, 0))  # one step per move while counted
    m = HelixMapper(3)
    m.clock(cmd, False, False)
    m.clock(None, True, False)
    made, flags = 0, []
    for k in range(n):
        made += m.steps(*_plane_moves(rng, 1)[0])[2]
        flags.append(m.count_error(k == n - 1))
        m.clock(None, False, True)
    assert made == min(n, n + miss)     # the steps beyond N dropped, or short of |d|
    assert flags == [False] * (n - 1) + [True]


def test_the_right_count_is_not_flagged():
    xs, ys, xe, ye, cw = 7, 0, -7, 0, 1
    n = arc_stop(xs, ys, xe, ye, cw)[2]
    pts = arc_points(xs, ys, xe, ye, cw)
    moves = [(b[0] - a[0], b[1] - a[1]) for a, b in zip(pts, pts[1:])]
    m = HelixMapper(3)
    m.clock(HelixCommand(2, 0, n, (-5, 0)), False, False)
    m.clock(None, True, False)
    for k, mv in enumerate(moves):
        assert not m.count_error(k == len(moves) - 1)
        m.clock(None, False, True)


def test_planes_map_the_arc_onto_their_axes():
    """A G18 half circle (Z X) and a G19 one (Y Z), CCW as seen from +Y and +X, from
    u = -5 to u = +5 about the centre: the G18 arc passes X-5, the G19 one Z-5."""
    for plane, far_axis, far in ((enc.PLANES[18], 0, -5), (enc.PLANES[19], 2, -5)):
        cmd = enc.encode_arc(0, 5, 0, 10, 0, plane=plane,
                             count=arc_stop(-5, 0, 5, 0, 0)[2], helix=(3,))
        trace, end, errors = expect(profiled([cmd], 3, 32, 3, 1 << 29, 1 << 33), 3, 32)
        assert errors == []
        u, v = plane
        normal = ({0, 1, 2} - {u, v}).pop()
        assert end[u] == 10 and end[v] == 0 and end[normal] == 3
        assert min(p[far_axis] for p in trace) == far


@pytest.mark.parametrize("axes", [2, 3, 4])
def test_decode_errors(axes):
    def code(cmd, width=32):
        dec = decode_for_core(cmd, axes, width)
        return dec[1] if dec[0] == "err" else 0

    flat = enc.encode_arc(0, -5, 0, 0, 5)
    assert code(flat) == 0
    # the axis pair out of range, one axis twice
    assert code(enc.encode_arc(0, -5, 0, 0, 5, plane=(0, axes))) == enc.E_FIELD
    assert code(enc.encode_arc(0, -5, 0, 0, 5, plane=(1, 1))) == enc.E_FIELD
    # a delta in a slot the core does not have is a reserved bit set
    slots = enc.helix_slots(axes)
    beyond = [0] * enc.HELIX_SLOTS
    if slots < enc.HELIX_SLOTS:
        beyond[slots] = 1
        assert code(enc.encode_arc(0, -5, 0, 0, 5, count=9, helix=beyond)) == enc.E_OPCODE
    if slots:
        # beyond N, or with no N
        assert code(enc.encode_arc(0, -5, 0, 0, 5, count=3, helix=(4,))) == enc.E_HELIX
        assert code(enc.encode_arc(0, -5, 0, 0, 5, count=3, helix=(-3,))) == 0
        assert code(enc.encode_arc(0, -5, 0, 0, 5, helix=(1,))) == enc.E_HELIX
        # a delta beyond the width
        assert code(enc.encode_arc(0, -5, 0, 0, 5, count=1 << 20, helix=(1 << 15,)),
                    16) == enc.E_FIELD
    # reserved bits of word 0 stay reserved
    assert code(flat | (1 << 12)) == enc.E_OPCODE


def test_encoding_round_trip():
    rng = random.Random(5)
    for _ in range(200):
        cmd = random_helix(rng, 4, cont=rng.random() < 0.5)
        d = enc.decode(cmd)
        assert d["reserved_ok"] and d["opcode"] in (enc.OP_ARC_CW, enc.OP_ARC_CCW)
        assert (d["u_axis"], d["v_axis"]) in enc.PLANES.values()
        i, j, x, y = d["i"], d["j"], d["x"], d["y"]
        assert d["count"] == arc_stop(-i, -j, x - i, y - j, d["cw"])[2]
        assert all(abs(h) <= d["count"] for h in d["helix"])
    with pytest.raises(ValueError):
        enc.encode_arc(0, 1, 0, 0, 0, plane=(8, 0))
    with pytest.raises(ValueError):
        enc.encode_arc(0, 1, 0, 0, 0, count=-1)
