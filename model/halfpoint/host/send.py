# SPDX-License-Identifier: Apache-2.0
"""``halfpoint send PROGRAM.ngc --port PORT``: a G-code program to a board over the
serial link (``spec.link``).

The program goes through the host pipeline of ``halfpoint run`` (parse with the
machine's stored positions, travel check, cutter compensation, quantisation, the
planner's PROFILE before every motion command: ``cam.motion.build_motion``) and
the commands are streamed to the board:

1. IDENT: the board must speak ``link.PROTOCOL_VERSION``, have 3 axes, and run
   at the machine file's ``clock_hz`` (the planner's clock); else nothing is sent.
2. STATUS: the board must be at rest with nothing queued and no fault.
3. Each command as a COMMAND frame; the next one after the board's TAKEN (the
   core took it), so the core's queue is kept full and never overrun.  A frame
   refused for a line error (NAK) is sent again, up to ``RETRIES`` times, then
   the job stops; a frame without any answer is retried after a STATUS tells
   whether the board has it.  Between a COMMAND's RECEIVED and its TAKEN the
   host polls STATUS for the progress bar (block, G-code line, position).
4. A dwell waits until the board is at rest, then the dwell's time.
5. At the end: wait until the board is at rest; the position must be the start
   position plus the program's moves.

A command the board rejects stops the job: the board stops the core (controlled
stop: it slows to rest along the path, nothing after the rejected command runs);
the host names the G-code line and the reason, sends STOP, and exits with
status 3.  Ctrl-C holds the machine (HOLD), waits for it to come to rest and asks
whether to resume (RESUME) or stop (STOP, exit status 4).
"""

from __future__ import annotations

import signal
import sys
import time
from dataclasses import dataclass, field

from ..spec import encoding as enc
from ..spec import link
from .board import Board, LinkError

RETRIES = 5             # resends of one frame after line errors before the job stops
POLL_S = 0.1            # status polls while a command waits for the core


class JobError(Exception):
    """The job stopped: ``status`` is the exit status, the message says why."""

    def __init__(self, message: str, status: int = 3):
        super().__init__(message)
        self.status = status


@dataclass
class Item:
    """One command of the stream with what names it to the user."""

    cmd: int | None             # the command (None: a dwell)
    lineno: int                 # its G-code line
    block: int                  # its motion command's number, from 1
    pause_s: float = 0.0        # a dwell's seconds


@dataclass
class Job:
    items: list
    blocks: int                         # motion commands
    delta: tuple                        # the program's total move, BLU per axis
    blu: tuple
    clock_hz: int
    stats: dict = field(default_factory=lambda: {"resent": 0, "naks": {}})


def plan_job(path: str, machine, radius=None, tools=None, strict=False) -> Job:
    """The commands of a program (``halfpoint run``'s pipeline up to the plan,
    ``cam.run.plan_motion``: its spindle, laser and coolant changes included)."""
    from ..cam.motion import Pause
    from ..cam.planner import OutputChange
    from ..cam.run import load_program, plan_motion

    prog, comp, _ = load_program(path, radius, tools, strict, 5, machine)
    _, motion = plan_motion(prog, comp, machine, 32)
    # an OUTPUT command is named by its M / S block: the output changes are in the
    # command stream in the order of the plan's OutputChange items
    output_lines = iter([it.lineno for it in motion.planned if isinstance(it, OutputChange)])
    items, k = [], 0
    delta = [0, 0, 0]
    commands = motion.commands
    for it in motion.items:
        if isinstance(it, Pause):
            items.append(Item(None, it.lineno, k, it.seconds))
            continue
        d = enc.decode(it)
        if d["opcode"] == enc.OP_OUTPUT:
            items.append(Item(it, next(output_lines), k))
            continue
        pc = commands[min(k, len(commands) - 1)]
        items.append(Item(it, pc.move.lineno, k + 1))
        if d["opcode"] != enc.OP_PROFILE:
            if d["opcode"] == enc.OP_LINE:
                for a in range(3):
                    delta[a] += d["deltas"][a]
            else:
                delta[0] += d["x"]
                delta[1] += d["y"]
            k += 1
    return Job(items, len(commands), tuple(delta), tuple(machine.blu), machine.clock_hz)


def _wrap(v: int, width: int) -> int:
    v &= (1 << width) - 1
    return v - (1 << width) if v >> (width - 1) else v


