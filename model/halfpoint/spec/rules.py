# SPDX-License-Identifier: Apache-2.0
"""Integer rules shared by every model and by the host: defined once, here.

* ``fits(value, width, margin)``: does ``value`` fit a signed ``width``-bit
  field, with ``margin`` values kept free at both ends?  ``margin = 0`` is the
  field itself (what a port can carry); the host uses ``margin = 1`` for
  lattice points and arc centres, so that a point stays representable after
  one more lattice move in either direction (|x| <= M - 2, M = 2^(width-1)).
* ``wrap(value, width)``: two's-complement wrap into a signed ``width``-bit
  field (what a ``width``-bit position register holds).
* ``check_width``: the coordinate widths the RTL accepts (8..32).
"""

from __future__ import annotations

WIDTH_MIN = 8
WIDTH_MAX = 32


def field_range(width: int, margin: int = 0) -> tuple[int, int]:
    """(lowest, highest) value that ``fits``: -2^(width-1) + margin and
    2^(width-1) - 1 - margin (for loops that compare inline)."""
    half = 1 << (width - 1)
    return -half + margin, half - 1 - margin


def fits(value: int, width: int, margin: int = 0) -> bool:
    """Does ``value`` lie in ``field_range(width, margin)``?"""
    lo, hi = field_range(width, margin)
    return lo <= value <= hi


def wrap(value: int, width: int) -> int:
    """``value`` modulo 2^width, as a signed ``width``-bit number."""
    value &= (1 << width) - 1
    return value - (1 << width) if value >> (width - 1) else value


def check_width(width: int) -> None:
    """Raise ``ValueError`` unless ``width`` is a coordinate width the RTL accepts."""
    if not (isinstance(width, int) and WIDTH_MIN <= width <= WIDTH_MAX):
        raise ValueError(
            f"coordinate width must be an integer in {WIDTH_MIN}..{WIDTH_MAX}, got {width!r}")
