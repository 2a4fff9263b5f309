# SPDX-License-Identifier: Apache-2.0
"""Non-circular curves for the core: tri-arc fitting (seed 003, ``triarc``)
and time-division parabola chords (seed 002, ``chords``).  Imports nothing of
``halfpoint.sim`` or ``halfpoint.flows``.
"""
