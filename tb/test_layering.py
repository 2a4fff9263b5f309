# SPDX-License-Identifier: Apache-2.0
"""The package's layering, read from the imports of every module (ast):

* ``halfpoint.spec`` (the specification) imports nothing of halfpoint outside
  itself, and nothing but the standard library and numpy;
* ``halfpoint.cam`` imports only ``spec`` (and itself) of halfpoint;
* ``halfpoint.curves`` imports nothing of ``sim`` or ``flows``;
* only ``halfpoint.sim`` imports cocotb (or a cocotb extension);
* no cycle between the subpackages (the top-level modules, ``cli``, count as
  one more node).

The checker is tried on a small package with planted violations first, so that
a checker that finds nothing cannot pass unnoticed.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "model" / "halfpoint"
TOP = "(top)"       # modules directly in halfpoint/: cli, __main__


def module_imports(path: Path, root: Path) -> list[str]:
    """Absolute names of everything ``path`` imports (relative imports resolved)."""
    rel = path.relative_to(root.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
        package = parts
    else:
        package = parts[:-1]
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            out += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - (node.level - 1)]
                name = ".".join(base + ([node.module] if node.module else []))
                if node.module is None:
                    out += [f"{name}.{alias.name}" for alias in node.names]
                    continue
            else:
                name = node.module
            out.append(name)
    return out


def subpackage(name: str, top: str, subpackages: set[str]) -> str | None:
    """The subpackage of ``top`` that module ``name`` belongs to (None: not ours)."""
    parts = name.split(".")
    if parts[0] != top:
        return None
    return parts[1] if len(parts) > 1 and parts[1] in subpackages else TOP


def violations(root: Path) -> list[str]:
    """Every layering rule broken by the package at ``root``."""
    top = root.name
    subpackages = {p.name for p in root.iterdir() if (p / "__init__.py").exists()}
    stdlib = set(sys.stdlib_module_names)
    found = []
    edges: dict[str, set[str]] = {}
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        mine = rel.parts[0] if len(rel.parts) > 1 else TOP
        for name in module_imports(path, root):
            first = name.split(".")[0]
            where = f"{top}/{rel}: imports {name}"
            if first in ("cocotb", "cocotb_tools") or first.startswith("cocotbext"):
                if mine != "sim":
                    found.append(f"{where} (only sim may import cocotb)")
                continue
            theirs = subpackage(name, top, subpackages)
            if theirs is None:
                if mine == "spec" and first not in stdlib and first != "numpy":
                    found.append(f"{where} (spec: standard library and numpy only)")
                continue
            if theirs != mine:
                edges.setdefault(mine, set()).add(theirs)
            if mine == "spec" and theirs != "spec":
                found.append(f"{where} (spec imports nothing outside itself)")
            if mine == "cam" and theirs not in ("spec", "cam"):
                found.append(f"{where} (cam imports spec only)")
            if mine == "curves" and theirs in ("sim", "flows"):
                found.append(f"{where} (curves imports nothing of sim or flows)")
    # cycles between subpackages (depth-first search on the import graph)
    state: dict[str, int] = {}

    def visit(node: str, trail: list[str]) -> None:
        state[node] = 1
        for nxt in sorted(edges.get(node, ())):
            if state.get(nxt) == 1:
                cycle = trail[trail.index(nxt):] + [nxt] if nxt in trail else [node, nxt]
                found.append("cycle between subpackages: " + " -> ".join(cycle))
            elif nxt not in state:
                visit(nxt, trail + [nxt])
        state[node] = 2

    for node in sorted(edges):
        if node not in state:
            visit(node, [node])
    return found


def test_halfpoint_layering():
    assert violations(PACKAGE) == []


def test_every_subpackage_exists():
    names = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()}
    assert {"spec", "cam", "curves", "sim", "flows"} <= names


def _plant(tmp_path: Path, files: dict[str, str]) -> Path:
    root = tmp_path / "pkg"
    for rel, text in files.items():
        f = root / rel
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(text)
    for sub in ("spec", "cam", "curves", "sim", "flows"):
        (root / sub).mkdir(parents=True, exist_ok=True)
        (root / sub / "__init__.py").touch()
    (root / "__init__.py").touch()
    return root


@pytest.mark.parametrize("files, expected", [
    ({"spec/a.py": "from ..cam import quant\n"}, "spec imports nothing outside itself"),
    ({"spec/a.py": "import matplotlib\n"}, "standard library and numpy only"),
    ({"spec/a.py": "import cocotb\n"}, "only sim may import cocotb"),
    ({"cam/a.py": "from ..sim.env import BUILD\n"}, "cam imports spec only"),
    ({"cam/a.py": "from pkg.curves import triarc\n"}, "cam imports spec only"),
    ({"curves/a.py": "from ..flows import bench\n"}, "curves imports nothing of sim or flows"),
    ({"sim/a.py": "from ..flows import bench\n", "flows/b.py": "from ..sim import a\n"},
     "cycle between subpackages"),
])
def test_checker_finds_planted_violations(tmp_path, files, expected):
    found = violations(_plant(tmp_path, files))
    assert any(expected in f for f in found), found


def test_checker_accepts_allowed_imports(tmp_path):
    root = _plant(tmp_path, {
        "spec/a.py": "import math\nimport numpy as np\nfrom . import b\nfrom .b import c\n",
        "spec/b.py": "c = 1\n",
        "cam/q.py": "from ..spec import a\nfrom . import r\n",
        "cam/r.py": "",
        "sim/s.py": "import cocotb\nfrom ..cam import q\n",
        "flows/f.py": "from ..sim import s\nfrom ..curves import t\n",
        "curves/t.py": "from ..spec import a\n",
        "cli.py": "from .flows import f\n",
    })
    assert violations(root) == []
