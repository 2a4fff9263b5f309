# SPDX-License-Identifier: Apache-2.0
"""Golden model of the N-axis line interpolator (seed 001, difference method).

Per segment: signed deltas d_i; Max = max |d_i| moves.  Every iteration each
axis accumulates F_i += |d_i| and steps when 2*F_i > Max (strictly), then
F_i -= Max.  The longest (base) axis therefore steps every iteration without
special logic, and every axis ends exactly on its delta.

The RTL keeps E_i = 2*(F_i + |d_i|) - Max - 1 (step iff E_i >= 0) and adds one
of two prepared constants per move: 2|d_i| - 2*Max after a step, 2|d_i|
otherwise -- sign bit -> select -> one add, like the arc unit.

``LineUnitModel`` is the clock-by-clock twin of ``rtl/halfpoint_line.v``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .rules import check_width, fits

ERR_NONE = 0
ERR_EMPTY = 1

ERR_TEXT = {ERR_NONE: "ok", ERR_EMPTY: "line of zero length"}


class LineRejected(ValueError):
    def __init__(self, code: int, detail: str = ""):
        self.code = code
        super().__init__(ERR_TEXT[code] + (f": {detail}" if detail else ""))


def check_axes(axes: int) -> None:
    if not (isinstance(axes, int) and 1 <= axes <= 6):
        raise ValueError(f"number of axes must be an integer in 1..6, got {axes!r}")


def line_steps(deltas) -> list[tuple[int, ...]]:
    """Signed unit steps per iteration, one tuple of per-axis steps each."""
    run = LineRun(list(deltas))
    return [mv for mv in run.run()]


@dataclass
class LineRun:
    """Run-stage state of one accepted line."""

    deltas: list[int]
    width: int = 32
    mags: list[int] = field(init=False)
    dirs: list[int] = field(init=False)
    total: int = field(init=False)
    acc: list[int] = field(init=False)
    left: int = field(init=False)

    def __post_init__(self) -> None:
        check_width(self.width)
        for d in self.deltas:
            if not fits(d, self.width):
                raise ValueError(f"delta {d} does not fit {self.width} bits")
        self.mags = [abs(d) for d in self.deltas]
        self.dirs = [1 if d > 0 else (-1 if d < 0 else 0) for d in self.deltas]
        self.total = max(self.mags) if self.mags else 0
        if self.total == 0:
            raise LineRejected(ERR_EMPTY)
        self.acc = [0] * len(self.deltas)
        self.left = self.total

    @property
    def done(self) -> bool:
        return self.left == 0

    def peek(self) -> tuple[int, ...]:
        """The signed step of every axis in the next iteration, not made yet."""
        return tuple(
            self.dirs[i] if 2 * (self.acc[i] + m) > self.total else 0
            for i, m in enumerate(self.mags)
        )

    def move(self) -> tuple[int, ...]:
        """One iteration: the signed step of every axis (0 = no step)."""
        assert self.left > 0
        steps = self.peek()
        for i, m in enumerate(self.mags):
            self.acc[i] += m - (self.total if steps[i] else 0)
        self.left -= 1
        return steps

    def run(self):
        while not self.done:
            yield self.move()


# --------------------------------------------------------------------------
# Cycle-accurate model of rtl/halfpoint_line.v at its ports.
# --------------------------------------------------------------------------

L_IDLE, L_MAX, L_INIT, L_HOLD = range(4)


def line_latency(axes: int) -> int:
    """Clocks from the accept cycle to the first cycle in the pending slot."""
    return axes + 2


@dataclass
class LineInputs:
    s_valid: int = 0
    s_delta: tuple = ()
    en: int = 1
    rst: int = 0
    start_en: int = 1
    abort: int = 0


@dataclass
class LineOutputs:
    s_ready: int
    busy: int
    move: int
    step: int      # bit i = axis i stepped
    dir: int       # bit i = direction of axis i's latest step, 1 = positive
    done: int
    reject: int
    err_code: int


class LineUnitModel:
    """Clock-by-clock twin of ``halfpoint_line``; use like ``ArcUnitModel``."""

    def __init__(self, axes: int = 3, width: int = 32):
        check_axes(axes)
        check_width(width)
        self.axes, self.width = axes, width
        self.reset()

    def reset(self) -> None:
        self.vstate = L_IDLE
        self.vcount = 0
        self.vcmd: tuple | None = None
        self.run: LineRun | None = None
        self.out = LineOutputs(s_ready=1, busy=0, move=0, step=0, dir=0, done=0, reject=0, err_code=0)

    def outputs(self, abort: int = 0) -> LineOutputs:
        """Outputs during this cycle; s_ready also depends on the abort input."""
        o = self.out
        o.s_ready = int(self.vstate == L_IDLE and not abort)
        o.busy = int(self.run is not None or self.vstate != L_IDLE)
        return LineOutputs(**vars(o))

    def clock(self, i: LineInputs) -> None:
        if i.rst:
            self.reset()
            return
        o = self.out
        o.move = o.step = o.done = o.reject = 0
        if i.abort:
            self.run = None
            self.vstate = L_IDLE
            return
        if self.run is not None and i.en:
            steps = self.run.move()
            o.move = 1
            for k, s in enumerate(steps):
                if s:
                    o.step |= 1 << k
                    o.dir = (o.dir & ~(1 << k)) | ((1 if s > 0 else 0) << k)
            if self.run.done:
                o.done = 1
                self.run = None
        st = self.vstate
        if st == L_IDLE:
            if i.s_valid:
                self.vcmd = tuple(i.s_delta)
                self.vstate, self.vcount = L_MAX, 0
        elif st == L_MAX:
            self.vcount += 1
            if self.vcount == self.axes:
                self.vstate = L_INIT
        elif st == L_INIT:
            if max(abs(d) for d in self.vcmd) == 0:
                o.reject, o.err_code = 1, ERR_EMPTY
                self.vstate = L_IDLE
            else:
                self.vstate = L_HOLD
        elif st == L_HOLD:
            if self.run is None and i.start_en:
                self.run = LineRun(list(self.vcmd), self.width)
                self.vstate = L_IDLE
