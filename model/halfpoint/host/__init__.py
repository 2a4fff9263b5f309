# SPDX-License-Identifier: Apache-2.0
"""Host programs that talk to a board: ``board`` (the serial link's host end over
pyserial) and ``send`` (``halfpoint send``: a G-code program streamed to a board)."""
