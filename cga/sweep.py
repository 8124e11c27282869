"""``cga batch --sweep difficulty=0:10``: one batch per value of a grammar variable.

Each value ``v`` is built as an ordinary batch (:func:`cga.batch.run_batch`, with the
variable overridden to ``v``, :mod:`cga.overrides`) into ``<out>/<name>=<v>/``, so every
value keeps its own manifest and resumes on its own. The sweep report gives, per value,
the batch report and the mean of every difficulty metric over its built seeds
(:func:`cga.difficulty.mean_metrics`); it is written to ``<out>/sweep.json``.
"""

from __future__ import annotations

import contextlib
import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .batch import BatchReport, run_batch
from .difficulty.metrics import METRICS, mean_metrics
from .errors import UsageError
from .fsutil import atomic_write

__all__ = ["SWEEP_REPORT", "SweepReport", "run_sweep", "value_text"]

SWEEP_REPORT = "sweep.json"


def value_text(value: float) -> str:
    """A sweep value as the override text and folder name: ``3``, ``2.5``."""
    return str(int(value)) if float(value).is_integer() else f"{value:g}"


@dataclass(frozen=True)
class SweepReport:
    """One batch report per swept value."""

    name: str
    values: tuple[float, ...]
    batches: tuple[BatchReport, ...]

    def means(self) -> list[dict[str, Any]]:
        """Per value: the value, built and valid counts and every metric's mean."""
        rows = []
        for value, report in zip(self.values, self.batches):
            rows.append({"value": value, "houses": report.count,
                         "failed": len(report.failed),
                         "validity_rate": round(report.validity_rate, 4),
                         **mean_metrics(r.difficulty for r in report.built if r.difficulty)})
        return rows

    def to_dict(self) -> dict[str, Any]:
        return {"variable": self.name, "metrics": list(METRICS), "values": self.means(),
                "batches": {value_text(v): b.to_dict() for v, b in zip(self.values, self.batches)}}


def run_sweep(grammar: str | Path, *, name: str, values: Sequence[float], count: int,
              out_dir: str | Path, build_options: dict[str, Any] | None = None,
              on_value: Callable[[float], None] | None = None,
              **batch_options: Any) -> SweepReport:
    """Run one batch of ``count`` seeds per value of variable ``name``.

    Parameters
    ----------
    grammar, count, out_dir:
        As :func:`cga.batch.run_batch`; value ``v`` goes to ``out_dir/<name>=<v>``.
    values:
        The values the variable takes.
    build_options:
        Build keywords; their ``overrides`` may set other variables, not ``name``.
    on_value:
        Called with each value before its batch starts.
    **batch_options:
        Passed to :func:`cga.batch.run_batch` (``jobs``, ``seed_start``, ``time_limit``,
        ``on_progress``, ``engine``, ...); with ``engine="ray"`` every value's batch runs
        on one cluster.

    Raises
    ------
    UsageError
        ``name`` is also given with ``--set``, or no values; whatever
        :func:`cga.batch.run_batch` raises.
    """
    options = dict(build_options or {})
    overrides = dict(options.pop("overrides", None) or {})
    if name in overrides:
        raise UsageError(f"--sweep {name} and --set {name} both set {name!r}")
    if not values:
        raise UsageError("--sweep needs at least one value")
    out = Path(out_dir)
    reports = []
    cluster: contextlib.AbstractContextManager[None] = contextlib.nullcontext()
    if batch_options.get("engine") == "ray":  # one cluster for every value
        from .batch_ray import ray_cluster

        cluster = ray_cluster(batch_options.get("address"), batch_options.get("jobs"))
    with cluster:
        for value in values:
            if on_value:
                on_value(value)
            text = value_text(value)
            reports.append(run_batch(grammar, count=count, out_dir=out / f"{name}={text}",
                                     build_options={**options,
                                                    "overrides": {**overrides, name: text}},
                                     **batch_options))
    report = SweepReport(name, tuple(values), tuple(reports))
    atomic_write(out / SWEEP_REPORT, json.dumps(report.to_dict(), indent=2, sort_keys=True) + "\n")
    return report
