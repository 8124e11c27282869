"""The sweep report: metric means per value over the built seeds, and its table."""

from __future__ import annotations

import pytest

from cga.batch import BatchRecord, BatchReport
from cga.cli import _print_sweep
from cga.difficulty import METRICS
from cga.sweep import SweepReport, value_text


def _record(seed: int, **metrics) -> BatchRecord:
    values = {name: None for name in METRICS}
    values.update(metrics)
    return BatchRecord(seed=seed, valid=True, seconds=1.0, difficulty=values)


def test_means_per_value_leave_out_failed_seeds_and_missing_values():
    low = BatchReport((_record(0, cycle_rank=1, tortuosity=1.5), _record(1, cycle_rank=3),
                       BatchRecord(seed=2, valid=False, seconds=0.1, error="boom")),
                      wall_seconds=1.0, built_now=2, seeds=3)
    high = BatchReport((_record(0, cycle_rank=10),), wall_seconds=1.0, built_now=1, seeds=1)
    report = SweepReport("difficulty", (0.0, 2.5), (low, high))
    rows = report.means()
    assert rows[0]["value"] == 0.0 and rows[0]["houses"] == 2 and rows[0]["failed"] == 1
    assert rows[0]["cycle_rank"] == 2 and rows[0]["tortuosity"] == 1.5
    assert rows[0]["exploration_path_m"] is None
    assert rows[1]["cycle_rank"] == 10
    assert set(report.to_dict()["batches"]) == {"0", "2.5"}


def test_table_lists_every_value_and_metric(capsys, tmp_path):
    report = SweepReport("difficulty", (1.0,), (BatchReport((_record(0, cycle_rank=4),),
                                                            wall_seconds=1.0, built_now=1, seeds=1),))
    _print_sweep(report.to_dict(), tmp_path / "sweep.json")
    out = capsys.readouterr().out
    assert "difficulty" in out and "cycle rank" in out and "sweep.json" in out


@pytest.mark.parametrize("value, text", [(3.0, "3"), (2.5, "2.5"), (0.0, "0")])
def test_value_text(value, text):
    assert value_text(value) == text
