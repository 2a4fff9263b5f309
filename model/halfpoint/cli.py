# SPDX-License-Identifier: Apache-2.0
"""The ``halfpoint`` command line.

    halfpoint arc XS YS XE YE (--cw | --ccw) [--engine model|rtl] [--width W]
    halfpoint segments FILE [--engine model|rtl]
    halfpoint compensate PROGRAM.ngc [--radius R] [--tools FILE] [--strict]
    halfpoint run PROGRAM.ngc [--machine FILE] [--engine model|rtl] [--trace out.csv]
        [--hold A:B ...] [--profile out.png] [--plot out.png] [--zoom X0,X1,Y0,Y1]
    halfpoint fit ellipse --a A --b B --tol T [--quadrant 1|2|3|4 | --full]  (parabola, hyperbola)
    halfpoint chords parabola --a A --b B --x0 X0 --x1 X1 --feed F --period T [--alg 1|2]
        [--substeps N]
    halfpoint demo [--out DIR] [--engine model|rtl|both]
    halfpoint send PROGRAM.ngc --port PORT [--machine FILE] [--baud N] [--quiet] [--timeout S]
        [--radius R] [--tools FILE] [--strict]
    halfpoint board-sim [--listen [127.0.0.1:]PORT] [--machine FILE] [--exit-when-idle]
"""

from __future__ import annotations

import argparse
import sys

from .spec.arc import ERR_TEXT, ArcRejected
from .spec.rules import check_width, fits
from .sim.engines import ENGINES, run_arcs
from .cam.gcode import GcodeError
from .cam.machine import MachineError
from .cam.run import EngineError


class UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    """argparse that reports errors in one line and exits with status 2."""

    def error(self, message):  # noqa: D401
        raise UsageError(message)


