"""Odd command-line input: each gives one clear message on stderr and exit status 2,
never a traceback (bad numbers, unusable output folders, grammars that are not text)."""

from __future__ import annotations

import json

import pytest

from cga.cli import main

GRAMMAR = "Lot: rectangle(12, 8)\nRules:\nLot --> extrude(6) Body\n"


@pytest.fixture
def grammar(tmp_path):
    path = tmp_path / "block.grammar"
    path.write_text(GRAMMAR)
    return path


def run(argv, capsys) -> tuple[int, str]:
    status = main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return status, err


@pytest.mark.parametrize("options, message", [
    (["--seed", "-1"], "--seed must be a whole number ≥ 0, got -1"),
    (["--units", "0"], "--units must be positive"),
    (["--units", "inf"], "--units must be positive"),
    (["--units", "nan"], "--units must be positive"),
    (["--robot-radius", "inf"], "--robot-radius must be positive"),
])
def test_bad_numbers(grammar, tmp_path, capsys, options, message):
    status, err = run(["build", grammar, "--out", tmp_path / "o", *options], capsys)
    assert status == 2 and message in err


def test_seed_that_is_not_a_number(grammar, capsys):
    with pytest.raises(SystemExit) as caught:
        main(["build", str(grammar), "--seed", "abc"])
    assert caught.value.code == 2
    assert "argument --seed: invalid int value: 'abc'" in capsys.readouterr().err


def test_out_naming_an_existing_file(grammar, tmp_path, capsys):
    taken = tmp_path / "taken"
    taken.write_text("mine")
    status, err = run(["build", grammar, "--out", taken], capsys)
    assert status == 2 and f"cannot write the output folder {taken}" in err
    assert taken.read_text() == "mine"
    status, err = run(["batch", grammar, "-n", "1", "--out", taken], capsys)
    assert status == 2 and f"cannot create the output folder {taken}" in err


def test_out_below_a_file(grammar, tmp_path, capsys):
    (tmp_path / "taken").write_text("mine")
    status, err = run(["build", grammar, "--out", tmp_path / "taken" / "sub"], capsys)
    assert status == 2 and "cannot write the output folder" in err


@pytest.mark.parametrize("command", ["build", "check"])
def test_grammar_that_is_a_folder(tmp_path, capsys, command):
    folder = tmp_path / "dir.grammar"
    folder.mkdir()
    status, err = run([command, folder], capsys)
    assert status == 2 and f"grammar not found: {folder} (a folder, not a grammar file)" in err


@pytest.mark.parametrize("command", ["build", "check"])
def test_binary_grammar(tmp_path, capsys, command):
    path = tmp_path / "binary.grammar"
    path.write_bytes(b"Rules:\nLot --> \xc6\x00\xff extrude(3) A\n")
    status, err = run([command, path, "--out", tmp_path / "o"] if command == "build"
                      else [command, path], capsys)
    assert status == 2
    assert f"{path}:2:9: error: the file is not UTF-8 text (byte 15 cannot be decoded)" in err


def test_empty_grammar(tmp_path, capsys):
    path = tmp_path / "empty.grammar"
    path.write_text("")
    status, err = run(["build", path, "--out", tmp_path / "o"], capsys)
    assert status == 2 and "the grammar has no `Rules:` section" in err


@pytest.mark.parametrize("content, message", [
    ("not json", "not a JSON file"),
    (json.dumps({"type": "Point", "coordinates": [0, 0]}), "expected exactly one polygon, found 0"),
    (json.dumps({"type": "MultiPolygon", "coordinates": [
        [[[0, 0], [10, 0], [10, 10], [0, 0]]], [[[20, 0], [30, 0], [30, 10], [20, 0]]]]}),
     "expected exactly one polygon, found 2"),
])
def test_bad_geojson_lots(grammar, tmp_path, capsys, content, message):
    lot = tmp_path / "lot.geojson"
    lot.write_text(content)
    status, err = run(["build", grammar, "--lot", lot, "--out", tmp_path / "o"], capsys)
    assert status == 2 and message in err


@pytest.mark.parametrize("options, message", [
    (["-n", "0"], "-n must be at least 1, got 0"),
    (["-n", "1", "--jobs", "0"], "--jobs must be at least 1, got 0"),
    (["-n", "1", "--seed-start", "-1"], "--seed-start must be a whole number ≥ 0, got -1"),
])
def test_bad_batch_options(grammar, tmp_path, capsys, options, message):
    out = tmp_path / "batch"
    status, err = run(["batch", grammar, "--out", out, "--quiet", *options], capsys)
    assert status == 2 and message in err
    assert not (out / "manifest.jsonl").exists()
