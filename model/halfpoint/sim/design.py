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
