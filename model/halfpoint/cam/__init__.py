# SPDX-License-Identifier: Apache-2.0
"""G-code in, core commands out: the host toolchain.

``gcode`` (parser), ``geom`` (lines, arcs, intersections), ``comp`` (cutter
radius compensation), ``quant`` (quantisation onto the core's lattice),
``segments`` (JSON-lines segment files), ``machine`` (the machine file),
``planner`` (lookahead speed planning), ``run`` (the ``compensate`` / ``run``
pipeline).  Imports ``halfpoint.spec`` only.
"""
