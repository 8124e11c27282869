"""Hand-made furniture facts for scene nodes built in tests."""

from __future__ import annotations

from pathlib import Path

from cga.scene import ItemInfo


def item_info(name: str = "item", *, model: str | None = None, room: int = 0,
              mass: float = 0.0, density: float = 500.0, rotation: int = 0,
              convex_parts: bool = True, parent: str | None = None) -> ItemInfo:
    """An :class:`ItemInfo` for a test node (``mass`` 0: the check derives it from the
    density and the mesh volume)."""
    model = model or name
    return ItemInfo(model=model, model_path=Path(f"{model}.obj"), room=room, name=name,
                    parent=parent, rotation=rotation, density=density, mass=mass,
                    convex_parts=convex_parts)
