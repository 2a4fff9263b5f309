# SPDX-License-Identifier: Apache-2.0
"""What ``make`` runs: ``lint``, ``synth`` (and the board tops), ``bench``
(with its ``baselines`` and model statistics), ``simspeed`` (Verilator speed
figures), ``wavedoc`` (timing diagrams for the README), ``hdlgen`` (Verilog
headers generated from the specification) and ``demo``.
"""
