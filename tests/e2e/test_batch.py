"""Batch generation: one folder per seed, manifest lines, resume without redoing work."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cga.batch import MANIFEST, read_manifest, run_batch, seed_folder

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
