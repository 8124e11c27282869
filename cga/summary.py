"""What ``cga build`` tells the user after a build (docs/outputs.md, "the terminal shows a short
summary").

:func:`summary_dict` condenses a Scene into plain data (``cga build --json`` prints it);
:func:`print_summary` renders the same data with rich: per floor a table of rooms (id,
type, area, doors, items), then diagnostics (items left out and why, repairs, warnings),
check results and the time per stage. Both read the Scene only.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal

from .pipeline import STAGES
from .model import FloorPlan
from .scene import Scene

__all__ = ["summary_dict", "print_summary"]


def _floor_summary(plan: FloorPlan) -> dict[str, Any]:
    rooms = []
    for room in plan.rooms:
        rooms.append({
            "id": room.id,
            "type": room.type,
            "area_m2": round(room.area, 2),
            "doors": sum(1 for d in plan.doors if room.id in d.rooms),
            "items": sum(1 for f in plan.furniture if f.room == room.id and not f.is_detail),
        })
    area = sum(r.area for r in plan.rooms)
    return {
        "index": plan.index,
        "area_m2": round(float(plan.footprint.area), 2),
        "circulation_share": round(sum(r.area for r in plan.rooms if r.circulation) / area, 4)
        if area else 0.0,
        "rooms": rooms,
        "doors": len(plan.doors),
        "windows": len(plan.windows),
        "items": sum(1 for f in plan.furniture if not f.is_detail),
    }


def summary_dict(scene: Scene, *, out_dir: str | Path | None = None) -> dict[str, Any]:
    """The build summary as JSON-ready data.

    Keys: ``name``, ``seed``, ``units``, ``floors`` (per floor: ``index``, ``area_m2``,
    ``circulation_share`` (halls and corridors over the rooms' area), ``rooms`` [``id``, ``type``, ``area_m2``, ``doors``, ``items``], ``doors``,
    ``windows``, ``items``), ``shapes`` (terminal masses and faces), ``diagnostics``
    (``level``, ``stage``, ``message``, ``floor``, ``room``), ``checks`` (per check:
    ``passed``, ``summary``), ``timings`` (seconds per stage and operation),
    ``difficulty`` (the measured difficulty, docs/difficulty.md; None without floors),
    ``materials`` (``neutral`` or ``random``) and ``lights`` (how many ceiling lights;
    docs/appearance.md), and ``out_dir`` when given.
    """
    data: dict[str, Any] = {
        "name": scene.name,
        "seed": scene.seed,
        "units": scene.units,
        "floors": [_floor_summary(plan) for plan in scene.floors],
        "shapes": len(scene.masses),
        "diagnostics": [{"level": d.level, "stage": d.stage, "message": d.message,
                         "floor": d.floor, "room": d.room} for d in scene.all_diagnostics()],
        "checks": {name: {"passed": report.passed, "summary": report.summary()}
                   for name, report in scene.checks.items()},
        "timings": {name: round(seconds, 4) for name, seconds in scene.timings.items()},
        "difficulty": scene.difficulty.to_dict() if scene.difficulty is not None else None,
        "materials": scene.looks().mode,
        "lights": len(scene.lights),
    }
    if out_dir is not None:
        data["out_dir"] = str(out_dir)
    return data


def _timing_line(timings: Mapping[str, float]) -> str:
    operations = {k: v for k, v in timings.items() if k not in STAGES}
    parts = []
    for stage in STAGES:
        if stage not in timings:
            continue
        text = f"{stage} {timings[stage]:.2f} s"
        if stage == "derive" and operations:
            inner = ", ".join(f"{name} {seconds:.2f}" for name, seconds in
                              sorted(operations.items(), key=lambda kv: -kv[1]))
            text += f" ({inner})"
        parts.append(text)
    total = sum(timings.get(stage, 0.0) for stage in STAGES)
    return " · ".join(parts) + f" · total {total:.2f} s"


def print_summary(scene: Scene, *, out_dir: str | Path | None = None, console: Any = None) -> None:
    """Print the build summary (rich tables) to ``console`` (default: stdout)."""
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    console = console or Console()
    data = summary_dict(scene, out_dir=out_dir)
    console.print(f"[bold]{escape(data['name'])}[/bold]  seed {data['seed']}  "
                  f"({len(data['floors'])} floor{'s' * (len(data['floors']) != 1)}, "
                  f"{data['shapes']} other shape{'s' * (data['shapes'] != 1)}; "
                  f"{data['materials']} materials, {data['lights']} lights)")
    for floor in data["floors"]:
        console.print(f"[bold]floor {floor['index']}[/bold]: {floor['area_m2']:.1f} m², "
                      f"circulation {100 * floor['circulation_share']:.0f} %, "
                      f"{floor['doors']} doors, {floor['windows']} windows, "
                      f"{floor['items']} items", highlight=False)
        table = Table()
        columns: tuple[tuple[str, Literal["left", "right"]], ...] = (
            ("room", "right"), ("type", "left"), ("area m²", "right"), ("doors", "right"),
            ("items", "right"))
        for column, justify in columns:
            table.add_column(column, justify=justify)
        for room in floor["rooms"]:
            table.add_row(str(room["id"]), escape(room["type"] or "—"), f"{room['area_m2']:.1f}",
                          str(room["doors"]), str(room["items"]))
        console.print(table)
    styles = {"error": "red", "warning": "yellow", "info": "dim"}
    for diagnostic in scene.all_diagnostics():
        style = styles.get(diagnostic.level, "")
        console.print(f"[{style}]{diagnostic.level}[/{style}] {escape(str(diagnostic))}",
                      highlight=False)
    for name, check in data["checks"].items():
        mark = "[green]✓[/green]" if check["passed"] else "[red]✗[/red]"
        console.print(f"{mark} {escape(check['summary'] or name)}", highlight=False)
    if scene.difficulty is not None:
        console.print(escape(scene.difficulty.summary()), highlight=False)
    console.print(f"[dim]{_timing_line(scene.timings)}[/dim]", highlight=False)
    if out_dir is not None:
        console.print(f"written to {escape(str(out_dir))}", highlight=False)
