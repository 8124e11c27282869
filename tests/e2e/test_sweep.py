"""cga batch --sweep: one batch per value, the difficulty means per value in sweep.json and
on the terminal; the measured difficulty in every manifest line and scene JSON."""

from __future__ import annotations

import json
from pathlib import Path

from cga.batch import MANIFEST
from cga.cli import main
from cga.difficulty import METRICS

USAR = Path(__file__).resolve().parents[2] / "demos" / "usar_maze.grammar"


def test_sweep_reports_metric_means_per_value(tmp_path, capsys):
    out = tmp_path / "sweep"
    status = main(["batch", str(USAR), "-n", "1", "--sweep", "difficulty=0:10:10",
                   "--out", str(out), "--json"])
    assert status == 0
    data = json.loads(capsys.readouterr().out)
    assert data["variable"] == "difficulty" and data["metrics"] == list(METRICS)
    assert [row["value"] for row in data["values"]] == [0, 10]
    assert json.loads((out / "sweep.json").read_text())["values"] == data["values"]
    for value in ("0", "10"):
        line = json.loads((out / f"difficulty={value}" / MANIFEST).read_text().splitlines()[0])
        assert set(line["difficulty"]) == set(METRICS)
        assert line["difficulty"]["exploration_path_m"] > 0
        scene = json.loads(next((out / f"difficulty={value}").glob("seed_*/*.scene.json")).read_text())
        assert scene["difficulty"]["totals"] == line["difficulty"]
    low, high = data["values"]
    # d = 10 never prevents cycles and opens every doorway; d = 0 opens 3 in 8
    assert high["doors_per_room"] > low["doors_per_room"]
    for row in data["values"]:
        assert row["houses"] == 1 and all(row[m] is not None for m in METRICS)


def test_sweep_and_set_of_the_same_variable_is_refused(tmp_path, capsys):
    status = main(["batch", str(USAR), "-n", "1", "--sweep", "difficulty=0:1",
                   "--set", "difficulty=3", "--out", str(tmp_path), "--quiet"])
    assert status == 2 and "both set 'difficulty'" in capsys.readouterr().err
