"""Hostile and odd inputs from the adversarial pass of issue 19 (defects 4, 5 and 7).

Each case is a regression test: it used to end in a traceback (exit 1), a wrong place, an
accepted bad input or unbounded time and memory. Now every one is read correctly or
refused with a positioned, short message and exit status 2. Cases that used to run away
run in a forked child with a 30 s and 2 GB limit (``tests/support/forked.py``).
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

from house_project import house_project

from cga.cli import main
from cga.resources import shipped_dir
from forked import run_forked

MODELS = shipped_dir("cga.furniture_models")


@pytest.fixture
def project(tmp_path):
    """The house demo with its own copies of both tables, in a folder of its own."""
    return house_project(tmp_path)


def cli(*argv: str) -> tuple[int, str]:
    """Exit status and stderr of ``cga *argv`` (run in this process)."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main([str(a) for a in argv])
        except SystemExit as exit_:  # argparse
            status = int(exit_.code or 0)
    return status, err.getvalue()


def cli_forked(*argv: str) -> tuple[int, str]:
    """:func:`cli` in a forked child with 30 s and 2 GB; a hang or a crash fails."""
    status, value = run_forked(cli, *argv, time_limit=30.0)
    assert status == "ok", f"cga {' '.join(map(str, argv))}: {status}\n{value}"
    return value


def refused(status: int, err: str, *fragments: str) -> None:
    assert status == 2, err
    assert "Traceback" not in err
    assert len(err) < 4000, f"{len(err)} characters of error"
    for fragment in fragments:
        assert fragment in err, err


