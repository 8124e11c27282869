"""``cga batch merge DIR...``: join the manifests of a sharded batch into one.

Shards (:mod:`cga.batch_shard`) write ``manifest.shard-I-of-N.jsonl`` into one shared
folder or into one folder each. Merging writes ``manifest.jsonl`` into ``--out`` (default:
the first folder) with one line per seed, sorted by seed; house folders stay where they
are: a line whose folder is not beside the merged manifest names it with ``folder``, a
path relative to ``--out``. Nothing is copied, so merging a million houses writes one
file.

Merging refuses, naming the seeds and files, rather than writing a manifest that does
not describe one complete dataset:

* **shards**: every shard ``0 .. N-1`` present once, all of the same ``N``;
* **duplicates**: a seed listed by two manifests;
* **gaps**: a seed of the ranges a shard was asked to build
  (``manifest.shard-I-of-N.json``) without a line, i.e. a shard that has not finished
  (failed seeds have lines: they are merged and reported, and a rerun of their shard
  builds them again);
* **one configuration**: every built house recorded the same inputs (grammar, files,
  options, version; :mod:`cga.provenance`).

The manifests are read twice, line by line, and only seeds and byte offsets are held in
memory, so merging a million lines takes well under a gigabyte.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .batch_shard import MANIFEST, MERGED, Shard, read_ranges, shard_of_manifest
from .errors import UsageError
from .provenance import RecordedInputs

__all__ = ["MergeReport", "merge_manifests"]

_LISTED = 10
"""Seeds named in an error message (the count is always given)."""


@dataclass
class _Source:
    """One manifest to merge: its file, its shard and its latest line per seed."""

    path: Path
    shard: Shard | None
    offsets: dict[int, int] = field(default_factory=dict)
    """Seed → byte offset of its latest complete line whose folder exists."""
    failed: set[int] = field(default_factory=set)


@dataclass(frozen=True)
class MergeReport:
    """What ``cga batch merge`` wrote."""

    manifest: Path
    seeds: int
    built: int
    failed: tuple[int, ...]
    sources: tuple[Path, ...]

    def to_dict(self) -> dict[str, Any]:
        return {"manifest": str(self.manifest), "seeds": self.seeds, "houses": self.built,
                "failed": len(self.failed), "failed_seeds": list(self.failed[:20]),
                "sources": [str(p) for p in self.sources]}


def _listed(seeds: Sequence[int]) -> str:
    shown = ", ".join(map(str, seeds[:_LISTED]))
    return shown + (f", … ({len(seeds)} in all)" if len(seeds) > _LISTED else "")


def _lines(path: Path) -> Iterator[tuple[int, dict[str, Any]]]:
    """(offset, record) of every complete line of a manifest that parses."""
    with open(path, "rb") as file:
        offset = 0
        for raw in file:
            start, offset = offset, offset + len(raw)
            if not raw.endswith(b"\n"):
                continue  # cut short by an interruption
            try:
                record = json.loads(raw)
                int(record["seed"])
            except (ValueError, KeyError, TypeError):
                continue
            yield start, record


def _scan(path: Path, recorded: RecordedInputs) -> _Source:
    """Read a manifest's latest line per seed, adding its built houses' inputs to
    ``recorded``."""
    from .batch import seed_folder

    source = _Source(path, shard_of_manifest(path.name))
    latest: dict[int, tuple[int, dict[str, Any]]] = {}
    for offset, record in _lines(path):
        latest[int(record["seed"])] = (offset, record)
    for seed, (offset, record) in latest.items():
        if not (path.parent / (record.get("folder") or seed_folder(seed))).is_dir():
            continue  # not done (read_manifest's rule): a gap if the shard owed it
        source.offsets[seed] = offset
        if record.get("error") is not None:
            source.failed.add(seed)
            continue
        recorded.add(record.get("provenance", {}), f"seed {seed} of {path}")
    return source


def _find_manifests(folders: Sequence[Path], out: Path) -> list[Path]:
    found: list[Path] = []
    for folder in folders:
        if not folder.is_dir():
            raise UsageError(f"cga batch merge: {folder} is not a folder")
        shards = sorted(p for p in folder.glob("manifest.shard-*-of-*.jsonl")
                        if shard_of_manifest(p.name) is not None)
        plain = folder / MANIFEST
        if plain.is_file() and folder.resolve() != out.resolve():
            shards.append(plain)  # an unsharded batch joined to others
        if not shards:
            raise UsageError(f"cga batch merge: {folder} holds no batch manifest "
                             f"(manifest.shard-I-of-N.jsonl)")
        found += shards
    return found


def _check_shards(sources: list[_Source]) -> None:
    sharded = [s for s in sources if s.shard is not None]
    counts = sorted({s.shard.count for s in sharded if s.shard is not None})
    if len(counts) > 1:
        raise UsageError(f"cga batch merge: the shards were made with different N "
                         f"({', '.join(map(str, counts))}); merge the shards of one batch")
    seen: dict[Shard, Path] = {}
    for source in sharded:
        assert source.shard is not None
        if source.shard in seen:
            raise UsageError(f"cga batch merge: shard {source.shard} appears twice: "
                             f"{seen[source.shard]} and {source.path}")
        seen[source.shard] = source.path
    if counts:
        missing = [f"{i}/{counts[0]}" for i in range(counts[0]) if Shard(i, counts[0]) not in seen]
        if missing:
            raise UsageError(f"cga batch merge: shard{'s' * (len(missing) > 1)} "
                             f"{', '.join(missing)} missing: no manifest.shard-I-of-"
                             f"{counts[0]}.jsonl for {'them' if len(missing) > 1 else 'it'} "
                             f"in the folders given")


def _check_seeds(sources: list[_Source]) -> None:
    owner: dict[int, Path] = {}
    for source in sources:
        duplicates = sorted(seed for seed in source.offsets if seed in owner)
        if duplicates:
            raise UsageError(f"cga batch merge: seed{'s' * (len(duplicates) > 1)} "
                             f"{_listed(duplicates)} listed by both {owner[duplicates[0]]} and "
                             f"{source.path}")
        owner.update(dict.fromkeys(source.offsets, source.path))
        shard = source.shard
        if shard is None:
            continue
        foreign = sorted(seed for seed in source.offsets if not shard.owns(seed))
        if foreign:
            raise UsageError(f"cga batch merge: {source.path} lists seed{'s' * (len(foreign) > 1)}"
                             f" {_listed(foreign)}, which are not shard {shard}'s")
        ranges = read_ranges(source.path.parent, shard)
        if not ranges:
            raise UsageError(f"cga batch merge: {source.path.parent}/manifest.{shard.tag}.json "
                             f"(the seeds shard {shard} was asked to build) is missing")
        gaps = [seed for seeds in ranges for seed in shard.seeds(seeds)
                if seed not in source.offsets]
        if gaps:
            raise UsageError(f"cga batch merge: shard {shard} in {source.path.parent} has not "
                             f"built seed{'s' * (len(gaps) > 1)} {_listed(gaps)}: run it again "
                             f"(cga batch ... --shard {shard}) and merge once it has finished")


def merge_manifests(folders: Sequence[str | Path], out: str | Path | None = None) -> MergeReport:
    """Join the batch manifests in ``folders`` into ``out/manifest.jsonl`` (see the
    module notes).

    Raises
    ------
    UsageError
        A folder holds no manifest; shards missing, repeated or of different N; a seed
        listed twice or in the wrong shard; a seed a shard owes; houses of different
        inputs; ``out`` holds a manifest that ``cga batch merge`` did not write.
    """
    if not folders:
        raise UsageError("cga batch merge: name at least one batch folder")
    paths = [Path(f) for f in folders]
    target = Path(out) if out is not None else paths[0]
    manifest = target / MANIFEST
    recorded = RecordedInputs()
    sources = [_scan(p, recorded) for p in _find_manifests(paths, target)]
    _check_shards(sources)
    _check_seeds(sources)
    conflicts = recorded.conflicts()
    if conflicts:
        raise UsageError(f"cga batch merge: the houses were built from different inputs: "
                         f"{'; '.join(conflicts)}; one dataset is one configuration")
    if manifest.exists() and not _made_by_merge(manifest):
        raise UsageError(f"cga batch merge: {manifest} exists and was not written by cga batch "
                         f"merge (an unsharded batch); merge into another --out")
    target.mkdir(parents=True, exist_ok=True)
    _write(manifest, sources)
    failed = sorted(seed for source in sources for seed in source.failed)
    total = sum(len(source.offsets) for source in sources)
    return MergeReport(manifest, total, total - len(failed), tuple(failed),
                       tuple(source.path for source in sources))


def _made_by_merge(manifest: Path) -> bool:
    return (manifest.parent / MERGED).is_file()


def _write(manifest: Path, sources: list[_Source]) -> None:
    """Write the merged lines sorted by seed (atomically: a temporary file renamed)."""
    from .batch import seed_folder

    order = sorted((seed, index) for index, source in enumerate(sources)
                   for seed in source.offsets)
    handles = [open(source.path, "rb") for source in sources]
    fd, tmp = tempfile.mkstemp(prefix=f".{manifest.name}.", suffix=".tmp", dir=manifest.parent)
    try:
        with os.fdopen(fd, "wb") as merged:
            for seed, index in order:
                handle = handles[index]
                handle.seek(sources[index].offsets[seed])
                line = handle.readline()
                folder = sources[index].path.parent.resolve()
                if folder != manifest.parent.resolve():
                    record = json.loads(line)
                    name = record.get("folder") or seed_folder(seed)
                    record["folder"] = os.path.relpath(folder / name, manifest.parent.resolve())
                    line = (json.dumps(record, sort_keys=True) + "\n").encode("utf-8")
                merged.write(line)
            merged.flush()
            os.fsync(merged.fileno())
        os.chmod(tmp, 0o644)
        (manifest.parent / MERGED).write_text("manifest.jsonl was written by cga batch merge\n")
        os.replace(tmp, manifest)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    finally:
        for handle in handles:
            handle.close()