def _int(text: str) -> int:
    try:
        return int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="halfpoint", description="halfpoint FPGA motion core toolchain")
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=_Parser)

    a = sub.add_parser("arc", help="interpolate one arc, print its lattice points")
    for name in ("xs", "ys", "xe", "ye"):
        a.add_argument(name, type=_int, help=f"{name.upper()} relative to the centre, in BLU")
    d = a.add_mutually_exclusive_group(required=True)
    d.add_argument("--cw", action="store_true", help="clockwise (G2)")
    d.add_argument("--ccw", action="store_true", help="counter-clockwise (G3)")
    a.add_argument("--engine", choices=ENGINES, default="model")
    a.add_argument("--width", type=_int, default=32, help="coordinate width in bits (8..32)")
    a.add_argument("--no-header", action="store_true", help="omit the 'x,y' header line")

    g = sub.add_parser("segments", help="run a segment file (JSON lines) through the motion core")
    g.add_argument("file", help="segment file, one JSON object per line")
    g.add_argument("--engine", choices=ENGINES, default="model")

    c = sub.add_parser("compensate", help="apply cutter compensation, print plain G-code")
    c.add_argument("program", help="G-code program (LinuxCNC dialect subset)")
    c.add_argument("--machine", help="machine file (TOML; default: the shipped example "
                                     "machine): stored positions and travel")
    _comp_args(c)

    r = sub.add_parser("run", help="G-code through compensation, quantisation and the core")
    r.add_argument("program", help="G-code program (LinuxCNC dialect subset)")
    _comp_args(r)
    r.add_argument("--engine", choices=ENGINES, default="model")
    r.add_argument("--machine", help="machine file (TOML; default: the shipped example "
                                     "machine, examples/machine.toml)")
    r.add_argument("--hold", action="append", default=[], metavar="A:B",
                   help="feed hold high from clock cycle A until cycle B (repeatable)")
    r.add_argument("--profile", help="write a PNG: path speed against time (measured, "
                                     "planned, limits) and the axis speeds")
    r.add_argument("--blu", help=argparse.SUPPRESS)
    r.add_argument("--blu-z", help=argparse.SUPPRESS)
    r.add_argument("--plot", help="write a PNG: programmed, compensated and lattice paths")
    r.add_argument("--trace", help="write a CSV: cycle and position (BLU) after every move")
    r.add_argument("--zoom", help="plot window XMIN,XMAX,YMIN,YMAX in mm")
    ch = sub.add_parser("chords", help="time-division chords of a curve (seed 002), as G-code")
    chs = ch.add_subparsers(dest="curve", required=True, parser_class=_Parser)
    pa = chs.add_parser("parabola", help="y = -a x^2 + b x")
    pa.add_argument("--a", type=float, required=True)
    pa.add_argument("--b", type=float, required=True)
    pa.add_argument("--x0", type=float, required=True)
    pa.add_argument("--x1", type=float, required=True)
    pa.add_argument("--feed", type=float, required=True, help="feed rate F in mm/min")
    pa.add_argument("--period", type=float, required=True, help="interpolation period T in ms")
    pa.add_argument("--alg", type=int, choices=(1, 2), default=1,
                    help="1: tangent, 2: corrected secant")
    pa.add_argument("--substeps", type=int, default=1, help="n substeps per period")

    ft = sub.add_parser("fit", help="tri-arc fit of a curve (seed 003), as G-code arcs")
    fts = ft.add_subparsers(dest="curve", required=True, parser_class=_Parser)
    fe = fts.add_parser("ellipse", help="x = A cos t, y = B sin t")
    fe.add_argument("--a", type=float, required=True)
    fe.add_argument("--b", type=float, required=True)
    q = fe.add_mutually_exclusive_group()
    q.add_argument("--quadrant", type=int, choices=(1, 2, 3, 4), default=None)
    q.add_argument("--full", action="store_true")
    fp = fts.add_parser("parabola", help="y = A x^2 + B x + C over [X0, X1]")
    fp.add_argument("--a", type=float, required=True)
    fp.add_argument("--b", type=float, default=0.0)
    fp.add_argument("--c", type=float, default=0.0)
    fp.add_argument("--x0", type=float, required=True)
    fp.add_argument("--x1", type=float, required=True)
    fh = fts.add_parser("hyperbola", help="x = A cosh t, y = B sinh t over [T0, T1]")
    fh.add_argument("--a", type=float, required=True)
    fh.add_argument("--b", type=float, required=True)
    fh.add_argument("--t0", type=float, required=True)
    fh.add_argument("--t1", type=float, required=True)
    for sp in (fe, fp, fh):
        sp.add_argument("--tol", type=float, required=True, help="tolerance in mm")
        sp.add_argument("--feed", type=float, default=600.0, help="F word in mm/min")

    m = sub.add_parser("demo", help="shipped arcs through model and RTL, with plots")
    m.add_argument("--out", default="build/demo", help="output directory")
    m.add_argument("--engine", choices=ENGINES + ("both",), default="both")

    s = sub.add_parser("send", help="stream a G-code program to a board over its serial port")
    s.add_argument("program", help="G-code program (LinuxCNC dialect subset)")
    s.add_argument("--port", required=True,
                   help="serial device (/dev/ttyUSB0) or pyserial URL (socket://HOST:PORT)")
    s.add_argument("--machine", help="machine file (TOML; default: the shipped example "
                                     "machine); its clock_hz must be the board's")
    s.add_argument("--baud", type=_int, default=115200, help="serial bit rate (default 115200)")
    s.add_argument("--quiet", action="store_true", help="no progress bar (for scripts)")
    s.add_argument("--timeout", type=float, default=2.0,
                   help="seconds to wait for a reply before retrying (default 2)")
    _comp_args(s)

    b = sub.add_parser("board-sim", help="the Verilator-simulated board top on a TCP port")
    b.add_argument("--listen", help="[127.0.0.1:]PORT to serve (default: any free port)")
    b.add_argument("--machine", help="machine file (default examples/machine_boardsim.toml)")
    b.add_argument("--exit-when-idle", action="store_true",
                   help="exit once a client came and went and the board is at rest")
    return p


def cmd_send(args) -> int:
    from .cam.machine import load, load_default
    from .host.board import LinkError
    from .host.send import JobError, send

    if args.baud <= 0 or args.timeout <= 0:
        raise UsageError("--baud and --timeout must be positive")
    machine = load(args.machine) if args.machine else load_default()
    try:
        return send(args.program, args.port, machine, args.baud, args.quiet, args.timeout,
                    radius=args.radius, tools=args.tools, strict=args.strict)
    except LinkError as exc:
        print(f"halfpoint: {exc}", file=sys.stderr)
        return 2
    except JobError as exc:
        print(f"halfpoint: {args.program}: {exc}", file=sys.stderr)
        return exc.status


def cmd_board_sim(args) -> int:
    from .sim.boardsim import BoardSimError, main as board_main

    try:
        return board_main(args.listen, args.machine, args.exit_when_idle)
    except BoardSimError as exc:
        print(f"halfpoint: board-sim: {exc}", file=sys.stderr)
        return 2


def _comp_args(p) -> None:
    p.add_argument("--radius", type=float,
                   help="tool radius in mm for every G41/G42 (overrides --tools)")
    p.add_argument("--tools", help="LinuxCNC tool table (T<n> P<p> D<diameter>) for G41/G42 D<n>")
    p.add_argument("--strict", action="store_true",
                   help="a contour the tool cannot follow is an error (default: skip it, warn)")
    p.add_argument("--window", type=int, default=5,
                   help="accepted for compatibility and ignored: interference is searched as far "
                        "as the tool reaches")


