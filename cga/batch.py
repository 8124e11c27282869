"""Dataset-scale generation: one build per seed, a manifest, honest resume after interruption.

``cga batch house.grammar -n 1000 --jobs 2 --out data/`` writes ``data/seed_000000/``,
``data/seed_000001/``, ... and appends one JSON line per finished build to
``data/manifest.jsonl``. A build is done only when its folder has been moved into place
*and* its manifest line has been written: both steps are atomic (folder rename, a single
``O_APPEND`` write of one line), so an interrupted batch never counts a half-written
item.

A seed whose build failed (an error in the grammar for that seed, the time limit, a
worker that died) gets a manifest line with its ``error`` and a folder with
``error.txt``, but it is never counted as done: every rerun builds it again
(issue 19, defect 2). Seeds built by an earlier run are skipped. One batch at a time
writes into a folder: a lock file (``.cga-batch.lock``, an ``flock`` the kernel drops
when the process dies) names the running batch to a second one, which is refused.
Seeds are generated lazily, so ``-n 1e12`` starts at once.
"""

from __future__ import annotations

import contextlib
import functools
import inspect
import json
import math
import os
import shutil
import socket
import time
import traceback
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .difficulty.metrics import mean_metrics
from .errors import CGAError, ExportError, UsageError
from .quality import quality_report

if TYPE_CHECKING:  # pragma: no cover
    from .scene import Scene

__all__ = ["BatchRecord", "BatchReport", "run_batch", "read_manifest", "seed_folder",
           "max_jobs", "MANIFEST", "LOCK"]

MANIFEST = "manifest.jsonl"
LOCK = ".cga-batch.lock"
_TMP_PREFIX = ".building-"
_REPORTED_FAILURES = 20
"""Failed seeds listed by name in a report (all of them are in the manifest)."""


def max_jobs() -> int:
    """The most worker processes a batch may start: four per core. More only adds
    memory and switching; a typo such as ``--jobs 2000`` used to start them all."""
    return 4 * (os.cpu_count() or 1)


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
    quality: dict[str, Any] = field(default_factory=dict)
    """Layout quality over the floors (:mod:`cga.quality`): worst circulation share,
    most doors of a room, counts of private rooms passed through, rooms reached only
    through private rooms, areas out of range and rule-less rooms."""
    views: int = 0
    """Camera views rendered (``--export render``: room views and top-down views)."""
    difficulty: dict[str, Any] = field(default_factory=dict)
    """The building's measured difficulty (:meth:`cga.difficulty.DifficultyReport.totals`)."""

    def to_json(self) -> str:
        return json.dumps(self.__dict__, sort_keys=True)


@dataclass(frozen=True)
class BatchReport:
    """What a run left in its seed range: built, failed and skipped seeds, and totals
    over the built houses (validity and placement rates, time per house, throughput)."""

    records: tuple[BatchRecord, ...]
    """The latest manifest line of every seed of the range that has one."""
    wall_seconds: float
    built_now: int
    """Seeds this run built successfully."""
    skipped: int = 0
    """Seeds of the range an earlier run had built: not rebuilt."""
    seeds: int = 0
    """Seeds in the range."""

    @property
    def built(self) -> tuple[BatchRecord, ...]:
        return tuple(r for r in self.records if r.error is None)

    @property
    def failed(self) -> tuple[BatchRecord, ...]:
        return tuple(r for r in self.records if r.error is not None)

    @property
    def count(self) -> int:
        """Houses in the range (built now or before)."""
        return len(self.built)

    @property
    def validity_rate(self) -> float:
        """Valid houses per seed that was attempted (a failed seed is not a valid house)."""
        return sum(r.valid for r in self.records) / len(self.records) if self.records else 0.0

    @property
    def placement_rate(self) -> float:
        wanted = sum(r.items + r.items_left_out for r in self.built)
        return sum(r.items for r in self.built) / wanted if wanted else 1.0

    @property
    def mean_seconds(self) -> float:
        times = [r.seconds for r in self.built]
        return sum(times) / len(times) if times else 0.0

    @property
    def p95_seconds(self) -> float:
        times = sorted(r.seconds for r in self.built)
        if not times:
            return 0.0
        return times[min(len(times) - 1, math.ceil(0.95 * len(times)) - 1)]

    @property
    def houses_per_second(self) -> float:
        return self.built_now / self.wall_seconds if self.wall_seconds > 0 else 0.0

    def to_dict(self) -> dict[str, Any]:
        failed = self.failed
        return {
            "seeds": self.seeds,
            "houses": self.count,
            "built_now": self.built_now,
            "skipped": self.skipped,
            "failed": len(failed),
            "errors": len(failed),  # the name before "failed" existed, kept for scripts
            "failed_seeds": [{"seed": r.seed, "error": r.error}
                             for r in failed[:_REPORTED_FAILURES]],
            "validity_rate": round(self.validity_rate, 4),
            "placement_rate": round(self.placement_rate, 4),
            "mean_seconds": round(self.mean_seconds, 4),
            "p95_seconds": round(self.p95_seconds, 4),
            "houses_per_second": round(self.houses_per_second, 3),
            "views": sum(r.views for r in self.built),
            "difficulty_means": mean_metrics(r.difficulty for r in self.built if r.difficulty),
        }


