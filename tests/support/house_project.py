"""A user's project folder: the house demo with its own copies of its tables."""

from __future__ import annotations

import shutil
from pathlib import Path

from cga.resources import shipped_dir

__all__ = ["HOUSE_TABLES", "house_project"]

HOUSE_TABLES = ("house_types.csv", "house_upper_types.csv", "furniture_house.csv")
DEMOS = Path(__file__).resolve().parents[2] / "demos"


def house_project(parent: Path) -> Path:
    """``parent/project`` holding ``house.grammar`` and copies of :data:`HOUSE_TABLES`, so
    a test may edit them."""
    folder = parent / "project"
    folder.mkdir()
    shutil.copy(DEMOS / "house.grammar", folder / "house.grammar")
    rules = shipped_dir("cga.rules")
    for table in HOUSE_TABLES:
        shutil.copy(rules / table, folder / table)
    return folder
