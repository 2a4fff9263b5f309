# SPDX-License-Identifier: Apache-2.0
"""Issue 12, item 5: every shipped ``examples/*.ngc`` runs as it is, with no
``--tools`` and no ``--radius`` (the tools.tbl beside the program, D words
that give the diameter), through the whole chain: parsing, compensation,
quantisation and the core model."""

from __future__ import annotations

from pathlib import Path

import pytest

from halfpoint.cam.run import run_program

EX = Path(__file__).resolve().parents[2] / "examples"
PROGRAMS = sorted(EX.glob("*.ngc"))

# tool radius (mm) each compensated example must end up with, as its source states
RADIUS = {"plate.ngc": 3.0, "seed004_test1.ngc": 0.03, "seed004_test2.ngc": 1.0}


def test_the_examples_are_found():
    assert {p.name for p in PROGRAMS} >= set(RADIUS) | {"bolt_circle.ngc"}


@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: p.name)
def test_example_runs_without_tool_options(path):
    # a 10 um lattice keeps the core model's run short; the tool choice is what is tested
    # (cam_style.ngc's helical bore runs in hardware: issue 14, item 2)
    res = run_program(str(path), blu=(0.01,) * 3)
    assert res.lattice, "the core made no move"
    radii = {m.radius for m in res.programmed if m.comp != "off"}
    if path.name in RADIUS:
        assert radii == {RADIUS[path.name]}, radii
    # the lattice path stays within the quantiser's bound of the compensated path
    assert res.max_dev_mm <= 1.0 * res.blu[0] + 1e-12, res.max_dev_mm
