# SPDX-License-Identifier: Apache-2.0
"""Lookahead planner: moves in mm -> one trapezoidal speed profile per motion block.

Input: the parser's ``Move`` list (``halfpoint.cam.gcode``; absolute mm, F in
mm/min, G20 already converted) with ``Dwell`` items (G4 P seconds; an
``OutputChange`` is one of 0 s) and ``PowerChange`` items in program order.
Output (``plan``): the same items in the same order, each ``Move`` as a
``Segment`` (length, entry / cruise / exit path speed in mm/s, acceleration in
mm/s^2, the times of the accelerate / cruise / decelerate phases and where
deceleration starts), each ``Dwell`` kept as it is: a timed pause at rest; each
``PowerChange`` kept as it is and planned through: no stop, no time.

Rules:

* **Speed limit** of a block (``Segment.v_limit``): F for G1/G2/G3; for G0 the
  axes' maximum speed.  Either way no axis may exceed its ``max_velocity``:
  the limit is projected onto the block's direction, v <= min_k vmax_k / |u_k|
  (grbl's ``limit_value_by_axis_maximum``), for an arc with |u_k| the largest
  over the swept angles.
* **Acceleration** (``Segment.accel``, the tangential ramp), lines:
  min_k amax_k / |u_k|.  Arcs also accelerate towards the centre by v^2 / R.
  An arc splits each axis's budget: the tangential ramp gets
  ``ARC_TANGENTIAL_SHARE`` (1/2) of the projected limit min_k amax_k / T_k,
  the centripetal acceleration the rest of min_k amax_k / N_k (T_k, N_k: the
  largest |tangent_k|, |normal_k| over the swept angles).  Since
  |a_t t_k + a_n n_k| <= a_t T_k + a_n N_k, no axis exceeds its limit anywhere
  on the arc.  The centripetal part caps the speed: v^2 / R <= (1 - share)
  min_k amax_k / N_k.
* **Helices** (an arc whose normal axis moves, G17/G18/G19): planned along the
  3-D path, length sqrt((R sweep)^2 + rise^2).  The tangent's in-plane part is
  k = R |sweep| / length of the arc's, its normal-axis part rise / length, so
  every axis's speed and acceleration limits apply, the normal axis's too; the
  centripetal limit acts on the in-plane speed k v: (k v)^2 / R <= (1 - share)
  min_k amax_k / N_k.  The core paces an arc in its plane's units, so the host
  hands it the helix's speeds times k (``plane_share``): the 3-D path speed is
  the planned one.
* **Junctions** by junction deviation, as grbl does it (gnea/grbl
  ``grbl/planner.c``, ``plan_buffer_line``; Klipper ``klippy/toolhead.py``,
  ``Move.calc_junction``, the same formula): with cos(theta) = -u_in . u_out
  (theta = 180 degrees for a straight junction, 0 for a reversal),
  v^2 = a_j * delta * sin(theta/2) / (1 - sin(theta/2)), where a_j is the axis
  acceleration projected onto the direction u_out - u_in (grbl's
  ``junction_unit_vec``) and delta is ``planner.junction_deviation_mm``.  A
  straight junction (cos < -0.999999) is limited only by the blocks' speeds,
  a reversal (cos > 0.999999) is a stop (grbl's MINIMUM_JUNCTION_SPEED, 0).
  An arc meets its neighbours with its tangent at its ends.  Klipper's extra cap
  applies too: v^2 <= a_j * 0.5 * length * tan(theta/2) for both blocks (the
  cornering circle touches each block no further than its middle), so tiny
  chords round a tight curve run no faster than the curve allows.  The entry
  speed is at most the smaller speed limit of the two blocks.
* **Lookahead over the whole program**: the backward pass (the program ends
  at rest; each entry speed at most what decelerating over the block reaches)
  and the forward pass (each exit speed at most what accelerating over the
  block reaches), as grbl's ``planner_recalculate`` and Klipper's
  ``MoveQueue.flush``, over every block at once: a chain of tiny collinear
  CAM segments cruises at F instead of stopping at every junction (the
  complaint of grbl #1144).  Every program starts and ends at rest, and so do
  the blocks either side of a dwell.
* **Profile** of each block: accelerate at ``accel`` from the entry speed,
  cruise at the highest speed the limit and the length allow, decelerate to
  the exit speed; a block too short to reach its limit is a triangle (no
  cruise).
* A block of zero length (a line to where the tool is) moves nothing: it stays
  in the plan as a ``Segment`` of length 0 and duration 0 at the speed the
  path has there, and the junction is computed between its neighbours.

``to_core(segment, machine)`` gives a segment in the motion core's units:
path units per clock and per clock squared (floats), with the path unit
documented there.  ``estimate_time(plan)`` is the planned run time in seconds
(in the core an arc takes a little longer: its lattice path costs up to 8 %
more per mm than the arc, see ``CoreSegment``).

What the profile does not model: the lattice's own per-move jerk, and on arcs
the speed ripple from that cost (the core runs the lattice path at the planned
rate, so the tool along the arc is up to 7.6 % slower, never faster; the
changing cost adds a tangential acceleration of at most 0.42 v^2 / R, which the
1/2 split absorbs for full circles and equal X/Y limits: |a| <= 0.87 a_max).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .gcode import PLANE_AXES, GcodeError, Move, arc_sweep
from .machine import Machine, MachineError

# arc acceleration budget: this share of each axis's limit for the tangential ramp,
# the rest for the centripetal acceleration v^2 / R
ARC_TANGENTIAL_SHARE = 0.5
# grbl's thresholds on cos(theta) for a reversal and a straight junction
REVERSAL_COS = 0.999999
STRAIGHT_COS = -0.999999
# grbl's MINIMUM_JUNCTION_SPEED (mm/s); 0 as in grbl's default
MINIMUM_JUNCTION_SPEED = 0.0


@dataclass(frozen=True)
class Dwell:
    """A timed pause at rest (G4 P seconds), kept in program order."""

    seconds: float
    lineno: int


@dataclass(frozen=True)
class OutputChange(Dwell):
    """A change of the spindle, laser or coolant outputs (M3/M4/M5, S, M7/M8/M9; in laser
    mode S alone is not one, see ``PowerChange``): the core's OUTPUT command,
    ``settings`` being ``encoding.encode_output``'s arguments.  The core runs it once
    everything before it has moved, so the motion before it ends at rest, as before a
    dwell of 0 s."""

    settings: tuple = ()


@dataclass(frozen=True)
class PowerChange:
    """Laser mode: from the next motion on, its PROFILEs carry this spindle / laser
    ``power`` (PWM duty, 65536 = 100 %; ``encoding.encode_profile``'s ``set_power`` and
    ``power``), so an S change, or the laser's gate around a G0, travels with the motion
    instead of stopping it.  Not a ``Dwell``: ``plan`` keeps it in place and plans
    through it (no stop, no time); ``cam.motion.build_motion`` takes these items out
    before planning and gives their power to the PROFILEs of the moves after them."""

    power: int
    lineno: int
    # M4 (dynamic power): the output stage scales the duty by the speed over the
    # segment's cruise speed; build_motion scales ``power`` by that cruise speed over
    # the programmed feed, so the duty is S x speed / F, as grbl's
    dynamic: bool = False


@dataclass
class Segment:
    """One planned motion block: geometry, limits and its trapezoidal profile.

    Speeds are path speeds in mm/s, ``accel`` in mm/s^2 (the same rate up and
    down), times in s, distances in mm from the segment's start.  The phases
    run in order: accelerate for ``t_accel`` (over ``d_accel``), cruise at
    ``v_cruise`` for ``t_cruise``, decelerate for ``t_decel`` from
    ``d_decel_start`` to the end.  ``t_cruise`` is 0 for a triangle profile.
    """

    move: Move
    length: float
    v_limit: float                  # largest cruise speed allowed (F or G0, axes, centripetal)
    accel: float
    dir_start: tuple                # unit tangent at the start
    dir_end: tuple                  # unit tangent at the end
    radius: float = 0.0             # arcs: radius (mm); 0 for lines
    sweep: float = 0.0              # arcs: signed swept angle (rad, CCW positive)
    v_entry: float = 0.0
    v_cruise: float = 0.0
    v_exit: float = 0.0
    t_accel: float = 0.0
    t_cruise: float = 0.0
    t_decel: float = 0.0
    d_accel: float = 0.0
    d_decel_start: float = 0.0

    @property
    def kind(self) -> str:
        return self.move.kind

    @property
    def lineno(self) -> int:
        return self.move.lineno

    @property
    def duration(self) -> float:
        return self.t_accel + self.t_cruise + self.t_decel

    def speed_at(self, t: float) -> float:
        """Path speed (mm/s) ``t`` seconds after the segment started (clamped to it)."""
        end = self.duration
        t = min(max(t, 0.0), end)
        if t <= self.t_accel:
            return self.v_entry + self.accel * t
        if t <= self.t_accel + self.t_cruise:
            return self.v_cruise
        return self.v_exit + self.accel * (end - t)

    def distance_at(self, t: float) -> float:
        """Path distance (mm) covered ``t`` seconds after the segment started."""
        t = min(max(t, 0.0), self.duration)
        if t <= self.t_accel:
            return self.v_entry * t + 0.5 * self.accel * t * t
        t -= self.t_accel
        d = self.d_accel
        if t <= self.t_cruise:
            return d + self.v_cruise * t
        t -= self.t_cruise
        return min(self.d_decel_start + self.v_cruise * t - 0.5 * self.accel * t * t,
                   self.length)


# --- geometry ---------------------------------------------------------------------------------

def _max_abs_sin(lo: float, hi: float) -> float:
    """Largest |sin(phi)| for phi in [lo, hi]."""
    half = math.pi / 2
    if math.ceil((lo - half) / math.pi) <= math.floor((hi - half) / math.pi):
        return 1.0
    return max(abs(math.sin(lo)), abs(math.sin(hi)))


def _max_abs_cos(lo: float, hi: float) -> float:
    return _max_abs_sin(lo + math.pi / 2, hi + math.pi / 2)


def _projected(limits, weights) -> float:
    """min_k limits_k / weights_k over the axes that move (weights_k > 0)."""
    best = math.inf
    for lim, w in zip(limits, weights):
        if w > 1e-12:
            best = min(best, lim / w)
    return best


def projected_limit(limits, weights) -> float:
    """A per-axis limit projected onto a direction: min_k limits_k / weights_k over
    the axes that move (``weights``: |unit direction| per axis)."""
    return _projected(limits, weights)


def _unit(v) -> tuple:
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def _segment(m: Move, machine: Machine) -> Segment:
    vmax, amax = machine.max_velocity, machine.max_accel
    if m.kind not in ("rapid", "line", "arc"):
        raise GcodeError(m.lineno, f"the planner cannot plan a move of kind {m.kind!r}")
    if m.kind != "rapid" and not (m.feed > 0 and math.isfinite(m.feed)):
        raise GcodeError(m.lineno, f"no usable feed rate for this move (F = {m.feed!r} mm/min)")
    feed = m.feed / 60.0 if m.kind != "rapid" else math.inf
    if m.kind != "arc":
        d = tuple(e - s for s, e in zip(m.start, m.end))
        length = math.sqrt(sum(c * c for c in d))
        if length == 0.0:
            return Segment(m, 0.0, feed, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        u = tuple(c / length for c in d)
        w = tuple(abs(c) for c in u)
        v_limit = min(feed, _projected(vmax, w))
        return Segment(m, length, v_limit, _projected(amax, w), u, u)
    if m.plane not in PLANE_AXES or m.center is None:
        raise GcodeError(m.lineno, "arc without a centre or in an unknown plane")
    a0, a1, ap = PLANE_AXES[m.plane]
    rise = m.end[ap] - m.start[ap]          # a helix: the normal axis moves with the arc
    cx, cy = m.center
    sx, sy = m.start[a0] - cx, m.start[a1] - cy
    radius = math.hypot(sx, sy)
    if radius == 0.0:
        raise GcodeError(m.lineno, "arc radius is zero (centre at the start point)")
    phi0 = math.atan2(sy, sx)
    sweep = arc_sweep(m)
    flat = radius * abs(sweep)
    length = math.hypot(flat, rise)
    # along a helix the plane takes the share k of the path, the normal axis h
    k, h = (flat / length, abs(rise) / length) if length > 0.0 else (1.0, 0.0)

    def tangent(phi):
        t = [0.0, 0.0, 0.0]
        sgn = -1.0 if m.cw else 1.0
        t[a0], t[a1] = -sgn * k * math.sin(phi), sgn * k * math.cos(phi)
        t[ap] = math.copysign(h, rise)
        return tuple(t)

    dir_start, dir_end = tangent(phi0), tangent(phi0 + sweep)
    if length == 0.0:
        return Segment(m, 0.0, feed, 0.0, dir_start, dir_end, radius, 0.0)
    lo, hi = sorted((phi0, phi0 + sweep))
    # tangent (-sin, cos) and normal (-cos, -sin) in the plane, up to signs; the
    # tangent's in-plane part scaled by k, its normal-axis part h
    tw = [0.0, 0.0, 0.0]
    nw = [0.0, 0.0, 0.0]
    tw[a0], tw[a1] = k * _max_abs_sin(lo, hi), k * _max_abs_cos(lo, hi)
    tw[ap] = h
    nw[a0], nw[a1] = _max_abs_cos(lo, hi), _max_abs_sin(lo, hi)
    accel = ARC_TANGENTIAL_SHARE * _projected(amax, tw)
    # centripetal: the in-plane speed k v on radius R
    a_normal = (1.0 - ARC_TANGENTIAL_SHARE) * _projected(amax, nw)
    v_limit = min(feed, _projected(vmax, tw), math.sqrt(a_normal * radius) / k)
    return Segment(m, length, v_limit, accel, dir_start, dir_end, radius, sweep)


def junction_speed_sqr(u_in, u_out, machine: Machine, len_in: float = math.inf,
                      len_out: float = math.inf) -> float:
    """Largest speed^2 (mm^2/s^2) where a block ending in direction ``u_in`` meets one
    starting in ``u_out`` (unit vectors), before the blocks' own speed limits.

    grbl's junction deviation: v^2 = a_j * delta * sin(theta/2) / (1 - sin(theta/2));
    ``math.inf`` for a straight junction, 0 for a reversal.  With the blocks' lengths
    ``len_in`` and ``len_out`` also Klipper's cap (``Move.calc_junction``,
    ``move_centripetal_v2``): the circle that gives the cornering speed must touch
    both blocks no further than their middles, radius 0.5 * length * tan(theta/2), so
    v^2 <= a_j * 0.5 * length * tan(theta/2) for each block.  Without it a chain of tiny
    chords round a tight curve would be planned faster than the axes can turn it
    (grbl's formula alone allows about 8 a delta R^2 / c^2 for chords c on radius R);
    with it such a chain is held to about a_j * R, the arc's centripetal limit.  Klipper
    uses each block's acceleration; here a_j, the axes' limit in the direction of the
    velocity change, which is the one that acts on that circle."""
    cos_theta = -sum(a * b for a, b in zip(u_in, u_out))
    if cos_theta > REVERSAL_COS:
        return MINIMUM_JUNCTION_SPEED ** 2
    if cos_theta < STRAIGHT_COS:
        return math.inf
    j = _unit(tuple(b - a for a, b in zip(u_in, u_out)))
    a_j = _projected(machine.max_accel, tuple(abs(c) for c in j))
    sin_half = math.sqrt(0.5 * (1.0 - cos_theta))
    tan_half = sin_half / math.sqrt(0.5 * (1.0 + cos_theta))
    v2 = a_j * machine.junction_deviation_mm * sin_half / (1.0 - sin_half)
    v2 = min(v2, a_j * 0.5 * min(len_in, len_out) * tan_half)
    return max(MINIMUM_JUNCTION_SPEED ** 2, v2)


# --- planning ---------------------------------------------------------------------------------

def plan(items, machine: Machine) -> list:
    """Plan a program: ``items`` is a list of ``Move``, ``Dwell`` and ``PowerChange`` in
    program order.  Returns a list of the same length and order, each ``Move`` replaced
    by its ``Segment``, each ``Dwell`` (a stop) and ``PowerChange`` (not a stop) kept."""
    out: list = []
    chain: list[Segment] = []           # segments of non-zero length, in order
    stop_before: list[bool] = []        # junction before chain[i] is a stop (dwell)
    zero_at: list[tuple[Segment, int]] = []   # zero-length segments, junction index
    pending_stop = True                 # the program starts at rest
    for item in items:
        if isinstance(item, PowerChange):
            out.append(item)
            continue
        if isinstance(item, Dwell):
            if not (item.seconds >= 0 and math.isfinite(item.seconds)):
                raise GcodeError(item.lineno, f"dwell time must be >= 0 s, got {item.seconds!r}")
            pending_stop = True
            out.append(item)
            continue
        if not isinstance(item, Move):
            raise TypeError(f"the planner takes Move, Dwell and PowerChange items, got "
                            f"{type(item).__name__}")
        seg = _segment(item, machine)
        out.append(seg)
        if seg.length == 0.0:
            zero_at.append((seg, len(chain)))
            continue
        chain.append(seg)
        stop_before.append(pending_stop)
        # G61.1, exact stop: the motion stops at the end of each block (LinuxCNC)
        pending_stop = item.path_mode == "G61.1"
    n = len(chain)
    # max_e2[i]: largest entry speed^2 of chain[i]; e2[n] = 0, the program ends at rest
    max_e2 = [0.0] * (n + 1)
    for i, seg in enumerate(chain):
        if stop_before[i]:
            continue
        prev = chain[i - 1]
        lim = min(prev.v_limit, seg.v_limit) ** 2
        max_e2[i] = min(lim, junction_speed_sqr(prev.dir_end, seg.dir_start, machine,
                                                 prev.length, seg.length))
    e2 = list(max_e2)
    # backward pass (grbl planner_recalculate's reverse pass, over the whole program)
    e2[n] = 0.0
    for i in range(n - 1, -1, -1):
        seg = chain[i]
        e2[i] = min(max_e2[i], e2[i + 1] + 2.0 * seg.accel * seg.length)
    # forward pass
    for i in range(n):
        seg = chain[i]
        e2[i + 1] = min(e2[i + 1], e2[i] + 2.0 * seg.accel * seg.length)
    for i, seg in enumerate(chain):
        _profile(seg, e2[i], e2[i + 1])
    for seg, j in zero_at:
        v = math.sqrt(e2[j]) if j < n and not stop_before[j] else 0.0
        seg.v_entry = seg.v_cruise = seg.v_exit = v
    return out


def _profile(seg: Segment, v0_sqr: float, v1_sqr: float) -> None:
    """Fill in the trapezoid (or triangle) from the entry and exit speeds squared."""
    a, length = seg.accel, seg.length
    peak_sqr = 0.5 * (2.0 * a * length + v0_sqr + v1_sqr)
    vc_sqr = max(min(seg.v_limit ** 2, peak_sqr), v0_sqr, v1_sqr)
    v0, v1, vc = math.sqrt(v0_sqr), math.sqrt(v1_sqr), math.sqrt(vc_sqr)
    d_accel = (vc_sqr - v0_sqr) / (2.0 * a)
    d_decel = (vc_sqr - v1_sqr) / (2.0 * a)
    d_cruise = length - d_accel - d_decel
    if d_cruise < 0.0:                  # a triangle, off by rounding only
        d_cruise = 0.0
        d_decel = min(d_decel, length)
        d_accel = length - d_decel
    seg.v_entry, seg.v_cruise, seg.v_exit = v0, vc, v1
    seg.t_accel = (vc - v0) / a
    seg.t_decel = (vc - v1) / a
    seg.t_cruise = d_cruise / vc if vc > 0.0 else 0.0
    seg.d_accel = d_accel
    seg.d_decel_start = length - d_decel


def estimate_time(planned) -> float:
    """Planned run time of a ``plan`` result, seconds (motion and dwells)."""
    total = 0.0
    for item in planned:
        if isinstance(item, PowerChange):
            continue
        total += item.seconds if isinstance(item, Dwell) else item.duration
    return total


# --- core units -------------------------------------------------------------------------------

@dataclass(frozen=True)
class CoreSegment:
    """A planned segment in the motion core's units (floats; the fixed point is the
    core's business).

    ``unit_mm`` is the length of one path unit in mm, as the core's feed credit
    counts it:

    * lines (and rapids): one iteration of the line unit, which steps the longest
      axis (in BLU) every iteration: Euclidean length / iteration count, the count
      being max_k |delta_k| in BLU between the lattice points the quantiser uses.
      The credit path is the line itself: ``units`` = the iteration count.
    * arcs: one BLU (X and Y share it): an axis move costs 1, a diagonal move
      sqrt(2).  The credit path is the *lattice* path, which is longer than the
      arc: per mm of arc with tangent components a >= b (in BLU) the lattice
      makes a axis-or-diagonal moves, b of them diagonal, costing
      a + (sqrt(2) - 1) b, between 1 (along an axis or a diagonal) and 1.0824
      (at 22.5 degrees); a full circle costs 16 (sqrt(2) - 1) R = 6.627 R
      instead of 2 pi R = 6.283 R.  ``units`` is that lattice length,
      ``lattice_arc_length`` (held to the arc model's real moves by a test).
      Speeds are converted with unit_mm = 1 BLU, so the tool's true speed along
      the arc is the planned speed divided by that local cost: never faster than
      planned, up to 7.6 % slower, and the arc takes longer than ``Segment.duration``
      (5.5 % over a full circle; ``clocks`` counts it).

    Speeds are path units per clock, ``accel`` path units per clock squared,
    ``decel_start`` the credit position (path units from the start) where
    deceleration must begin to reach ``v_exit`` at the end of ``units``:
    units - (v_cruise^2 - v_exit^2) / (2 accel).  ``clocks`` is the duration of
    that trapezoid in clocks.  A line that does not leave its lattice point (0
    iterations) has ``unit_mm`` 0 and everything 0: the quantiser sends no
    command for it.

    The core's PROFILE commands (``halfpoint.cam.motion``) count every command in
    one BLU of X, a line iteration costing its length (``line_cost``): their speeds
    are this segment's ``v_cruise`` etc. times ``unit_mm / blu_x`` for lines, the same
    for arcs.
    """

    unit_mm: float
    units: float
    v_entry: float
    v_cruise: float
    v_exit: float
    accel: float
    decel_start: float
    clocks: float


def line_iterations(start, end, blu) -> int:
    """Iterations of the core's line unit between the lattice points nearest
    ``start`` and ``end`` (mm): max_k |round(end_k / blu_k) - round(start_k / blu_k)|."""
    return max(abs(round(e / b) - round(s / b)) for s, e, b in zip(start, end, blu))


_DIAGONAL_EXTRA = math.sqrt(2.0) - 1.0


def lattice_arc_length(radius: float, phi0: float, sweep: float) -> float:
    """Length of the core's lattice path along an arc, in the units of ``radius``
    (axis moves 1, diagonal moves sqrt(2)): radius times the integral over the
    swept angles of max(|cos|, |sin|) + (sqrt(2) - 1) min(|cos|, |sin|), exact
    piece by piece between multiples of 45 degrees."""
    lo, hi = sorted((phi0, phi0 + sweep))
    eighth = math.pi / 4
    total, a = 0.0, lo
    while a < hi:
        k = math.floor(a / eighth) + 1
        b = k * eighth
        if b <= a:
            b = (k + 1) * eighth
        b = min(b, hi)
        mid = 0.5 * (a + b)
        c, s = math.cos(mid), math.sin(mid)
        if abs(c) >= abs(s):
            alpha, beta = math.copysign(1.0, c), math.copysign(_DIAGONAL_EXTRA, s)
        else:
            alpha, beta = math.copysign(_DIAGONAL_EXTRA, c), math.copysign(1.0, s)
        total += alpha * (math.sin(b) - math.sin(a)) - beta * (math.cos(b) - math.cos(a))
        a = b
    return radius * total


def plane_share(seg: Segment) -> float:
    """The share of an arc's path in its plane: R |sweep| / length (1 for a flat arc,
    less for a helix).  The core paces an arc in its plane's units, so a helix's
    speeds and acceleration go to the core times this: the 3-D path speed is then
    the planned one."""
    if seg.kind != "arc" or seg.length == 0.0:
        return 1.0
    return seg.radius * abs(seg.sweep) / seg.length


def to_core(seg: Segment, machine: Machine) -> CoreSegment:
    """``seg`` in path units per clock and per clock squared (see ``CoreSegment``)."""
    clock = float(machine.clock_hz)
    scale = 1.0
    if seg.kind == "arc":
        m = seg.move
        a0, a1, _ = PLANE_AXES[m.plane]
        b0, b1 = machine.axes[a0].blu_mm, machine.axes[a1].blu_mm
        if b0 != b1:
            names = "xyz"
            raise MachineError(f"axis.{names[a1]}.blu_mm",
                               f"{b1:g} differs from axis.{names[a0]}.blu_mm {b0:g}; the arc "
                               f"on line {seg.lineno} needs the two axes of its plane to "
                               f"share the BLU", machine.source)
        unit = b0
        phi0 = math.atan2(m.start[a1] - m.center[1], m.start[a0] - m.center[0])
        units = lattice_arc_length(seg.radius / unit, phi0, seg.sweep)
        scale = plane_share(seg)
    else:
        n = line_iterations(seg.move.start, seg.move.end, machine.blu)
        if n == 0:
            return CoreSegment(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        unit = seg.length / n
        units = float(n)
    per_clock = scale / (unit * clock)
    v0, vc, v1 = seg.v_entry * per_clock, seg.v_cruise * per_clock, seg.v_exit * per_clock
    accel = seg.accel * per_clock / clock
    if accel > 0.0:
        d_accel = (vc * vc - v0 * v0) / (2.0 * accel)
        d_decel = (vc * vc - v1 * v1) / (2.0 * accel)
        t_ramps = (2.0 * vc - v0 - v1) / accel
    else:
        d_accel = d_decel = t_ramps = 0.0
    d_cruise = max(units - d_accel - d_decel, 0.0)
    clocks = t_ramps + (d_cruise / vc if vc > 0.0 else 0.0)
    return CoreSegment(unit_mm=unit, units=units, v_entry=v0, v_cruise=vc, v_exit=v1,
                       accel=accel, decel_start=units - d_decel, clocks=clocks)
