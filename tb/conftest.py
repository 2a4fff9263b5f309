# SPDX-License-Identifier: Apache-2.0
"""pytest options for every test under tb/.

``--sim icarus`` runs every cocotb runner (``halfpoint.sim.env.run_cocotb``) on
Icarus Verilog instead of Verilator, by setting $HALFPOINT_SIM for this
process and its pytest-xdist workers; ``--sim verilator`` (the default, or
$HALFPOINT_SIM when set) keeps Verilator.  Icarus must be on PATH
(iverilog, vvp): asking for it without is a usage error, not a silent skip.
"""

from __future__ import annotations

import os

import pytest

from halfpoint.sim.env import SIM_ENV, SIMULATORS, icarus_missing


def pytest_addoption(parser):
    parser.addoption(
        "--sim", choices=SIMULATORS, default=None,
        help=f"simulator of the cocotb tests (default ${SIM_ENV} or verilator)")


def pytest_configure(config):
    sim = config.getoption("--sim")
    if sim is None:
        return
    if sim == "icarus":
        why = icarus_missing()
        if why:
            raise pytest.UsageError(f"--sim icarus: {why}")
    os.environ[SIM_ENV] = sim


def pytest_report_header(config):
    return f"cocotb simulator: {os.environ.get(SIM_ENV) or 'verilator'}"
