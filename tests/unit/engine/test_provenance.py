"""Provenance records (cga/provenance.py) and the shard partition (cga/batch_shard.py)."""

from __future__ import annotations

import hashlib
import os

from hypothesis import given, settings
from hypothesis import strategies as st

from cga.batch_shard import Shard
from cga.provenance import (RecordedInputs, file_digest, input_label, label_path, note_input,
                            provenance, recording)
from cga.resources import shipped_dir


def test_labels_name_files_portably_and_find_them_again(tmp_path):
    shipped = shipped_dir("cga.rules") / "house_types.csv"
    own = tmp_path / "rules" / "types.csv"
    own.parent.mkdir()
    own.write_text("x")
    elsewhere = tmp_path.parent / f"{tmp_path.name}-allowed.csv"
    elsewhere.write_text("y")
    try:
        for path, label in ((shipped, "cga.rules/house_types.csv"), (own, "rules/types.csv"),
                            (elsewhere, str(elsewhere.resolve()))):
            assert input_label(path, tmp_path) == label
            assert label_path(label, tmp_path).resolve() == path.resolve()
    finally:
        elsewhere.unlink()


def test_digests_are_sha256_prefixes_and_follow_edits(tmp_path):
    path = tmp_path / "table.csv"
    path.write_text("a;b\n")
    assert file_digest(path) == hashlib.sha256(b"a;b\n").hexdigest()[:16]
    path.write_text("a;b;c\n")
    os.utime(path, ns=(1, 1))  # even a file whose time goes backwards is hashed again
    assert file_digest(path) == hashlib.sha256(b"a;b;c\n").hexdigest()[:16]
    assert file_digest(tmp_path / "missing.csv") is None


def test_reads_are_noted_only_inside_a_recording(tmp_path):
    note_input(tmp_path / "ignored.csv")
    with recording() as reads:
        note_input(tmp_path / "a.csv")
    note_input(tmp_path / "b.csv")
    assert reads == [tmp_path / "a.csv"]


def test_changes_name_each_input_that_differs(tmp_path):
    grammar = tmp_path / "g.grammar"
    grammar.write_text("Lot: rectangle(4, 4)\n")
    table = tmp_path / "types.csv"
    table.write_text("t\n")
    gone = tmp_path / "old.obj"
    gone.write_text("v 0 0 0\n")
    recorded = RecordedInputs()
    recorded.add(provenance(grammar, {"physics": True}, [table, gone]), "seed 0")
    assert recorded.changes(grammar, {"physics": True}) == []
    table.write_text("u\n")
    gone.unlink()
    found = recorded.changes(grammar, {"physics": False})
    assert [phrase.split(" (")[0] for phrase in found] == [
        "the model old.obj", "the rule table types.csv", "the option physics"]
    assert found[0].endswith("→ missing)") and found[2] == "the option physics (true → false)"


def test_files_read_by_some_seeds_only_do_not_conflict(tmp_path):
    grammar = tmp_path / "g.grammar"
    grammar.write_text("x")
    bed, bath = tmp_path / "bed.obj", tmp_path / "bathtub.obj"
    bed.write_text("1")
    bath.write_text("2")
    recorded = RecordedInputs()
    recorded.add(provenance(grammar, {}, [bed]), "seed 0")
    recorded.add(provenance(grammar, {}, [bed, bath]), "seed 1")
    assert recorded.conflicts() == []
    bed.write_text("3")
    recorded.add(provenance(grammar, {}, [bed]), "seed 2")
    (conflict,) = recorded.conflicts()
    assert conflict.startswith("the model bed.obj (") and "in seed 0" in conflict
    assert "in seed 2" in conflict


@settings(deadline=None)  # timing on a loaded machine is not what this checks
@given(start=st.integers(0, 10**9), count=st.integers(1, 200), shards=st.integers(1, 20))
def test_shards_partition_any_range(start, count, shards):
    seeds = range(start, start + count)
    parts = [list(Shard(i, shards).seeds(seeds)) for i in range(shards)]
    assert sorted(s for part in parts for s in part) == list(seeds)
    for index, part in enumerate(parts):
        assert all(seed % shards == index for seed in part)
