# SPDX-License-Identifier: Apache-2.0
"""The host end of the serial link (``spec.link``) over pyserial.

``Board(port, baud)`` opens ``port`` with ``serial.serial_for_url``: a device
(``/dev/ttyUSB0``) or any pyserial URL (``socket://127.0.0.1:7000``, ``loop://``).
It writes frames and turns the board's bytes into events:

    ("received",)            a frame arrived whole (COMMAND, HOLD, RESUME, STOP)
    ("taken",)               the core took the waiting COMMAND
    ("nak", reason)          a frame was refused (``link.NAK_*``)
    ("status", dict)         a STATUS reply (``link.parse_status``)
    ("ident", dict)          an IDENT reply (``link.parse_ident``)
    ("garbled", byte)        a byte that starts no reply, or a reply with a bad check

Every failure is a ``LinkError`` with a message that names the port.
"""

from __future__ import annotations

import time
from collections import deque

from ..spec import link


class LinkError(Exception):
    """The link failed: the message says how (no board, no answer, wrong protocol)."""


class Board:
    def __init__(self, port: str, baud: int = 115200, timeout: float = 2.0):
        import serial

        self.port = port
        self.timeout = timeout
        self.axes = 3
        self.buffer = bytearray()
        self.events: deque = deque()
        self.commands_written = 0       # COMMAND frames written (resends included)
        try:
            self.serial = serial.serial_for_url(port, baudrate=baud, timeout=0.02,
                                                write_timeout=timeout)
        except (serial.SerialException, ValueError, OSError) as exc:
            raise LinkError(f"cannot open {port}: {exc}") from None

    def close(self) -> None:
        try:
            self.serial.close()
        except Exception:       # noqa: BLE001 - closing a broken port must not mask the error
            pass

    # --------------------------------------------------------------------- writing
    def write(self, data: bytes) -> None:
        import serial

        if data[:1] == bytes([link.F_COMMAND]):
            self.commands_written += 1
        try:
            self.serial.write(data)
            self.serial.flush()
        except (serial.SerialException, OSError) as exc:
            raise LinkError(f"{self.port}: write failed: {exc}") from None

    # --------------------------------------------------------------------- reading
    def _parse(self) -> None:
        buf = self.buffer
        while buf:
            first = buf[0]
            if first == link.R_RECEIVED:
                self.events.append(("received",))
                del buf[:1]
            elif first == link.R_TAKEN:
                self.events.append(("taken",))
                del buf[:1]
            elif first == link.R_NAK:
                if len(buf) < 2:
                    return
                self.events.append(("nak", buf[1]))
                del buf[:2]
            elif first in (link.R_STATUS, link.R_IDENT):
                n = link.status_payload(self.axes) if first == link.R_STATUS \
                    else link.IDENT_PAYLOAD
                if len(buf) < n + 2:
                    return
                body, check = bytes(buf[:n + 1]), buf[n + 1]
                if link.crc8(body) != check:
                    self.events.append(("garbled", first))
                    del buf[:1]             # resynchronise on the next byte
                    continue
                if first == link.R_STATUS:
                    self.events.append(("status", link.parse_status(body[1:], self.axes)))
                else:
                    self.events.append(("ident", link.parse_ident(body[1:])))
                del buf[:n + 2]
            else:
                self.events.append(("garbled", first))
                del buf[:1]

    def poll(self, wait: float = 0.02):
        """The next event, or None after about ``wait`` seconds without one."""
        import serial

        if self.events:
            return self.events.popleft()
        end = time.monotonic() + wait
        while True:
            try:
                data = self.serial.read(max(1, self.serial.in_waiting))
            except (serial.SerialException, OSError) as exc:
                raise LinkError(f"{self.port}: read failed: {exc}") from None
            if data:
                self.buffer += data
                self._parse()
                if self.events:
                    return self.events.popleft()
            if time.monotonic() >= end:
                return None

    def request(self, opcode: int, want: str, retries: int = 3):
        """Send a control frame and return its reply event (``want``: "received",
        "status" or "ident"), resending it after a line NAK or a timeout.  Other
        events that arrive meanwhile are kept for the caller (``pending``)."""
        kept = []
        try:
            for _ in range(retries + 1):
                self.write(link.frame(opcode))
                end = time.monotonic() + self.timeout
                while time.monotonic() < end:
                    ev = self.poll(0.05)
                    if ev is None:
                        continue
                    if ev[0] == want:
                        return ev
                    if ev[0] == "nak" and ev[1] in link.NAK_LINE:
                        break                   # refused by a line error: send it again
                    kept.append(ev)
            raise LinkError(f"the board at {self.port} does not answer (no "
                            f"{want.upper() if want != 'received' else 'RECEIVED'} reply to a "
                            f"{_OPNAME.get(opcode, hex(opcode))} frame within "
                            f"{self.timeout:g} s, {retries + 1} tries)")
        finally:
            self.events.extendleft(reversed(kept))

    def ident(self) -> dict:
        return self.request(link.F_IDENT, "ident")[1]

    def status(self) -> dict:
        return self.request(link.F_STATUS, "status")[1]


_OPNAME = {link.F_COMMAND: "COMMAND", link.F_STATUS: "STATUS", link.F_HOLD: "HOLD",
           link.F_RESUME: "RESUME", link.F_STOP: "STOP", link.F_IDENT: "IDENT"}
