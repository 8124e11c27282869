"""``cga batch --engine ray``: builds as tasks on a Ray cluster (https://docs.ray.io).

A batch on one machine is bounded by its cores; Ray spreads the same builds over a
cluster with no scheduler of our own (issue 18). The engine connects to a running
cluster (``--address``, or ``RAY_ADDRESS``; ``auto`` finds one started on this node
with ``ray start``) or starts a local one with ``--jobs`` CPUs, and stops it again when
the batch ends. A caller that has already called :func:`ray.init` keeps its connection.

* **A task per seed.** A build takes a tenth of a second or more; Ray's overhead per
  task is about a millisecond (measured: 1,000 empty tasks in 0.7 s on 2 cores), so
  chunks of seeds would save nothing and would delay the manifest and widen what a
  lost worker takes with it.
* **Streaming.** At most twice the cluster's CPUs of tasks are submitted at once (with
  ``--address``, ``--jobs`` sets the number instead); the next seed is submitted as a build finishes (:func:`ray.wait`), so the seed range is
  never listed (``-n 1e12`` starts at once) and each result reaches the manifest as
  soon as it exists.
* **Failures.** A build's own errors are results (the seed's failure record). A task
  whose worker dies (killed, out of memory, a lost node) or that raises is retried up
  to ``retries`` times by Ray (``max_retries``, ``retry_exceptions``); after that the
  seed is recorded as failed with Ray's error, never lost.
* **Time limit.** With ``time_limit`` only as many tasks as CPUs are in flight, so a
  task runs from the moment it is submitted; one over its time is cancelled with
  ``force=True`` (Ray kills its worker) and recorded as failed with the reason, and so
  is one whose result came in past its time before this process looked (its folder is
  replaced by the failure's). A busy shared cluster delays starts, and the delay counts.
* **Files.** Workers write the seed folders into ``--out`` themselves and this process
  writes the manifest, so ``--out`` must be the same path on every node (shared
  storage, docs/batch.md), and cga (``pip install "cga[ray]"``) must be installed in
  the cluster's Python environment. A probe task checks both before the first seed.
"""

from __future__ import annotations

import contextlib
import logging
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

from .batch_pool import over_time_limit
from .errors import UsageError

__all__ = ["DEFAULT_RETRIES", "RayEngine", "ray_cluster"]

DEFAULT_RETRIES = 2
"""Retries of a task whose worker died or that raised (``--retries``)."""

_POLL = 1.0
"""Longest wait for a result, in seconds, before this process handles signals."""

_INSTALL = 'the Ray engine needs Ray: pip install "cga[ray]"'


def _import_ray() -> Any:
    try:
        import ray
    except ImportError:
        raise UsageError(_INSTALL) from None
    return ray


@contextlib.contextmanager
def ray_cluster(address: str | None = None, jobs: int | None = None) -> Iterator[None]:
    """Connect to (or start) one cluster for several batches, a sweep's: the batches
    inside reuse it instead of starting a local cluster each (seconds every time)."""
    ray = _import_ray()
    started = RayEngine(address=address, jobs=jobs)._connect(ray)
    try:
        yield
    finally:
        if started:
            ray.shutdown()


def _call(build: Callable[[int], Any], seed: int) -> Any:
    """The task: one seed's build (``build`` comes from the object store, put once)."""
    return build(seed)


def _probe(warm_up: Callable[[], None] | None) -> None:
    """The first task: imports what builds need (cga itself must be installed on the
    cluster) and runs the batch's own checks of the worker's machine."""
    if warm_up is not None:
        warm_up()


def _first_line(error: BaseException) -> str:
    text = str(error).strip()
    return (text.splitlines() or [type(error).__name__])[-1 if "Traceback" in text else 0]


