# SPDX-License-Identifier: Apache-2.0
"""Parameters of the design under test, read from the elaborated design.

The cocotb benches take NA, W, DEPTH, TW ... from the simulator (Verilator
exposes every parameter of the top level through VPI), so a test can never
run against a build with other values than the ones it believes in.  Test
settings that are not parameters of the design (a seed, a baud-rate error)
still come from the environment.
"""

from __future__ import annotations


def read_parameters(dut, *names: str) -> tuple[int, ...]:
    """Values of the top level's parameters ``names``, in that order."""
    return tuple(int(getattr(dut, name).value) for name in names)


# --- the files of a design, read from the RTL's own instantiations -----------------------

def strip_comments(text: str) -> str:
    """Verilog ``text`` without its comments."""
    import re

    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def rtl_modules(rtl) -> dict:
    """module name -> file, for every module declared in ``rtl``/*.v (a module declared
    twice is an error)."""
    import re

    found = {}
    for path in sorted(rtl.glob("*.v")):
        for name in re.findall(r"^\s*module\s+(\w+)", strip_comments(path.read_text()), re.M):
            if name in found:
                raise ValueError(f"module {name} declared in {found[name]} and {path}")
            found[name] = path
    return found


def instantiated(text: str, known) -> set:
    """The modules of ``known`` that Verilog ``text`` instantiates
    (``name #(...) inst (...)`` or ``name inst (...)``; comments ignored)."""
    import re

    text = strip_comments(text)
    used = set()
    for name in known:
        pattern = rf"(?<![\w`$.]){name}\b\s*(?:#\s*\(|[A-Za-z_]\w*\s*\()"
        for m in re.finditer(pattern, text):
            if not re.search(r"\bmodule\s+$", text[:m.start()]):
                used.add(name)
    return used


def design_sources(top: str, rtl=None) -> list:
    """The RTL files of ``top`` and of every module below it (``rtl/`` by default),
    top first: the one answer to "which files make this design", so that a module
    added to the core reaches every simulation without a list to update by hand."""
    from .env import RTL

    modules = rtl_modules(rtl or RTL)
    files, todo = [], [top]
    while todo:
        path = modules[todo.pop(0)]
        if path in files:
            continue
        files.append(path)
        todo += sorted(instantiated(path.read_text(), modules))
    return files