def cmd_compensate(args) -> int:
    from .cam.machine import load, load_default
    from .cam.run import load_program, print_messages, print_warnings, to_gcode

    if args.window < 1:
        raise UsageError("--window must be at least 1")
    machine = load(args.machine) if args.machine else load_default()
    prog, comp, _ = load_program(args.program, args.radius, args.tools, args.strict,
                                 args.window, machine)
    for note in prog.notes:
        print(f"halfpoint: {args.program}: note: {note}", file=sys.stderr)
    print_messages(args.program, prog.messages)
    print_warnings(args.program, comp.warnings)
    sys.stdout.write(to_gcode(comp.moves))
    return 0


def _holds(texts) -> list[tuple[int, int]]:
    out = []
    for t in texts:
        parts = t.split(":")
        try:
            a, b = (int(v, 0) for v in parts)
        except ValueError:
            raise UsageError(f"--hold {t}: needs A:B, two whole clock cycles") from None
        if not 0 <= a < b:
            raise UsageError(f"--hold {t}: needs 0 <= A < B")
        out.append((a, b))
    return out


def cmd_run(args) -> int:
    from .cam.machine import load, load_default
    from .cam.run import (plot_profile, plot_run, print_messages, print_warnings,
                          run_program, write_trace)
    from .sim.engines import executor

    if args.blu is not None or args.blu_z is not None:
        raise UsageError("--blu and --blu-z are gone: the BLU of each axis comes from the "
                         "machine file (--machine FILE, axis.<name>.blu_mm)")
    holds = _holds(args.hold)
    zoom = None
    if args.zoom:
        try:
            zoom = [float(v) for v in args.zoom.split(",")]
        except ValueError:
            zoom = []
        if len(zoom) != 4:
            raise UsageError("--zoom needs XMIN,XMAX,YMIN,YMAX")
    machine = load(args.machine) if args.machine else load_default()
    res = run_program(args.program, executor(args.engine), args.radius, args.tools,
                      args.strict, machine, holds, args.window)
    print_messages(args.program, res.messages)
    print_warnings(args.program, res.warnings)
    for note in res.notes:
        print(f"halfpoint: {args.program}: note: {note}", file=sys.stderr)
    print(res.summary)
    blu = res.blu
    print(f"machine: {machine.source}, clock {machine.clock_hz} Hz, BLU "
          f"{'/'.join(f'{b:g}' for b in blu)} mm, profile tick 2^{res.motion.div} clocks")
    print(f"moves: {len(res.programmed)} programmed, {len(res.compensated)} after "
          f"compensation")
    print(f"commands: {len(res.motion.commands)} motion commands with their PROFILEs, "
          f"{len(res.motion.pauses)} dwell pauses, {res.motion.outputs} output changes (each "
          f"a stop), {res.motion.power_changes} power changes with the motion")
    print(f"lattice moves: {len(res.lattice)}")
    end = res.lattice[-1] if res.lattice else (0,) * len(blu)
    print(f"final position: {', '.join(f'{v * b:.4f}' for v, b in zip(end, blu))} mm")
    print(f"max deviation of the lattice path from the compensated path: "
          f"{res.max_dev_mm:.6f} mm ({res.max_dev_mm / blu[0]:.3f} BLU, every lattice point "
          f"against its own block; {res.corrections} correcting lines)")
    ex = res.execution
    print(f"simulated time: {res.seconds:.6f} s ({ex.cycles} clock cycles"
          + (f"; holds {', '.join(f'{a}:{b}' for a, b in holds)}" if holds else "") + ")")
    if ex.approximate:
        print("note: a long run with dwells on the fast model: the lattice path is the "
              "core's, the cycles after each dwell are within a few ticks of it")
    if ex.dry:
        print("dry flag set: the command stream ran dry and the core had to slow down")
    if ex.underrun:
        print("underrun flag set: a segment marked CONT ended with no next profile")
    if args.plot:
        plot_run(res, args.plot, args.program, zoom)
        print(f"plot: {args.plot}")
    if args.profile:
        plot_profile(res, args.profile, f"{args.program}: path speed")
        print(f"profile: {args.profile}")
    if args.trace:
        write_trace(res, args.trace)
        print(f"trace: {args.trace}")
    return 0


