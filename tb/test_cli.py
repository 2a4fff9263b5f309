# SPDX-License-Identifier: Apache-2.0
"""The ``halfpoint`` command line: output format, errors, engine equality."""

from __future__ import annotations

import subprocess
import sys

import pytest

from halfpoint.arc import arc_points


def hp(*args):
    return subprocess.run([sys.executable, "-m", "halfpoint", *args], capture_output=True, text=True)


def test_arc_prints_points_with_header():
    p = hp("arc", "5", "0", "0", "5", "--ccw")
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0] == "x,y"
    pts = [tuple(map(int, ln.split(","))) for ln in lines[1:]]
    assert pts == arc_points(5, 0, 0, 5, 0)
    assert pts[0] == (5, 0) and pts[-1] == (0, 5)


def test_arc_no_header_and_cw():
    p = hp("arc", "--no-header", "0", "7", "7", "0", "--cw")
    assert p.returncode == 0
    assert p.stdout.splitlines()[0] == "0,7"
    assert p.stdout.splitlines()[-1] == "7,0"


@pytest.mark.parametrize(
    "args, needle",
    [
        (["arc", "0", "0", "1", "1", "--cw"], "radius is zero"),
        (["arc", "10", "0", "0", "13", "--cw"], "off the circle"),
        (["arc", "40000", "0", "40000", "0", "--cw", "--width", "16"], "does not fit"),
        (["arc", "32767", "0", "32767", "0", "--cw", "--width", "16"], "does not fit the coordinate width"),
        (["arc", "1", "2", "3", "--cw"], "arguments"),
        (["arc", "1", "0", "1", "0"], "--cw"),
        (["arc", "1", "0", "x", "0", "--ccw"], "not an integer"),
        (["arc", "1", "0", "1", "0", "--ccw", "--engine", "spice"], "engine"),
        (["arc", "1", "0", "1", "0", "--ccw", "--width", "64"], "width"),
    ],
)
def test_bad_input_one_line_reason_nonzero_exit(args, needle):
    p = hp(*args)
    assert p.returncode != 0
    assert p.stdout == ""
    err = p.stderr.strip().splitlines()
    assert len(err) == 1 and needle in err[0], p.stderr


@pytest.mark.parametrize(
    "args",
    [
        ["arc", "5", "0", "5", "0", "--ccw"],
        ["arc", "17", "-9", "-18", "-6", "--cw", "--width", "16"],
        ["arc", "0", "0", "1", "1", "--cw"],
    ],
)
def test_rtl_engine_prints_exactly_what_the_model_prints(args):
    m = hp(*args, "--engine", "model")
    r = hp(*args, "--engine", "rtl")
    assert (m.returncode, m.stdout, m.stderr) == (r.returncode, r.stdout, r.stderr)
