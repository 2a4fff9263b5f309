# SPDX-License-Identifier: Apache-2.0
"""Golden model of the half-point minimum-deviation arc interpolator (seed 000).

Two layers:

* ``ArcRun``: the algorithm, one lattice move per call of :meth:`ArcRun.move`,
  with the decision rule, quadrant table, quadrant crossing and end-point
  detection exactly as ``rtl/halfpoint_arc.v`` implements them.  ``arc_points``
  runs one arc to its stop point.
* ``ArcUnitModel``: the cycle-accurate twin of the RTL module at its ports:
  command handshake, the multi-cycle validator, the pending slot, the run
  stage, and every registered output, clock by clock.  A pending arc enters
  only an idle run stage: one clock without a move at an arc->arc boundary.

Coordinates are signed integers in BLU relative to the arc centre.  The
direction bit is ``cw`` (1 = clockwise, G2; 0 = counter-clockwise, G3).

Frame of a point (SEEDS.md, table for seed 000): in the quadrant the motion is
in (a point on an axis belongs to the quadrant being entered), ``u`` is the
magnitude of the coordinate that shrinks and ``v`` the one that grows.  With
F = x^2 + y^2 - R^2 (R^2 = xs^2 + ys^2, so F = 0 at the start):

    D1 = F - 2u + v + 1   (deviation at half point N1, minus 1/4)
    D2 = F - u + 2v + 1   (deviation at half point N2, minus 1/4)
    D1 >= 0 -> B (u - 1);  else D2 >= 0 -> A (u - 1, v + 1);  else C (v + 1)

End-point detection ("progress order"): inside the end point's quadrant every
move strictly increases the pair (v, -u) and also the pair (-u, v).  If the end
point E has v_e <= u_e (first octant of the quadrant) the order (v, -u) is
used, otherwise (-u, v).  A point is *past* E when it is in E's quadrant and
not before E in that order.  The arc stops after the first move that reaches a
point past E, or that leaves E's quadrant.  Stop checks are *armed* from the
start unless the start lies in E's quadrant at or past E (this includes a full
circle, start == end); then they are armed by the first quadrant crossing.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator

from .rules import check_width, fits

# Error codes reported by the core on a rejected command (err_code output).
ERR_NONE = 0
ERR_RADIUS_ZERO = 1
ERR_RANGE = 2
ERR_END_OFF = 3

ERR_TEXT = {
    ERR_NONE: "ok",
    ERR_RADIUS_ZERO: "radius is zero (start point at the centre)",
    ERR_RANGE: "circle does not fit the coordinate width",
    ERR_END_OFF: "end point is off the circle beyond the tolerance",
}

MOVE_B, MOVE_A, MOVE_C = "B", "A", "C"


class ArcRejected(ValueError):
    """The core would reject this command (see ``code``)."""

    def __init__(self, code: int, detail: str = ""):
        self.code = code
        msg = ERR_TEXT[code]
        super().__init__(f"{msg}{': ' + detail if detail else ''}")


def limits(width: int) -> tuple[int, int]:
    """(largest |coordinate|, largest accepted R^2) for a coordinate width.

    R^2 <= (M-1)(M-2) with M = 2^(width-1) is the same as R < M - 1.5, so every
    lattice point of the path (|x|, |y| <= R + 0.5) and every accepted end point
    fits a signed ``width``-bit field without reaching -M.
    """
    m = 1 << (width - 1)
    return m - 1, (m - 1) * (m - 2)


def quadrant(x: int, y: int, cw: int) -> int:
    """Quadrant index 0..3 (I..IV) of a non-origin point for a direction.

    A point on an axis belongs to the quadrant the motion is entering.
    """
    if cw:
        if x >= 0 and y > 0:
            return 0
        if x < 0 and y >= 0:
            return 1
        if x <= 0 and y < 0:
            return 2
        return 3  # x > 0, y <= 0
    if x > 0 and y >= 0:
        return 0
    if x <= 0 and y > 0:
        return 1
    if x < 0 and y <= 0:
        return 2
    return 3  # x >= 0, y < 0


def u_is_x(q: int, cw: int) -> bool:
    """True when the shrinking coordinate u is |x| (CCW I/III, CW II/IV)."""
    return (q & 1) == cw


def frame(x: int, y: int, cw: int) -> tuple[int, int, int]:
    """(q, u, v) of a non-origin point."""
    q = quadrant(x, y, cw)
    if u_is_x(q, cw):
        return q, abs(x), abs(y)
    return q, abs(y), abs(x)


def before(u: int, v: int, ue: int, ve: int) -> bool:
    """Whether (u, v) comes strictly before (ue, ve) in E's progress order."""
    return before_in_order(u, v, ue, ve, ve <= ue)


