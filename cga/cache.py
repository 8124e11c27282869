"""The on-disk cache: results that cost far more to compute than to read, kept between runs.

A build spends much of its start-up on the same work every time: building the grammar
parser's tables, parsing and measuring the furniture models, decomposing concave user
models (V-HACD). Each result is stored under ``<root>/<kind>/<key><suffix>``, where the
key is a SHA-256 of everything the result depends on (the input file's bytes, the
version of the library that computed it, the cache format), so an entry can never be
stale: a changed input or library is a different key. Entries are written atomically;
the folder is safe to delete at any time, and a cache that cannot be written (a
read-only home) only costs the time the entry would have saved.

Root: ``$CGA_CACHE_DIR`` when set, else ``~/.cache/cga``.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from .fsutil import atomic_write

__all__ = ["cache_root", "digest", "has_entry", "read_entry", "write_entry"]


def cache_root() -> Path:
    """``$CGA_CACHE_DIR``, or ``~/.cache/cga``."""
    root = os.environ.get("CGA_CACHE_DIR")
    return Path(root) if root else Path.home() / ".cache" / "cga"


def digest(*parts: bytes | str) -> str:
    """SHA-256 (hex) of ``parts``, each length-prefixed so no two lists collide."""
    sha = hashlib.sha256()
    for part in parts:
        data = part.encode("utf-8") if isinstance(part, str) else part
        sha.update(len(data).to_bytes(8, "little"))
        sha.update(data)
    return sha.hexdigest()


def _path(kind: str, key: str, suffix: str) -> Path:
    return cache_root() / kind / f"{key}{suffix}"


def read_entry(kind: str, key: str, suffix: str = "") -> bytes | None:
    """The stored bytes of an entry, or None when there is none (or it cannot be read)."""
    try:
        return _path(kind, key, suffix).read_bytes()
    except OSError:
        return None


def has_entry(kind: str, key: str, suffix: str = "") -> bool:
    """Whether an entry is stored, without reading it."""
    return _path(kind, key, suffix).is_file()


def write_entry(kind: str, key: str, data: bytes, suffix: str = "") -> None:
    """Store an entry atomically; a cache folder that cannot be written is skipped."""
    try:
        atomic_write(_path(kind, key, suffix), data)
    except OSError:
        pass
