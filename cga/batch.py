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

Builds run on an engine (:mod:`cga.batch_engine`): local worker processes by default, a
Ray cluster with ``engine="ray"`` (:mod:`cga.batch_ray`). ``shard=Shard(I, N)`` builds
every N-th seed into its own manifest (:mod:`cga.batch_shard`, joined by
:mod:`cga.batch_merge`). Every line records the inputs of its build
(:mod:`cga.provenance`); a resume whose inputs differ from the built houses' is refused,
naming what changed, unless ``force`` starts a new manifest.
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
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .batch_engine import Engine, make_engine, max_jobs
from .batch_shard import LOCK, MANIFEST, MERGED, Shard, manifest_name, write_ranges
from .difficulty.metrics import mean_metrics
from .errors import CGAError, ExportError, UsageError
from .provenance import RecordedInputs, provenance, recording
from .quality import quality_report

if TYPE_CHECKING:  # pragma: no cover
    from .scene import Scene

__all__ = ["BatchRecord", "BatchReport", "run_batch", "read_manifest", "seed_folder",
           "max_jobs", "MANIFEST", "LOCK", "VOLATILE_FIELDS"]

_TMP_PREFIX = ".building-"
_REPORTED_FAILURES = 20
"""Failed seeds listed by name in a report (all of them are in the manifest)."""


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
    provenance: dict[str, Any] = field(default_factory=dict)
    """What the build was made from (:func:`cga.provenance.provenance`): digests of the
    grammar and of every file it read, the build options and the cga version."""
    folder: str | None = None
    """The seed's folder relative to the manifest's, when it is not ``seed_NNNNNN``
    beside it (a manifest joined by ``cga batch merge`` from other folders)."""

    def to_json(self) -> str:
        data = dict(self.__dict__)
        if data["folder"] is None:
            del data["folder"]
        return json.dumps(data, sort_keys=True)


VOLATILE_FIELDS = ("seconds",)
"""Manifest fields that differ between two runs of the same seeds: the build's wall
time. Every other field of a line is a function of the seed and the inputs."""


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


def read_manifest(out_dir: Path, shard: Shard | None = None) -> dict[int, BatchRecord]:
    """The latest manifest line of each seed whose folder exists, built or failed (of
    ``shard``'s manifest when given).

    A line cut short by an interruption is ignored; a later line for a seed (a rebuild
    of a failed seed) replaces an earlier one.
    """
    path = Path(out_dir) / manifest_name(shard)
    records: dict[int, BatchRecord] = {}
    if not path.exists():
        return records
    shared: dict[Any, dict[str, Any]] = {}
    with open(path, encoding="utf-8", errors="replace") as lines:
        for line in lines:
            try:
                record = BatchRecord(**json.loads(line))
                inputs = record.provenance
                key = (tuple(inputs.get("files", {}).items()), json.dumps(inputs.get("options")),
                       inputs.get("grammar"), inputs.get("version"))
            except (ValueError, TypeError, AttributeError):
                continue
            # most lines record the same inputs: one dict for all of them (a million
            # lines took 9 GB, two thirds of it in copies of the same digests)
            records[record.seed] = replace(record, provenance=shared.setdefault(key, inputs))
    return {seed: record for seed, record in records.items()
            if (Path(out_dir) / (record.folder or seed_folder(seed))).is_dir()}


def _rewrite_manifest(path: Path, records: dict[int, BatchRecord]) -> None:
    """Rewrite a manifest with one complete line per seed (drops a partial line)."""
    from .fsutil import atomic_write

    lines = "".join(records[s].to_json() + "\n" for s in sorted(records))
    atomic_write(path, lines)


def _append_record(path: Path, record: BatchRecord) -> None:
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
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


def _failure(out_dir: Path, inputs: dict[str, Any], seed: int, message: str, seconds: float,
             details: str | None = None) -> BatchRecord:
    """Record a failed seed: a folder holding ``error.txt`` and a manifest record
    carrying ``inputs`` (its provenance)."""
    staging = _staging(out_dir, seed)
    shutil.rmtree(staging, ignore_errors=True)
    staging.mkdir(parents=True)
    (staging / "error.txt").write_text((details or message) + "\n", encoding="utf-8")
    _publish(out_dir, seed, staging)
    return BatchRecord(seed=seed, valid=False, seconds=round(seconds, 4),
                       error=message.splitlines()[0] if message else "failed",
                       provenance=inputs)


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


_NOT_RECORDED = ("grammar_path", "seed", "out_dir", "quiet", "operations")
"""Build keywords that are not options of a dataset: set per seed by the batch, or
(``operations``, Python callers only) code rather than data."""