def before_in_order(u: int, v: int, ue: int, ve: int, first_octant: bool) -> bool:
    """Whether (u, v) comes strictly before (ue, ve) in the order of the first
    octant of the quadrant, (v, -u), or else of the second, (-u, v); E's own
    octant picks the order (``before``), and the two agree on every point of the
    lattice path (each move lowers u or raises v)."""
    if first_octant:
        return v < ve or (v == ve and u > ue)
    return u > ue or (u == ue and v < ve)


def validate(xs: int, ys: int, xe: int, ye: int, width: int) -> int:
    """Error code the core gives the command (ERR_NONE when it runs).

    Checks, in priority order:
      1. R^2 = xs^2 + ys^2 == 0                     -> ERR_RADIUS_ZERO
      2. R^2 > (M-1)(M-2), M = 2^(width-1)          -> ERR_RANGE
      3. |xe^2 + ye^2 - R^2| > 2*max(|xs|, |ys|)    -> ERR_END_OFF
    The tolerance in 3 is a radial distance between 0.71 and 1 BLU (it is
    F_e/(2R) <= max(|xs|,|ys|)/R): every end point within 0.5 BLU of the circle
    is accepted and none further than 1 BLU is.  Inputs are ``width``-bit
    signed fields; the caller checks that they fit (the port cannot carry more).
    """
    r2 = xs * xs + ys * ys
    if r2 == 0:
        return ERR_RADIUS_ZERO
    if r2 > limits(width)[1]:
        return ERR_RANGE
    fe = xe * xe + ye * ye - r2
    if abs(fe) > 2 * max(abs(xs), abs(ys)):
        return ERR_END_OFF
    return ERR_NONE


def step(q, u, v, f, cw):
    """One lattice move of the half-point method: the algorithm, written once.

    From the frame (q, u, v) of the current point and its deviation f, returns
    ``(du, dv, dx, dy, q2, u2, v2, f2, crossing)``: whether u shrinks (B or A)
    and v grows (A or C), the physical steps, the frame and deviation after the
    move, and whether the move crossed into the next quadrant.  Only adds,
    compares and selects written as arithmetic, so the same function runs on
    Python integers (``ArcRun``, the stop prediction) and elementwise on numpy
    integer arrays (the sweeps of ``full_circle_stats``).

    Decision: D1 = F - 2u + v + 1 >= 0 -> B; else D2 = F - u + 2v + 1 >= 0 -> A;
    else C.  Since D2 - D1 = u + v >= 0, u shrinks exactly when D2 >= 0 and v
    grows exactly when D1 < 0.  u steps towards the axis, v away from it; when
    u reaches 0 the point lies on an axis and belongs to the next quadrant,
    where the old v becomes u and v = 0 (F does not change with the frame).
    """
    du = (f - u + 2 * v + 1 >= 0) * 1           # D2 >= 0: B or A
    dv = (f - 2 * u + v + 1 < 0) * 1            # D1 < 0: A or C
    ux = u_is_x(q, cw) * 1                      # u is |x| (CCW I/III, CW II/IV)
    sx = 1 - 2 * (((q == 1) | (q == 2)) * 1)    # sign of x in quadrant q
    sy = 1 - 2 * ((q >= 2) * 1)                 # sign of y
    dx = ux * (-sx * du) + (1 - ux) * (sx * dv)
    dy = ux * (sy * dv) - (1 - ux) * (sy * du)
    f2 = f - du * (2 * u - 1) + dv * (2 * v + 1)
    nu, nv = u - du, v + dv
    crossing = (nu == 0) * 1
    q2 = (q + crossing * (1 - 2 * cw)) % 4
    return du, dv, dx, dy, q2, nu + crossing * nv, nv * (1 - crossing), f2, crossing


def move_kind(du: int, dv: int) -> str:
    return MOVE_A if du and dv else (MOVE_B if du else MOVE_C)


@dataclass
class Move:
    """One lattice move: kind, unit steps per axis and the point reached."""

    kind: str
    dx: int
    dy: int
    x: int
    y: int
    f: int
    last: bool


