# SPDX-License-Identifier: Apache-2.0
"""The executable specification of the halfpoint core.

Bit-exact, cycle-accurate models of each RTL module under the module's own
name (``arc``, ``line``, ``stepgen``, ``core``), the command encoding
(``encoding``) and the small integer rules they share (``rules``: the signed
range check and two's-complement wrap).  Pure Python plus numpy: nothing here
imports another subpackage of halfpoint, nor cocotb (``tb/test_layering.py``).
"""
