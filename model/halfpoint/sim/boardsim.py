# SPDX-License-Identifier: Apache-2.0
"""``halfpoint board-sim``: the Verilator-simulated board top behind a TCP port.

The board top ``rtl/halfpoint_uart_top.v`` (NA 3, W 32, DEPTH 16) is built with a
compiled C++ harness (``boardsim_harness.cpp`` beside this module: no cocotb, no
Python in the clock loop) that bridges a TCP socket on 127.0.0.1 to the simulated
UART pins, bit by bit, and counts and timing-checks the STEP/DIR pins.  Anyone can
then run ``halfpoint send PROGRAM --port socket://127.0.0.1:PORT`` against it.

The board's parameters come from the machine file (``--machine``, default
``examples/machine_boardsim.toml``): CLK_HZ its ``clock_hz``, DIV
``profile.choose_div(clock_hz)``, STEPLEN .. DIRHOLD the largest of the axes'
timing ticks (the top has one setting for every axis), BAUD = CLK_HZ / 8 (the
fastest the serial port takes: 8 clocks a bit), so the link is no slower in
simulated time than the motion.  Each parameter set is built once into
``build/boardsim/<key>/``.

On exit (Ctrl-C, or ``--exit-when-idle`` once a client came and went and the board
is at rest) it prints the STEP counts per axis and ``position: x,y,z`` in BLU.
"""

from __future__ import annotations

import fcntl
import hashlib
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from ..cam.machine import Machine, load
from ..spec import profile as pf
from .env import BUILD, REPO, rtl_sources, setup_verilator_env

HARNESS = Path(__file__).resolve().parent / "boardsim_harness.cpp"
SOURCES = ("halfpoint_uart_top", "halfpoint_uart_cmd", "halfpoint_core", "halfpoint_arc",
           "halfpoint_line", "halfpoint_stepgen", "halfpoint_profile")
DEFAULT_MACHINE = REPO / "examples" / "machine_boardsim.toml"
CLOCKS_PER_BIT = 8          # the serial port's minimum: the fastest link


class BoardSimError(Exception):
    pass


def board_parameters(machine: Machine) -> dict:
    """The board top's parameters for a machine file."""
    clock = machine.clock_hz
    timing = {name: max(1, max(getattr(a.timing, name.lower()) for a in machine.axes))
              for name in ("STEPLEN", "STEPSPACE", "DIRSETUP", "DIRHOLD")}
    if len(machine.axes) != 3:
        raise BoardSimError("the board top has 3 axes: the machine file must have x, y, z")
    return {"CLK_HZ": clock, "BAUD": clock // CLOCKS_PER_BIT, "NA": 3, "W": 32, "DEPTH": 16,
            **timing, "BTN_ACTIVE_LOW": 0, "DIV": pf.choose_div(clock)}


