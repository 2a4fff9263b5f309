# SPDX-License-Identifier: Apache-2.0
"""The register map's generated files: rtl/halfpoint_regs.vh and
include/halfpoint_regs.h are current (what ``halfpoint.flows.regmapgen``
writes from ``halfpoint.spec.regmap`` now), their macros say what the map says
(the C header checked by gcc itself, with static assertions), the register
file decodes through the Verilog header (no address of its own), and the
README's register table, between ``<!-- regmap begin -->`` and
``<!-- regmap end -->``, is the generated one."""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from halfpoint.flows import regmapgen
from halfpoint.sim.env import REPO, RTL
from halfpoint.spec import regmap as rm


def macros(text: str) -> dict[str, str]:
    return {m[1]: m[2].strip() for m in re.finditer(r"^`define\s+(\w+)[ \t]*(.*)$", text, re.M)}


def number(value: str) -> int:
    m = re.fullmatch(r"(?:\d+)?'([dh])([0-9a-fA-F_]+)", value)
    if m:
        return int(m[2].replace("_", ""), 10 if m[1] == "d" else 16)
    return int(value)


def test_generated_files_are_current():
    for path, text in regmapgen.outputs().items():
        assert path.read_text() == text, (
            f"{path.relative_to(REPO)} is not current: run `python -m halfpoint.flows.regmapgen`")
    assert regmapgen.main(["--check"]) == 0


def test_check_mode_detects_a_stale_header(tmp_path, monkeypatch):
    stale = tmp_path / "halfpoint_regs.vh"
    stale.write_text(regmapgen.verilog().replace("`define HALFPOINT_REG_CONTROL 8'h10",
                                                 "`define HALFPOINT_REG_CONTROL 8'h14"))
    monkeypatch.setattr(regmapgen, "VERILOG_HEADER", stale)
    assert regmapgen.main(["--check"]) == 1


def test_verilog_macros_are_the_map():
    m = macros(regmapgen.VERILOG_HEADER.read_text())
    assert number(m["HALFPOINT_REGS_ADDR_BITS"]) == rm.ADDR_BITS
    assert number(m["HALFPOINT_REG_ID_VALUE"]) == rm.ID_VALUE
    for reg in rm.REGISTERS:
        name = f"HALFPOINT_REG_{reg.name}"
        assert number(m[name]) == reg.offset
        if reg.count != 1:
            assert number(m[f"{name}_STRIDE"]) == reg.stride
        for f in reg.fields:
            assert number(m[f"{name}_{f.name}_LSB"]) == f.lsb
            assert number(m[f"{name}_{f.name}_WIDTH"]) == f.width


def test_register_file_decodes_through_the_header():
    """Every register's address macro is used by halfpoint_regs.v, and the file
    writes no address literal of the window's width."""
    text = (RTL / "halfpoint_regs.v").read_text()
    for reg in rm.REGISTERS:
        assert re.search(rf"`HALFPOINT_REG_{reg.name}\b", text), reg.name
    assert not re.search(rf"\b{rm.ADDR_BITS}'[hdb]", text), "an address literal in the RTL"


@pytest.mark.skipif(shutil.which("gcc") is None, reason="no gcc on this machine")
def test_c_header_is_the_map(tmp_path):
    """gcc -Wall -Werror -std=c11 -pedantic compiles the header with a static
    assertion per register and field, written from the map here."""
    lines = ['#include "halfpoint_regs.h"',
             f"_Static_assert(HALFPOINT_ID_VALUE == 0x{rm.ID_VALUE:X}u, \"ID\");"]
    for reg in rm.REGISTERS:
        name = f"HALFPOINT_{reg.name}"
        for k in range(reg.size(6)):
            where = f"{name}({k})" if reg.count != 1 else name
            lines.append(f"_Static_assert({where} == {reg.address(k)}u, \"{reg.name}\");")
        for f in reg.fields:
            lines.append(f"_Static_assert({name}_{f.name}_MASK == 0x{f.mask:X}u && "
                         f"{name}_{f.name}_SHIFT == {f.lsb}u, \"{reg.name}.{f.name}\");")
    lines.append("_Static_assert(HALFPOINT_GET(0x1234u, CONTROL_OVERRIDE) == 0x12u, \"GET\");")
    lines.append("_Static_assert(HALFPOINT_PUT(CONTROL_OVERRIDE, 0x12u) == 0x1200u, \"PUT\");")
    src = tmp_path / "check.c"
    src.write_text("\n".join(lines) + "\nint main(void) { return 0; }\n")
    subprocess.run(["gcc", "-Wall", "-Wextra", "-Werror", "-std=c11", "-pedantic",
                    f"-I{regmapgen.C_HEADER.parent}", "-o", str(tmp_path / "check"), str(src)],
                   check=True)


def test_readme_register_table_is_current():
    readme = (REPO / "README.md").read_text()
    table = regmapgen.readme_table(readme)
    assert table is not None, (f"README.md has no register table between "
                               f"{regmapgen.README_BEGIN} and {regmapgen.README_END}")
    assert table == regmapgen.markdown_table(), (
        "the README's register table is not current: paste "
        "`python -m halfpoint.flows.regmapgen --markdown` between the markers")


def test_readme_table_reader(tmp_path):
    text = f"intro\n{regmapgen.README_BEGIN}\n{regmapgen.markdown_table()}{regmapgen.README_END}\n"
    assert regmapgen.readme_table(text) == regmapgen.markdown_table()
    assert regmapgen.readme_table("no markers") is None
