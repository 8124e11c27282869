"""The physics check catches overlaps, floating and toppling items, and passes items at rest."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from cga.checks import check_physics, physics
from cga.scene import SceneNode
from items import item_info

pytestmark = pytest.mark.physics


@pytest.fixture
def room(kit, two_rooms):
    return two_rooms, kit.structure(two_rooms)


def _item(report, name):
    return next(i for i in report.items if i.name == name)


def test_item_at_rest_passes(kit, room):
    plan, nodes = room
    table = kit.box_item("table", (1.2, 0.75, 0.8), (2.0, 2.0))
    report = check_physics(kit.scene_of(plan), nodes + [table])
    result = _item(report, "table")
    assert report.passed, report.summary()
    assert result.penetration < 0.001
    assert result.displacement < 0.005
    assert result.rotation_deg < 0.5
    assert not result.fell_through and not result.tipped


def test_item_against_a_wall_face_passes(kit, room):
    plan, nodes = room
    # Room 0's wall at x = 0 occupies x in [0, 0.2]; the wardrobe's back touches x = 0.2.
    wardrobe = kit.box_item("wardrobe", (0.6, 2.0, 1.0), (0.5, 2.0))
    report = check_physics(kit.scene_of(plan), nodes + [wardrobe])
    assert report.passed, report.summary()
    assert _item(report, "wardrobe").penetration < 0.001


def test_item_intersecting_a_wall_is_detected(kit, room):
    plan, nodes = room
    # 0.15 m of the wardrobe's depth lies inside the wall solid x in [0, 0.2].
    wardrobe = kit.box_item("wardrobe", (0.6, 2.0, 1.0), (0.35, 2.0))
    report = check_physics(kit.scene_of(plan), nodes + [wardrobe])
    result = _item(report, "wardrobe")
    assert not report.passed
    assert result.penetration == pytest.approx(0.15, abs=0.005)
    assert result.penetrating is not None and result.penetrating.startswith("floor0/wall")
    assert any("overlaps" in p for p in result.problems)


def test_floating_item_is_detected(kit, room):
    plan, nodes = room
    chair = kit.box_item("chair", (0.5, 0.9, 0.5), (2.0, 2.0), lift=0.5)
    report = check_physics(kit.scene_of(plan), nodes + [chair])
    result = _item(report, "chair")
    assert not report.passed
    assert result.penetration == 0.0
    assert result.displacement == pytest.approx(0.5, abs=0.01)
    assert not result.fell_through
    assert any(p.startswith("moved") for p in result.problems)


def test_overlapping_items_both_report_the_other(kit, room):
    plan, nodes = room
    a = kit.box_item("a", (1.0, 0.8, 1.0), (2.0, 2.0))
    b = kit.box_item("b", (1.0, 0.8, 1.0), (2.9, 2.0))  # 0.1 m overlap along x
    report = check_physics(kit.scene_of(plan), nodes + [a, b])
    assert _item(report, "a").penetrating == b.path
    assert _item(report, "b").penetrating == a.path
    assert _item(report, "a").penetration == pytest.approx(0.1, abs=0.005)


def test_item_over_a_hole_falls(kit, room):
    plan, nodes = room
    lamp = kit.box_item("lamp", (0.3, 1.5, 0.3), (20.0, 20.0))  # beyond the slab
    report = check_physics(kit.scene_of(plan), nodes + [lamp])
    result = _item(report, "lamp")
    assert result.fell_through and not report.passed


def test_top_heavy_item_tips_over(kit, room):
    plan, nodes = room
    post = kit.box_mesh((0.1, 1.5, 0.1), (2.0, 0.2 + 0.75, 2.0))
    arm = kit.box_mesh((1.2, 0.1, 0.3), (2.6, 0.2 + 1.45, 2.0))
    node = SceneNode("floor0/room0/furniture/sign", "furniture",
                     trimesh.util.concatenate([post, arm]),
                     item=item_info("sign", density=500.0),
                     static=False, parts=(post, arm))
    report = check_physics(kit.scene_of(plan), nodes + [node])
    result = _item(report, "sign")
    assert result.tipped and result.rotation_deg > 30
    assert not report.passed


def test_static_furniture_is_not_simulated(kit, room):
    plan, nodes = room
    rug = kit.box_item("rug", (2.0, 0.02, 1.5), (2.0, 2.0), static=True)
    sofa = kit.box_item("sofa", (1.8, 0.8, 0.9), (2.0, 2.0))  # stands on (in) the rug
    report = check_physics(kit.scene_of(plan), nodes + [rug, sofa])
    assert [i.name for i in report.items] == ["sofa"]
    assert report.ignored == (rug.path,)
    assert report.passed, report.summary()


def test_thresholds_are_honoured(kit, room):
    plan, nodes = room
    chair = kit.box_item("chair", (0.5, 0.9, 0.5), (2.0, 2.0), lift=0.05)
    strict = check_physics(kit.scene_of(plan), nodes + [chair])
    lenient = check_physics(kit.scene_of(plan), nodes + [chair], move_tol=0.1)
    assert not strict.passed and lenient.passed


def test_settling_stops_early_once_everything_rests(kit, room):
    plan, nodes = room
    table = kit.box_item("table", (1.2, 0.75, 0.8), (2.0, 2.0))
    report = check_physics(kit.scene_of(plan), nodes + [table])
    assert report.simulated_seconds < report.settle_seconds


def test_storeys_settle_independently(kit, room):
    """A storey that has rested leaves the simulation: its items' results do not depend
    on another storey still moving, and the other storey is simulated to the end."""
    plan, nodes = room
    table = kit.box_item("table", (1.2, 0.75, 0.8), (2.0, 2.0))
    alone = check_physics(kit.scene_of(plan), nodes + [table])
    chair = kit.box_item("chair", (0.5, 0.9, 0.5), (6.0, 2.0), lift=0.5, floor=1)
    both = check_physics(kit.scene_of(plan), nodes + [table, chair])
    assert _item(both, "table") == _item(alone, "table")
    assert both.simulated_seconds > alone.simulated_seconds
    assert _item(both, "chair").displacement == pytest.approx(0.5, abs=0.01)


def test_report_is_json_ready(kit, room):
    plan, nodes = room
    chair = kit.box_item("chair", (0.5, 0.9, 0.5), (2.0, 2.0), lift=0.5)
    data = json.loads(json.dumps(check_physics(kit.scene_of(plan), nodes + [chair]).to_dict()))
    assert data["passed"] is False
    assert data["failed_count"] == 1
    assert data["items"][0]["path"] == chair.path
    assert data["thresholds"] == {"penetration_m": 0.005, "displacement_m": 0.01,
                                  "rotation_deg": 2.0}


def test_bad_threshold_is_rejected(kit, room):
    plan, nodes = room
    with pytest.raises(ValueError, match="settle_seconds"):
        check_physics(kit.scene_of(plan), nodes, settle_seconds=0)


def test_concave_user_model_is_decomposed(kit, room, tmp_path):
    plan, nodes = room
    # An L-shaped desk as one concave mesh whose model is flagged as not convex-part.
    top = kit.box_mesh((1.6, 0.75, 0.6), (2.0, 0.2 + 0.375, 1.5))
    wing = kit.box_mesh((0.6, 0.75, 1.0), (2.5, 0.2 + 0.375, 2.3))
    desk = trimesh.boolean.union([top, wing], engine="manifold")
    assert not desk.is_convex
    node = SceneNode("floor0/room0/furniture/desk", "furniture", desk,
                     item=item_info("desk", mass=40.0, convex_parts=False),
                     static=False, parts=(desk,))
    report = check_physics(kit.scene_of(plan), nodes + [node], cache_dir=tmp_path)
    assert report.passed, report.summary()
    assert len(list(tmp_path.glob("*.obj"))) == 1


def test_items_placed_side_by_side_stay_put(kit, room):
    plan, nodes = room
    # A kitchen run: three cabinets touching each other and the wall at x = 0.2.
    cabinets = [kit.box_item(f"cabinet{k}", (0.6, 0.9, 0.6), (0.5, 1.0 + 0.6 * k))
                for k in range(3)]
    report = check_physics(kit.scene_of(plan), nodes + cabinets)
    assert report.passed, report.summary()
    assert report.max_penetration < 0.001 and report.max_displacement < 0.002


def test_barely_unbalanced_item_is_caught(kit, room):
    plan, nodes = room
    # A small foot (x 1.9-2.1) carrying a post twice its weight centred at x = 2.18: the
    # centre of mass (x = 2.12) is 2 cm past the foot. It may tip too slowly to move much
    # while settling, but it stands on nothing under its centre of mass.
    foot = kit.box_mesh((0.2, 0.05, 0.2), (2.0, 0.2 + 0.025, 2.0))
    top = kit.box_mesh((0.1, 0.4, 0.1), (2.18, 0.2 + 0.25, 2.0))
    node = SceneNode("floor0/room0/furniture/stand", "furniture",
                     trimesh.util.concatenate([foot, top]),
                     item=item_info("stand"),
                     static=False, parts=(foot, top))
    report = check_physics(kit.scene_of(plan), nodes + [node])
    result = _item(report, "stand")
    assert not result.stable or result.tipped
    assert not report.passed


def test_same_scene_gives_the_same_report(kit, room):
    plan, nodes = room
    items = [kit.box_item("chair", (0.5, 0.9, 0.5), (2.0, 2.0), lift=0.3),
             kit.box_item("table", (1.2, 0.75, 0.8), (3.0, 3.0))]
    first = check_physics(kit.scene_of(plan), nodes + items).to_dict()
    second = check_physics(kit.scene_of(plan), nodes + items).to_dict()
    assert json.dumps(first, sort_keys=True) == json.dumps(second, sort_keys=True)


def test_wardrobe_on_a_finely_cut_slab_against_a_wall_rests(kit):
    """Regression (house seed 71): a slab triangulated as make_floor leaves it (T-junction
    vertices on its outline, long thin triangles) and a wardrobe flush against a wall.
    Loaded as one triangle mesh, the slab's contacts under the wardrobe pushed sideways
    and it walked 2 cm off the wall; the structure is now cut into convex pieces."""
    outline = [(0.0, 0.0), (4.59, 0.0), (7.7, 0.0), (14.0, 0.0), (14.0, 5.16), (14.0, 10.0),
               (7.7, 10.0), (0.0, 10.0), (0.0, 6.29)]
    vertices = [(x, 0.0, z) for x, z in outline] + [(x, 0.2, z) for x, z in outline]
    faces = [[8, 0, 1], [2, 3, 4], [4, 5, 6], [2, 4, 6], [6, 7, 8], [1, 2, 6], [1, 6, 8],
             [10, 9, 17], [13, 12, 11], [15, 14, 13], [15, 13, 11], [17, 16, 15],
             [15, 11, 10], [17, 15, 10]]
    faces += [f for k in range(9) for f in ([k, 9 + k, 9 + (k + 1) % 9],
                                            [k, 9 + (k + 1) % 9, (k + 1) % 9])]
    slab = trimesh.Trimesh(vertices, faces, process=False)
    wall = kit.box_mesh((0.2, 2.8, 5.99), (4.59, 1.6, 3.195))
    z = 0.92
    boxes = [((3.93, 0.2, z + 0.02), (4.47, 0.28, z + 0.98)),
             ((3.91, 0.28, z), (4.49, 2.2, z + 1.0)),
             ((3.89, 0.3, z + 0.505), (3.91, 2.18, z + 0.995)),
             ((3.89, 0.3, z + 0.005), (3.91, 2.18, z + 0.495))]
    parts = tuple(kit.box_mesh(np.subtract(hi, lo), np.add(lo, hi) / 2) for lo, hi in boxes)
    wardrobe = SceneNode("floor0/room2/furniture/wardrobe", "furniture",
                         trimesh.util.concatenate(parts),
                         item=item_info("wardrobe", room=2, mass=89.4), static=False,
                         parts=parts)
    nodes = [SceneNode("floor0/slab", "slab", slab), SceneNode("floor0/wall15", "wall", wall),
             wardrobe]
    report = check_physics(kit.scene_of(), nodes)
    assert report.passed, report.summary()
    assert report.items[0].displacement < 0.002


def _connected_clients() -> list[int]:
    from cga.checks._bullet import pybullet

    pb = pybullet()
    return [k for k in range(32) if pb.isConnected(physicsClientId=k)]


def test_server_is_closed_after_a_check_and_after_a_failure(kit, room, monkeypatch):
    plan, nodes = room
    table = kit.box_item("table", (1, 0.7, 1), (2, 2))
    before = _connected_clients()
    check_physics(kit.scene_of(plan), nodes + [table])
    assert _connected_clients() == before

    def broken(*_args):
        raise RuntimeError("simulation failed")

    monkeypatch.setattr(physics._World, "settle", broken)
    with pytest.raises(RuntimeError, match="simulation failed"):
        check_physics(kit.scene_of(plan), nodes + [table])
    assert _connected_clients() == before


def test_item_without_geometry_is_rejected(kit, room):
    plan, nodes = room
    empty = SceneNode("floor0/room0/furniture/ghost", "furniture", trimesh.Trimesh(),
                      item=item_info("ghost"), static=False)
    with pytest.raises(ValueError, match="ghost has no geometry"):
        check_physics(kit.scene_of(plan), nodes + [empty])