def build(params: dict, log=None) -> Path:
    """The harness built for ``params`` (cached by the parameters and the sources)."""
    srcs = [HARNESS, *rtl_sources(*SOURCES), *sorted((REPO / "rtl").glob("*.vh"))]
    digest = hashlib.sha256(repr(sorted(params.items())).encode())
    for s in srcs:
        digest.update(s.read_bytes())
    work = BUILD / "boardsim" / digest.hexdigest()[:16]
    binary = work / "obj" / "Vhalfpoint_uart_top"
    if binary.exists():
        return binary
    work.mkdir(parents=True, exist_ok=True)
    with open(work / "build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)        # one build at a time (pytest -n workers)
        if not binary.exists():
            _build(params, work, binary, log)
    return binary


def _build(params: dict, work: Path, binary: Path, log) -> None:
    exe = setup_verilator_env()
    if log:
        print("board-sim: building the simulated board (Verilator, about a minute) ...",
              file=log, flush=True)
    cmd = [str(exe), "--cc", "--exe", "--build", "-O3", "-j", "2", "--output-split", "0",
           "--top-module", "halfpoint_uart_top", *(f"-G{k}={v}" for k, v in params.items()),
           "-Wno-fatal", "-Mdir", str(work / "obj"), "-CFLAGS", "-O2",
           f"-I{REPO / 'rtl'}", str(HARNESS), *(str(p) for p in rtl_sources(*SOURCES))]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    (work / "build.log").write_text(proc.stdout + proc.stderr)
    if proc.returncode != 0 or not binary.exists():
        raise BoardSimError(f"the Verilator build of the board failed, see {work / 'build.log'}")


def harness_args(params: dict, port: int, exit_when_idle: bool,
                 check: dict | None = None) -> list[str]:
    """The harness's arguments; ``check`` overrides the timing it checks against
    (a test that the checker catches a violation)."""
    args = ["--port", str(port), "--cpb", str(params["CLK_HZ"] // params["BAUD"]),
            "--axes", str(params["NA"])]
    for name in ("STEPLEN", "STEPSPACE", "DIRSETUP", "DIRHOLD"):
        args += [f"--{name.lower()}", str((check or {}).get(name, params[name]))]
    return args + (["--exit-when-idle"] if exit_when_idle else [])


@dataclass
class Result:
    position: tuple
    steps: str
    timing: str
    clocks: int
    status: int
    text: str


def parse_result(text: str, status: int) -> Result:
    vals = {}
    for line in text.splitlines():
        key, _, rest = line.partition(": ")
        vals[key] = rest
    if "position" not in vals:
        raise BoardSimError(f"the simulated board ended without its report:\n{text}")
    return Result(tuple(int(v) for v in vals["position"].split(",")), vals.get("steps", ""),
                  vals.get("timing", ""), int(vals.get("clocks", 0)), status, text)


class BoardSim:
    """A running simulated board (for tests and scripts)::

        with BoardSim(machine) as board:
            ... halfpoint send --port board.url ...
        board.result.position
    """

    def __init__(self, machine: Machine, port: int = 0, exit_when_idle: bool = False,
                 check: dict | None = None):
        self.params = board_parameters(machine)
        self.binary = build(self.params)
        self.proc = subprocess.Popen([str(self.binary),
                                      *harness_args(self.params, port, exit_when_idle, check)],
                                     stdout=subprocess.PIPE, text=True)
        first = self.proc.stdout.readline()
        if not first.startswith("listening on "):
            self.proc.kill()
            raise BoardSimError(f"the simulated board did not start: {first!r}")
        self.address = first.split()[-1]
        self.port = int(self.address.rsplit(":", 1)[1])
        self.url = f"socket://{self.address}"
        self.result: Result | None = None

    def stop(self, timeout: float = 30.0) -> Result:
        """Ctrl-C the board; its report."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        return self.wait(timeout)

    def wait(self, timeout: float = 60.0) -> Result:
        out, _ = self.proc.communicate(timeout=timeout)
        self.result = parse_result(out, self.proc.returncode)
        return self.result

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.result is None:
            try:
                self.stop()
            except Exception:       # noqa: BLE001 - a failed test must still end the board
                self.proc.kill()
                raise
        return False


def main(listen: str | None, machine_path: str | None, exit_when_idle: bool,
         out=sys.stdout) -> int:
    """The ``halfpoint board-sim`` command."""
    host, port = "127.0.0.1", 0
    if listen:
        host, _, text = listen.rpartition(":")
        if host not in ("", "127.0.0.1", "localhost"):
            raise BoardSimError(f"--listen {listen}: the simulated board serves 127.0.0.1 only")
        try:
            port = int(text)
        except ValueError:
            raise BoardSimError(f"--listen {listen}: needs [127.0.0.1:]PORT") from None
        if not 0 <= port <= 65535:
            raise BoardSimError(f"--listen {listen}: port out of range")
    machine = load(machine_path) if machine_path else load(DEFAULT_MACHINE)
    params = board_parameters(machine)
    binary = build(params, log=out)
    print(f"board-sim: {machine.source}: clock {params['CLK_HZ']} Hz, serial "
          f"{params['BAUD']} baud, DIV {params['DIV']}, STEP/DIR timing "
          f"{params['STEPLEN']}/{params['STEPSPACE']}/{params['DIRSETUP']}/"
          f"{params['DIRHOLD']} clocks", file=out, flush=True)
    proc = subprocess.Popen([str(binary), *harness_args(params, port, exit_when_idle)],
                            stdout=subprocess.PIPE, text=True)
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)     # the harness gets the Ctrl-C
    try:
        first = proc.stdout.readline()
        address = first.split()[-1] if first.startswith("listening on ") else None
        if address is None:
            proc.wait()
            raise BoardSimError(f"the simulated board did not start ({first.strip()})")
        print(f"board-sim: listening on {address}: halfpoint send PROGRAM --port "
              f"socket://{address} --machine {machine.source}", file=out, flush=True)
        t0 = time.monotonic()
        rest = proc.stdout.read()
        proc.wait()
    finally:
        signal.signal(signal.SIGINT, old)
    res = parse_result(rest, proc.returncode)
    out.write(rest)
    print(f"board-sim: {res.clocks} clocks simulated in {time.monotonic() - t0:.1f} s",
          file=out, flush=True)
    return 1 if res.status else 0

