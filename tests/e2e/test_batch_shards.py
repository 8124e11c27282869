"""Shards, merge and provenance of `cga batch` (issue 18): `--shard I/N` builds every N-th
seed into its own manifest, `cga batch merge` joins them (refusing gaps, duplicates and
mixed inputs), and a resume whose inputs changed is refused, naming what changed."""

from __future__ import annotations

import fcntl
import json
import os
from pathlib import Path

import pytest

from batch_outputs import ONE_ROOM, TYPES, manifest_records, output_tree

from cga.batch import LOCK, MANIFEST, read_manifest, run_batch, seed_folder
from cga.batch_shard import parse_shard
from cga.cli import main
from cga.errors import UsageError

BLOCK = "Lot: rectangle(12, 8)\nRules:\nLot --> extrude([5;7]) Body\n"
"""Builds in a few hundredths of a second; the random height makes seeds differ."""

NO_PHYSICS = {"physics": False, "formats": ["glb", "json"]}


@pytest.fixture
def block(tmp_path) -> Path:
    path = tmp_path / "block.grammar"
    path.write_text(BLOCK)
    return path


def test_shards_merged_equal_one_run(block, tmp_path, capsys):
    whole = tmp_path / "whole"
    run_batch(block, count=30, out_dir=whole, build_options=NO_PHYSICS)
    shared = tmp_path / "shards"
    for index in range(3):
        report = run_batch(block, count=30, out_dir=shared, build_options=NO_PHYSICS,
                           shard=parse_shard(f"{index}/3"))
        assert [r.seed for r in report.records] == list(range(index, 30, 3))
        assert (shared / f"manifest.shard-{index}-of-3.jsonl").is_file()
    assert not (shared / MANIFEST).exists()
    folders = {p.name: p.stat().st_ino for p in shared.glob("seed_*")}

    assert main(["batch", "merge", str(shared), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["houses"] == 30
    assert manifest_records(shared / MANIFEST) == manifest_records(whole / MANIFEST)
    assert {p.name: p.stat().st_ino for p in shared.glob("seed_*")} == folders  # not copied
    for seed in (0, 13, 29):
        assert output_tree(shared / seed_folder(seed)) == output_tree(whole / seed_folder(seed))
    # the merged folder resumes as an ordinary batch: nothing left to build
    assert run_batch(block, count=32, out_dir=shared, build_options=NO_PHYSICS).skipped == 30
    # a merge would now drop seeds 30 and 31, which only manifest.jsonl lists
    err = _cli_error(capsys, ["batch", "merge", str(shared)])
    assert "manifest.jsonl exists and was not written by cga batch merge" in err


def test_merge_of_shards_in_separate_folders_points_at_their_houses(block, tmp_path):
    parts = [tmp_path / f"node{i}" for i in range(2)]
    for index, part in enumerate(parts):
        run_batch(block, count=6, out_dir=part, build_options=NO_PHYSICS,
                  shard=parse_shard(f"{index}/2"))
    assert main(["batch", "merge", *map(str, parts), "--quiet"]) == 0
    lines = {line["seed"]: line for line in manifest_records(parts[0] / MANIFEST)}
    assert sorted(lines) == list(range(6))
    assert "folder" not in lines[0] and lines[1]["folder"] == "../node1/seed_000001"
    assert set(read_manifest(parts[0])) == set(range(6))  # every folder found
    assert not (parts[0] / seed_folder(1)).exists()


def _cli_error(capsys, argv) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err


def test_merge_refuses_a_missing_shard(block, tmp_path, capsys):
    for index in (0, 2):
        run_batch(block, count=6, out_dir=tmp_path / "out", build_options=NO_PHYSICS,
                  shard=parse_shard(f"{index}/3"))
    err = _cli_error(capsys, ["batch", "merge", str(tmp_path / "out")])
    assert "shard 1/3 missing" in err
    assert not (tmp_path / "out" / MANIFEST).exists()


def test_merge_refuses_a_shard_given_twice(block, tmp_path, capsys):
    for folder in ("a", "b"):
        for index in (0, 1):
            run_batch(block, count=4, out_dir=tmp_path / folder, build_options=NO_PHYSICS,
                      shard=parse_shard(f"{index}/2"))
    err = _cli_error(capsys, ["batch", "merge", str(tmp_path / "a"), str(tmp_path / "b")])
    assert "shard 0/2 appears twice" in err


def test_merge_refuses_duplicate_seeds(block, tmp_path, capsys):
    for index in (0, 1):
        run_batch(block, count=4, out_dir=tmp_path / "shards", build_options=NO_PHYSICS,
                  shard=parse_shard(f"{index}/2"))
    run_batch(block, count=2, seed_start=2, out_dir=tmp_path / "plain", build_options=NO_PHYSICS)
    err = _cli_error(capsys, ["batch", "merge", str(tmp_path / "shards"), str(tmp_path / "plain"),
                              "--out", str(tmp_path / "merged")])
    assert "seeds 2, 3 listed by both" in err


def test_merge_refuses_a_shard_that_has_not_finished(block, tmp_path, capsys):
    out = tmp_path / "out"
    for index in range(3):
        run_batch(block, count=30, out_dir=out, build_options=NO_PHYSICS,
                  shard=parse_shard(f"{index}/3"))
    # shard 1 was stopped before its last two seeds: they have no line
    manifest = out / "manifest.shard-1-of-3.jsonl"
    manifest.write_text("".join(line + "\n" for line in manifest.read_text().splitlines()
                                if json.loads(line)["seed"] < 23))
    err = _cli_error(capsys, ["batch", "merge", str(out)])
    assert "shard 1/3" in err and "has not built seeds 25, 28" in err


def test_merge_refuses_houses_of_different_inputs(block, tmp_path, capsys):
    out = tmp_path / "out"
    run_batch(block, count=4, out_dir=out, build_options=NO_PHYSICS, shard=parse_shard("0/2"))
    run_batch(block, count=4, out_dir=out, build_options={**NO_PHYSICS, "formats": ["glb"]},
              shard=parse_shard("1/2"))
    err = _cli_error(capsys, ["batch", "merge", str(out)])
    assert "different inputs" in err and "the option formats" in err


def test_failed_seeds_are_merged_and_reported(tmp_path, capsys):
    grammar = tmp_path / "broken.grammar"
    grammar.write_text("Lot: rectangle(12, 8)\nRules:\nLot --> extrud(6) Body\n")
    for index in (0, 1):
        run_batch(grammar, count=4, out_dir=tmp_path / "out", shard=parse_shard(f"{index}/2"))
    err = _cli_error(capsys, ["batch", "merge", str(tmp_path / "out")])
    assert "seeds 0, 1, 2, 3 failed" in err
    assert all(line["error"] for line in manifest_records(tmp_path / "out" / MANIFEST))


@pytest.mark.parametrize("text", ["3/3", "-1/3", "1", "a/b", "1/0"])
def test_bad_shards_are_refused(text):
    with pytest.raises(UsageError, match="--shard"):
        parse_shard(text)


def test_an_unsharded_batch_waits_for_shards_in_its_folder(block, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    fd = os.open(out / LOCK, os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_SH)  # what a running shard holds
    try:
        err = _cli_error(capsys, ["batch", str(block), "-n", "2", "--out", str(out),
                                  "--no-physics", "--quiet"])
        assert f"shards of a batch are writing into {out}" in err
        assert main(["batch", str(block), "-n", "2", "--out", str(out), "--no-physics",
                     "--quiet", "--shard", "1/2"]) == 0  # another shard may join
    finally:
        os.close(fd)


# --- provenance ------------------------------------------------------------------------

def test_every_line_records_the_inputs_the_build_read(tmp_path):
    grammar = tmp_path / "room.grammar"
    grammar.write_text(ONE_ROOM)
    (tmp_path / "types.csv").write_text(TYPES)
    run_batch(grammar, count=2, out_dir=tmp_path / "out", build_options=NO_PHYSICS)
    import hashlib

    for line in manifest_records(tmp_path / "out" / MANIFEST):
        inputs = line["provenance"]
        assert inputs["grammar"] == hashlib.sha256(ONE_ROOM.encode()).hexdigest()[:16]
        assert inputs["files"]["types.csv"] == hashlib.sha256(TYPES.encode()).hexdigest()[:16]
        # every build notes them, though a process parses each table once
        assert {"cga.rules/furniture_house.csv", "cga.rules/materials.csv",
                "cga.rules/lights.csv"} <= set(inputs["files"])
        assert any(name.startswith("cga.furniture_models/") and name.endswith(".obj")
                   for name in inputs["files"])
        assert inputs["options"] == {"allow_paths": [], "formats": ["glb", "json"],
                                     "lot": None, "materials": None, "max_depth": 64,
                                     "overrides": {},
                                     "physics": False, "robot_radius": 0.25, "strict": False,
                                     "units": None}
        assert inputs["version"]


def test_resuming_after_the_grammar_changed_is_refused(block, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["batch", str(block), "-n", "3", "--out", str(out), "--no-physics", "--quiet"]
    assert main(argv[:3] + ["2"] + argv[4:]) == 0
    before = (out / MANIFEST).read_bytes()
    block.write_text(BLOCK.replace("[5;7]", "[8;9]"))
    err = _cli_error(capsys, argv)
    assert "2 houses built from other inputs" in err
    assert "changed: the grammar block.grammar (" in err and "--force" in err
    assert (out / MANIFEST).read_bytes() == before and not (out / seed_folder(2)).exists()

    assert main([*argv, "--force"]) == 0  # a new manifest; the old houses are kept aside
    (superseded,) = out.glob("superseded-*")
    assert (superseded / MANIFEST).read_bytes() == before
    assert sorted(p.name for p in superseded.glob("seed_*")) == [seed_folder(0), seed_folder(1)]
    assert [line["seed"] for line in manifest_records(out / MANIFEST)] == [0, 1, 2]
    assert main(argv) == 0  # the new configuration resumes


def test_resuming_after_a_rule_table_or_an_option_changed_is_refused(tmp_path, capsys):
    grammar = tmp_path / "room.grammar"
    grammar.write_text(ONE_ROOM)
    (tmp_path / "types.csv").write_text(TYPES)
    out = tmp_path / "out"
    argv = ["batch", str(grammar), "-n", "1", "--out", str(out), "--no-physics", "--quiet"]
    assert main(argv) == 0
    err = _cli_error(capsys, [*argv[:-2], "--quiet"])  # the checks on now
    assert "the option physics (false → true)" in err
    (tmp_path / "types.csv").write_text(TYPES.replace(";1;1;", ";1;0.5;"))
    err = _cli_error(capsys, argv)
    assert "changed: the rule table types.csv (" in err and "grammar" not in err.split("changed")[1]
