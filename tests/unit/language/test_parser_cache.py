"""The parser's tables are kept in the on-disk cache: a second process loads them, a
damaged entry is rebuilt, and the parse is the same either way."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
_PROBE = ("from cga.parser import parse_file; g = parse_file('demos/house.grammar'); "
          "print(repr(g))")


def _parse_in_fresh_process(cache: Path) -> str:
    env = dict(os.environ, PYTHONPATH=str(ROOT), CGA_CACHE_DIR=str(cache))
    return subprocess.run([sys.executable, "-c", _PROBE], cwd=ROOT, env=env, check=True,
                          capture_output=True, text=True, timeout=120).stdout


def test_the_tables_are_cached_and_reused(tmp_path):
    first = _parse_in_fresh_process(tmp_path)
    (entry,) = (tmp_path / "parser").iterdir()
    assert entry.suffix == ".lark" and entry.stat().st_size > 1000
    stamp = entry.stat().st_mtime_ns
    assert _parse_in_fresh_process(tmp_path) == first
    assert entry.stat().st_mtime_ns == stamp  # read, not written again


def test_a_damaged_entry_is_rebuilt(tmp_path):
    first = _parse_in_fresh_process(tmp_path)
    (entry,) = (tmp_path / "parser").iterdir()
    entry.write_bytes(b"garbage")
    assert _parse_in_fresh_process(tmp_path) == first
