# SPDX-License-Identifier: Apache-2.0
"""The arc-to-axes mapper of helical and any-plane arcs: the specification of
``rtl/halfpoint_helix.v`` (issue 14, item 2).

The arc unit makes its moves in its own (u, v) plane.  For each arc command the
mapper knows the plane's two axes, the arc's exact move count N (the host's
``spec.arc.arc_stop``) and the signed delta of each helix slot (the axes outside
the plane, ``encoding.helix_axes``).  For every move of the arc it

* puts the arc's u step on axis u and its v step on axis v;
* steps each slot's axis by the difference method against N, as the line unit
  steps its minor axes against the longest one: an accumulator gains |delta| per
  move, and when it reaches N the axis steps (in the delta's sign) and the
  accumulator drops by N.  It starts at floor(N / 2), so after k moves the axis
  has made floor((k |delta| + floor(N / 2)) / N) steps (the nearest to the ideal
  k |delta| / N, halves rounded down): after exactly N moves, exactly |delta|
  (floor(N / 2) < N), at most one step per move (|delta| <= N, the core rejects
  more: ``encoding.E_HELIX``).

The registers keep the accumulator as e = acc + |delta| - N, so that the step of
the next move is the sign of a register (e >= 0) and the update one addition:
e += |delta| - N after a step, e += |delta| otherwise.

If the arc makes more than N moves, the moves after the N-th step no helix axis;
if it makes fewer, the steps not yet made are dropped.  Either way the arc's last
move reports the mismatch (``count_error``: the core sets E_HELIX_COUNT), and
nothing runs away.  N = 0 means no count given: a flat arc, not checked.

``HelixMapper`` is the clock-by-clock twin of the RTL module: a pending slot
loaded when the dispatcher hands the arc to the arc unit, the running state loaded
when the arc unit starts that arc (the arc unit loads only into an idle run stage:
behind an arc, the edge after its last move; the mapper itself makes a move at a
loading edge first, should both come together).
"""

from __future__ import annotations

from dataclasses import dataclass

from . import encoding as enc


@dataclass(frozen=True)
class HelixCommand:
    """The mapper's part of an arc command."""

    u: int                  # axis of the arc's first coordinate
    v: int                  # axis of its second
    count: int              # the arc's exact move count N (0: not given)
    deltas: tuple           # signed delta of each helix slot


FLAT_XY = HelixCommand(*enc.PLANE_XY, 0, (0,) * enc.HELIX_SLOTS)


def helix_error(cmd: HelixCommand, axes: int, fits) -> int:
    """The core's code for the mapper's fields (0 if good): a delta in a slot the
    core does not have (E_OPCODE), the axis pair out of range or a delta beyond W
    (``fits``) (E_FIELD), a delta larger than N (E_HELIX)."""
    if any(cmd.deltas[enc.helix_slots(axes):]):
        return enc.E_OPCODE
    if cmd.u >= axes or cmd.v >= axes or cmd.u == cmd.v or \
            not all(fits(d) for d in cmd.deltas):
        return enc.E_FIELD
    if any(abs(d) > cmd.count for d in cmd.deltas):
        return enc.E_HELIX
    return 0


def steps_after(k: int, count: int, delta: int) -> int:
    """Signed steps a slot with ``delta`` has made after ``k`` <= N moves (the
    closed form of the accumulator)."""
    made = (k * abs(delta) + (count >> 1)) // count if count else 0
    return made if delta >= 0 else -made


@dataclass
class _Run:
    cmd: HelixCommand
    axes: tuple             # the slots' axes
    e: list                 # per slot: acc + |delta| - N
    remaining: int          # moves left of the N


class HelixMapper:
    """Clock-by-clock twin of ``halfpoint_helix``."""

    def __init__(self, axes: int):
        self.axes = axes
        self.reset()

    def reset(self) -> None:
        self.pending = FLAT_XY
        self.run = _Run(FLAT_XY, enc.helix_axes(*enc.PLANE_XY, self.axes),
                        [-1] * enc.HELIX_SLOTS, 0)

    def steps(self, du: int, dv: int) -> tuple:
        """Signed step per axis of the running arc's next move, (du, dv) being the
        arc unit's move in its plane (combinational)."""
        r = self.run
        out = [0] * self.axes
        out[r.cmd.u], out[r.cmd.v] = du, dv
        if r.remaining:
            for axis, e, d in zip(r.axes, r.e, r.cmd.deltas):
                if e >= 0:
                    out[axis] = 1 if d > 0 else -1
        return tuple(out)

    def count_error(self, last: bool) -> bool:
        """The running arc's move at this edge is its last and its count was not N."""
        r = self.run
        return bool(last and r.cmd.count and r.remaining != 1)

    def clock(self, take: HelixCommand | None, load: bool, move: bool,
              abort: bool = False) -> None:
        """One edge: ``move`` the running arc made a move, ``load`` the arc unit
        started the pending arc, ``take`` the dispatcher handed an arc over."""
        if abort:
            self.reset()
            return
        r = self.run
        if move and r.remaining:
            n = r.cmd.count
            r.e = [e + abs(d) - (n if e >= 0 else 0) for e, d in zip(r.e, r.cmd.deltas)]
            r.remaining -= 1
        if load:
            c = self.pending
            self.run = _Run(c, enc.helix_axes(c.u, c.v, self.axes),
                            [(c.count >> 1) + abs(d) - c.count for d in c.deltas], c.count)
        if take is not None:
            self.pending = take


def map_arc(moves, cmd: HelixCommand, axes: int) -> list:
    """Signed steps per axis of each of an arc's ``moves`` ((du, dv) per move), as
    the mapper makes them (for the host and the tests)."""
    m = HelixMapper(axes)
    m.clock(cmd, False, False)
    m.clock(None, True, False)
    out = []
    for du, dv in moves:
        out.append(m.steps(du, dv))
        m.clock(None, False, True)
    return out