def recorded_options(build_options: dict[str, Any]) -> dict[str, Any]:
    """Every option of :func:`cga.pipeline.build`, defaults filled in, as a manifest line
    records it: a Python caller that leaves an option at its default and the command
    line that passes the default record the same configuration."""
    from .pipeline import build

    bound = inspect.signature(build).bind_partial(**build_options)
    bound.apply_defaults()
    options = {name: value for name, value in bound.arguments.items() if name not in _NOT_RECORDED}
    options["overrides"] = dict(options.get("overrides") or {})  # None and {}: none
    return options


def _inputs(grammar: str, build_options: dict[str, Any], reads: Sequence[Path] = ()
            ) -> dict[str, Any]:
    return provenance(Path(grammar), recorded_options(build_options), reads)


def _build_one(grammar: str, seed: int, out_dir: str, build_options: dict[str, Any]) -> BatchRecord:
    """Build one seed into a staging folder, then move it into place (in a worker or in
    the batch's own process). A failure is a result of the batch, not a crash: it is
    recorded with its message (a project error) or its traceback (anything else)."""
    from .pipeline import build

    out = Path(out_dir)
    staging = _staging(out, seed)
    shutil.rmtree(staging, ignore_errors=True)
    start = time.perf_counter()
    with recording() as reads:
        try:
            scene = build(grammar, seed=seed, out_dir=staging, quiet=True, **build_options)
        except CGAError as error:
            return _failure(out, _inputs(grammar, build_options, reads), seed,
                            error.report(), time.perf_counter() - start)
        except Exception as error:  # a defect must not stop the other seeds of the dataset
            return _failure(out, _inputs(grammar, build_options, reads), seed,
                            f"internal error: {type(error).__name__}: {error}",
                            time.perf_counter() - start, traceback.format_exc())
        except BaseException:  # interrupted: leave nothing half-built behind
            shutil.rmtree(staging, ignore_errors=True)
            raise
    record = _summarise(scene, time.perf_counter() - start, seed)
    views = sum(1 for _ in staging.glob("*.render/*.camera.json"))
    record = replace(record, views=views, provenance=_inputs(grammar, build_options, reads))
    staging.mkdir(parents=True, exist_ok=True)  # a build that writes no files
    _publish(out, seed, staging)
    return record


@contextlib.contextmanager
def _lock(path: Path, out: Path, shared: bool, busy: Callable[[str], str]) -> Iterator[None]:
    """Hold the lock file ``path`` (exclusively, naming this batch in it, or shared);
    refuse with ``busy(owner)`` if another live batch holds it."""
    from .fsutil import lock_exclusive, lock_shared

    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as error:
        raise ExportError(f"cannot write into the output folder {out}: "
                          f"{error.strerror or error}") from None
    try:
        try:
            locked = (lock_shared if shared else lock_exclusive)(fd)
        except OSError as error:  # a network file system mounted without locks
            raise ExportError(f"cannot lock {path}: {error.strerror or error} (the output "
                              f"folder's file system must support flock: on Lustre mount "
                              f"with -o flock, on NFS use version 4)") from None
        if not locked:
            owner = os.read(fd, 4096).decode("utf-8", "replace").strip()
            raise UsageError(busy(owner))
        if not shared:
            os.ftruncate(fd, 0)
            os.write(fd, f"pid {os.getpid()} on {socket.gethostname()}, started "
                         f"{time.strftime('%Y-%m-%d %H:%M:%S %Z')}\n".encode())
        try:
            yield
        finally:
            if not shared:  # the shards that lock the folder next name nobody
                os.ftruncate(fd, 0)
    finally:
        os.close(fd)


@contextlib.contextmanager
def _exclusive(out: Path, shard: Shard | None) -> Iterator[None]:
    """Hold the batch locks of ``out``: an unsharded batch has the folder to itself;
    shards share it, each holding its own shard's lock (:mod:`cga.batch_shard`)."""
    def busy(owner: str) -> str:
        if shard is None and not owner:
            return (f"shards of a batch are writing into {out}; wait for them to finish or "
                    f"choose another --out")
        return (f"another batch is writing into {out} ({owner or 'another process'}); wait "
                f"for it to finish or choose another --out")

    with _lock(out / LOCK, out, shard is not None, busy):
        if shard is None:
            yield
            return
        with _lock(out / f".cga-batch.{shard.tag}.lock", out, False,
                   lambda owner: f"shard {shard} is already being built into {out} "
                                 f"({owner or 'another process'})"):
            yield


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