def _replace(path: Path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8")
    assert old in text
    path.write_text(text.replace(old, new), encoding="utf-8")


# -- defect 4: tracebacks ------------------------------------------------------------

@pytest.mark.parametrize("command", ["check", "build"])
def test_table_name_longer_than_a_file_name_may_be(project, command):
    _replace(project / "house.grammar", '"house_types.csv"', f'"{"t" * 300}.csv"')
    extra = ["--no-physics", "--out", project / "out"] if command == "build" else []
    refused(*cli(command, project / "house.grammar", *extra), "rule table not found")


def test_csv_cell_longer_than_the_csv_field_limit(project):
    table = project / "furniture_house.csv"
    table.write_text(table.read_text() + 'Livingroom;"' + "x" * 140_000 + '";false\n')
    refused(*cli("check", project / "house.grammar"), "furniture_house.csv, row")


def test_obj_that_is_not_utf8(project):
    (project / "sofa.obj").write_bytes(b"# a sofa\nv 0 0 0\xff\xfe\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    refused(*cli("check", project / "house.grammar"), "sofa.obj", "not UTF-8")


def _lot_cli(project: Path, document: str, *extra: str) -> tuple[int, str]:
    lot = project / "lot.geojson"
    lot.write_text(document, encoding="utf-8")
    return cli_forked("build", project / "house.grammar", "--lot", lot, "--no-physics",
                      "--out", project / "out", *extra)


def test_geojson_nested_100k_deep(project):
    refused(*_lot_cli(project, "[" * 100_000 + "]" * 100_000), "lot.geojson")


def test_geojson_with_a_5001_digit_integer(project):
    refused(*_lot_cli(project, '{"type": "Polygon", "coordinates": [[[' + "9" * 5001 +
                      ', 0], [1, 0], [1, 1], [0, 0]]]}'), "lot.geojson")


def test_geojson_features_not_a_list(project):
    refused(*_lot_cli(project, '{"type": "FeatureCollection", "features": 5}'),
            "lot.geojson", "'features'")


@pytest.mark.parametrize("radius", ["1e6", "nan", "-1"])
def test_robot_radius_out_of_range(project, radius):
    refused(*cli("build", project / "house.grammar", "--robot-radius", radius),
            "--robot-radius")


def _uncapped(project: Path) -> None:
    """Empty the house tables' maxSize column: rooms of a huge lot can then be typed."""
    for name in ("house_types.csv", "house_upper_types.csv"):
        lines = (project / name).read_text().splitlines()
        header = next(n for n, line in enumerate(lines) if not line.startswith("#"))
        column = lines[header].split(";").index("maxSize")
        rows = [";".join("" if i == column and n > header else c
                         for i, c in enumerate(line.split(";")))
                for n, line in enumerate(lines)]
        (project / name).write_text("\n".join(rows) + "\n")


def test_lot_of_99999_metres_builds_within_limits(project):
    _uncapped(project)
    status, err = cli_forked("build", project / "house.grammar", "--lot", "99999x40",
                             "--out", project / "out", "--export", "map", "--quiet",
                             "--no-physics")
    assert status == 0, err
    assert (project / "out" / "house.floor0.png").is_file()


def _grid_of_a_huge_floor() -> tuple[int, float]:
    from cga.authoring import floor_from_rectangles
    from cga.checks.occupancy import occupancy_grid

    plan = floor_from_rectangles([(0, 0, 50_000, 40), (50_000, 0, 99_999, 40)])
    grid = occupancy_grid(plan, [], margin=4_000.0)  # as a 2 km robot would need
    return grid.occupied.size, grid.resolution


def test_occupancy_grid_of_a_huge_floor_stays_within_its_cell_budget():
    from cga.checks.occupancy import MAX_GRID_CELLS

    status, value = run_forked(_grid_of_a_huge_floor, time_limit=30.0)
    assert status == "ok", value
    cells, resolution = value
    assert cells <= MAX_GRID_CELLS and resolution > 0.05


# -- defect 5: unbounded time and memory ----------------------------------------------

def test_nested_repeat_splits_fail_fast_with_a_budget_error(tmp_path):
    grammar = tmp_path / "nested.grammar"
    grammar.write_text('Lot: rectangle(14, 10)\nRules:\nLot --> extrude(3) A\n'
                       'A --> split("x"){ ~0.0014 : B }*\n'
                       'B --> split("z"){ ~0.001 : C }*\n')
    refused(*cli_forked("build", grammar, "--no-physics", "--out", tmp_path / "out"),
            "nested.grammar:5:7: error:", "more shapes")


def test_mutual_recursion_with_a_huge_depth_limit(tmp_path):
    grammar = tmp_path / "ab.grammar"
    grammar.write_text("Rules:\nA --> B\nB --> A\n")
    refused(*cli_forked("build", grammar, "--max-depth", "100000"), "--max-depth", "1,000")
    refused(*cli_forked("build", grammar, "--max-depth", "1000", "--no-physics",
                        "--out", tmp_path / "out"), "recursion deeper than 1000")


def test_300_metre_lot_exports_within_limits(project):
    _uncapped(project)
    status, err = cli_forked("build", project / "house.grammar", "--lot", "300x300",
                             "--no-physics", "--out", project / "out", "--quiet")
    assert status == 0, err


def test_furniture_table_over_the_row_budget(project):
    table = project / "furniture_house.csv"
    row = "Livingroom;plant{};true;false;false;;0;0;false;0;0;0;false;false;false;false;false\n"
    table.write_text(table.read_text() + "".join(row.format(i) for i in range(2, 2002)))
    refused(*cli_forked("build", project / "house.grammar", "--no-physics",
                        "--out", project / "out"), "rows; at most 1,000")


@pytest.mark.parametrize("form", ["geojson", "text"])
def test_lot_with_200k_corners(project, form):
    import math

    corners = [(50 * math.cos(2 * math.pi * i / 200_000), 50 * math.sin(2 * math.pi * i / 200_000))
               for i in range(200_000)]
    if form == "geojson":
        ring = [list(c) for c in corners] + [list(corners[0])]
        status, err = _lot_cli(project, json.dumps({"type": "Polygon", "coordinates": [ring]}))
    else:
        text = "polygon(" + ",".join(f"({x:.4f},{z:.4f})" for x, z in corners) + ")"
        status, err = cli_forked("build", project / "house.grammar", "--lot", text,
                                 "--no-physics", "--out", project / "out")
    refused(status, err, "1,000")


# -- defect 7: wrong places and accepted bad input -------------------------------------

def test_lot_with_3d_coordinates_names_the_lot_file(project):
    refused(*_lot_cli(project, '{"type": "Polygon", "coordinates": '
                               '[[[0,0,5],[10,0,5],[10,8,5],[0,8,5],[0,0,5]]]}'),
            "lot.geojson", "[x, y]")


def test_infinite_density_names_the_model(project):
    text = (MODELS / "sofa.obj").read_text()
    (project / "sofa.obj").write_text("# density inf\n" + text.replace("# density", "#"))
    refused(*cli("check", project / "house.grammar"), "sofa.obj", "density")


BOM = "\ufeff"


def test_byte_order_marks_are_read(project):
    grammar = project / "house.grammar"
    grammar.write_text(BOM + grammar.read_text(encoding="utf-8"), encoding="utf-8")
    for table in ("house_types.csv", "furniture_house.csv"):
        path = project / table
        path.write_text(BOM + path.read_text(encoding="utf-8"), encoding="utf-8")
    (project / "sofa.obj").write_text(BOM + (MODELS / "sofa.obj").read_text(encoding="utf-8"),
                                      encoding="utf-8")
    assert cli("check", grammar) == (0, "")
    lot = project / "lot.geojson"
    # the demo's own 14 m x 10 m, read from a GeoJSON file with a byte order mark
    lot.write_text(BOM + '{"type": "Polygon", "coordinates": [[[0,0],[14,0],[14,10],[0,10],'
                         '[0,0]]]}', encoding="utf-8")
    status, err = cli_forked("build", grammar, "--lot", lot, "--no-physics", "--quiet",
                             "--out", project / "out")
    assert status == 0, err


def test_cr_only_line_endings_are_read(project):
    for name in ("house.grammar", "house_types.csv", "furniture_house.csv"):
        path = project / name
        path.write_bytes(path.read_bytes().replace(b"\r\n", b"\n").replace(b"\n", b"\r"))
    (project / "sofa.obj").write_bytes((MODELS / "sofa.obj").read_bytes().replace(b"\n", b"\r"))
    assert cli("check", project / "house.grammar") == (0, "")


@pytest.mark.parametrize("table, old, column", [
    ("house_types.csv", "Kitchen;", "'Type'"),
    ("furniture_house.csv", "Livingroom;sofa;", "'Name'"),
])
@pytest.mark.parametrize("char", ["\x00", "\x1b", "\x07"])
def test_control_characters_in_names_are_rejected_with_a_position(project, table, old,
                                                                  column, char):
    path = project / table
    new = old.replace("Kitchen", f"Kit{char}chen").replace("sofa", f"so{char}fa")
    _replace(path, old, new)
    status, err = cli("check", project / "house.grammar")
    refused(status, err, f"{table}, row", column, "control character")
    assert char not in err


def test_ten_megabyte_csv_header_gives_a_short_error(project):
    (project / "house_types.csv").write_text("Type;" + "x" * 10_000_000 + "\n")
    refused(*cli("check", project / "house.grammar"), "house_types.csv")


@pytest.mark.parametrize("old, new, message", [
    ("extrude(buildingHeight)", "extrude(-3)", "extrude height must be positive"),
    ("extrude(buildingHeight)", "extrude(1e-9)", "below a micrometre"),
    ("wallWidth = 0.2;", "wallWidth = 0;", "wallWidth must be positive"),
    ('repeated_split("Y", floorHeight)', 'repeated_split("Y", 0)',
     "repeated_split size must be positive"),
    ("doorWidth = 0.9;", "doorWidth = -1;", "doorWidth must be positive"),
])
def test_check_reports_values_a_build_would_reject(project, old, new, message):
    _replace(project / "house.grammar", old, new)
    status, err = cli("check", project / "house.grammar")
    refused(status, err, message, "house.grammar:")


@pytest.mark.parametrize("table, content, message", [
    ("house_types.csv", b"", "the table is empty"),
    ("furniture_house.csv", b"", "the table is empty"),
    ("house_types.csv", bytes(range(256)) * 4, "not UTF-8"),
    ("furniture_house.csv", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff", "not UTF-8"),
    ("house_types.csv", b"Type;Size;Bogus\n", "unknown column 'Bogus'"),
    ("furniture_house.csv", b"Room;Name;Colour\n", "unknown column 'Colour'"),
])
def test_check_reads_the_tables(project, table, content, message):
    (project / table).write_bytes(content)
    refused(*cli("check", project / "house.grammar"), table, message)


@pytest.mark.parametrize("content, message", [
    (b"v 0 0 0\nf 1 2 3\n", "cannot read the OBJ file"),
    (b"# nothing\n", "no faces"),
    (b"v 0 0 0\nv 1 0 0\nv 0 nan 1\nf 1 2 3\n", "OBJ"),
])
def test_check_loads_the_models(project, content, message):
    (project / "sofa.obj").write_bytes(content)
    refused(*cli("check", project / "house.grammar"), "sofa.obj")


@pytest.mark.parametrize("lines, message", [
    (["v 0 0 0"] * 50_001 + ["f 1 2 3"], "50,000 vertices"),
    ([f"g part{i}\nv {i} 0 0\nv {i} 1 0\nv {i} 0 1\nf {3 * i + 1} {3 * i + 2} {3 * i + 3}"
      for i in range(501)], "500 parts"),
])
def test_models_over_their_budget_are_refused_before_parsing(project, lines, message):
    (project / "sofa.obj").write_text("\n".join(lines))
    refused(*cli("check", project / "house.grammar"), "sofa.obj", message)
