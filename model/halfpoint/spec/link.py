# SPDX-License-Identifier: Apache-2.0
"""The serial link between a host and a board top: the one definition.

``rtl/halfpoint_uart_cmd.v`` implements it (its constants come from
``rtl/halfpoint_link.vh``, generated from this module by
``python -m halfpoint.flows.hdlgen``); ``halfpoint.host.send`` speaks it.
Bytes are UART 8N1, LSB first.

Host -> board: frames ``[opcode] [payload] [check]``; ``check`` is the CRC-8
(polynomial x^8 + x^2 + x + 1, 0x07, initial value 0, no reflection) of the
opcode and the payload.

============  ======  ========  ==============================================
frame         opcode  payload   the board's reply
============  ======  ========  ==============================================
COMMAND       0xC1    32 bytes  RECEIVED when the frame is complete and its
                                check is good, then TAKEN when the core has
                                taken the command (``spec.encoding``, the
                                256-bit word, little-endian)
STATUS        0xC2    none      a STATUS reply
HOLD          0xC3    none      RECEIVED; the core's feed hold goes high
RESUME        0xC4    none      RECEIVED; feed hold low
STOP          0xC5    none      RECEIVED; a controlled stop (below)
IDENT         0xC6    none      an IDENT reply
============  ======  ========  ==============================================

Board -> host: replies, each known by its first byte.

* RECEIVED ``0x06``: the frame arrived whole with a good check.
* TAKEN ``0x80``: the core took the waiting command.  The host sends the next
  COMMAND only after the TAKEN of the previous one (the flow control: the
  command waits in the port while the core's queue is full, so the queue stays
  full and the link never overruns it).  Between a COMMAND's RECEIVED and its
  TAKEN the host may send any other frame (status polls, hold, stop).
* NAK ``0x15`` then a reason byte (NAK_*): the frame was refused and had no
  effect.  A line error (bad check, a bad stop bit, a frame left unfinished for
  IDLE_BITS bit times, an unknown opcode) is reported once the line has been
  quiet for IDLE_BITS bit times, so the host resends the whole frame.  NAK_BUSY:
  a COMMAND while another waits (a host that broke the flow control).
  NAK_STOPPED: a COMMAND refused, or the waiting one dropped, because a stop is
  under way or a command was rejected (FAULT); it is the reply that takes the
  place of the COMMAND's TAKEN.
* STATUS ``0x53``, STATUS_PAYLOAD bytes, check: positions, queue level, flags
  (STATUS_FIELDS).
* IDENT ``0x49``, IDENT_PAYLOAD bytes, check: protocol version and the board's
  build (IDENT_FIELDS).  A host refuses a board with another PROTOCOL_VERSION.

Replies carry the same CRC-8 over their first byte and payload.  Every number
is little-endian; positions are the core's W-bit positions sign-extended to 32
bits.

A command the core rejects stops the job: the port latches FAULT with the
command's index (its count among the commands the core took since reset,
16 bits) and the core's code, asserts the core's controlled stop (it slows to
rest along the path and drops what is queued: nothing after the rejected
command runs), drops a waiting command (NAK_STOPPED) and refuses COMMAND
frames until the host sends STOP.  STOP clears FAULT, drops a waiting command
and asserts the core's stop until the core is at rest and empty (flag
STOPPING); it also releases a hold.
"""

from __future__ import annotations

PROTOCOL_VERSION = 1

# host -> board opcodes
F_COMMAND = 0xC1
F_STATUS = 0xC2
F_HOLD = 0xC3
F_RESUME = 0xC4
F_STOP = 0xC5
F_IDENT = 0xC6
COMMAND_BYTES = 32              # the payload of a COMMAND frame (encoding.CMD_BITS / 8)

# board -> host first bytes
R_RECEIVED = 0x06
R_TAKEN = 0x80
R_NAK = 0x15
R_STATUS = 0x53
R_IDENT = 0x49

# NAK reasons
NAK_CHECK = 1       # the check byte does not match
NAK_FRAMING = 2     # a byte with a bad stop bit
NAK_INCOMPLETE = 3  # the frame stopped short for IDLE_BITS bit times
NAK_OPCODE = 4      # an unknown opcode
NAK_BUSY = 5        # a COMMAND while another command waits for the core
NAK_STOPPED = 6     # a stop or a rejected command: the COMMAND was not run