class ArcRun:
    """Run-stage state of one accepted arc (the RTL's datapath registers).

    ``advance`` makes one move with :func:`step` and the end detection of the
    module docstring; ``move`` does the same and reports it; ``peek`` tells the
    next move without making it.  With ``check`` (the default) every value the
    RTL keeps in its W + 2-bit datapath is asserted to fit, on every move.
    """

    __slots__ = ("xs", "ys", "xe", "ye", "cw", "width", "x", "y", "f", "q", "u", "v",
                 "qe", "ue", "ve", "armed", "done", "moves", "check", "_dw")

    def __init__(self, xs: int, ys: int, xe: int, ye: int, cw: int, width: int = 32,
                 check: bool = True):
        check_width(width)
        for name, value in (("xs", xs), ("ys", ys), ("xe", xe), ("ye", ye)):
            if not fits(value, width):
                raise ArcRejected(ERR_RANGE, f"{name} does not fit {width} bits")
        code = validate(xs, ys, xe, ye, width)
        if code:
            raise ArcRejected(code)
        self.xs, self.ys, self.xe, self.ye, self.cw, self.width = xs, ys, xe, ye, cw, width
        self.x, self.y, self.f = xs, ys, 0
        self.q, self.u, self.v = frame(xs, ys, cw)
        self.qe, self.ue, self.ve = frame(xe, ye, cw)
        # At or past E in E's quadrant already (a full circle is the case
        # start == end): the stop checks wait for the first quadrant crossing.
        self.armed = not (self.q == self.qe and not self.before_end(self.u, self.v))
        self.done = False
        self.moves = 0
        self.check = check
        self._dw = width + 2  # datapath width of the RTL (D1, D2, F, increments)

    def _fits(self, value: int) -> int:
        lim = 1 << (self._dw - 1)
        assert -lim <= value < lim, f"datapath overflow: {value} needs more than {self._dw} bits"
        return value

    def before_end(self, u: int, v: int) -> bool:
        """Whether (u, v) of E's quadrant comes before E in E's progress order (the
        end test; a subclass may test another order, as the octant tests do)."""
        return before(u, v, self.ue, self.ve)

    @property
    def d1(self) -> int:
        return self.f - 2 * self.u + self.v + 1

    @property
    def d2(self) -> int:
        return self.f - self.u + 2 * self.v + 1

    def peek(self) -> tuple[str, int, int]:
        """(kind, dx, dy) of the next move, without making it."""
        du, dv, dx, dy = step(self.q, self.u, self.v, self.f, self.cw)[:4]
        return move_kind(du, dv), dx, dy

    def advance(self) -> tuple[int, int, int, int]:
        """Make the next lattice move: (du, dv, dx, dy); ``done`` after the last."""
        assert not self.done, "arc already finished"
        if self.check:
            self._fits(self.d1)
            self._fits(self.d2)
        du, dv, dx, dy, q, u, v, f, crossing = step(self.q, self.u, self.v, self.f, self.cw)
        if self.check:
            self._fits(f)
            # candidate increments the RTL keeps in registers must fit as well
            for inc in (-2 * self.u + 3, 2 * self.v + 3, -2 * self.u + 2 * self.v + 5,
                        -3 * self.v + 1):
                self._fits(inc)
        q_old = self.q
        self.x += dx
        self.y += dy
        self.q, self.u, self.v, self.f = q, u, v, f
        if self.check:
            assert u > 0 or v > 0, "path reached the centre"
            assert (q, u, v) == frame(self.x, self.y, self.cw)
        stop = False
        if self.armed:
            if q_old == self.qe:
                stop = bool(crossing) or not self.before_end(u, v)
            elif crossing and q == self.qe:
                stop = not self.before_end(u, v)
        if crossing:
            self.armed = True
        self.moves += 1
        self.done = stop
        return du, dv, dx, dy

    def move(self) -> Move:
        """Make the next lattice move; ``last`` is set on the arc's final move."""
        du, dv, dx, dy = self.advance()
        return Move(move_kind(du, dv), dx, dy, self.x, self.y, self.f, self.done)

    def run(self) -> Iterator[Move]:
        while not self.done:
            yield self.move()


