"""Dataset-scale generation: one build per seed, a manifest, resume after interruption.

``cga batch house.grammar -n 1000 --jobs 2 --out data/`` writes ``data/seed_000000/``,
``data/seed_000001/``, ... and appends one JSON line per finished build to
``data/manifest.jsonl``. A build is done only when its folder has been moved into place
*and* its manifest line has been written: both steps are atomic (folder rename, a single
``O_APPEND`` write of one line), so an interrupted batch never counts a half-written
item. On a rerun, seeds with a manifest line and a folder are skipped, stray temporary
folders are removed, and a trailing partial manifest line is dropped.
"""

from __future__ import annotations

import functools
import json
import math
import multiprocessing
import os
import shutil
import signal
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

from .errors import CGAError, ExportError, UsageError

__all__ = ["BatchRecord", "BatchReport", "run_batch", "read_manifest", "seed_folder"]

MANIFEST = "manifest.jsonl"
_TMP_PREFIX = ".building-"


def seed_folder(seed: int) -> str:
    """Folder name of one seed's outputs (zero-padded so folders sort by seed)."""
    return f"seed_{seed:06d}"


@dataclass(frozen=True)
class BatchRecord:
    """One manifest line: what a single build produced and whether it is valid."""

    seed: int
    valid: bool
    seconds: float
    rooms: int = 0
    items: int = 0
    items_left_out: int = 0
    checks: dict[str, Any] = field(default_factory=dict)
    error: str | None = None

    def to_json(self) -> str:
        return json.dumps(self.__dict__, sort_keys=True)


@dataclass(frozen=True)
class BatchReport:
    """Totals over a manifest: validity and placement rates, time per house, throughput."""

    records: tuple[BatchRecord, ...]
    wall_seconds: float
    built_now: int

    @property
    def count(self) -> int:
        return len(self.records)

    @property
    def validity_rate(self) -> float:
        return sum(r.valid for r in self.records) / self.count if self.count else 0.0

    @property
    def placement_rate(self) -> float:
        wanted = sum(r.items + r.items_left_out for r in self.records)
        return sum(r.items for r in self.records) / wanted if wanted else 1.0

    @property
    def mean_seconds(self) -> float:
        return sum(r.seconds for r in self.records) / self.count if self.count else 0.0

    @property
    def p95_seconds(self) -> float:
        times = sorted(r.seconds for r in self.records)
        if not times:
            return 0.0
        return times[min(len(times) - 1, math.ceil(0.95 * len(times)) - 1)]

    @property
    def houses_per_second(self) -> float:
        return self.built_now / self.wall_seconds if self.wall_seconds > 0 else 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "houses": self.count,
            "built_now": self.built_now,
            "validity_rate": round(self.validity_rate, 4),
            "placement_rate": round(self.placement_rate, 4),
            "mean_seconds": round(self.mean_seconds, 4),
            "p95_seconds": round(self.p95_seconds, 4),
            "houses_per_second": round(self.houses_per_second, 3),
            "errors": sum(r.error is not None for r in self.records),
        }


def read_manifest(out_dir: Path) -> dict[int, BatchRecord]:
    """Finished builds by seed. A line cut short by an interruption is ignored."""
    path = Path(out_dir) / MANIFEST
    records: dict[int, BatchRecord] = {}
    if not path.exists():
        return records
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            data = json.loads(line)
            record = BatchRecord(**data)
        except (json.JSONDecodeError, TypeError):
            continue
        if (Path(out_dir) / seed_folder(record.seed)).is_dir():
            records[record.seed] = record
    return records


def _rewrite_manifest(out_dir: Path, records: dict[int, BatchRecord]) -> None:
    """Rewrite the manifest with only complete lines (drops a partial trailing line)."""
    from .fsutil import atomic_write

    lines = "".join(records[s].to_json() + "\n" for s in sorted(records))
    atomic_write(out_dir / MANIFEST, lines)