class Sender:
    """Streams a ``Job`` to a ``Board`` (module docstring)."""

    def __init__(self, board: Board, job: Job, quiet: bool = False, out=sys.stderr,
                 ask=input):
        self.board = board
        self.job = job
        self.quiet = quiet
        self.out = out
        self.ask = ask
        self.interrupted = False
        self.width = 32
        self.taken = 0              # commands of this job the core took
        self.taken_base = 0         # the board's taken count at the start (16 bits)
        self.last_status = None
        self.bar = None
        # job.items index of each command, in order
        self.command_items = [i for i, it in enumerate(job.items) if it.cmd is not None]

    def say(self, text: str) -> None:
        if self.bar is not None:
            self.bar.clear()
        print(f"halfpoint: {text}", file=self.out, flush=True)
        if self.bar is not None:
            self.bar.refresh()

    # ------------------------------------------------------------------- checks
    def check_board(self) -> dict:
        ident = self.board.ident()
        if ident["version"] != link.PROTOCOL_VERSION:
            raise JobError(f"the board at {self.board.port} speaks serial protocol version "
                           f"{ident['version']}, this host speaks {link.PROTOCOL_VERSION}: "
                           "update the bitstream or the host; nothing was sent", 2)
        if ident["axes"] != 3:
            raise JobError(f"the board has {ident['axes']} axes, the host plans for 3; "
                           "nothing was sent", 2)
        if ident["clock_hz"] != self.job.clock_hz:
            raise JobError(f"the board runs at {ident['clock_hz']} Hz, the machine file says "
                           f"clock_hz = {self.job.clock_hz}: the plan would run at the wrong "
                           "speed; nothing was sent", 2)
        if ident["width"] != 32:
            raise JobError(f"the board's core is {ident['width']} bits wide, the host plans "
                           "for 32; nothing was sent", 2)
        self.width = ident["width"]
        self.board.axes = ident["axes"]
        st = self.board.status()
        if st["flags"] & (link.FLAG_BUSY | link.FLAG_STOPPING | link.FLAG_WAITING) or \
                st["level"]:
            raise JobError("the board is busy (a job is running or stopping); nothing was "
                           "sent", 2)
        if st["flags"] & link.FLAG_FAULT:
            raise JobError("the board holds a rejected command from an earlier job "
                           "(send STOP: reset the board); nothing was sent", 2)
        if st["flags"] & link.FLAG_ABORT:
            raise JobError("the abort button is held; nothing was sent", 2)
        if st["flags"] & link.FLAG_HOLD:
            self.board.request(link.F_RESUME, "received")
        self.taken_base = st["taken"]
        self.last_status = st
        return ident

    # ----------------------------------------------------------------- progress
    def _open_bar(self) -> None:
        if self.quiet:
            return
        from tqdm import tqdm

        self.bar = tqdm(total=self.job.blocks, unit="block", file=self.out, leave=True,
                        dynamic_ncols=True)

    def _progress(self, st: dict) -> None:
        self.last_status = st
        if self.bar is None:
            return
        done = (st["taken"] - self.taken_base - st["level"]) & 0xFFFF
        done = min(done, self.taken)
        item = self.job.items[min(self._item_of(done), len(self.job.items) - 1)] \
            if self.job.items else None
        block = item.block if item else 0
        self.bar.n = max(0, min(block - 1 if st["flags"] & link.FLAG_BUSY else block,
                                self.job.blocks))
        pos = ",".join(f"{p * b:.3f}" for p, b in zip(st["position"], self.job.blu))
        self.bar.set_postfix_str(f"line {item.lineno if item else '-'} pos {pos} mm",
                                 refresh=True)

    def _item_of(self, command_index: int) -> int:
        """Index in job.items of the job's command number ``command_index``."""
        if 0 <= command_index < len(self.command_items):
            return self.command_items[command_index]
        return len(self.job.items) - 1

    # ------------------------------------------------------------------ running
    def run(self) -> dict:
        self.check_board()
        start = self.last_status["position"]
        old = signal.getsignal(signal.SIGINT)
        signal.signal(signal.SIGINT, self._on_sigint)
        if not self.quiet:
            self.say(f"streaming {self.job.blocks} blocks to {self.board.port} "
                     "(Ctrl-C holds the machine)")
        self._open_bar()
        try:
            for item in self.job.items:
                if item.cmd is None:
                    self._wait_idle()
                    time.sleep(item.pause_s)
                    continue
                self._send_command(item)
            st = self._wait_idle()
        finally:
            signal.signal(signal.SIGINT, old)
            if self.bar is not None:
                self.bar.close()
                self.bar = None
        expect = tuple(_wrap(s + d, self.width) for s, d in zip(start, self.job.delta))
        if st["position"] != expect:
            raise JobError(f"the board ended at {st['position']} BLU, the program should "
                           f"end at {expect}", 3)
        return st

    def _on_sigint(self, signum, frame) -> None:
        self.interrupted = True

    def _events(self, wait: float = POLL_S, can_hold: bool = True):
        """One event (or None); Ctrl-C handled between events (``can_hold``: no frame
        waits for its first reply, so a HOLD's reply cannot be confused with it)."""
        if self.interrupted and can_hold:
            self.interrupted = False
            self._hold_and_ask()
        ev = self.board.poll(wait)
        if ev is not None and ev[0] == "nak":
            self.job.stats["naks"][ev[1]] = self.job.stats["naks"].get(ev[1], 0) + 1
        return ev

    def _send_command(self, item: Item) -> None:
        frame = link.command_frame(item.cmd)
        tries = 0
        self.board.write(frame)
        sent = time.monotonic()
        received = False
        status_sent = None          # time of an unanswered STATUS poll
        while True:
            ev = self._events(0.02 if not received else POLL_S, can_hold=received)
            now = time.monotonic()
            if ev is None:
                if not received and now - sent > self.board.timeout:
                    # no answer to the COMMAND: does the board have it?
                    st = self.board.status()
                    self._check_flags(st, item)
                    taken_now = (st["taken"] - self.taken_base) & 0xFFFF
                    if taken_now > self.taken:
                        self.taken += 1
                        return
                    if st["flags"] & link.FLAG_WAITING:
                        received = True
                        continue
                    tries = self._resend(frame, tries, item, "no answer")
                    sent = time.monotonic()
                    continue
                if received and (status_sent is None or now - status_sent > self.board.timeout):
                    if status_sent is not None:
                        self.job.stats["resent"] += 1
                    self.board.write(link.frame(link.F_STATUS))
                    status_sent = now
                continue
            kind = ev[0]
            if kind == "received" and not received:
                received = True
                self.board.write(link.frame(link.F_STATUS))
                status_sent = now
            elif kind == "taken":
                self.taken += 1
                return
            elif kind == "nak" and ev[1] in link.NAK_LINE:
                if not received:
                    tries = self._resend(frame, tries, item, link.NAK_TEXT[ev[1]])
                    sent = time.monotonic()
                else:               # the STATUS poll was refused: poll again later
                    status_sent = None
            elif kind == "nak" and ev[1] == link.NAK_STOPPED:
                self._stopped(item)
            elif kind == "nak":
                raise JobError(f"the board refused a command ({link.NAK_TEXT.get(ev[1], ev[1])})"
                               f" at line {item.lineno}", 3)
            elif kind == "status":
                status_sent = None
                self._check_flags(ev[1], item)
                self._progress(ev[1])
                if received and (ev[1]["taken"] - self.taken_base) & 0xFFFF > self.taken:
                    self.taken += 1         # its TAKEN was lost on the way back
                    self.job.stats["lost_replies"] = self.job.stats.get("lost_replies", 0) + 1
                    return

    def _resend(self, frame: bytes, tries: int, item: Item, why: str) -> int:
        tries += 1
        if tries > RETRIES:
            self._stop_machine()
            raise JobError(f"line {item.lineno}: the link failed {tries} times sending block "
                           f"{item.block} ({why}); the job was stopped, the machine is at rest",
                           3)
        self.job.stats["resent"] += 1
        self.board.write(frame)
        return tries

    def _check_flags(self, st: dict, item: Item) -> None:
        if st["flags"] & link.FLAG_ABORT:
            self._stop_machine()
            raise JobError(f"the abort button was pressed (at line {item.lineno}); the job "
                           "was stopped", 3)
        if st["flags"] & link.FLAG_FAULT:
            self._stopped(item, st)

    def _stopped(self, item: Item, st: dict | None = None) -> None:
        """The board stopped (a rejected command): name it, clear it, end the job."""
        st = st or self.board.status()
        if not st["flags"] & link.FLAG_FAULT:
            raise JobError(f"the board stopped the job at line {item.lineno} (a STOP from "
                           "elsewhere, or a reset)", 3)
        # the rejected command's number in this job, from the board's 16-bit index
        index = self.taken - 1 - ((self.taken_base + self.taken - 1 - st["reject_index"])
                                  & 0xFFFF)
        at = self.job.items[self._item_of(index)] if 0 <= index < self.taken else None
        code = st["reject_code"]
        st = self._wait_idle(stopping=True)
        self._stop_machine()
        where = f"line {at.lineno}" if at else f"command {index} (not this job's)"
        pos = ",".join(str(p) for p in st["position"])
        raise JobError(f"{where}: the board rejected block {at.block if at else '?'} (code "
                       f"{code}: {enc.ERR_TEXT.get(code, 'unknown code')}); the job was "
                       f"stopped, the machine is at rest at {pos} BLU", 3)

    def _stop_machine(self) -> None:
        self.board.request(link.F_STOP, "received")
        self._wait_idle(stopping=True)

    def _wait_idle(self, stopping: bool = False) -> dict:
        """Poll until the board is at rest and empty (and, with ``stopping``, its stop
        finished)."""
        while True:
            if self.interrupted and not stopping:
                self.interrupted = False
                self._hold_and_ask()
            st = self.board.status()
            if not stopping:
                self._check_flags(st, self.job.items[-1] if self.job.items else Item(0, 0, 0))
            self._progress(st)
            busy = st["flags"] & (link.FLAG_BUSY | link.FLAG_WAITING | link.FLAG_STOPPING)
            if not busy and not st["level"]:
                return st
            time.sleep(POLL_S)

    def _hold_and_ask(self) -> None:
        self.board.request(link.F_HOLD, "received")
        prev = None
        while True:            # at rest: the same position twice in a row
            st = self.board.status()
            if st["position"] == prev:
                break
            prev = st["position"]
            time.sleep(POLL_S)
        self._progress(st)
        pos = ",".join(f"{p * b:.4f}" for p, b in zip(st["position"], self.job.blu))
        self.say(f"held at {pos} mm; resume or stop? [r/s]")
        while True:
            try:
                answer = self.ask("").strip().lower()
            except (EOFError, KeyboardInterrupt):
                answer = "s"
            if answer in ("r", "resume"):
                self.board.request(link.F_RESUME, "received")
                self.say("resumed")
                return
            if answer in ("s", "stop"):
                self._stop_machine()
                st = self.board.status()
                raise JobError("stopped by the user; the machine is at rest at "
                               + ",".join(str(p) for p in st["position"]) + " BLU", 4)
            self.say("answer r (resume) or s (stop)")