def move_bound(xs: int, ys: int) -> int:
    """Upper bound on the moves of any accepted arc from this start point.

    Within one quadrant every move lowers u or raises v by one, u starts at most
    R + 1/2 and v ends at most R + 1/2, so a quadrant takes at most 2*floor(R)+2
    moves.  An arc is less than one full turn plus the partial quadrant it
    starts in: at most 5 quadrant traversals, and the stop move itself.
    """
    r_floor = _isqrt(xs * xs + ys * ys)
    return 5 * (2 * r_floor + 2) + 1


def _isqrt(n: int) -> int:
    import math

    return math.isqrt(n)


def arc_points(xs: int, ys: int, xe: int, ye: int, cw: int, width: int = 32) -> list[tuple[int, int]]:
    """Lattice points from the start to the stop point inclusive."""
    run = ArcRun(xs, ys, xe, ye, cw, width)
    pts = [(xs, ys)]
    bound = move_bound(xs, ys)
    for mv in run.run():
        pts.append((mv.x, mv.y))
        assert run.moves <= bound, "move bound exceeded"
    return pts


def lattice_point_near(r2: int, theta: float) -> tuple[int, int]:
    """Non-origin lattice point with the smallest |x^2 + y^2 - r2| next to the
    point at angle ``theta`` on the circle of radius sqrt(r2)."""
    import math

    r = math.sqrt(r2)
    cx, cy = round(r * math.cos(theta)), round(r * math.sin(theta))
    best = None
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            x, y = cx + dx, cy + dy
            if x == 0 and y == 0:
                continue
            key = (abs(x * x + y * y - r2), abs(dx) + abs(dy))
            if best is None or key < best[0]:
                best = (key, (x, y))
    return best[1]


def arc_stop(xs: int, ys: int, xe: int, ye: int, cw: int) -> tuple[int, int, int]:
    """(x, y, moves) where an accepted arc stops: :class:`ArcRun` without the
    datapath assertions (the host's prediction; the caller has validated the
    command)."""
    run = ArcRun(xs, ys, xe, ye, cw, check=False)
    advance = run.advance
    while not run.done:
        advance()
    return run.x, run.y, run.moves


def radial_errors(points, r: float):
    """Radial distance of each lattice point from the true circle, in BLU."""
    import numpy as np

    p = np.asarray(points, dtype=float)
    return np.hypot(p[:, 0], p[:, 1]) - r


def full_circle_stats(radii, cw: int):
    """Full circles from (R, 0) for many integer radii at once (numpy).

    :func:`step` applied elementwise to arrays of frames, one move per
    iteration for every circle still running; a circle ends when it is back
    at its start.  Returns (moves, max |radial error|) arrays.  Used for the
    long sweeps; checked against :class:`ArcRun` in the tests.
    """
    import numpy as np

    r = np.asarray(radii, dtype=np.int64)
    x, y = r.copy(), np.zeros_like(r)
    f = np.zeros_like(r)
    q0, _, _ = frame(1, 0, cw)                  # (R, 0) lies in the same quadrant for every R
    q = np.full_like(r, q0)
    u, v = r.copy(), np.zeros_like(r)           # on the x axis: u = |x| = R, v = 0
    moves = np.zeros_like(r)
    maxerr = np.zeros(r.shape, dtype=float)
    active = np.ones(r.shape, dtype=np.int64)
    rf = r.astype(float)
    limit = int(8 * r.max() + 8)
    for _ in range(limit):
        if not active.any():
            break
        _, _, dx, dy, q2, u2, v2, f2, _ = step(q, u, v, f, cw)
        keep = 1 - active
        x, y = x + dx * active, y + dy * active
        q, u = q2 * active + q * keep, u2 * active + u * keep
        v, f = v2 * active + v * keep, f2 * active + f * keep
        moves += active
        err = np.abs(np.hypot(x, y) - rf)
        maxerr = np.where(active == 1, np.maximum(maxerr, err), maxerr)
        active &= 1 - ((x == r) & (y == 0))
    if active.any():
        raise AssertionError(f"circles did not close: radii {r[active == 1][:5]}")
    return moves, maxerr


# --------------------------------------------------------------------------
# Cycle-accurate model of rtl/halfpoint_arc.v at its ports.
# --------------------------------------------------------------------------

V_IDLE, V_SQ, V_SUM, V_CHK, V_DEC, V_INIT, V_HOLD = range(7)


def validate_latency(width: int) -> int:
    """Clocks from the accepting edge until the command is ready to load."""
    return width + 5