def _append_record(out_dir: Path, record: BatchRecord) -> None:
    fd = os.open(out_dir / MANIFEST, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
    try:
        os.write(fd, (record.to_json() + "\n").encode("utf-8"))
        os.fsync(fd)
    finally:
        os.close(fd)


def _summarise(scene: Any, seconds: float, seed: int) -> BatchRecord:
    checks = {name: bool(result.get("passed")) for name, result in scene.checks.items()
              if isinstance(result, dict) and "passed" in result}
    left_out = sum(1 for d in scene.all_diagnostics()
                   if d.stage == "add_furniture" and d.level == "warning")
    items = sum(1 for plan in scene.floors for item in plan.furniture if not item.is_detail)
    errors = [d for d in scene.all_diagnostics() if d.level == "error"]
    return BatchRecord(
        seed=seed,
        valid=all(checks.values()) and not errors,
        seconds=round(seconds, 4),
        rooms=sum(len(plan.rooms) for plan in scene.floors),
        items=items,
        items_left_out=left_out,
        checks=checks,
    )


def _build_one(grammar: str, seed: int, out_dir: str, build_options: dict[str, Any]) -> BatchRecord:
    """Worker: build one seed into a temporary folder, then move it into place."""
    from .pipeline import build

    final = Path(out_dir) / seed_folder(seed)
    staging = Path(out_dir) / f"{_TMP_PREFIX}{seed_folder(seed)}"
    shutil.rmtree(staging, ignore_errors=True)
    start = time.perf_counter()
    try:
        scene = build(grammar, seed=seed, out_dir=staging, quiet=True, **build_options)
        record = _summarise(scene, time.perf_counter() - start, seed)
    except CGAError as exc:  # an invalid house is a result of the batch, not a crash
        staging.mkdir(parents=True, exist_ok=True)
        (staging / "error.txt").write_text(str(exc) + "\n", encoding="utf-8")
        record = BatchRecord(seed=seed, valid=False, seconds=round(time.perf_counter() - start, 4),
                             error=str(exc).splitlines()[0])
    shutil.rmtree(final, ignore_errors=True)
    os.replace(staging, final)
    return record


def run_batch(grammar: str | Path, *, count: int, out_dir: str | Path, jobs: int = 1,
              seed_start: int = 0, build_options: dict[str, Any] | None = None,
              on_progress: Callable[[int, int], None] | None = None) -> BatchReport:
    """Build ``count`` seeds of a grammar, skipping seeds a previous run finished.

    Parameters
    ----------
    grammar : path of the grammar file.
    count, seed_start : build seeds ``seed_start .. seed_start + count - 1``.
    out_dir : folder for the per-seed folders and ``manifest.jsonl``.
    jobs : worker processes (1 builds in this process).
    build_options : keyword arguments passed to :func:`cga.pipeline.build` (e.g.
        ``physics=False``).
    on_progress : called with (done, total) after each finished build.

    Returns
    -------
    BatchReport over every seed of the range that has a manifest line.
    """
    if count < 1:
        raise UsageError(f"-n must be at least 1, got {count}")
    if jobs < 1:
        raise UsageError(f"--jobs must be at least 1, got {jobs}")
    if seed_start < 0:
        raise UsageError(f"--seed-start must be a whole number ≥ 0, got {seed_start}")
    from .export import check_formats

    check_formats((build_options or {}).get("formats", ()))
    grammar = str(Path(grammar).resolve())
    if not Path(grammar).is_file():
        from .errors import ResourceNotFoundError
        raise ResourceNotFoundError("grammar file", grammar)
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise ExportError(f"cannot create the output folder {out}: "
                          f"{error.strerror or error}") from None
    for stale in out.glob(f"{_TMP_PREFIX}*"):
        shutil.rmtree(stale, ignore_errors=True)
    done = read_manifest(out)
    _rewrite_manifest(out, done)
    seeds = [s for s in range(seed_start, seed_start + count) if s not in done]
    options = dict(build_options or {})
    total = count
    finished = count - len(seeds)
    if on_progress:
        on_progress(finished, total)
    start = time.perf_counter()
    for record in _run(grammar, seeds, str(out), options, jobs):
        _append_record(out, record)
        done[record.seed] = record
        finished += 1
        if on_progress:
            on_progress(finished, total)
    wall = time.perf_counter() - start
    in_range = tuple(done[s] for s in range(seed_start, seed_start + count) if s in done)
    return BatchReport(records=in_range, wall_seconds=wall, built_now=len(seeds))


def _ignore_interrupts() -> None:
    """Worker initializer: Ctrl-C in a terminal reaches the whole process group; only
    the parent handles it (and stops the workers), so workers print no tracebacks."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _run(grammar: str, seeds: list[int], out_dir: str, options: dict[str, Any],
         jobs: int) -> Iterable[BatchRecord]:
    """Yield records as builds finish.

    On an interruption (or any error) in the parent, the workers are terminated at once:
    a build they had not finished is left as a staging folder, which the next run
    removes, and it has no manifest line, so it is built again.
    """
    if jobs == 1:
        for seed in seeds:
            yield _build_one(grammar, seed, out_dir, options)
        return
    work = functools.partial(_build_one, grammar, out_dir=out_dir, build_options=options)
    pool = multiprocessing.get_context("spawn").Pool(jobs, initializer=_ignore_interrupts)
    try:
        yield from pool.imap_unordered(work, seeds, chunksize=1)
    except BaseException:
        pool.terminate()
        raise
    else:
        pool.close()
    finally:
        pool.join()
