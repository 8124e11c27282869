"""Where a batch's builds run: an engine turns seeds into results as builds finish.

:func:`cga.batch.run_batch` owns the manifest, the lock and the report; an engine only
runs builds. Two engines implement :class:`Engine`:

* :class:`LocalEngine` (the default): this process (one job, no time limit) or the
  worker processes of :mod:`cga.batch_pool`;
* :class:`cga.batch_ray.RayEngine` (``--engine ray``, the optional extra ``cga[ray]``):
  tasks on a Ray cluster, a running one or a local one started for the batch.

Both yield one result per seed in the order builds finish, pull seeds from the iterator
only as workers become free (``-n 1e12`` starts at once), report a build that could not
finish (killed, over its time limit, its worker lost) through ``failed`` and leave no
build running when they return or raise, so the caller can remove unfinished staging
folders.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, Protocol

from .errors import UsageError

__all__ = ["ENGINES", "Engine", "LocalEngine", "make_engine", "max_jobs"]

ENGINES = ("local", "ray")

Build = Callable[[int], Any]
"""Builds one seed (in a worker) and returns a picklable result."""

Failed = Callable[[int, str, float], Any]
"""Makes the result of a seed whose build could not finish: (seed, reason, seconds)."""


def max_jobs() -> int:
    """The most worker processes a local batch may start: four per core. More only
    adds memory and switching; a typo such as ``--jobs 2000`` used to start them all."""
    return 4 * (os.cpu_count() or 1)


class Engine(Protocol):
    """Runs builds; see the module notes for what every engine guarantees."""

    def run(self, seeds: Iterator[int], build: Build, failed: Failed,
            warm_up: Callable[[], None] | None = None) -> Iterator[Any]:
        """Yield ``build(seed)`` (or ``failed(seed, reason, seconds)``) per seed, in the
        order builds finish. ``warm_up`` runs in a worker before its first build where
        the engine controls its workers."""
        ...


def _check_jobs(jobs: int) -> None:
    if jobs < 1:
        raise UsageError(f"--jobs must be at least 1, got {jobs}")
    if jobs > max_jobs():
        raise UsageError(f"--jobs must be at most {max_jobs()} (4 per core on this machine's "
                         f"{os.cpu_count()} cores), got {jobs}")


@dataclass(frozen=True)
class LocalEngine:
    """Builds in this process (one job, no time limit) or in ``jobs`` worker processes
    (:func:`cga.batch_pool.run_pool`), which stop a build over ``time_limit`` seconds."""

    jobs: int = 1
    time_limit: float | None = None

    def __post_init__(self) -> None:
        _check_jobs(self.jobs)

    def run(self, seeds: Iterator[int], build: Build, failed: Failed,
            warm_up: Callable[[], None] | None = None) -> Iterator[Any]:
        if self.jobs == 1 and self.time_limit is None:
            yield from map(build, seeds)
            return
        from .batch_pool import run_pool

        yield from run_pool(seeds, build, failed, jobs=self.jobs, time_limit=self.time_limit,
                            warm_up=warm_up)


def make_engine(name: str, *, jobs: int | None = None, time_limit: float | None = None,
                address: str | None = None, retries: int | None = None) -> Engine:
    """The engine called ``name`` (:data:`ENGINES`) with the batch's options.

    Raises
    ------
    UsageError
        An unknown engine, an option the engine does not take (``--address`` or
        ``--retries`` without Ray), a bad job count.
    """
    if name == "local":
        for option, value in (("--address", address), ("--retries", retries)):
            if value is not None:
                raise UsageError(f"{option} needs --engine ray")
        return LocalEngine(jobs=1 if jobs is None else jobs, time_limit=time_limit)
    if name == "ray":
        from .batch_ray import DEFAULT_RETRIES, RayEngine

        if jobs is not None and address is None:
            _check_jobs(jobs)
        return RayEngine(address=address, jobs=jobs, time_limit=time_limit,
                         retries=DEFAULT_RETRIES if retries is None else retries)
    raise UsageError(f"unknown --engine {name!r}; expected one of {', '.join(ENGINES)}")
