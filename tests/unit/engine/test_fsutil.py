"""Atomic writes: complete files or nothing, and a failed build leaves the target as it was."""

import os
import stat

import pytest

from cga.fsutil import atomic_output_dir, atomic_write


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


def test_output_dir_moves_files_in_on_success(tmp_path):
    target = tmp_path / "out" / "house"
    with atomic_output_dir(target) as stage:
        assert stage != target and stage.parent == target.parent
        (stage / "house.glb").write_bytes(b"glb")
        (stage / "sub").mkdir()
        (stage / "sub" / "x.txt").write_text("x")
        assert not target.exists()
    assert (target / "house.glb").read_bytes() == b"glb"
    assert (target / "sub" / "x.txt").read_text() == "x"
    assert sorted(p.name for p in target.parent.iterdir()) == ["house"]


def test_output_dir_failure_leaves_target_untouched(tmp_path):
    target = tmp_path / "house"
    target.mkdir()
    (target / "house.glb").write_bytes(b"old")
    with pytest.raises(RuntimeError):
        with atomic_output_dir(target) as stage:
            (stage / "house.glb").write_bytes(b"new, half")
            raise RuntimeError("exporter failed")
    assert (target / "house.glb").read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["house"]


def test_output_dir_removes_stale_matching_files_only(tmp_path):
    target = tmp_path / "house"
    target.mkdir()
    for name in ("house.floor3.svg", "house.glb", "notes.txt"):
        (target / name).write_text("old")
    with atomic_output_dir(target, replace_matching="house.*") as stage:
        (stage / "house.glb").write_text("new")
    assert sorted(p.name for p in target.iterdir()) == ["house.glb", "notes.txt"]
    assert (target / "house.glb").read_text() == "new"


def test_output_dir_removes_stale_files_in_subfolders_it_writes_to(tmp_path):
    target = tmp_path / "out"
    (target / "meshes").mkdir(parents=True)
    (target / "docs").mkdir()
    for name in ("meshes/house.sofa.old.obj", "meshes/house.bed.obj", "docs/house.md"):
        (target / name).write_text("old")
    with atomic_output_dir(target, replace_matching="house.*") as stage:
        (stage / "meshes").mkdir()
        (stage / "meshes" / "house.bed.obj").write_text("new")
    assert sorted(p.name for p in (target / "meshes").iterdir()) == ["house.bed.obj"]
    assert (target / "docs" / "house.md").read_text() == "old"  # not a folder of this build
