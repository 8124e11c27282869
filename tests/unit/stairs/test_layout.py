"""The stair between two storeys, laid out in the core, and its solids."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from shapely.geometry import box

from cga.errors import DerivationError
from cga.model import FloorSettings
from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.operations.stairs import StairParams, place_core, stair_between
from cga.meshing.stairs import rail_footprint, stair_mesh, stair_nodes


def _floors(kind: str, storey: float = 3.0):
    footprint = box(0, 0, 14, 10)
    core = place_core(footprint, storey, 2, StairParams(kind=kind), wall=0.2, door_width=0.9,
                      min_width=2.4, rng=np.random.default_rng(1))
    x0, z0, x1, z1 = core.polygon.bounds
    # a floor whose only room besides the core is the rest of the footprint: tile it by hand
    rects = [(x0, z0, x1, z1)]
    rest = footprint.difference(core.polygon)
    for piece in [box(*b) for b in _tiles(footprint.bounds, core.polygon.bounds)]:
        if piece.intersection(rest).area > 1e-9:
            rects.append(piece.bounds)
    plans = []
    for index in (0, 1):
        plan = plan_from_rectangles(rects, settings=FloorSettings(), index=index,
                                    elevation=index * storey, height=storey)
        plans.append(plan.with_changes(core=core, core_room=0))
    return core, plans


def _tiles(outer, inner):
    """Rectangles tiling ``outer`` minus ``inner`` (a 3 x 3 grid on inner's edges)."""
    xs = sorted({outer[0], inner[0], inner[2], outer[2]})
    zs = sorted({outer[1], inner[1], inner[3], outer[3]})
    out = []
    for a, b in zip(xs, xs[1:]):
        for c, d in zip(zs, zs[1:]):
            if b - a > 1e-9 and d - c > 1e-9 and not (a >= inner[0] - 1e-9 and b <= inner[2] + 1e-9
                                                     and c >= inner[1] - 1e-9 and d <= inner[3] + 1e-9):
                out.append((a, c, b, d))
    return out


def _heights_at(mesh: trimesh.Trimesh, x: float, z: float) -> list[float]:
    """Heights where the vertical line through plan point (x, z) crosses the mesh's
    triangles (barycentric coordinates in plan)."""
    tri = np.asarray(mesh.triangles)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    v0, v1 = (b - a)[:, [0, 2]], (c - a)[:, [0, 2]]
    p = np.array([x, z]) - a[:, [0, 2]]
    det = v0[:, 0] * v1[:, 1] - v0[:, 1] * v1[:, 0]
    ok = np.abs(det) > 1e-12
    u = np.where(ok, (p[:, 0] * v1[:, 1] - p[:, 1] * v1[:, 0]) / np.where(ok, det, 1), -1)
    v = np.where(ok, (v0[:, 0] * p[:, 1] - v0[:, 1] * p[:, 0]) / np.where(ok, det, 1), -1)
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1)
    return list(a[hit, 1] + u[hit] * (b - a)[hit, 1] + v[hit] * (c - a)[hit, 1])


@pytest.mark.parametrize("kind", ["U", "straight"])
def test_the_stair_climbs_exactly_one_storey_in_equal_steps(kind):
    core, (lower, upper) = _floors(kind)
    stair = stair_between(core, lower, upper, 0)
    assert stair.floors == (0, 1) and stair.rooms == (0, 0)
    assert stair.risers * stair.rise == pytest.approx(upper.floor_y - lower.floor_y)
    heights = [y for f in stair.flights for _, y in f.treads()] + [f.top_y for f in stair.flights]
    steps = np.diff(sorted(set(np.round([lower.floor_y] + heights, 9))))
    assert np.allclose(steps, stair.rise)
    assert stair.flights[-1].top_y == pytest.approx(upper.floor_y)
    # the stair and the landings lie inside the core, the landings outside the stairwell
    inside = core.polygon.buffer(1e-9)
    assert inside.covers(stair.polygon) and all(inside.covers(p) for p in stair.landings)
    assert all(stair.polygon.intersection(p).area < 1e-9 for p in stair.landings)
    for flight in stair.flights:
        assert stair.polygon.buffer(1e-9).covers(flight.polygon())


def test_storeys_of_other_heights_cannot_share_a_core():
    core, (lower, upper) = _floors("U")
    with pytest.raises(DerivationError, match="equally high"):
        stair_between(core, lower, upper.with_changes(elevation=3.5), 0)


@pytest.mark.parametrize("kind", ["U", "straight"])
def test_the_stair_solid_is_watertight_and_its_treads_are_where_the_model_says(kind):
    core, (lower, upper) = _floors(kind)
    stair = stair_between(core, lower, upper, 0)
    mesh = stair_mesh(stair)
    assert mesh.is_watertight and mesh.is_volume and mesh.volume > 0
    assert mesh.bounds[0][1] == pytest.approx(lower.floor_y)
    assert mesh.bounds[1][1] == pytest.approx(upper.floor_y)
    # a ray dropped on every tread's centre hits the solid at that tread's height
    for flight in stair.flights:
        for tread, top in flight.treads():
            assert max(_heights_at(mesh, *tread.centroid.coords[0])) == pytest.approx(top, abs=1e-6)


def test_the_upper_floor_has_a_stairwell_a_rail_and_the_lower_one_the_stair():
    core, (lower, upper) = _floors("U")
    stair = stair_between(core, lower, upper, 0)
    lower = lower.with_changes(stairs=(stair,))
    upper = upper.with_changes(stairs=(stair,), is_top=True)
    assert upper.stairwell is stair.polygon and lower.stairwell is None
    assert [n.kind for n in stair_nodes(lower)] == ["stair"]
    [rail] = stair_nodes(upper)
    assert rail.kind == "rail" and rail.mesh.is_watertight
    assert rail.mesh.bounds[1][1] - rail.mesh.bounds[0][1] == pytest.approx(1.0)
    strip = rail_footprint(stair, upper)
    # on the top floor the rail guards the edge beside the arriving flight, not the flight
    assert strip.intersection(stair.flights[-1].polygon()).area < 1e-9
    assert strip.distance(stair.polygon) < 1e-6
