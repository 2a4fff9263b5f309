# SPDX-License-Identifier: Apache-2.0
"""``halfpoint send`` against the simulated board (``halfpoint board-sim``), through
pyserial's ``socket://`` URL, with the unmodified command line in a subprocess:

* a whole part (examples/boardsim_part.ngc, 104 blocks with arcs): the STEP/DIR
  pins counted by the board-sim add up to the host's final position, timing ok;
* a dropped byte on the link (a proxy between the two drops one): NAK, the frame
  is sent again, the part ends where it should;
* a TAKEN lost on the way back (the proxy drops it): the status poll shows the
  command was taken, nothing is sent twice, the part ends right;
* a rejected block in the middle (the proxy sets a reserved bit in one motion
  command and fixes its check, so the board takes it and the core rejects it): the
  job stops naming the block's G-code line and the code; the machine came to rest
  (controlled stop from where it was when the core rejected the command, which is
  as the block before it starts) on the lattice path of the blocks before it, as
  the model makes it: nothing after it ran;
* Ctrl-C: the machine holds, the sender asks, "r" resumes, the part ends right.

And bad input, against fake boards (a TCP server written here): a port that does
not exist, a board that does not answer, a board with another protocol version,
a board at another clock: each a clear error, and nothing but IDENT was sent.
"""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from halfpoint.cam.machine import load
from halfpoint.cli import main as cli_main
from halfpoint.host.send import plan_job
from halfpoint.sim.boardsim import BoardSim
from halfpoint.spec import encoding as enc
from halfpoint.spec import link

REPO = Path(__file__).resolve().parents[2]
MACHINE = REPO / "examples" / "machine_boardsim.toml"
PART = REPO / "examples" / "boardsim_part.ngc"
SHORT = """G21 G90 G17
G1 X2 Y1 F6000
G1 X4 Y0
G2 X6 Y0 I1 J0
G1 X6 Y-2 Z-0.5
G3 X4 Y-2 I-1 J0
G1 X0 Y0 Z0
M2
"""
LONG = """G21 G90 G17
G1 X20 Y5 F3000
G1 X0 Y0
M2
"""


def send_cli(program, url, *extra, stdin=None, timeout=120):
    env = dict(os.environ)
    return subprocess.Popen([sys.executable, "-m", "halfpoint", "send", str(program), "--port",
                             url, "--machine", str(MACHINE), *extra],
                            stdin=stdin, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)


def finish(proc, timeout=120):
    out, err = proc.communicate(timeout=timeout)
    return proc.returncode, out, err


class Proxy:
    """A TCP proxy between the sender and the board that can drop one byte of the
    host's stream or rewrite one COMMAND frame (keeping its check good)."""

    def __init__(self, target_port: int, drop_byte: int | None = None,
                 rewrite_command: int | None = None, drop_taken: int | None = None):
        self.target = target_port
        self.drop_byte = drop_byte
        self.drop_taken = drop_taken      # drop the board's n-th TAKEN reply
        self.dropped_taken = False
        self.rewrite = rewrite_command
        self.server = socket.socket()
        self.server.bind(("127.0.0.1", 0))
        self.server.listen(1)
        self.url = f"socket://127.0.0.1:{self.server.getsockname()[1]}"
        self.sent = 0
        self.commands = 0
        self.rewritten = None
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        client, _ = self.server.accept()
        board = socket.create_connection(("127.0.0.1", self.target))
        threading.Thread(target=self._replies, args=(board, client), daemon=True).start()
        buf = bytearray()
        while True:
            try:
                data = client.recv(4096)
            except OSError:
                data = b""
            if not data:
                board.close()
                return
            buf += data
            out = bytearray()
            while buf:
                n = 2 + link.COMMAND_BYTES if buf[0] == link.F_COMMAND else 2
                if len(buf) < n:
                    break
                frame = bytearray(buf[:n])
                del buf[:n]
                if frame[0] == link.F_COMMAND:
                    cmd = int.from_bytes(frame[1:-1], "little")
                    if self.commands == self.rewrite:
                        cmd |= 1 << 12      # word 0 bit 12: reserved in every command
                        frame = bytearray(link.command_frame(cmd))
                        self.rewritten = cmd
                    self.commands += 1
                for b in frame:
                    if self.sent != self.drop_byte:
                        out.append(b)
                    self.sent += 1
            board.sendall(out)

    def _replies(self, src, dst):
        """Board to host: reply by reply (spec/link.py), the n-th TAKEN dropped."""
        if self.drop_taken is None:
            return self._pipe(src, dst)
        buf, taken = bytearray(), 0
        sizes = {link.R_NAK: 2, link.R_STATUS: link.status_payload(3) + 2,
                 link.R_IDENT: link.IDENT_PAYLOAD + 2}
        try:
            while True:
                data = src.recv(4096)
                if not data:
                    break
                buf += data
                out = bytearray()
                while buf and len(buf) >= sizes.get(buf[0], 1):
                    n = sizes.get(buf[0], 1)
                    if buf[0] == link.R_TAKEN:
                        if taken == self.drop_taken:
                            self.dropped_taken = True
                            del buf[:1]
                            taken += 1
                            continue
                        taken += 1
                    out += buf[:n]
                    del buf[:n]
                dst.sendall(out)
        except OSError:
            pass
        dst.close()

    @staticmethod
    def _pipe(src, dst):
        try:
            while True:
                data = src.recv(4096)
                if not data:
                    break
                dst.sendall(data)
        except OSError:
            pass                # the other side closed first
        dst.close()