def cmd_fit(args) -> int:
    import math

    from .curves import triarc

    if args.tol <= 0:
        raise UsageError("--tol must be positive")
    if args.curve == "ellipse":
        if args.a <= 0 or args.b <= 0:
            raise UsageError("--a and --b must be positive")
        if args.full:
            t0, t1 = 0.0, 2 * math.pi
        else:
            k = (args.quadrant or 1) - 1
            t0, t1 = k * math.pi / 2, (k + 1) * math.pi / 2
        curve = triarc.ellipse(args.a, args.b, t0, t1)
    elif args.curve == "parabola":
        if args.a == 0 or args.x0 == args.x1:
            raise UsageError("a parabola needs --a non-zero and --x0 different from --x1")
        curve = triarc.parabola(args.a, args.b, args.c, args.x0, args.x1)
    else:
        if args.a <= 0 or args.b <= 0 or args.t0 == args.t1:
            raise UsageError("a hyperbola needs positive --a, --b and --t0 different from --t1")
        curve = triarc.hyperbola(args.a, args.b, args.t0, args.t1)
    arcs, groups = triarc.fit(curve, args.tol)
    dev, tang = triarc.verify(curve, arcs, args.tol)
    if dev > args.tol:
        raise UsageError(f"fit exceeds the tolerance: {dev:.3g} mm")
    print(f"halfpoint: {len(groups)} groups, {len(arcs)} arcs, max deviation {dev:.4g} mm, "
          f"tangent jump {tang:.1e} rad", file=sys.stderr)
    sys.stdout.write(triarc.to_gcode(arcs, args.feed))
    return 0


def cmd_chords(args) -> int:
    from .curves.chords import chords_gcode, parabola_chords

    if args.feed <= 0 or args.period <= 0:
        raise UsageError("--feed and --period must be positive")
    f = args.feed / 60000.0 * args.period          # mm per period
    try:
        pts = parabola_chords(args.a, args.b, args.x0, args.x1, f, args.alg, args.substeps)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    sys.stdout.write(chords_gcode(pts, args.feed))
    return 0


def cmd_arc(args) -> int:
    try:
        check_width(args.width)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    for name in ("xs", "ys", "xe", "ye"):
        if not fits(getattr(args, name), args.width):
            raise UsageError(f"{name.upper()}={getattr(args, name)} does not fit a signed "
                             f"{args.width}-bit field")
    cmd = (1 if args.cw else 0, args.xs, args.ys, args.xe, args.ye)
    (res,) = run_arcs([cmd], args.engine, args.width)
    if res.rejected:
        print(f"halfpoint: arc rejected (code {res.rejected}): {ERR_TEXT[res.rejected]}",
              file=sys.stderr)
        return 3
    lines = [] if args.no_header else ["x,y"]
    lines += [f"{x},{y}" for x, y in res.points]
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def cmd_segments(args) -> int:
    from .cam.segments import CONFIG, SegmentError, parse_segments, segment_items
    from .sim.engines import executor

    try:
        with open(args.file, encoding="utf-8") as fh:
            text = fh.read()
    except OSError as exc:
        raise UsageError(f"cannot read {args.file}: {exc.strerror}") from None
    try:
        segs = parse_segments(text)
    except SegmentError as exc:
        print(f"halfpoint: {args.file}: {exc}", file=sys.stderr)
        return 3
    run = executor(args.engine)(segment_items(segs), CONFIG, ())
    if run.errors:
        print(f"halfpoint: {args.file}: the core rejected a command (codes {run.errors})",
              file=sys.stderr)
        return 3
    out = [",".join("0" for _ in range(3))] + [",".join(str(v) for v in p)
                                                for _, p in run.moves]
    sys.stdout.write("\n".join(out) + "\n")
    return 0


def main(argv=None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.cmd == "demo":
            from .flows.demo import run_demo

            return run_demo(args.out, args.engine)
        handlers = {"arc": cmd_arc, "segments": cmd_segments, "fit": cmd_fit, "chords": cmd_chords,
                    "compensate": cmd_compensate, "run": cmd_run, "send": cmd_send,
                    "board-sim": cmd_board_sim}
        return handlers[args.cmd](args)
    except UsageError as exc:
        print(f"halfpoint: {exc}", file=sys.stderr)
        return 2
    except ArcRejected as exc:
        print(f"halfpoint: arc rejected (code {exc.code}): {exc}", file=sys.stderr)
        return 3
    except GcodeError as exc:
        print(f"halfpoint: {getattr(args, 'program', '')}: {exc}", file=sys.stderr)
        return 3
    except MachineError as exc:
        print(f"halfpoint: machine file: {exc}", file=sys.stderr)
        return 3
    except EngineError as exc:
        print(f"halfpoint: {getattr(args, 'program', '')}: the {getattr(args, 'engine', '')} "
              f"engine: {exc}; a program the host accepted should run: please report it",
              file=sys.stderr)
        return 4
    except OSError as exc:
        print(f"halfpoint: cannot read {exc.filename}: {exc.strerror}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