def read_manifest(out_dir: Path) -> dict[int, BatchRecord]:
    """The latest manifest line of each seed whose folder exists, built or failed.

    A line cut short by an interruption is ignored; a later line for a seed (a rebuild
    of a failed seed) replaces an earlier one.
    """
    path = Path(out_dir) / MANIFEST
    records: dict[int, BatchRecord] = {}
    if not path.exists():
        return records
    with open(path, encoding="utf-8", errors="replace") as lines:
        for line in lines:
            try:
                record = BatchRecord(**json.loads(line))
            except (ValueError, TypeError):
                continue
            records[record.seed] = record
    return {seed: record for seed, record in records.items()
            if (Path(out_dir) / seed_folder(seed)).is_dir()}


def _rewrite_manifest(out_dir: Path, records: dict[int, BatchRecord]) -> None:
    """Rewrite the manifest with one complete line per seed (drops a partial line)."""
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


def _summarise(scene: Scene, seconds: float, seed: int) -> BatchRecord:
    checks = {name: report.passed for name, report in scene.checks.items()}
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
        quality=_quality_totals(quality_report(list(scene.floors))),
        difficulty=scene.difficulty.totals() if scene.difficulty is not None else {},
    )


def _staging(out_dir: Path, seed: int) -> Path:
    return out_dir / f"{_TMP_PREFIX}{seed_folder(seed)}"


def _publish(out_dir: Path, seed: int, staging: Path) -> None:
    """Move a seed's staged folder into place (replacing an earlier attempt)."""
    final = out_dir / seed_folder(seed)
    shutil.rmtree(final, ignore_errors=True)
    os.replace(staging, final)


def _failure(out_dir: Path, seed: int, message: str, seconds: float,
             details: str | None = None) -> BatchRecord:
    """Record a failed seed: a folder holding ``error.txt`` and a manifest record."""
    staging = _staging(out_dir, seed)
    shutil.rmtree(staging, ignore_errors=True)
    staging.mkdir(parents=True)
    (staging / "error.txt").write_text((details or message) + "\n", encoding="utf-8")
    _publish(out_dir, seed, staging)
    return BatchRecord(seed=seed, valid=False, seconds=round(seconds, 4),
                       error=message.splitlines()[0] if message else "failed")


def _quality_totals(floors: list[dict[str, Any]]) -> dict[str, Any]:
    """One manifest line's worth of :func:`cga.quality.quality_report`."""
    if not floors:
        return {}
    return {
        "circulation_share": [f["circulation_share"] for f in floors],
        "max_doors_per_room": max((max(f["doors_per_room"].values(), default=0) for f in floors)),
        "pass_through_private": sum(len(f["pass_through_private"]) for f in floors),
        "reached_only_through_private": sum(len(f["reached_only_through_private"]) for f in floors),
        "area_out_of_range": sum(len(f["area_out_of_range"]) for f in floors),
        "ruleless": sum(len(f["ruleless"]) for f in floors),
    }