def run_batch(grammar: str | Path, *, count: int, out_dir: str | Path, jobs: int | None = None,
              seed_start: int = 0, build_options: dict[str, Any] | None = None,
              time_limit: float | None = None,
              on_progress: Callable[[int, int], None] | None = None,
              engine: str = "local", address: str | None = None, retries: int | None = None,
              shard: Shard | None = None, force: bool = False) -> BatchReport:
    """Build ``count`` seeds of a grammar, skipping seeds an earlier run built.

    Parameters
    ----------
    grammar : path of the grammar file.
    count, seed_start : build seeds ``seed_start .. seed_start + count - 1``.
    out_dir : folder for the per-seed folders and ``manifest.jsonl``.
    jobs : worker processes, at most :func:`max_jobs` (default 1, which builds in this
        process unless there is a time limit); with ``engine="ray"``, the CPUs of the
        local cluster started, or the most builds in flight on the cluster at
        ``address``.
    build_options : keyword arguments passed to :func:`cga.pipeline.build` (e.g.
        ``physics=False``).
    time_limit : seconds one build may take; a build over it is stopped and recorded as
        failed (builds then run in worker processes).
    on_progress : called with (done, total) after each finished build.
    engine : ``"local"`` (worker processes on this machine) or ``"ray"``
        (:mod:`cga.batch_ray`).
    address, retries : the Ray cluster to use (None: start a local one) and how often a
        lost task is retried (Ray only).
    shard : build only this shard's seeds (every N-th), into its own manifest.
    force : when the built houses' recorded inputs differ from the current ones, move
        the manifest and its seed folders to ``superseded-<time>/`` and start anew
        (without it, such a resume is refused).

    Returns
    -------
    BatchReport over every seed of the range (of the shard) that has a manifest line;
    its ``failed`` seeds are the ones to look at (a rerun builds them again).

    Raises
    ------
    UsageError
        A bad count, seed, job count or time limit; another batch writes into
        ``out_dir``; an unknown build option or engine; the manifest's houses were
        built from other inputs (the message names what changed).
    CGAError
        Whatever every seed would fail with: a syntax error in the grammar, a missing
        grammar, an unknown export format, an output folder that cannot be written.
    """
    if count < 1:
        raise UsageError(f"-n must be at least 1, got {count}")
    if seed_start < 0:
        raise UsageError(f"--seed-start must be a whole number ≥ 0, got {seed_start}")
    if time_limit is not None and not 0 < time_limit < math.inf:
        raise UsageError(f"--time-limit must be a positive number of seconds, got {time_limit}")
    runner = make_engine(engine, jobs=jobs, time_limit=time_limit, address=address,
                         retries=retries)
    grammar = str(Path(grammar).resolve())
    options = dict(build_options or {})
    _check_options(grammar, options)
    out = Path(out_dir).absolute()  # workers on other nodes and in other folders
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise ExportError(f"cannot create the output folder {out}: "
                          f"{error.strerror or error}") from None
    seeds = range(seed_start, seed_start + count)
    with _exclusive(out, shard):
        if shard is not None:
            write_ranges(out, shard, seeds)
        return _run_locked(_Run(grammar, out, options, runner, shard, force),
                           shard.seeds(seeds) if shard else seeds, on_progress)


@dataclass(frozen=True)
class _Run:
    """What one batch run builds, with what, and where its manifest is."""

    grammar: str
    out: Path
    options: dict[str, Any]
    engine: Engine
    shard: Shard | None
    force: bool

    @property
    def manifest(self) -> Path:
        return self.out / manifest_name(self.shard)

    def owns(self, seed: int) -> bool:
        return self.shard is None or self.shard.owns(seed)


def _remove_staging(run: _Run) -> None:
    """Remove this run's unfinished seed folders and manifest temporaries. Only under
    the lock: then no other batch builds these seeds, so every one of them is stale
    (other shards' seeds are theirs to clean)."""
    prefix = f"{_TMP_PREFIX}seed_"
    stale = [path for path in run.out.glob(f"{prefix}*")
             if path.name[len(prefix):].isdigit() and run.owns(int(path.name[len(prefix):]))]
    for path in (*stale, *run.out.glob(f".{run.manifest.name}.*.tmp")):
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)


def _check_inputs(run: _Run, records: dict[int, BatchRecord]) -> dict[int, BatchRecord]:
    """The records to resume from: ``records`` if every built house was made from the
    current inputs. Otherwise refuse, naming what changed, or (``force``) move the
    manifest and its folders aside and start from none."""
    recorded = RecordedInputs()
    built = 0
    for seed, record in records.items():
        if record.error is None:
            recorded.add(record.provenance, f"seed {seed}")
            built += 1
    changed = recorded.changes(Path(run.grammar), recorded_options(run.options))
    if not changed:
        return records
    if not run.force:
        raise UsageError(
            f"{run.manifest} lists {built} house{'s' * (built != 1)} built from other inputs "
            f"than this batch's; changed: {'; '.join(changed)}. One dataset is one "
            f"configuration: resume with the inputs they were built from, choose another "
            f"--out, or pass --force to start a new manifest (the old one and its seed "
            f"folders are moved to {run.out}/superseded-<time>/)")
    _supersede(run, records)
    return {}


