"""Batch generation: one folder per seed, manifest lines, resume without redoing work."""

from __future__ import annotations

import json
import os
import tracemalloc
from pathlib import Path

import pytest

from cga import pipeline
from cga.batch import MANIFEST, read_manifest, run_batch, seed_folder
from cga.cli import _parser as cli_parser
from cga.cli import main
from cga.errors import UsageError

DEMOS = Path(__file__).resolve().parents[2] / "demos"
MASSING = DEMOS / "massing.grammar"


class Interrupted(Exception):
    pass


def _manifest_seeds(out: Path) -> list[int]:
    return [json.loads(line)["seed"] for line in (out / MANIFEST).read_text().splitlines()]


def test_batch_writes_one_folder_and_line_per_seed(tmp_path):
    report = run_batch(MASSING, count=3, out_dir=tmp_path, seed_start=5,
                       build_options={"physics": False})
    assert report.count == 3 and report.built_now == 3
    assert sorted(_manifest_seeds(tmp_path)) == [5, 6, 7]
    for seed in (5, 6, 7):
        assert (tmp_path / seed_folder(seed) / "massing.glb").is_file()
    assert report.validity_rate == 1.0
    assert report.p95_seconds >= report.mean_seconds * 0.5 > 0


def test_interrupted_batch_resumes_without_redoing_seeds(tmp_path):
    built_first = []

    def stop_after_two(done, total):
        built_first.append(done)
        if done == 2:
            raise Interrupted

    with pytest.raises(Interrupted):
        run_batch(MASSING, count=5, out_dir=tmp_path, build_options={"physics": False},
                  on_progress=stop_after_two)
    first_folders = {p.name: p.stat().st_mtime_ns for p in tmp_path.glob("seed_*")}
    assert sorted(_manifest_seeds(tmp_path)) == [0, 1]

    # a half-written manifest line and a stale staging folder from the interruption
    with open(tmp_path / MANIFEST, "a") as fh:
        fh.write('{"seed": 2, "val')
    (tmp_path / ".building-seed_000002").mkdir()

    report = run_batch(MASSING, count=5, out_dir=tmp_path, build_options={"physics": False})
    assert report.built_now == 3
    assert sorted(_manifest_seeds(tmp_path)) == [0, 1, 2, 3, 4]
    assert not list(tmp_path.glob(".building-*"))
    for name, mtime in first_folders.items():  # finished seeds were not rebuilt
        assert (tmp_path / name).stat().st_mtime_ns == mtime
    assert set(read_manifest(tmp_path)) == {0, 1, 2, 3, 4}


def test_folder_without_manifest_line_is_rebuilt(tmp_path):
    run_batch(MASSING, count=2, out_dir=tmp_path, build_options={"physics": False})
    lines = (tmp_path / MANIFEST).read_text().splitlines()
    (tmp_path / MANIFEST).write_text(lines[0] + "\n")  # seed 1's line was never written
    report = run_batch(MASSING, count=2, out_dir=tmp_path, build_options={"physics": False})
    assert report.built_now == 1
    assert sorted(_manifest_seeds(tmp_path)) == [0, 1]


def test_parallel_batch_stops_its_workers_when_interrupted_and_resumes(tmp_path):
    def stop_after_one(done, total):
        if done == 1:
            raise Interrupted

    with pytest.raises(Interrupted):
        run_batch(MASSING, count=6, out_dir=tmp_path, jobs=2, build_options={"physics": False},
                  on_progress=stop_after_one)
    assert len(_manifest_seeds(tmp_path)) == 1
    report = run_batch(MASSING, count=6, out_dir=tmp_path, jobs=2,
                       build_options={"physics": False})
    assert report.built_now == 5
    assert sorted(_manifest_seeds(tmp_path)) == list(range(6))
    assert not list(tmp_path.glob(".building-*"))


# --- issue 19: honest batches -------------------------------------------------------

GOOD = "Lot: rectangle(12, 8)\nRules:\nLot --> extrude(6) Body\n"
BROKEN = "Lot: rectangle(12, 8)\nRules:\nLot --> extrud(6) Body\n"  # fails in every derivation


def _lines(out: Path) -> list[dict]:
    return [json.loads(line) for line in (out / MANIFEST).read_text().splitlines()]


