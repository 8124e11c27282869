"""``--export usd`` without usd-core stops before building, naming the package and extra."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from cga.cli import main
from cga.errors import UsageError
from cga.pipeline import build

MASSING = Path(__file__).resolve().parents[3] / "demos" / "massing.grammar"


@pytest.fixture()
def without_pxr(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "pxr" else real(name, *a))


def test_build_names_the_missing_package(without_pxr, tmp_path):
    with pytest.raises(UsageError, match=r"needs usd-core.*pip install 'cga\[robot\]'"):
        build(MASSING, out_dir=tmp_path, formats=["glb", "usd"], quiet=True)
    assert not any(tmp_path.iterdir())  # nothing built, nothing written


def test_cli_exits_2_with_the_message(without_pxr, tmp_path, capsys):
    status = main(["build", str(MASSING), "--out", str(tmp_path / "o"), "--export", "mjcf,usd"])
    assert status == 2
    assert "usd-core" in capsys.readouterr().err


def test_mjcf_needs_no_extra_package(tmp_path):
    build(MASSING, out_dir=tmp_path, formats=["mjcf"], quiet=True)
    assert (tmp_path / "massing.mjcf.xml").is_file()
