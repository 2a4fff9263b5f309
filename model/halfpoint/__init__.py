# SPDX-License-Identifier: Apache-2.0
"""halfpoint: golden model and host toolchain of the halfpoint motion core."""

__version__ = "0.1.0"