@pytest.fixture(scope="module")
def machine():
    return load(MACHINE)


def test_whole_part(machine):
    job = plan_job(str(PART), machine)
    assert job.blocks > 100 and any(enc.decode(i.cmd)["opcode"] in (enc.OP_ARC_CW,
                                                                    enc.OP_ARC_CCW)
                                    for i in job.items if i.cmd is not None)
    with BoardSim(machine) as board:
        t0 = time.monotonic()
        status, out, err = finish(send_cli(PART, board.url, "--quiet"))
        wall = time.monotonic() - t0
        res = board.stop()
    assert status == 0, err
    assert res.timing == "ok", res.text
    assert res.position == job.delta, (res.position, job.delta)
    assert f"position {','.join(map(str, job.delta))} BLU" in out
    assert "0 NAKs" in out
    print(f"whole part: {job.blocks} blocks in {wall:.1f} s wall")


SPINDLE = """G21 G90 G17
M3 S12000
G1 X2 Y1 F6000
M8
G1 X4 Y0
M5 M9
G1 X0 Y0
M2
"""


def test_spindle_and_coolant_are_sent(machine):
    """The job carries the program's spindle and coolant changes as OUTPUT commands,
    each named by its M block, between the motion of the blocks around it, as
    ``halfpoint run`` plans them (until 2026-11-28 ``send`` planned without the machine
    and sent none: the board's spindle and coolant pins never switched); the board
    runs them and ends where the motion says."""
    job = plan_job_text(SPINDLE, machine)
    bare = plan_job_text("\n".join(ln for ln in SPINDLE.splitlines()
                                   if not ln.startswith("M") or ln == "M2") + "\n", machine)
    outputs = [(i.lineno, i.block) for i in job.items
               if i.cmd is not None and enc.decode(i.cmd)["opcode"] == enc.OP_OUTPUT]
    assert outputs == [(2, 0), (4, 1), (6, 2)], outputs
    assert job.blocks == bare.blocks == 3 and job.delta == bare.delta
    with BoardSim(machine) as board:
        status, out, err = finish(send_cli(job.path, board.url, "--quiet"))
        res = board.stop()
    assert status == 0, err
    assert res.position == job.delta and res.timing == "ok", res.text


def test_board_sim_timing_checker_catches_a_violation(machine):
    """The harness's STEP/DIR checker told to expect STEP 1 clock longer than the
    board makes it: it must report the violation and exit 1 (exit-when-idle)."""
    job = plan_job_text(SHORT, machine)
    board = BoardSim(machine, exit_when_idle=True, check={"STEPLEN": 3})
    status, out, err = finish(send_cli(job.path, board.url, "--quiet"))
    res = board.wait()
    assert status == 0, err
    assert res.status == 1 and "steplen: STEP active 2 clocks, need 3" in res.timing, res.text
    assert res.position == job.delta


def test_dropped_byte(machine):
    job = plan_job_text(SHORT, machine)
    with BoardSim(machine) as board:
        proxy = Proxy(board.port, drop_byte=3 * 34 + 10)    # inside the fourth COMMAND
        status, out, err = finish(send_cli(job.path, proxy.url, "--quiet"))
        res = board.stop()
    assert status == 0, err
    assert "1 NAKs, 1 frames resent" in out, out
    assert res.position == job.delta and res.timing == "ok", res.text


def test_lost_reply(machine):
    """A TAKEN lost on the way back: the sender's status poll shows the command was
    taken; nothing is sent twice, the part ends where it should."""
    job = plan_job_text(SHORT, machine)
    with BoardSim(machine) as board:
        proxy = Proxy(board.port, drop_taken=4)
        status, out, err = finish(send_cli(job.path, proxy.url, "--quiet"))
        res = board.stop()
    assert proxy.dropped_taken
    assert status == 0, err
    assert res.position == job.delta and res.timing == "ok", res.text