def _build_one(grammar: str, seed: int, out_dir: str, build_options: dict[str, Any]) -> BatchRecord:
    """Build one seed into a staging folder, then move it into place (in a worker or in
    the batch's own process). A failure is a result of the batch, not a crash: it is
    recorded with its message (a project error) or its traceback (anything else)."""
    from .pipeline import build

    out = Path(out_dir)
    staging = _staging(out, seed)
    shutil.rmtree(staging, ignore_errors=True)
    start = time.perf_counter()
    try:
        scene = build(grammar, seed=seed, out_dir=staging, quiet=True, **build_options)
    except CGAError as error:
        return _failure(out, seed, str(error), time.perf_counter() - start)
    except Exception as error:  # a defect must not stop the other seeds of the dataset
        return _failure(out, seed, f"internal error: {type(error).__name__}: {error}",
                        time.perf_counter() - start, traceback.format_exc())
    except BaseException:  # interrupted: leave nothing half-built behind
        shutil.rmtree(staging, ignore_errors=True)
        raise
    record = _summarise(scene, time.perf_counter() - start, seed)
    views = sum(1 for _ in staging.glob("*.render/*.camera.json"))
    if views:
        record = replace(record, views=views)
    staging.mkdir(parents=True, exist_ok=True)  # a build that writes no files
    _publish(out, seed, staging)
    return record


@contextlib.contextmanager
def _exclusive(out: Path) -> Iterator[None]:
    """Hold the batch lock of ``out`` (refuse if another live batch holds it)."""
    from .fsutil import lock_exclusive

    path = out / LOCK
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as error:
        raise ExportError(f"cannot write into the output folder {out}: "
                          f"{error.strerror or error}") from None
    try:
        if not lock_exclusive(fd):
            owner = os.read(fd, 4096).decode("utf-8", "replace").strip() or "another process"
            raise UsageError(f"another batch is writing into {out} ({owner}); wait for it to "
                             f"finish or choose another --out")
        os.ftruncate(fd, 0)
        os.write(fd, f"pid {os.getpid()} on {socket.gethostname()}, started "
                     f"{time.strftime('%Y-%m-%d %H:%M:%S %Z')}\n".encode())
        yield
    finally:
        os.close(fd)


def _check_options(grammar: str, build_options: dict[str, Any]) -> None:
    """Reject what every seed would reject before any work starts: the grammar's syntax,
    unknown options, bad option values (``--export foo``)."""
    from .pipeline import build, check_grammar

    reserved = {"seed", "out_dir", "quiet"} & set(build_options)
    if reserved:
        raise UsageError(f"build options {', '.join(sorted(reserved))} are set by the batch")
    try:
        inspect.signature(build).bind_partial(grammar, **build_options)
    except TypeError as error:
        raise UsageError(f"build options: {error}") from None
    check_grammar(grammar, **build_options)


def run_batch(grammar: str | Path, *, count: int, out_dir: str | Path, jobs: int = 1,
              seed_start: int = 0, build_options: dict[str, Any] | None = None,
              time_limit: float | None = None,
              on_progress: Callable[[int, int], None] | None = None) -> BatchReport:
    """Build ``count`` seeds of a grammar, skipping seeds an earlier run built.

    Parameters
    ----------
    grammar : path of the grammar file.
    count, seed_start : build seeds ``seed_start .. seed_start + count - 1``.
    out_dir : folder for the per-seed folders and ``manifest.jsonl``.
    jobs : worker processes, at most :func:`max_jobs` (1 builds in this process unless
        there is a time limit).
    build_options : keyword arguments passed to :func:`cga.pipeline.build` (e.g.
        ``physics=False``).
    time_limit : seconds one build may take; a build over it is stopped and recorded as
        failed (builds then run in worker processes).
    on_progress : called with (done, total) after each finished build.

    Returns
    -------
    BatchReport over every seed of the range that has a manifest line; its ``failed``
    seeds are the ones to look at (a rerun builds them again).

    Raises
    ------
    UsageError
        A bad count, seed, job count or time limit; another batch writes into
        ``out_dir``; an unknown build option.
    CGAError
        Whatever every seed would fail with: a syntax error in the grammar, a missing
        grammar, an unknown export format, an output folder that cannot be written.
    """
    if count < 1:
        raise UsageError(f"-n must be at least 1, got {count}")
    if jobs < 1:
        raise UsageError(f"--jobs must be at least 1, got {jobs}")
    if jobs > max_jobs():
        raise UsageError(f"--jobs must be at most {max_jobs()} (4 per core on this machine's "
                         f"{os.cpu_count()} cores), got {jobs}")
    if seed_start < 0:
        raise UsageError(f"--seed-start must be a whole number ≥ 0, got {seed_start}")
    if time_limit is not None and not 0 < time_limit < math.inf:
        raise UsageError(f"--time-limit must be a positive number of seconds, got {time_limit}")
    grammar = str(Path(grammar).resolve())
    options = dict(build_options or {})
    _check_options(grammar, options)
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise ExportError(f"cannot create the output folder {out}: "
                          f"{error.strerror or error}") from None
    with _exclusive(out):
        return _run_locked(grammar, out, range(seed_start, seed_start + count), options,
                           jobs, time_limit, on_progress)


