"""The layout-quality report (cga.quality) on hand-made floors with known answers."""

import dataclasses

from cga.authoring import floor_from_rectangles, type_floor
from cga.quality import floor_quality

HEADER = ("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom;"
          "maxSize;enteredFrom;passThrough;needsWindow;circulation")


def typed(tmp_path, rows, rectangles, circulation=(0,)):
    path = tmp_path / "t.csv"
    path.write_text("\n".join([HEADER, *rows]) + "\n")
    return type_floor(floor_from_rectangles(rectangles, circulation=circulation), path, seed=0)


def test_en_suite_bathroom_is_reported_behind_its_bedroom(tmp_path):
    plan = typed(tmp_path, ["Hall;2;1;Bedroom;true;1;0;;;true;false;true",
                            "Bedroom;9;1;Hall;0;2;0;18;Hall;false;true;false",
                            "Bathroom;3;0;Bedroom;0;1;0;9;Bedroom;false;false;false"],
                 [(0, 0, 10, 1.6), (0, 1.6, 5, 5), (5, 1.6, 10, 5), (0, 5, 3, 8)])
    report = floor_quality(plan)
    assert report["circulation_share"] == round(16 / (16 + 17 + 17 + 9), 4)
    assert report["pass_through_private"] == [{"room": 1, "behind": [3]}]
    assert report["reached_only_through_private"] == [3]
    assert report["doors_per_room"] == {"0": 3, "1": 2, "2": 1, "3": 1}
    assert report["area_out_of_range"] == [] and report["ruleless"] == []


def test_areas_out_of_range_and_rooms_without_rule(tmp_path):
    plan = typed(tmp_path, ["Hall;2;1;Office;true;1;0;;;true;false;true",
                            "Office;9;1;Hall;0;1;0;;Hall;false;true;false"],
                 [(0, 0, 10, 1.6), (0, 1.6, 5, 5), (5, 1.6, 10, 5)])
    (office,) = [r for r in plan.rooms if r.type == "Office"]
    (other,) = [r for r in plan.rooms if r.type == "Commonroom"]  # no rule left for it
    assert office.area_range == (9, None) and other.area_range is None
    capped = plan.with_changes(rooms=tuple(
        dataclasses.replace(r, area_range=(9, 12)) if r is office else r for r in plan.rooms))
    report = floor_quality(capped)
    assert report["area_out_of_range"] == [
        {"room": office.id, "type": "Office", "area": 17.0, "range": [9, 12]}]
    assert report["ruleless"] == [other.id]