def test_rejected_block(machine):
    from halfpoint.cam.run import run_program

    job = plan_job_text(SHORT, machine)
    # the third motion command: commands are PROFILE, motion, PROFILE, motion, ...
    target = 5
    bad = job.items[target]
    model = run_program(str(job.path), machine=machine)
    moves_before = sum(c.moves for c in model.motion.commands[:(target - 1) // 2])
    path_before = {(0, 0, 0), *model.lattice[:moves_before]}
    with BoardSim(machine) as board:
        proxy = Proxy(board.port, rewrite_command=target)
        status, out, err = finish(send_cli(job.path, proxy.url, "--quiet"))
        res = board.stop()
    assert proxy.rewritten is not None
    assert status == 3, (out, err)
    assert f"line {bad.lineno}: the board rejected block {bad.block} (code 1:" in err, err
    pos = ",".join(map(str, res.position))
    assert f"machine is at rest at {pos} BLU" in err, err
    assert res.position in path_before, res.position            # nothing after it ran
    assert res.position != (0, 0, 0), "the blocks before the rejected one ran"
    assert res.timing == "ok", res.text


def test_hold_and_resume(machine):
    job = plan_job_text(LONG, machine)
    with BoardSim(machine) as board:
        proc = send_cli(job.path, board.url, stdin=subprocess.PIPE)
        seen = ""
        while "streaming" not in seen:
            line = proc.stderr.readline()
            assert line, f"sender ended early: {seen}"
            seen += line
        time.sleep(1.0)
        proc.send_signal(signal.SIGINT)
        buf = ""
        while "resume or stop" not in buf:
            ch = proc.stderr.read(1)
            assert ch, f"no prompt: {buf}"
            buf += ch
        proc.stdin.write("r\n")
        proc.stdin.flush()
        status, out, err = finish(proc)
        res = board.stop()
    assert status == 0, buf + err
    assert "held at" in buf and "resumed" in err, buf + err
    assert res.position == job.delta and res.timing == "ok", res.text


def plan_job_text(text: str, machine, _dir=[]):     # noqa: B006 - one temp dir per session
    import tempfile

    if not _dir:
        _dir.append(Path(tempfile.mkdtemp(prefix="hp_send_")))
    path = _dir[0] / f"p{abs(hash(text))}.ngc"
    path.write_text(text)
    job = plan_job(str(path), machine)
    job.path = path
    return job


# --- bad input: fake boards -------------------------------------------------------------------

class FakeBoard:
    """Accepts one client, records its bytes, answers IDENT frames with ``ident``
    (None: never answers)."""

    def __init__(self, ident: dict | None):
        self.ident = ident
        self.server = socket.socket()
        self.server.bind(("127.0.0.1", 0))
        self.server.listen(1)
        self.url = f"socket://127.0.0.1:{self.server.getsockname()[1]}"
        self.got = bytearray()
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        conn, _ = self.server.accept()
        while True:
            data = conn.recv(4096)
            if not data:
                return
            self.got += data
            if self.ident is not None and link.frame(link.F_IDENT) in bytes(data):
                conn.sendall(link.reply(link.R_IDENT, link.ident_payload(**self.ident)))


IDENT = {"version": link.PROTOCOL_VERSION, "axes": 3, "width": 32, "depth": 16,
         "clock_hz": 10_000_000, "baud": 1_250_000, "div": 10}


def run_cli(capsys, *args):
    status = cli_main(["send", str(PART), "--machine", str(MACHINE), "--quiet", *args])
    return status, capsys.readouterr().err


def test_port_does_not_exist(capsys):
    status, err = run_cli(capsys, "--port", "/dev/ttyHALFPOINT_NONE")
    assert status == 2 and "cannot open /dev/ttyHALFPOINT_NONE" in err, err


@pytest.mark.parametrize("ident, message", [
    (None, "does not answer"),
    ({**IDENT, "version": 99}, "speaks serial protocol version 99"),
    ({**IDENT, "clock_hz": 12_000_000}, "the board runs at 12000000 Hz"),
])
def test_bad_boards(capsys, ident, message):
    fake = FakeBoard(ident)
    status, err = run_cli(capsys, "--port", fake.url, "--timeout", "0.3")
    assert status == 2 and message in err and "nothing" in err, err
    # nothing but IDENT frames went out: nothing moved
    sent = bytes(fake.got)
    ident_frame = link.frame(link.F_IDENT)
    assert sent and sent == ident_frame * (len(sent) // len(ident_frame)), sent.hex()