def _remove_staging(out: Path) -> None:
    """Remove unfinished seed folders and manifest temporaries. Only under the lock: then
    no other batch is writing, so every one of them is stale."""
    for stale in (*out.glob(f"{_TMP_PREFIX}*"), *out.glob(f".{MANIFEST}.*.tmp")):
        if stale.is_dir() and not stale.is_symlink():
            shutil.rmtree(stale, ignore_errors=True)
        else:
            stale.unlink(missing_ok=True)


def _run_locked(grammar: str, out: Path, seeds: range, options: dict[str, Any], jobs: int,
                time_limit: float | None,
                on_progress: Callable[[int, int], None] | None) -> BatchReport:
    _remove_staging(out)
    records = read_manifest(out)
    _rewrite_manifest(out, records)
    built_before = {seed for seed, r in records.items() if r.error is None and seed in seeds}
    todo = (seed for seed in seeds if seed not in built_before)
    finished = len(built_before)
    if on_progress:
        on_progress(finished, len(seeds))
    start = time.perf_counter()
    built_now = 0
    replaced = False
    try:
        for record in _run(grammar, todo, out, options, jobs, time_limit):
            _append_record(out, record)
            replaced |= record.seed in records
            records[record.seed] = record
            built_now += record.error is None
            finished += 1
            if on_progress:
                on_progress(finished, len(seeds))
    finally:
        _remove_staging(out)  # seeds in flight when stopped; their workers are gone
        if replaced:  # one line per seed again (a rebuilt seed was appended after its failure)
            _rewrite_manifest(out, records)
    wall = time.perf_counter() - start
    in_range = tuple(records[seed] for seed in sorted(records) if seed in seeds)
    return BatchReport(records=in_range, wall_seconds=wall, built_now=built_now,
                       skipped=len(built_before), seeds=len(seeds))


def _run(grammar: str, seeds: Iterator[int], out: Path, options: dict[str, Any], jobs: int,
         time_limit: float | None) -> Iterator[BatchRecord]:
    """Yield records as builds finish: in this process (one job, no time limit) or in
    worker processes (:mod:`cga.batch_pool`), which are all gone when this returns or
    raises, so their unfinished seeds can be cleaned up."""
    work = functools.partial(_build_one, grammar, out_dir=str(out), build_options=options)
    if jobs == 1 and time_limit is None:
        yield from map(work, seeds)
        return
    from .batch_pool import run_pool

    yield from run_pool(seeds, work, functools.partial(_failure, out), jobs=jobs,
                        time_limit=time_limit,
                        warm_up=functools.partial(_warm_up, options.get("physics", True)))


def _warm_up(physics: bool) -> None:
    """Import what a build needs before a worker takes its first seed: a second or two
    that would otherwise count against the first build's time limit."""
    import importlib

    modules = ["cga.pipeline", "cga.meshing", "cga.export", "cga.operations"]
    if physics:
        modules += ["cga.checks.physics", "cga.checks.navigability"]
    for name in modules:
        importlib.import_module(name)
