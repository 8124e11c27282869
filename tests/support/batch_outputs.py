"""Shared pieces of the batch tests: a one-room grammar that reads a table of its own, and
what two batches must agree on (manifest lines and output files, less what varies between
two builds of the same seed; docs/outputs.md, docs/batch.md)."""

from __future__ import annotations

import json
from pathlib import Path

from cga.batch import VOLATILE_FIELDS

__all__ = ["ONE_ROOM", "TYPES", "manifest_records", "output_tree"]

ONE_ROOM = ("units = 1;\nLot: rectangle(5, 4)\nRules:\n"
            "Lot --> extrude(3) Storey\n"
            "Storey --> make_floor(0, 0.2, 1>1.2>1.2, 0.9, 2.1) Floor\n"
            'Floor --> type_rooms("types.csv") Typed\n'
            'Typed --> add_furniture("furniture_house.csv") Furnished\n')
"""Reads a rule table of its own (``types.csv``: :data:`TYPES`), a shipped one and shipped
models."""
TYPES = ("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\n"
         "Livingroom;1;1;Livingroom;true;1;0\n")


def manifest_records(manifest: Path) -> list[dict]:
    """The manifest's lines, sorted by seed, without the fields that vary between runs."""
    lines = [json.loads(line) for line in manifest.read_text().splitlines()]
    for line in lines:
        for name in VOLATILE_FIELDS:
            line.pop(name)
    return sorted(lines, key=lambda line: line["seed"])


def output_tree(folder: Path) -> dict[str, object]:
    """Every file's bytes; a scene JSON's as data without ``timings``, the one part that
    changes between two builds of a seed."""
    files: dict[str, object] = {}
    for path in sorted(folder.rglob("*")):
        name = path.relative_to(folder).as_posix()
        if path.name.endswith(".scene.json"):
            scene = json.loads(path.read_bytes())
            scene.pop("timings")
            files[name] = scene
        elif path.is_file():
            files[name] = path.read_bytes()
    return files
