# SPDX-License-Identifier: Apache-2.0
"""The items the planner takes for a program: its (compensated) moves with its dwells,
spindle, laser and coolant changes in program order (``plan_items_compensated``), and
the OUTPUT command's settings for a spindle and coolant state (``output_settings``).
``halfpoint run`` and ``halfpoint send`` plan these (``cam.run.plan_motion``), and
``cam.summary`` estimates the time of the same items."""

from __future__ import annotations

from ..spec import encoding as enc
from .gcode import Coolant, Spindle
from .gcode import Dwell as GcodeDwell
from .machine import Machine
from .planner import Dwell, OutputChange, PowerChange


def output_settings(machine: Machine, on: bool, cw: bool, speed: float, mist: bool,
                    flood: bool) -> tuple:
    """``encoding.encode_output``'s arguments for a spindle and coolant state: the duty
    of S is clamp(S, min_speed, max_speed) / max_speed (S 0: 0 %); in laser mode M4 is
    dynamic power (the duty follows the path speed) and M3 constant, outside it M4 is
    the reverse direction."""
    top = machine.spindle_max
    s = 0.0 if speed <= 0 else min(max(speed, machine.spindle_min), top)
    power = round(enc.OUTPUT_POWER_FULL * s / top)
    laser = machine.laser_mode
    return (power, int(on), int(on and not cw and not laser), int(laser),
            int(on and not cw and laser), int(mist), int(flood))


def plan_items_compensated(prog, moves, machine: Machine | None = None) -> list:
    """The compensated ``moves`` with the program's dwells (``planner.Dwell``) and, with
    a ``machine``, its spindle and coolant changes (``planner.OutputChange``) in program
    order.  An event stands before the programmed move index ``before``; each
    compensated move is traced back to its programmed move (the same object, else the
    next programmed move of its line, in order), and the event goes before the first
    compensated move from that index on.

    Laser mode (``machine.laser_mode``, grbl's ``$32``): only a change of the laser's
    state (on / off, M3 constant / M4 dynamic) or of the coolant is an OutputChange (a
    stop); the power travels with the motion: before a move that needs another power
    than the last ``planner.PowerChange`` (the first move: any), a PowerChange of it,
    0 for a G0 or with the laser off, else the duty of S.  So an S change and the G0s
    run without stopping; during a G0 the laser stays enabled at duty 0, as in grbl."""
    kinds = (GcodeDwell, Spindle, Coolant) if machine is not None else (GcodeDwell,)
    events = sorted((e for e in prog.events if isinstance(e, kinds)), key=lambda e: e.before)
    if not events:
        return list(moves)
    laser = machine is not None and machine.laser_mode
    state = {"on": False, "cw": True, "speed": 0.0, "mist": False, "flood": False}
    # the outputs as the core has them, and as it had them before the last item when
    # that is an OutputChange (changes with no move between them are merged into one)
    emitted = [output_settings(machine, **state)] if machine is not None else [None]
    before_last = [None]
    power = [None]              # laser mode: the last PowerChange's (power, dynamic)
    items: list = []

    def same(a: tuple | None, b: tuple | None) -> bool:
        """The same outputs (in laser mode the power aside: it travels with the motion)."""
        if laser and a is not None and b is not None:
            return a[1:] == b[1:]
        return a == b

    def emit(settings: tuple, lineno: int) -> None:
        if same(settings, emitted[0]):
            return
        if items and isinstance(items[-1], OutputChange):
            items.pop()
            if same(settings, before_last[0]):
                emitted[0] = settings
                return
        else:
            before_last[0] = emitted[0]
        items.append(OutputChange(0.0, lineno, settings))
        emitted[0] = settings

    def put(ev) -> None:
        if isinstance(ev, GcodeDwell):
            items.append(Dwell(ev.seconds, ev.lineno))
            return
        if isinstance(ev, Spindle):
            state.update(on=ev.on, cw=ev.cw, speed=ev.speed)
        else:
            state.update(mist=ev.mist, flood=ev.flood)
        emit(output_settings(machine, **state), ev.lineno)

    def laser_power(m) -> None:
        """Laser mode: the power ``m`` needs (0 for a G0 or with the laser off), with
        the motion."""
        if not laser:
            return
        want = (0, False)
        if state["on"] and m.kind != "rapid":
            settings = output_settings(machine, **state)
            want = (settings[0], bool(settings[4]))        # M4: dynamic
        if want != power[0]:
            items.append(PowerChange(want[0], m.lineno, want[1]))
            power[0] = want

    where = {id(m): i for i, m in enumerate(prog.moves)}
    d, p = 0, 0
    for m in moves:
        if id(m) in where:
            p = where[id(m)]
        else:
            j = p
            while j < len(prog.moves) and prog.moves[j].lineno != m.lineno:
                j += 1
            if j < len(prog.moves):
                p = j
        while d < len(events) and events[d].before <= p:
            put(events[d])
            d += 1
        laser_power(m)
        items.append(m)
    for ev in events[d:]:
        put(ev)
    return items


__all__ = ["output_settings", "plan_items_compensated"]
