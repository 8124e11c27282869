"""The resource sandbox: a grammar reads only inside its folder tree, the shipped data
and the folders the user allows (issue 19, defect 3)."""

import os
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cga.cli import main
from cga.errors import ResourceAccessError, ResourceNotFoundError, UsageError
from cga.resources import resolve_resource, shipped_dir
from cga.sandbox import Sandbox

DEMOS = Path(__file__).resolve().parents[3] / "demos"

GRAMMAR = """\
Lot: rectangle(8, 6)
Rules:
Lot --> extrude(3) Mass
Mass --> make_floor(2, 0.2, 1>1.2>1.2, 0.9, 2.1) Floor
Floor --> type_rooms("{table}") Typed
"""


@pytest.fixture
def layout(tmp_path):
    """``project/`` (the grammar's folder, with a table and a sub-folder) next to
    ``outside/`` (a table a grammar must not read)."""
    project = tmp_path / "project"
    (project / "tables").mkdir(parents=True)
    shipped = shipped_dir("cga.rules")
    table = (shipped / "house_types.csv").read_text(encoding="utf-8")
    (project / "tables" / "types.csv").write_text(table, encoding="utf-8")
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.csv").write_text("SECRET-LINE;x\n", encoding="utf-8")
    return project, outside


def _write_grammar(project: Path, table: str) -> Path:
    grammar = project / "g.grammar"
    grammar.write_text(GRAMMAR.format(table=table.replace("\\", "\\\\")), encoding="utf-8")
    return grammar


@pytest.mark.parametrize("written", [
    "../outside/secret.csv",
    "..\\outside\\secret.csv",
    "../../../../../../../../etc/passwd",
    "..\\..\\..\\..\\..\\..\\..\\..\\etc\\passwd",
    "/etc/passwd",
    "/proc/self/status",
])
def test_paths_leaving_the_tree_are_refused(layout, written):
    project, _ = layout
    sandbox = Sandbox.for_grammar(project)
    with pytest.raises(ResourceAccessError) as info:
        resolve_resource(written, "rules", base_dir=project, sandbox=sandbox)
    message = str(info.value)
    assert "--allow-path" in message
    assert written[:20] in message
    assert "SECRET" not in message and "root:" not in message


def test_a_sibling_folder_sharing_the_name_as_prefix_is_outside(tmp_path):
    """``project2/`` and ``project.old/`` start with the text of ``project`` but are not
    inside it; the folder itself and anything below it are."""
    project = tmp_path / "project"
    for folder in (project / "sub", tmp_path / "project2", tmp_path / "project.old"):
        folder.mkdir(parents=True)
    sandbox = Sandbox(((project, "the grammar's folder"),))
    assert sandbox.contains(project) and sandbox.contains(project / "sub" / "t.csv")
    assert not sandbox.contains(tmp_path / "project2" / "t.csv")
    assert not sandbox.contains(tmp_path / "project.old")
    assert not sandbox.contains(tmp_path)
    assert Sandbox(((Path("/"), "everything"),)).contains(tmp_path / "project2")


def test_absolute_path_inside_the_tree_is_read(layout):
    project, _ = layout
    table = project / "tables" / "types.csv"
    found = resolve_resource(str(table), "rules", base_dir=project,
                             sandbox=Sandbox.for_grammar(project))
    assert found == table


@pytest.mark.parametrize("written", ["../outside/secret.csv",   # as written
                                     "D:\\Elsewhere\\secret"])  # by name
def test_allowed_folder_is_read(layout, written):
    project, outside = layout
    sandbox = Sandbox.for_grammar(project, [outside])
    found = resolve_resource(written, "rules", base_dir=project, sandbox=sandbox)
    assert found.resolve() == (outside / "secret.csv").resolve()


def test_windows_path_from_another_machine_found_by_name_inside(layout):
    project, _ = layout
    found = resolve_resource("D:\\Rooms\\tables\\Types.csv", "rules", base_dir=project,
                             sandbox=Sandbox.for_grammar(project))
    assert found.resolve() == (project / "tables" / "types.csv").resolve()


def test_symlink_out_of_the_tree_is_refused(layout):
    project, outside = layout
    (project / "link.csv").symlink_to(outside / "secret.csv")
    with pytest.raises(ResourceAccessError, match="link.csv"):
        resolve_resource("link.csv", "rules", base_dir=project,
                         sandbox=Sandbox.for_grammar(project))


def test_symlinked_folder_out_of_the_tree_is_refused(layout):
    project, outside = layout
    (project / "shared").symlink_to(outside, target_is_directory=True)
    with pytest.raises(ResourceAccessError):
        resolve_resource("shared/secret.csv", "rules", base_dir=project,
                         sandbox=Sandbox.for_grammar(project))


def test_symlink_inside_the_tree_is_read(layout):
    project, _ = layout
    (project / "alias.csv").symlink_to(project / "tables" / "types.csv")
    found = resolve_resource("alias.csv", "rules", base_dir=project,
                             sandbox=Sandbox.for_grammar(project))
    assert found == project / "alias.csv"


@pytest.mark.parametrize("written", ["x" * 300, "a\x00b.csv", "loop.csv"])
def test_names_the_os_rejects_are_not_found(layout, written):
    project, _ = layout
    (project / "loop.csv").symlink_to(project / "loop.csv")
    with pytest.raises(ResourceNotFoundError) as info:
        resolve_resource(written, "rules", base_dir=project,
                         sandbox=Sandbox.for_grammar(project))
    assert len(str(info.value)) < 4000
    assert "\x00" not in str(info.value)


