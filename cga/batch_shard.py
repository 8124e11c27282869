"""``cga batch --shard I/N``: every N-th seed, for schedulers without Ray (SLURM arrays).

Shard ``I`` of ``N`` builds the seeds ``s`` of the range with ``s % N == I``, so shards
of any ranges partition the seeds the same way and a job array needs no bookkeeping:
``--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT``. Shards may share one ``--out``
(on shared storage) or use one each: a shard writes its own manifest
``manifest.shard-I-of-N.jsonl``, its own lock ``.cga-batch.shard-I-of-N.lock``, and
``manifest.shard-I-of-N.json``, the seed ranges it was asked to build (what
``cga batch merge`` checks for gaps). An unsharded batch and shards cannot write into
one folder at the same time: the unsharded batch holds the folder's lock exclusively,
each shard holds it shared.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

from .errors import UsageError

__all__ = ["MANIFEST", "LOCK", "MERGED", "Shard", "parse_shard", "manifest_name", "shard_of_manifest",
           "read_ranges", "write_ranges"]

MANIFEST = "manifest.jsonl"
LOCK = ".cga-batch.lock"
MERGED = ".cga-merged"
"""Beside a ``manifest.jsonl`` that ``cga batch merge`` wrote (and may write again); a
batch that then writes that manifest itself removes it."""
_SHARD_MANIFEST = re.compile(r"manifest\.shard-(\d+)-of-(\d+)\.jsonl")


@dataclass(frozen=True)
class Shard:
    """Shard ``index`` of ``count`` (0 ≤ index < count)."""

    index: int
    count: int

    def __str__(self) -> str:
        return f"{self.index}/{self.count}"

    @property
    def tag(self) -> str:
        return f"shard-{self.index}-of-{self.count}"

    def owns(self, seed: int) -> bool:
        return seed % self.count == self.index

    def seeds(self, seeds: range) -> range:
        """The seeds of ``seeds`` (a step-1 range) this shard builds, as a range."""
        first = seeds.start + (self.index - seeds.start) % self.count
        return range(first, seeds.stop, self.count)


def parse_shard(text: str) -> Shard:
    """``"I/N"`` as a :class:`Shard`.

    Raises
    ------
    UsageError
        Not two whole numbers with 0 ≤ I < N.
    """
    match = re.fullmatch(r"\s*(\d+)\s*/\s*(\d+)\s*", text)
    if match is None:
        raise UsageError(f"--shard must be I/N (shard I of N, 0 ≤ I < N), got {text!r}")
    index, count = int(match.group(1)), int(match.group(2))
    if not 0 <= index < count:
        raise UsageError(f"--shard {text}: I must be at least 0 and less than N")
    return Shard(index, count)


def manifest_name(shard: Shard | None) -> str:
    return MANIFEST if shard is None else f"manifest.{shard.tag}.jsonl"


def shard_of_manifest(name: str) -> Shard | None:
    """The shard whose manifest file is called ``name`` (None: not a shard manifest)."""
    match = _SHARD_MANIFEST.fullmatch(name)
    if match is None:
        return None
    index, count = int(match.group(1)), int(match.group(2))
    return Shard(index, count) if index < count else None


def _ranges_path(out: Path, shard: Shard) -> Path:
    return out / f"manifest.{shard.tag}.json"


def read_ranges(out: Path, shard: Shard) -> list[range]:
    """The seed ranges shard ``shard`` was asked to build into ``out`` (empty if none
    were recorded)."""
    try:
        data = json.loads(_ranges_path(out, shard).read_text(encoding="utf-8"))
        return [range(int(a), int(b)) for a, b in data["seeds"]]
    except (OSError, ValueError, KeyError, TypeError):
        return []


def write_ranges(out: Path, shard: Shard, seeds: range) -> None:
    """Add ``seeds`` to the ranges the shard was asked to build (merged where they touch)."""
    from .fsutil import atomic_write

    merged: list[list[int]] = []
    for part in sorted([*read_ranges(out, shard), seeds], key=lambda r: r.start):
        if merged and part.start <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], part.stop)
        else:
            merged.append([part.start, part.stop])
    atomic_write(_ranges_path(out, shard),
                 json.dumps({"shard": str(shard), "seeds": merged}) + "\n")
