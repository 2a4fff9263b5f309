# SPDX-License-Identifier: Apache-2.0
"""``make soak`` in small: a short soak through the compiled harness passes, and the
same soak with one expected move altered fails naming the mismatch, the batch and a
command that reproduces it (so the checker can fail)."""

import dataclasses
import io
import multiprocessing
import shutil
from pathlib import Path

import pytest

from halfpoint.flows import simspeed
from halfpoint.flows.soak import main, make_batch, report, soak
from halfpoint.flows.simspeed import (
    check_intervals, harness_binary, model_run, run_harness, write_vectors,
)

SEED = 5
BUILD = "quick"         # the harness built quickest (-O1, one build): a lean test


@pytest.fixture(scope="module")
def passed():
    return soak(segments=240, seed=SEED, axes=3, per_batch=40, jobs=1, chunk=3, build=BUILD)


def test_short_soak_passes(passed):
    out = io.StringIO()
    report(passed, SEED, 3, out)
    assert passed.ok, out.getvalue()
    assert passed.segments == 240 and passed.batches == 6
    assert passed.moves > 240 and passed.clocks > passed.moves
    text = out.getvalue()
    assert "240 segments" in text and f"seed {SEED}" in text and "M clocks/s" in text
    kinds = {label[0] for label in passed.classes}
    assert kinds == {"arc", "line"}


def test_altered_expectation_fails(passed):
    res = soak(segments=240, seed=SEED, axes=3, per_batch=40, jobs=1, chunk=3,
               corrupt=(4, 17), build=BUILD)
    assert not res.ok
    assert res.failed_batch == 4
    assert res.failure.startswith("FAIL batch 4: move 17 at clock")
    assert "--seed 5" in res.repro and "--only-batch 4" in res.repro
    assert res.vectors is not None and res.vectors.exists()
    out = io.StringIO()
    report(res, SEED, 3, out)
    assert "SOAK FAILED" in out.getvalue() and "first mismatch: FAIL batch 4" in out.getvalue()


def test_only_batch_reproduces(capsys):
    assert main(["--segments", "240", "--seed", str(SEED), "--per-batch", "40",
                 "--only-batch", "4", "--jobs", "1", "--build", BUILD]) == 0
    assert main(["--segments", "240", "--seed", str(SEED), "--per-batch", "40",
                 "--only-batch", "4", "--jobs", "1", "--corrupt", "4", "3",
                 "--build", BUILD]) == 1
    assert "FAIL batch 4: move 3" in capsys.readouterr().out


def test_batches_are_reproducible_and_varied():
    a, ca = make_batch(SEED, 7, 6, 60)
    b, cb = make_batch(SEED, 7, 6, 60)
    assert a == b and ca == cb
    assert {label[1] for label in ca if label[0] == "line"} >= {"1 axes", "6 axes"}
    # the short soak above has gaps in the stream while the core runs
    assert sum(len(make_batch(SEED, i, 3, 40)[0].stream_gaps) for i in range(6)) >= 3


def test_harness_keeps_the_stream_gaps(tmp_path):
    """The harness drops tvalid in a batch's stream gaps as the model does: vectors the
    model computed with a long gap pass with it and fail without it."""
    batch, _ = make_batch(SEED, 2, 3, 40)
    batch = dataclasses.replace(batch, holds=[], stream_gaps=[])
    plain = model_run(batch)
    start = plain.times[0]          # while commands remain: the queue runs dry
    gapped = dataclasses.replace(batch, stream_gaps=[(start, start + 20000)])
    exp = model_run(gapped)
    assert exp.times != plain.times
    binary, _ = harness_binary(3, BUILD)
    for sent, ok in ((gapped, True), (batch, False)):
        path = tmp_path / f"gaps_{ok}.vec"
        write_vectors(path, 3, [(0, sent, exp)])
        res = run_harness(binary, path)
        assert res.ok == ok, res.failure


def test_bad_holds_are_refused():
    with pytest.raises(ValueError, match="disjoint"):
        check_intervals([(10, 20), (20, 30)])
    with pytest.raises(ValueError, match="non-empty"):
        check_intervals([(5, 5)])
    assert check_intervals([(30, 40), (1, 2)]) == [(1, 2), (30, 40)]


def test_parts_cover_the_whole_run(passed, capsys):
    """Two parts (batches 0..2 and 3..5) check exactly the segments, moves and clocks
    of the whole run; a range outside the run is refused."""
    first = soak(segments=240, seed=SEED, axes=3, per_batch=40, jobs=1, chunk=3,
                 build=BUILD, batches=(0, 3))
    second = soak(segments=240, seed=SEED, axes=3, per_batch=40, jobs=1, chunk=3,
                  build=BUILD, batches=(3, 6))
    assert first.ok and second.ok
    assert first.batches == second.batches == 3
    for name in ("segments", "moves", "clocks"):
        assert getattr(first, name) + getattr(second, name) == getattr(passed, name), name
    assert first.classes + second.classes == passed.classes
    out = io.StringIO()
    report(second, SEED, 3, out)
    assert "part of a run: batches 3 .. 5 of 0 .. 5" in out.getvalue()
    with pytest.raises(ValueError, match="not a range of the 6 batches"):
        soak(segments=240, seed=SEED, axes=3, per_batch=40, jobs=1, build=BUILD,
             batches=(4, 7))
    with pytest.raises(SystemExit):
        main(["--segments", "240", "--batches", "2-4", "--build", BUILD])
    assert "expected FIRST:END" in capsys.readouterr().err


def _build_harness(name, results):
    try:
        results.put(str(harness_binary(3, name)[0]))
    except Exception as exc:            # the parent reports it
        results.put(f"error: {exc}")


def test_concurrent_builds_wait_for_each_other(monkeypatch, tmp_path):
    """Two processes that ask for the same harness while it is not built (pytest-xdist
    workers do) both get a working one: the second waits for the first's build under
    its lock instead of deleting the build directory under it."""
    name = "concurrent-test"
    monkeypatch.setitem(simspeed.HARNESS_BUILDS, name, simspeed.HARNESS_BUILDS[BUILD])
    shutil.rmtree(simspeed.BUILD / "harness" / f"na3_{name}", ignore_errors=True)
    ctx = multiprocessing.get_context("fork")     # the children see the new build name
    results = ctx.Queue()
    procs = [ctx.Process(target=_build_harness, args=(name, results)) for _ in range(2)]
    for p in procs:
        p.start()
    got = [results.get(timeout=900) for _ in procs]
    for p in procs:
        p.join()
    assert not any(g.startswith("error") for g in got), got
    assert got[0] == got[1]
    batch, _ = make_batch(SEED, 1, 3, 20)
    path = tmp_path / "one.vec"
    write_vectors(path, 3, [(0, batch, model_run(batch))])
    res = run_harness(Path(got[0]), path)
    assert res.ok, res.failure
    shutil.rmtree(simspeed.BUILD / "harness" / f"na3_{name}", ignore_errors=True)