def test_failed_seeds_are_reported_never_done_and_rebuilt_on_resume(tmp_path, capsys):
    """Defect 2: a batch of a broken grammar exited 0, recorded each failed seed as done
    and a resume after the fix rebuilt nothing."""
    grammar = tmp_path / "block.grammar"
    grammar.write_text(BROKEN)
    out = tmp_path / "out"
    argv = ["batch", str(grammar), "-n", "3", "--out", str(out), "--json"]
    assert main(argv) == 2
    captured = capsys.readouterr()
    report = json.loads(captured.out)
    assert (report["houses"], report["built_now"], report["failed"]) == (0, 0, 3)
    assert [f["seed"] for f in report["failed_seeds"]] == [0, 1, 2]
    assert "unknown operation" in report["failed_seeds"][0]["error"]
    assert "seed 0 failed" in captured.err and "Traceback" not in captured.err
    assert all(line["error"] for line in _lines(out))
    assert "extrud" in (out / seed_folder(1) / "error.txt").read_text()

    grammar.write_text(GOOD)
    assert main(argv) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["houses"], report["built_now"], report["skipped"], report["failed"]) == \
        (3, 3, 0, 0)
    assert sorted(line["seed"] for line in _lines(out)) == [0, 1, 2]  # one line per seed
    assert not (out / seed_folder(1) / "error.txt").exists()
    assert (out / seed_folder(1) / "block.glb").is_file()


def test_resume_rebuilds_exactly_the_failed_seeds(tmp_path, monkeypatch):
    grammar = tmp_path / "block.grammar"
    grammar.write_text(GOOD)
    real_build = pipeline.build

    def fails_on_odd_seeds(path, *, seed, **options):
        if seed % 2:
            raise UsageError(f"seed {seed} is odd")
        return real_build(path, seed=seed, **options)

    monkeypatch.setattr(pipeline, "build", fails_on_odd_seeds)
    first = run_batch(grammar, count=5, out_dir=tmp_path / "out")
    assert [r.seed for r in first.failed] == [1, 3] and first.built_now == 3
    assert first.to_dict()["failed"] == 2 and first.validity_rate == 0.6
    built_first = {s: (tmp_path / "out" / seed_folder(s)).stat().st_mtime_ns for s in (0, 2, 4)}

    rebuilt = []
    monkeypatch.setattr(pipeline, "build", lambda path, *, seed, **options: (
        rebuilt.append(seed), real_build(path, seed=seed, **options))[1])
    second = run_batch(grammar, count=5, out_dir=tmp_path / "out")
    assert rebuilt == [1, 3]
    assert (second.built_now, second.skipped, len(second.failed), second.count) == (2, 3, 0, 5)
    for seed, mtime in built_first.items():
        assert (tmp_path / "out" / seed_folder(seed)).stat().st_mtime_ns == mtime


def test_an_internal_error_fails_its_seed_with_a_traceback_file(tmp_path, monkeypatch):
    grammar = tmp_path / "block.grammar"
    grammar.write_text(GOOD)

    def defect(path, *, seed, **options):
        raise ZeroDivisionError("a defect")

    monkeypatch.setattr(pipeline, "build", defect)
    report = run_batch(grammar, count=2, out_dir=tmp_path)
    assert [r.error for r in report.failed] == ["internal error: ZeroDivisionError: a defect"] * 2
    assert "Traceback" in (tmp_path / seed_folder(0) / "error.txt").read_text()