@dataclass
class ArcInputs:
    s_valid: int = 0
    s_cw: int = 0
    s_xs: int = 0
    s_ys: int = 0
    s_xe: int = 0
    s_ye: int = 0
    en: int = 1
    rst: int = 0
    start_en: int = 1
    abort: int = 0


@dataclass
class ArcOutputs:
    s_ready: int
    busy: int
    move: int
    step_x: int
    step_y: int
    dir_x: int
    dir_y: int
    x: int
    y: int
    f: int
    done: int
    reject: int
    err_code: int


class ArcUnitModel:
    """Clock-by-clock twin of ``halfpoint_arc``.

    Call :meth:`outputs` to read what the RTL shows during the current clock
    cycle, then :meth:`clock` with that cycle's inputs to apply the rising edge.

    Cycle behaviour: a command taken at the edge ending cycle t is validated
    in ``validate_latency(W)`` = W + 5 clocks and then waits in the pending
    slot (state ``V_HOLD``).  It enters the run stage at an edge where
    ``start_en`` is high and the run stage is idle during that clock (no arc
    in it); its start point then shows on x/y (F = 0) for a cycle, and its
    first move is made at the next enabled edge.  The unit never loads at the
    edge of the running arc's last move: that edge empties the run stage and
    the pending arc enters at the next one, so two arcs queued back to back
    run with exactly one clock without a move between them (the motion core's
    move queue hides it from the pins).  ``s_ready`` rises in the cycle after
    the load.
    """

    def __init__(self, width: int = 32):
        check_width(width)
        self.width = width
        self.reset()

    def reset(self) -> None:
        self.vstate = V_IDLE
        self.vcount = 0
        self.vcmd: tuple[int, int, int, int, int] | None = None
        self.verr = ERR_NONE
        self.run: ArcRun | None = None
        self.out = ArcOutputs(
            s_ready=1, busy=0, move=0, step_x=0, step_y=0, dir_x=0, dir_y=0,
            x=0, y=0, f=0, done=0, reject=0, err_code=ERR_NONE,
        )

    def outputs(self, abort: int = 0) -> ArcOutputs:
        """Outputs during this cycle; s_ready also depends on the abort input."""
        o = self.out
        o.s_ready = int(self.vstate == V_IDLE and not abort)
        o.busy = int(self.run is not None or self.vstate != V_IDLE)
        return ArcOutputs(**vars(o))

    def clock(self, i: ArcInputs) -> None:
        if i.rst:
            self.reset()
            return
        o = self.out
        o.move = o.step_x = o.step_y = o.done = o.reject = 0
        if i.abort:
            self.run = None
            self.vstate = V_IDLE
            return

        # The pending arc enters only a run stage that is idle during this
        # clock: not at the edge of the running arc's last move, but at the
        # next one (an arc->arc boundary costs one clock; the end test then
        # feeds neither the load nor the run stage's clock enables).
        idle = self.run is None

        # Run stage: one move when enabled.
        if self.run is not None and i.en:
            mv = self.run.move()
            o.move = 1
            o.step_x, o.step_y = int(mv.dx != 0), int(mv.dy != 0)
            if mv.dx:
                o.dir_x = int(mv.dx > 0)
            if mv.dy:
                o.dir_y = int(mv.dy > 0)
            o.x, o.y, o.f = mv.x, mv.y, mv.f
            if mv.last:
                o.done = 1
                self.run = None

        # Validator and pending slot.
        st = self.vstate
        if st == V_IDLE:
            if i.s_valid:
                self.vcmd = (i.s_cw, i.s_xs, i.s_ys, i.s_xe, i.s_ye)
                self.vstate, self.vcount = V_SQ, 0
        elif st == V_SQ:
            self.vcount += 1
            if self.vcount == self.width:
                self.vstate = V_SUM
        elif st == V_SUM:
            self.vstate = V_CHK
        elif st == V_CHK:
            self.vstate = V_DEC
        elif st == V_DEC:
            cw, xs, ys, xe, ye = self.vcmd
            code = validate(xs, ys, xe, ye, self.width)
            if code:
                o.reject, o.err_code = 1, code
                self.vstate = V_IDLE
            else:
                self.vstate = V_INIT
        elif st == V_INIT:
            self.vstate = V_HOLD
        elif st == V_HOLD:
            if idle and i.start_en:
                cw, xs, ys, xe, ye = self.vcmd
                self.run = ArcRun(xs, ys, xe, ye, cw, self.width)
                o.x, o.y, o.f = xs, ys, 0
                self.vstate = V_IDLE