NAK_TEXT = {
    NAK_CHECK: "check byte mismatch",
    NAK_FRAMING: "framing error (bad stop bit)",
    NAK_INCOMPLETE: "incomplete frame",
    NAK_OPCODE: "unknown frame opcode",
    NAK_BUSY: "a command while another one waits",
    NAK_STOPPED: "stopped: the command was not run",
}
NAK_LINE = (NAK_CHECK, NAK_FRAMING, NAK_INCOMPLETE, NAK_OPCODE)   # retried by the host

# STATUS flags (the flags byte)
FLAG_BUSY = 1 << 0          # the core's busy output
FLAG_HOLD = 1 << 1          # feed hold asserted (HOLD received, no RESUME or STOP yet)
FLAG_STOPPING = 1 << 2      # the core's stop asserted (STOP, or a rejected command)
FLAG_FAULT = 1 << 3         # a command was rejected; cleared by STOP
FLAG_UNDERRUN = 1 << 4      # the core's sticky underrun flag
FLAG_DRY = 1 << 5           # the core's sticky dry flag
FLAG_ABORT = 1 << 6         # the abort button is held
FLAG_WAITING = 1 << 7       # a command waits in the port for the core

# payload fields, in order: (name, bytes); "position" is 4 bytes per axis
IDENT_FIELDS = (
    ("version", 1),         # PROTOCOL_VERSION
    ("axes", 1),            # the core's NA
    ("width", 1),           # the core's W
    ("depth", 2),           # the core's queue depth
    ("clock_hz", 4),        # the board clock (the machine file's clock_hz must equal it)
    ("baud", 4),            # the serial bit rate
    ("div", 1),             # the core's profile tick, 2^DIV clocks
)
STATUS_TAIL_FIELDS = (
    ("level", 1),           # the core's queue level
    ("flags", 1),           # FLAG_*
    ("taken", 2),           # commands the core took since reset, modulo 2^16
    ("reject_index", 2),    # FAULT: index of the rejected command (as counted by taken)
    ("reject_code", 1),     # FAULT: the core's error code (encoding.E_*)
)
IDENT_PAYLOAD = sum(n for _, n in IDENT_FIELDS)


def status_payload(axes: int) -> int:
    """Bytes of a STATUS reply's payload from a board with ``axes`` axes."""
    return 4 * axes + sum(n for _, n in STATUS_TAIL_FIELDS)


def crc8(data: bytes, crc: int = 0) -> int:
    """CRC-8, polynomial 0x07, initial value 0, MSB first (the board's check)."""
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x07) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc


def frame(opcode: int, payload: bytes = b"") -> bytes:
    """A host frame: opcode, payload, check."""
    body = bytes([opcode]) + payload
    return body + bytes([crc8(body)])


def command_frame(cmd: int) -> bytes:
    """The COMMAND frame of an encoded command (``spec.encoding``)."""
    return frame(F_COMMAND, cmd.to_bytes(COMMAND_BYTES, "little"))


def reply(first: int, payload: bytes) -> bytes:
    """A STATUS or IDENT reply (used by the tests' fake boards)."""
    body = bytes([first]) + payload
    return body + bytes([crc8(body)])


def _fields(fields, values: dict) -> bytes:
    return b"".join(int(values[name]).to_bytes(n, "little") for name, n in fields)


def _unfields(fields, data: bytes) -> dict:
    out, k = {}, 0
    for name, n in fields:
        out[name] = int.from_bytes(data[k:k + n], "little")
        k += n
    return out


def ident_payload(**values) -> bytes:
    return _fields(IDENT_FIELDS, values)


def parse_ident(payload: bytes) -> dict:
    return _unfields(IDENT_FIELDS, payload)


def status_bytes(position, **values) -> bytes:
    """A STATUS payload (positions then STATUS_TAIL_FIELDS)."""
    return b"".join(int(p).to_bytes(4, "little", signed=True) for p in position) + \
        _fields(STATUS_TAIL_FIELDS, values)


def parse_status(payload: bytes, axes: int) -> dict:
    out = _unfields(STATUS_TAIL_FIELDS, payload[4 * axes:])
    out["position"] = tuple(int.from_bytes(payload[4 * k:4 * k + 4], "little", signed=True)
                            for k in range(axes))
    return out
