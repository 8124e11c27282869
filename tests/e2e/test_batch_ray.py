"""`cga batch --engine ray` (issue 18) on a local Ray cluster of 2 CPUs, started once for
the module: the same files and manifest as the local engine, and a worker killed in the
middle of a run loses no seed. Skipped when Ray is not installed (the extra cga[ray])."""

from __future__ import annotations

import json
import logging
import os
import signal
import time
from pathlib import Path

import pytest

from batch_outputs import ONE_ROOM, TYPES, manifest_records, output_tree

import cga
from cga.batch import MANIFEST, run_batch, seed_folder
from cga.cli import main

ray = pytest.importorskip("ray")

TASK_TITLE = "ray::_call"
"""The process title of a Ray worker while it runs a build (Ray names it after the task)."""


@pytest.fixture(scope="module")
def cluster():
    """A local Ray cluster of 2 CPUs whose workers import this cga."""
    source = str(Path(cga.__file__).resolve().parents[1])
    path = os.pathsep.join(p for p in (source, os.environ.get("PYTHONPATH")) if p)
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False,
             logging_level=logging.ERROR, runtime_env={"env_vars": {"PYTHONPATH": path}})
    yield
    ray.shutdown()


@pytest.fixture
def grammar(tmp_path) -> Path:
    path = tmp_path / "room.grammar"
    path.write_text(ONE_ROOM)
    (tmp_path / "types.csv").write_text(TYPES)
    return path


def test_ray_builds_what_the_local_engine_builds(cluster, grammar, tmp_path, capsys):
    common = ["batch", str(grammar), "-n", "20", "--no-physics", "--json"]
    assert main([*common, "--out", str(tmp_path / "local")]) == 0
    capsys.readouterr()
    assert main([*common, "--out", str(tmp_path / "ray"), "--engine", "ray", "--jobs", "2"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["houses"], report["built_now"], report["failed"]) == (20, 20, 0)
    assert (manifest_records(tmp_path / "ray" / MANIFEST)
            == manifest_records(tmp_path / "local" / MANIFEST))
    folders = sorted(p.name for p in (tmp_path / "local").glob("seed_*"))
    assert folders == [seed_folder(s) for s in range(20)]
    assert sorted(p.name for p in (tmp_path / "ray").glob("seed_*")) == folders
    for folder in folders:
        assert output_tree(tmp_path / "ray" / folder) == output_tree(tmp_path / "local" / folder)
    assert not list((tmp_path / "ray").glob(".building-*"))


def _ancestors(pid: int) -> set[int]:
    found = set()
    while pid > 1:
        try:
            pid = int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            break
        found.add(pid)
    return found


def _kill_a_busy_worker() -> int:
    """SIGKILL a worker of this test's cluster while it runs a build; its pid."""
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        for entry in Path("/proc").iterdir():
            if not entry.name.isdigit():
                continue
            try:
                title = (entry / "cmdline").read_bytes().split(b"\0")[0].decode(errors="replace")
            except OSError:
                continue
            if title.startswith(TASK_TITLE) and os.getpid() in _ancestors(int(entry.name)):
                os.kill(int(entry.name), signal.SIGKILL)
                return int(entry.name)
        time.sleep(0.01)
    raise AssertionError("no Ray worker was running a build")


@pytest.mark.parametrize("retries", [0, 2])
def test_a_killed_worker_loses_no_seed(cluster, grammar, tmp_path, retries):
    killed = []

    def kill_once(done, total):
        if done == 3 and not killed:
            killed.append(_kill_a_busy_worker())

    report = run_batch(grammar, count=20, out_dir=tmp_path / "out", engine="ray",
                       retries=retries, build_options={"physics": False},
                       on_progress=kill_once)
    assert killed
    lines = manifest_records(tmp_path / "out" / MANIFEST)
    assert [line["seed"] for line in lines] == list(range(20))  # every seed accounted for
    failed = [line for line in lines if line["error"]]
    if retries:  # Ray ran the lost build again
        assert not failed and report.built_now == 20
    else:  # recorded as failed, with the reason, and rebuilt by the next run
        assert len(failed) == 1 and "Ray task failed 1 time" in failed[0]["error"]
        assert (tmp_path / "out" / seed_folder(failed[0]["seed"]) / "error.txt").is_file()
        again = run_batch(grammar, count=20, out_dir=tmp_path / "out", engine="ray",
                          build_options={"physics": False})
        assert (again.built_now, again.skipped) == (1, 19)
    assert not list((tmp_path / "out").glob(".building-*"))


def test_ray_options_without_ray_are_refused(grammar, tmp_path, capsys):
    assert main(["batch", str(grammar), "-n", "1", "--out", str(tmp_path / "out"),
                 "--retries", "1"]) == 2
    assert "--retries needs --engine ray" in capsys.readouterr().err


def test_a_build_over_the_time_limit_is_stopped_and_recorded(cluster, tmp_path):
    """No build of the house demo takes under 10 ms: about 0.25 s in a warm worker, so
    a result is not in before this process, on a loaded machine, looks at its clock
    again (a one-room build, 10-30 ms warm, sometimes was)."""
    from house_checks import HOUSE

    report = run_batch(HOUSE, count=3, out_dir=tmp_path / "out", engine="ray",
                       time_limit=0.01, build_options={"physics": False})
    assert [r.seed for r in report.failed] == [0, 1, 2]
    assert all("over the time limit of 0.01 s per build" in r.error for r in report.failed)
    assert not list((tmp_path / "out").glob(".building-*"))
