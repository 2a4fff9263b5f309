# SPDX-License-Identifier: Apache-2.0
"""The ``halfpoint`` command line.

    halfpoint arc XS YS XE YE (--cw | --ccw) [--engine model|rtl] [--width W]
    halfpoint segments FILE [--engine model|rtl]
    halfpoint demo [--out DIR] [--engine model|rtl|both]
"""

from __future__ import annotations

import argparse
import sys

from .arc import ERR_TEXT, ArcRejected, check_width, field_ok
from .engines import ENGINES, run_arcs


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

    m = sub.add_parser("demo", help="shipped arcs through model and RTL, with plots")
    m.add_argument("--out", default="build/demo", help="output directory")
    m.add_argument("--engine", choices=ENGINES + ("both",), default="both")
    return p


def cmd_arc(args) -> int:
    try:
        check_width(args.width)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    for name in ("xs", "ys", "xe", "ye"):
        if not field_ok(getattr(args, name), args.width):
            raise UsageError(f"{name.upper()}={getattr(args, name)} does not fit a signed {args.width}-bit field")
    cmd = (1 if args.cw else 0, args.xs, args.ys, args.xe, args.ye)
    (res,) = run_arcs([cmd], args.engine, args.width)
    if res.rejected:
        print(f"halfpoint: arc rejected (code {res.rejected}): {ERR_TEXT[res.rejected]}", file=sys.stderr)
        return 3
    lines = [] if args.no_header else ["x,y"]
    lines += [f"{x},{y}" for x, y in res.points]
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def cmd_segments(args) -> int:
    from .segments import SegmentError, parse_segments, run_segments_model, run_segments_rtl

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
    cmds = [s.cmd for s in segs]
    trace = (run_segments_rtl if args.engine == "rtl" else run_segments_model)(cmds)
    out = [",".join("0" for _ in range(3))] + [",".join(str(v) for v in p) for p in trace]
    sys.stdout.write("\n".join(out) + "\n")
    return 0


def main(argv=None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.cmd == "arc":
            return cmd_arc(args)
        if args.cmd == "segments":
            return cmd_segments(args)
        if args.cmd == "demo":
            from .demo import run_demo

            return run_demo(args.out, args.engine)
    except UsageError as exc:
        print(f"halfpoint: {exc}", file=sys.stderr)
        return 2
    except ArcRejected as exc:
        print(f"halfpoint: arc rejected (code {exc.code}): {exc}", file=sys.stderr)
        return 3
    return 1


if __name__ == "__main__":
    sys.exit(main())
