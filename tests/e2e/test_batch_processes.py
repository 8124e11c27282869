"""`cga batch` as real processes (issue 19, defects 2, 5 and 6): a second batch into the
same folder, the parent killed with SIGKILL, a build over its time limit.

The batch runs from a script that adds an exporter which stalls on chosen seeds (the
``STALL_SEEDS`` environment variable), so a build is reliably in flight when the test
acts. The script is a file, not ``-c``: worker processes (spawned) import it too.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from cga.batch import LOCK, MANIFEST, read_manifest, seed_folder
from cga.cli import main

GRAMMAR = "Lot: rectangle(12, 8)\nRules:\nLot --> extrude(6) Body\n"

SCRIPT = """
import os, sys, time
from cga.export import EXPORTERS

STALL = {int(s) for s in os.environ.get("STALL_SEEDS", "").split(",") if s}

def stall(scene, nodes, out_dir, name):
    if scene.seed in STALL:
        marks = os.environ["STALL_MARKS"]
        with open(os.path.join(marks, f"stalled-{scene.seed}"), "w") as mark:
            mark.write(str(os.getpid()))
        time.sleep(300)
    return []

EXPORTERS["stall"] = stall

if __name__ == "__main__":
    from cga.cli import main
    sys.exit(main(sys.argv[1:]))
"""


@pytest.fixture
def batch(tmp_path):
    """Start `cga batch` on a small grammar into tmp_path/out: batch(*options, stall=...)."""
    script = tmp_path / "stalling_cga.py"
    script.write_text(SCRIPT)
    grammar = tmp_path / "block.grammar"
    grammar.write_text(GRAMMAR)
    started = []

    def start(*options: str, stall: str = "") -> subprocess.Popen:
        process = subprocess.Popen(
            [sys.executable, str(script), "batch", str(grammar), "--out", str(tmp_path / "out"),
             *([] if "--json" in options else ["--quiet"]), "--no-physics", "--export", "stall",
             *options],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
            env={**os.environ, "STALL_SEEDS": stall, "STALL_MARKS": str(tmp_path)},
            start_new_session=True)
        started.append(process)
        return process

    yield start, grammar, tmp_path / "out", tmp_path
    for process in started:  # never leave a stalled process group behind
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        process.communicate()


def _wait_for(path: Path, process: subprocess.Popen) -> None:
    for _ in range(3000):
        if path.exists():
            return
        if process.poll() is not None:
            raise AssertionError(f"the batch ended early: {process.communicate()}")
        time.sleep(0.02)
    raise AssertionError(f"{path.name} never appeared")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:  # a zombie waiting for its (dead) parent counts as gone
        return Path(f"/proc/{pid}/stat").read_text().split()[2] != "Z"
    except OSError:
        return True


def test_a_second_batch_into_the_same_folder_is_refused(batch, capsys):
    start, grammar, out, marks = batch
    first = start("-n", "3", stall="1")
    _wait_for(marks / "stalled-1", first)
    assert main(["batch", str(grammar), "-n", "3", "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"another batch is writing into {out} (pid {first.pid} " in err
    assert "Traceback" not in err
    assert sorted(r for r in read_manifest(out)) == [0]  # only the first batch's line


def test_sigkill_of_the_parent_ends_its_workers_quietly_and_the_next_run_cleans_up(batch):
    """Defect 2 (orphaned workers printed BrokenPipeError tracebacks) and defect 6 (a
    killed batch's staging was not matched by the resume's cleanup)."""
    start, grammar, out, marks = batch
    parent = start("-n", "4", "--jobs", "2", stall="0,1")
    _wait_for(marks / "stalled-0", parent)
    _wait_for(marks / "stalled-1", parent)
    workers = [int((marks / f"stalled-{s}").read_text()) for s in (0, 1)]
    os.kill(parent.pid, signal.SIGKILL)
    _, stderr = parent.communicate(timeout=60)  # EOF only once the workers are gone too
    assert stderr == ""
    for _ in range(500):
        if not any(_alive(pid) for pid in workers):
            break
        time.sleep(0.02)
    assert not any(_alive(pid) for pid in workers)
    assert list(out.glob(".building-*"))  # what SIGKILL leaves behind

    assert main(["batch", str(grammar), "-n", "4", "--out", str(out), "--quiet"]) == 0
    assert not list(out.glob(".building-*")) and not list(out.glob(f".{MANIFEST}.*"))
    assert sorted(read_manifest(out)) == [0, 1, 2, 3]


def test_sigterm_stops_the_batch_and_removes_unfinished_seeds(batch):
    start, grammar, out, marks = batch
    parent = start("-n", "3", "--jobs", "2", stall="1")
    _wait_for(marks / "stalled-1", parent)
    parent.send_signal(signal.SIGTERM)
    _, stderr = parent.communicate(timeout=60)
    assert parent.returncode == 128 + signal.SIGTERM
    assert "Traceback" not in stderr
    assert not list(out.glob(".building-*"))
    assert 1 not in read_manifest(out)


def test_a_build_over_the_time_limit_fails_with_the_reason_and_the_rest_go_on(batch):
    start, grammar, out, _ = batch
    process = start("-n", "3", "--time-limit", "10", "--json", stall="1")
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == 2, stderr
    report = json.loads(stdout)
    assert (report["houses"], report["failed"]) == (2, 1)
    assert report["failed_seeds"][0]["seed"] == 1
    assert "over the time limit of 10 s per build (--time-limit)" in \
        report["failed_seeds"][0]["error"]
    assert "time limit" in (out / seed_folder(1) / "error.txt").read_text()
    assert "Traceback" not in stderr and "seed 1 failed" in stderr
    assert not list(out.glob(".building-*"))
    assert (out / LOCK).exists()