@pytest.mark.parametrize("argv, message", [
    (["--export", "foo"], "unknown export format foo"),
    (["--jobs", "100000"], "--jobs must be at most"),
    (["--time-limit", "0"], "--time-limit must be a positive number of seconds"),
    (["--time-limit", "nan"], "--time-limit must be a positive number of seconds"),
])
def test_bad_batch_options_are_rejected_before_any_build(tmp_path, capsys, argv, message):
    grammar = tmp_path / "block.grammar"
    grammar.write_text(GOOD)
    out = tmp_path / "out"
    assert main(["batch", str(grammar), "-n", "2", "--out", str(out), "--quiet", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (out / MANIFEST).exists()


def test_a_syntax_error_is_reported_once_with_its_position(tmp_path, capsys):
    grammar = tmp_path / "block.grammar"
    grammar.write_text("Lot: rectangle(12, 8)\nRules:\nLot --> extrude(6 Body\n")
    out = tmp_path / "out"
    assert main(["batch", str(grammar), "-n", "1000", "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"{grammar}:3:" in err and "^" in err
    assert not out.exists() or not list(out.glob("seed_*"))


def test_counts_written_as_powers_of_ten():
    args = cli_parser().parse_args(["batch", "g.grammar", "-n", "1e12", "--seed-start", "2e3"])
    assert (args.count, args.seed_start) == (10**12, 2000)
    with pytest.raises(SystemExit):
        cli_parser().parse_args(["batch", "g.grammar", "-n", "1.5"])


@pytest.mark.parametrize("jobs", [1, 2])
def test_a_huge_seed_range_is_streamed_not_listed(tmp_path, jobs):
    """Defect 5: `-n 1e12` materialised the seed list (4 GB) before building anything. A
    list of 10^7 seeds alone would take hundreds of MB; the run is stopped after two builds."""
    grammar = tmp_path / "block.grammar"
    grammar.write_text(GOOD)

    def stop_after_two(done, total):
        assert total == 10**7
        if done == 2:
            raise Interrupted

    tracemalloc.start()
    try:
        with pytest.raises(Interrupted):
            run_batch(grammar, count=10**7, out_dir=tmp_path / "out", jobs=jobs,
                      build_options={"formats": ["glb"]}, on_progress=stop_after_two)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 64 * 2**20
    assert len(read_manifest(tmp_path / "out")) == 2
    assert not list((tmp_path / "out").glob(".building-*"))


def test_an_output_folder_that_cannot_be_written_is_an_error(tmp_path, capsys, monkeypatch):
    grammar = tmp_path / "block.grammar"
    grammar.write_text(GOOD)
    out = tmp_path / "out"
    out.mkdir()
    real_open = os.open

    def read_only(path, flags, *args):
        if Path(path).parent == out and flags & (os.O_WRONLY | os.O_RDWR | os.O_CREAT):
            raise PermissionError(13, "Permission denied", str(path))
        return real_open(path, flags, *args)

    monkeypatch.setattr(os, "open", read_only)
    assert main(["batch", str(grammar), "-n", "1", "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"cannot write into the output folder {out}: Permission denied" in err
    assert "Traceback" not in err


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write into a read-only folder")
def test_a_read_only_output_folder_is_an_error(tmp_path, capsys):
    grammar = tmp_path / "block.grammar"
    grammar.write_text(GOOD)
    out = tmp_path / "out"
    out.mkdir()
    out.chmod(0o555)
    try:
        assert main(["batch", str(grammar), "-n", "1", "--out", str(out), "--quiet"]) == 2
    finally:
        out.chmod(0o755)
    assert "cannot write into the output folder" in capsys.readouterr().err


@pytest.mark.parametrize("physics", [False, True])
def test_a_warmed_up_worker_builds_without_importing_cga_modules(tmp_path, physics):
    """A worker imports what builds need before it takes a seed, so the first build's
    time limit is not spent importing (the operations import their internals lazily)."""
    import subprocess
    import sys

    demo = Path(__file__).resolve().parents[2] / "demos" / "house.grammar"
    script = (
        "import sys\n"
        "from cga.batch import _build_modules, _build_one, _warm_up\n"
        f"options = {{'physics': {physics}, 'formats': ['glb', 'json']}}\n"
        f"_warm_up(_build_modules({physics}, options['formats']), {str(tmp_path)!r})\n"
        "before = set(sys.modules)\n"
        f"record = _build_one({str(demo)!r}, 0, {str(tmp_path)!r}, options)\n"
        "assert record.error is None, record.error\n"
        "print(sorted(m for m in set(sys.modules) - before if m.startswith('cga')))\n")
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "[]"


# --- issue 18: engines ------------------------------------------------------------

def test_the_local_engine_never_imports_ray(tmp_path):
    """Ray is an optional extra: the default engine and the command line run without it."""
    import subprocess
    import sys

    grammar = tmp_path / "block.grammar"
    grammar.write_text(GOOD)
    script = ("import sys\nfrom cga.cli import main\n"
              f"assert main(['batch', {str(grammar)!r}, '-n', '2', '--jobs', '2', '--out', "
              f"{str(tmp_path / 'out')!r}, '--no-physics', '--quiet']) == 0\n"
              "assert 'ray' not in sys.modules, 'ray was imported'\n")
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_the_ray_engine_without_ray_says_how_to_install_it(tmp_path, monkeypatch, capsys):
    import sys

    grammar = tmp_path / "block.grammar"
    grammar.write_text(GOOD)
    monkeypatch.setitem(sys.modules, "ray", None)  # `import ray` fails as if not installed
    assert main(["batch", str(grammar), "-n", "1", "--out", str(tmp_path / "out"),
                 "--engine", "ray", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert 'the Ray engine needs Ray: pip install "cga[ray]"' in err and "Traceback" not in err


def test_a_sweep_on_ray_starts_one_cluster_for_every_value(tmp_path, monkeypatch):
    """Starting a local Ray cluster takes seconds; a sweep of eleven values paid it eleven
    times. A stand-in for Ray counts the starts; the batches record what they saw."""
    import sys
    import types

    from cga import sweep
    from cga.batch import BatchReport

    state = {"running": False, "starts": 0, "stops": 0}
    fake = types.ModuleType("ray")
    fake.is_initialized = lambda: state["running"]
    fake.init = lambda **options: state.update(running=True, starts=state["starts"] + 1)
    fake.shutdown = lambda: state.update(running=False, stops=state["stops"] + 1)
    monkeypatch.setitem(sys.modules, "ray", fake)
    seen = []

    def batch(grammar, **options):
        seen.append((options["engine"], state["running"]))
        return BatchReport(records=(), wall_seconds=0.0, built_now=0)

    monkeypatch.setattr(sweep, "run_batch", batch)
    sweep.run_sweep(MASSING, name="difficulty", values=[0, 1, 2], count=1,
                    out_dir=tmp_path, engine="ray")
    assert seen == [("ray", True)] * 3
    assert (state["starts"], state["stops"], state["running"]) == (1, 1, False)