@dataclass(frozen=True)
class RayEngine:
    """Builds as Ray tasks (see the module notes).

    Parameters
    ----------
    address:
        A running cluster (``ray://host:10001``, ``host:6379``, ``auto``); None starts a
        local cluster unless this process is already connected to one.
    jobs:
        CPUs of the local cluster started (default: all of this machine's); with an
        address, the most builds in flight at once (default: the cluster's CPUs).
    time_limit:
        Seconds one build may take, from submission.
    retries:
        Times a task whose worker died or that raised is run again.
    """

    address: str | None = None
    jobs: int | None = None
    time_limit: float | None = None
    retries: int = DEFAULT_RETRIES

    def __post_init__(self) -> None:
        if self.retries < 0:
            raise UsageError(f"--retries must be a whole number ≥ 0, got {self.retries}")
        if self.jobs is not None and self.jobs < 1:
            raise UsageError(f"--jobs must be at least 1, got {self.jobs}")

    def _connect(self, ray: Any) -> bool:
        """Connect or start a cluster; True if this engine must shut it down."""
        if ray.is_initialized():
            return False
        # builds are quiet and report through their results; Ray's own notices would
        # break the progress bar
        options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False,
                                   "logging_level": logging.ERROR}
        if self.address is None:
            options["num_cpus"] = self.jobs
        try:
            ray.init(address=self.address, **options)
        except (ConnectionError, RuntimeError, ValueError) as error:
            where = f"the Ray cluster at {self.address}" if self.address else "a local Ray cluster"
            raise UsageError(f"cannot start or reach {where}: {_first_line(error)}") from None
        return True

    def _in_flight(self, ray: Any) -> int:
        if self.address is not None and self.jobs is not None:
            return self.jobs  # the user's share of a shared cluster
        cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
        return cpus if self.time_limit is not None else 2 * cpus

    def _over_time(self, seconds: float) -> str:
        return over_time_limit(seconds, self.time_limit)

    def _reason(self, error: BaseException, over_time: bool, seconds: float) -> str:
        """Why a seed failed whose task raised (after its retries) or was cancelled."""
        if over_time:
            return self._over_time(seconds)
        return (f"the build's Ray task failed {self.retries + 1} "
                f"time{'s' * (self.retries > 0)}: {_first_line(error)}")

    def run(self, seeds: Iterator[int], build: Callable[[int], Any],
            failed: Callable[[int, str, float], Any],
            warm_up: Callable[[], None] | None = None) -> Iterator[Any]:
        ray = _import_ray()
        started = self._connect(ray)
        pending: dict[Any, tuple[int, float]] = {}
        try:
            try:
                ray.get(ray.remote(_probe).options(max_retries=self.retries).remote(warm_up))
            except ray.exceptions.RayError as error:
                raise UsageError(f"the Ray cluster cannot build: {_first_line(error)} (is cga "
                                 f"installed on every node, and --out on shared storage?)"
                                 ) from None
            task = ray.remote(_call).options(max_retries=self.retries, retry_exceptions=True)
            shared = ray.put(build)
            limit = self._in_flight(ray)
            cancelled: set[Any] = set()
            exhausted = False
            while True:
                while not exhausted and len(pending) < limit:
                    seed = next(seeds, None)
                    if seed is None:
                        exhausted = True
                        break
                    pending[task.remote(shared, seed)] = (seed, time.monotonic())
                if not pending:
                    return
                timeout = _POLL  # wake up now and then: Ctrl-C and SIGTERM are handled here
                running = [t for ref, (_, t) in pending.items() if ref not in cancelled]
                if self.time_limit is not None and running:
                    timeout = min(timeout, max(0.0, min(running) + self.time_limit -
                                               time.monotonic()))
                done, _ = ray.wait(list(pending), num_returns=1, timeout=timeout)
                if done:  # every finished build at once: a wait costs O(builds in flight)
                    done, _ = ray.wait(list(pending), num_returns=len(pending), timeout=0)
                now = time.monotonic()
                if not done:  # a build over its time limit: Ray kills its worker
                    for ref, (_, submitted) in pending.items():
                        if self.time_limit is None or ref in cancelled:
                            continue
                        if now - submitted >= self.time_limit:
                            ray.cancel(ref, force=True)
                            cancelled.add(ref)
                    continue
                for ref in done:
                    seed, submitted = pending.pop(ref)
                    seconds = now - submitted
                    try:
                        result = ray.get(ref)
                    except ray.exceptions.RayError as error:
                        result = failed(seed, self._reason(error, ref in cancelled, seconds),
                                        seconds)
                    else:  # in after its time, before this process looked: over it all the same
                        if self.time_limit is not None and seconds >= self.time_limit:
                            result = failed(seed, self._over_time(seconds), seconds)
                    cancelled.discard(ref)
                    yield result
        finally:
            for ref in pending:  # stopped early: no build may outlive the batch
                ray.cancel(ref, force=True)
            if pending:
                ray.wait(list(pending), num_returns=len(pending), timeout=30)
            if started:
                ray.shutdown()