def test_allow_path_must_be_a_folder(tmp_path):
    with pytest.raises(UsageError, match="not an existing folder"):
        Sandbox.for_grammar(tmp_path, [tmp_path / "missing"])


@pytest.mark.parametrize("command", ["check", "build"])
def test_cli_refuses_reading_outside(layout, command, capsys, tmp_path):
    project, _ = layout
    grammar = _write_grammar(project, "../outside/secret.csv")
    extra = ["--no-physics", "--out", str(tmp_path / "out")] if command == "build" else []
    assert main([command, str(grammar), *extra]) == 2
    err = capsys.readouterr().err
    assert "outside the folders a build may read" in err
    assert "--allow-path" in err and "../outside/secret.csv" in err
    assert "SECRET" not in err
    assert "Traceback" not in err
    assert not (tmp_path / "out").exists()


def test_cli_allow_path_lets_check_read_it(layout, capsys):
    project, outside = layout
    (outside / "types.csv").write_text((project / "tables" / "types.csv").read_text())
    grammar = _write_grammar(project, "../outside/types.csv")
    assert main(["check", str(grammar), "--allow-path", str(outside)]) == 0
    assert main(["check", str(grammar)]) == 2


def test_model_linking_out_of_the_tree_is_refused(tmp_path, capsys):
    project = tmp_path / "project"
    project.mkdir()
    outside = tmp_path / "outside"
    outside.mkdir()
    chair = shipped_dir("cga.furniture_models") / "chair.obj"
    (outside / "chair.obj").write_text(chair.read_text())
    (project / "chair.obj").symlink_to(outside / "chair.obj")
    text = (DEMOS / "office.grammar").read_text(encoding="utf-8")
    for table in ("office_types.csv", "furniture_office.csv"):
        (project / table).write_text((shipped_dir("cga.rules") / table).read_text())
    (project / "office.grammar").write_text(text, encoding="utf-8")
    status = main(["build", str(project / "office.grammar"), "--no-physics", "--quiet",
                   "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == 2, err
    assert "model" in err and "chair.obj" in err and "--allow-path" in err


def test_lot_file_outside_is_refused_and_allowed(tmp_path, monkeypatch):
    from cga.pipeline import build

    project = tmp_path / "project"
    project.mkdir()
    (project / "m.grammar").write_text("Rules:\nLot --> extrude(3) Mass\n")
    lot = tmp_path / "elsewhere" / "lot.geojson"
    lot.parent.mkdir()
    lot.write_text('{"type": "Polygon", "coordinates": [[[0,0],[5,0],[5,4],[0,4],[0,0]]]}')
    monkeypatch.chdir(project)
    with pytest.raises(ResourceAccessError, match="--allow-path"):
        build(project / "m.grammar", lot=str(lot), formats=(), physics=False, quiet=True)
    scene = build(project / "m.grammar", lot=str(lot), formats=(), physics=False, quiet=True,
                  allow_paths=[lot.parent])
    assert scene.masses


def test_lot_symlink_loop_is_a_clear_error(tmp_path, monkeypatch, capsys):
    project = tmp_path / "project"
    project.mkdir()
    (project / "m.grammar").write_text("Rules:\nLot --> extrude(3) Mass\n")
    (project / "loop.geojson").symlink_to(project / "loop.geojson")
    monkeypatch.chdir(project)
    assert main(["build", "m.grammar", "--lot", "loop.geojson", "--no-physics"]) == 2
    err = capsys.readouterr().err
    assert "lot file not found" in err and "Traceback" not in err


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX symbolic links")
def test_grammar_symlink_loop_is_a_clear_error(tmp_path, capsys):
    loop = tmp_path / "loop.grammar"
    os.symlink(loop, loop)
    for command in ("check", "build"):
        assert main([command, str(loop)]) == 2
        err = capsys.readouterr().err
        assert "not found" in err and "Traceback" not in err


# -- property: whatever a grammar writes, what is read lies inside the allowed folders --

_PARTS = st.sampled_from(["..", ".", "project", "outside", "tables", "types.csv",
                          "secret.csv", "link", "shared", "etc", "passwd", "", "D:", "x"])


@st.composite
def _written_paths(draw):
    parts = draw(st.lists(_PARTS, min_size=1, max_size=7))
    separator = draw(st.sampled_from(["/", "\\", "\\\\"]))
    return draw(st.sampled_from(["", "/", "C:" + separator])) + separator.join(parts)


@settings(max_examples=300, deadline=None)
@given(written=_written_paths())
def test_every_path_a_grammar_writes_resolves_inside_or_is_refused(tmp_path_factory, written):
    root = tmp_path_factory.mktemp("prop")
    project = root / "project"
    (project / "tables").mkdir(parents=True)
    (project / "tables" / "types.csv").write_text("inside\n")
    (root / "outside").mkdir()
    (root / "outside" / "secret.csv").write_text("outside\n")
    (project / "link").symlink_to(root / "outside" / "secret.csv")
    (project / "shared").symlink_to(root / "outside", target_is_directory=True)
    allowed = [os.path.realpath(project), os.path.realpath(shipped_dir("cga.rules")),
               os.path.realpath(shipped_dir("cga.furniture_models"))]
    try:
        found = resolve_resource(written, "rules", base_dir=project,
                                 sandbox=Sandbox.for_grammar(project))
    except (ResourceAccessError, ResourceNotFoundError):
        return
    real = os.path.realpath(found)
    assert any(real == folder or real.startswith(folder + os.sep) for folder in allowed), \
        f"{written!r} read {real}"
    assert os.path.isfile(real)
