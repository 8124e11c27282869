"""Atomic writes: complete files or nothing, and a failed build leaves the target as it was."""

import json
import os
import stat
import tempfile
from pathlib import Path

import pytest

from cga.fsutil import (STAGING_PREFIX, OutputConflictError, atomic_output_dir, atomic_write,
                        remove_stale_staging)
from cga.output_record import record_path


def test_atomic_write_creates_parents_and_writes_bytes_and_text(tmp_path):
    target = tmp_path / "a" / "b" / "out.bin"
    atomic_write(target, b"\x00\x01")
    assert target.read_bytes() == b"\x00\x01"
    atomic_write(target, "héllo\n")
    assert target.read_bytes() == "héllo\n".encode("utf-8")
    assert [p.name for p in target.parent.iterdir()] == ["out.bin"]


def test_atomic_write_uses_umask_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        target = atomic_write(tmp_path / "f.txt", "x")
    finally:
        os.umask(old)
    assert stat.S_IMODE(target.stat().st_mode) == 0o644


def test_atomic_write_failure_keeps_old_file_and_no_temp(tmp_path, monkeypatch):
    target = tmp_path / "f.txt"
    target.write_text("old")

    def disk_full(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", disk_full)
    with pytest.raises(OSError):
        atomic_write(target, "new")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["f.txt"]


def _names(folder):
    return sorted(p.name for p in folder.iterdir())


def test_output_dir_stages_inside_the_target_and_moves_files_in_on_success(tmp_path):
    target = tmp_path / "out" / "house"
    with atomic_output_dir(target) as stage:
        assert stage.parent == target and stage.name.startswith(STAGING_PREFIX)
        (stage / "house.glb").write_bytes(b"glb")
        (stage / "sub").mkdir()
        (stage / "sub" / "x.txt").write_text("x")
        assert not (target / "house.glb").exists()
    assert (target / "house.glb").read_bytes() == b"glb"
    assert (target / "sub" / "x.txt").read_text() == "x"
    assert _names(target) == ["house.glb", "sub"]
    assert _names(tmp_path / "out") == ["house"]


def test_output_dir_needs_no_write_permission_beside_the_target(tmp_path, monkeypatch):
    target = tmp_path / "house"
    target.mkdir()
    real_mkdtemp = tempfile.mkdtemp

    def only_inside_target(*args, dir=None, **kwargs):
        assert dir is not None and Path(dir) == target, "staging outside the output folder"
        return real_mkdtemp(*args, dir=dir, **kwargs)

    monkeypatch.setattr(tempfile, "mkdtemp", only_inside_target)
    with atomic_output_dir(target) as stage:
        (stage / "a.txt").write_text("a")
    assert _names(target) == ["a.txt"]


def test_output_dir_failure_leaves_target_untouched(tmp_path):
    target = tmp_path / "house"
    target.mkdir()
    (target / "house.glb").write_bytes(b"old")
    with pytest.raises(RuntimeError):
        with atomic_output_dir(target) as stage:
            (stage / "house.glb").write_bytes(b"new, half")
            raise RuntimeError("exporter failed")
    assert (target / "house.glb").read_bytes() == b"old"
    assert _names(target) == ["house.glb"]


def _build(target, files, **options):
    with atomic_output_dir(target, owner="house", **options) as stage:
        for name, text in files.items():
            (stage / name).parent.mkdir(parents=True, exist_ok=True)
            (stage / name).write_text(text)


def test_rebuild_removes_only_files_an_earlier_build_of_the_name_wrote(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    for name in ("house.grammar", "house.notes.txt", "notes.txt", "house.floor7.svg"):
        (target / name).write_text("user")
    _build(target, {"house.glb": "1", "house.floor3.svg": "1", "meshes/house.bed.obj": "1"})
    _build(target, {"house.glb": "2"})
    assert (target / "house.glb").read_text() == "2"
    assert not (target / "house.floor3.svg").exists()
    assert not (target / "meshes").exists()  # emptied by the rebuild
    for name in ("house.grammar", "house.notes.txt", "notes.txt", "house.floor7.svg"):
        assert (target / name).read_text() == "user"


def test_a_file_the_build_did_not_write_is_never_replaced(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    (target / "house.glb").write_text("the user's own model")
    with pytest.raises(OutputConflictError, match=r"house\.glb already exists.*move it away"):
        _build(target, {"house.glb": "new", "house.scene.json": "new"})
    assert (target / "house.glb").read_text() == "the user's own model"
    assert _names(target) == ["house.glb"]  # nothing moved in, staging removed


def _edit(path, text):
    """Write as a user would, later than the build (whatever the clock's resolution)."""
    path.write_text(text)
    later = path.stat().st_mtime_ns + 10**9
    os.utime(path, ns=(later, later))


def test_an_output_edited_since_the_build_is_neither_replaced_nor_removed(tmp_path):
    target = tmp_path / "out"
    _build(target, {"house.glb": "1", "house.floor1.svg": "1"})
    _edit(target / "house.floor1.svg", "annotated by hand")
    _build(target, {"house.glb": "2"})  # does not write floor1 again: keeps the edited one
    assert (target / "house.floor1.svg").read_text() == "annotated by hand"
    _edit(target / "house.glb", "edited")
    with pytest.raises(OutputConflictError):
        _build(target, {"house.glb": "3"})
    assert (target / "house.glb").read_text() == "edited"


def test_a_tampered_record_cannot_reach_outside_the_folder_or_the_inputs(tmp_path):
    target = tmp_path / "out"
    outside = tmp_path / "precious.txt"
    outside.write_text("x")
    grammar = target / "house.grammar"
    _build(target, {"house.glb": "1"})
    grammar.write_text("x")
    for path in (grammar, outside):  # older than the record: only the checks save them
        os.utime(path, ns=(0, 0))
    record = record_path(target, "house")
    data = json.loads(record.read_text())
    data["files"] += ["../precious.txt", str(outside), "house.grammar", "."]
    record.write_text(json.dumps(data))
    _build(target, {"house.glb": "2"}, protect=[grammar])
    assert outside.read_text() == "x" and grammar.read_text() == "x"


def test_a_star_in_the_build_name_matches_nothing(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    (target / "house.txt").write_text("user")
    with atomic_output_dir(target, owner="*") as stage:
        (stage / "*.glb").write_text("1")
    with atomic_output_dir(target, owner="*") as stage:
        (stage / "*.scene.json").write_text("2")
    assert _names(target) == sorted([".cga-*.files.json", "*.scene.json", "house.txt"])


def test_stale_staging_of_a_dead_build_is_removed_but_a_live_one_is_kept(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    dead = target / f"{STAGING_PREFIX}123-abc"
    (dead / "sub").mkdir(parents=True)
    (dead / "sub" / "house.glb").write_text("half")
    with atomic_output_dir(target) as live:
        assert not dead.exists()
        assert remove_stale_staging(target) == []  # the live build holds its lock
        assert live.exists()
        (live / "a.txt").write_text("a")
    assert _names(target) == ["a.txt"]