def send(program: str, port: str, machine, baud: int = 115200, quiet: bool = False,
         timeout: float = 2.0, out=sys.stderr, radius=None, tools=None,
         strict: bool = False) -> int:
    """The ``halfpoint send`` command; returns the exit status.  ``radius``, ``tools``,
    ``strict``: cutter compensation, as ``halfpoint run`` takes them."""
    job = plan_job(program, machine, radius, tools, strict)
    try:
        board = Board(port, baud, timeout)
    except LinkError as exc:
        raise LinkError(f"{exc}; nothing was sent") from None
    try:
        sender = Sender(board, job, quiet, out)
        st = sender.run()
    except LinkError as exc:
        if not board.commands_written:
            raise LinkError(f"{exc}; nothing was sent") from None
        raise LinkError(f"{exc}; the job stopped after {sender.taken} commands taken by the "
                        "board (the machine may still be moving: check it)") from None
    finally:
        board.close()
    pos = ",".join(str(p) for p in st["position"])
    mm = ",".join(f"{p * b:.4f}" for p, b in zip(st["position"], job.blu))
    naks = sum(job.stats["naks"].values())
    print(f"done: {job.blocks} blocks, {len([i for i in job.items if i.cmd is not None])} "
          f"commands; position {pos} BLU ({mm} mm); link: {naks} NAKs, "
          f"{job.stats['resent']} frames resent", flush=True)
    if st["flags"] & link.FLAG_DRY:
        print("note: the core's dry flag is set: the link did not keep up with short blocks "
              "and the core slowed down for them (a faster --baud helps)", flush=True)
    if st["flags"] & link.FLAG_UNDERRUN:
        print("note: the core's underrun flag is set: a block ended with no next one queued",
              flush=True)
    return 0