def _supersede(run: _Run, records: dict[int, BatchRecord]) -> Path:
    """Move the manifest and the seed folders it lists (those inside ``out``) into a
    new ``superseded-<UTC time>[-<shard>]/`` folder of ``out``: nothing is deleted."""
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    target = run.out / f"superseded-{stamp}{f'-{run.shard.tag}' if run.shard else ''}"
    target.mkdir()
    for seed, record in records.items():
        folder = record.folder or seed_folder(seed)
        if "/" not in folder and (run.out / folder).is_dir():
            os.replace(run.out / folder, target / folder)
    os.replace(run.manifest, target / run.manifest.name)
    return target


def _run_locked(run: _Run, seeds: range,
                on_progress: Callable[[int, int], None] | None) -> BatchReport:
    _remove_staging(run)
    records = _check_inputs(run, read_manifest(run.out, run.shard))
    _rewrite_manifest(run.manifest, records)
    if run.shard is None:  # this batch's lines are in manifest.jsonl now: no merge replaces it
        (run.out / MERGED).unlink(missing_ok=True)
    built_before = {seed for seed, r in records.items() if r.error is None and seed in seeds}
    todo = (seed for seed in seeds if seed not in built_before)
    finished = len(built_before)
    if on_progress:
        on_progress(finished, len(seeds))
    start = time.perf_counter()
    built_now = 0
    replaced = False
    inputs = _inputs(run.grammar, run.options)
    work = functools.partial(_build_one, run.grammar, out_dir=str(run.out),
                             build_options=run.options)
    try:
        modules = _build_modules(run.options.get("physics", True),
                                run.options.get("formats", ()))
        for record in run.engine.run(todo, work, functools.partial(_failure, run.out, inputs),
                                     functools.partial(_warm_up, modules, str(run.out))):
            _append_record(run.manifest, record)
            replaced |= record.seed in records
            records[record.seed] = record
            built_now += record.error is None
            finished += 1
            if on_progress:
                on_progress(finished, len(seeds))
    finally:
        _remove_staging(run)  # seeds in flight when stopped; their workers are gone
        if replaced:  # one line per seed again (a rebuilt seed was appended after its failure)
            _rewrite_manifest(run.manifest, records)
    wall = time.perf_counter() - start
    in_range = tuple(records[seed] for seed in sorted(records) if seed in seeds)
    return BatchReport(records=in_range, wall_seconds=wall, built_now=built_now,
                       skipped=len(built_before), seeds=len(seeds))


_BUILD_MODULES = (
    "cga.pipeline", "cga.parser", "cga.rules", "cga.wings", "cga.appearance.dress",
    "cga.building", "cga.furniture_models", "cga.interrupts", "cga.output_record",
    "cga.meshing", "cga.meshing.solids", "cga.meshing.items", "cga.meshing.doors",
    "cga.meshing.stairs",
    "cga.operations.floorplan.assemble", "cga.operations.floorplan.bsp",
    "cga.operations.floorplan.circulation", "cga.operations.floorplan.layout",
    "cga.operations.floorplan.tiling", "cga.operations.floorplan.treemap",
    "cga.operations.roomtyping.assign", "cga.operations.roomtyping.backtrack",
    "cga.operations.roomtyping.room_graph", "cga.operations.roomtyping.targets",
    "cga.operations.furniture.solver", "cga.operations.stairs.access", "numpy.random",
)
"""What builds import besides their operations and exporters: the operations import
their internals on first use (so ``cga check`` stays light), which in a batch would be
the first build's cost in every worker. A module missing here is only imported later."""


def _build_modules(physics: bool, formats: Sequence[str]) -> list[str]:
    """The modules a batch's builds import: :data:`_BUILD_MODULES`, the grammar
    operations, the exporters of ``formats`` and, with ``physics``, the checks."""
    from .export import EXPORTERS
    from .registry import OperationRegistry

    modules = [*_BUILD_MODULES, *OperationRegistry().modules(),
               *(EXPORTERS.module(name) for name in formats if name in EXPORTERS)]
    if physics:
        modules += ["cga.checks.physics", "cga.checks.navigability", "cga.difficulty.exploration"]
    return [name for name in modules if name is not None]


def _warm_up(modules: Sequence[str], out_dir: str) -> None:
    """Import ``modules`` (:func:`_build_modules`) before a worker takes its first seed
    (a second or two that would otherwise count against the first build's time limit),
    and check that the worker sees the output folder (a Ray worker on another node may
    not); then set the garbage collector for building (:mod:`cga.collector`)."""
    import importlib

    from .collector import tune_for_building

    if not os.path.isdir(out_dir):
        raise UsageError(f"the output folder {out_dir} does not exist on {socket.gethostname()}")
    for name in modules:
        importlib.import_module(name)
    tune_for_building()
