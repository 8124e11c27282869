"""build(), the summary, `cga build` and `cga check` in-process (the e2e tests use a subprocess)."""

from __future__ import annotations

import json

import pytest
from shapely.geometry import Polygon

from cga import pipeline as build_module
from cga.pipeline import build
from cga.cli import main
from cga.errors import (DerivationError, GrammarSyntaxError, NoSolutionError,
                        ResourceNotFoundError, UsageError)
from cga.export import EXPORTERS
from cga.report import CheckReport
from cga.summary import summary_dict
from cga.validate import check_file

GRAMMAR = """\
Lot: rectangle(12, 8)
Variables:
  h = 6;
Rules:
Lot --> extrude(h) Body
Body --> repeated_split("y", 3){ Ground, Upper }
Ground --> component_split("side_faces"){ Facade }
"""


@pytest.fixture
def grammar_file(tmp_path):
    path = tmp_path / "block.grammar"
    path.write_text(GRAMMAR)
    return path


def test_build_writes_files_and_times_stages(grammar_file, tmp_path):
    out = tmp_path / "out"
    scene = build(grammar_file, seed=2, out_dir=out, formats=("glb", "json"), quiet=True)
    assert scene.name == "block" and scene.seed == 2 and scene.source == grammar_file
    assert [t.symbol for t in scene.terminals] == ["Facade"] * 4 + ["Upper"]
    assert sorted(p.name for p in out.iterdir()) == [
        ".cga-block.files.json", "block.glb", "block.scene.json"]
    assert {"parse", "derive", "extrude", "repeated_split", "component_split", "meshing",
            "export"} <= set(scene.timings)
    assert "physics" not in scene.timings  # no floors: checks do not run


def test_build_lot_option_overrides_grammar(grammar_file):
    scene = build(grammar_file, lot="20x5", formats=(), quiet=True)
    assert scene.terminals[-1].geometry.footprint.bounds == (0, 0, 20, 5)
    clockwise = Polygon([(0, 0), (0, 4), (4, 4), (4, 0)])
    scene = build(grammar_file, lot=clockwise, formats=(), quiet=True)
    assert scene.terminals[-1].geometry.footprint.exterior.is_ccw
    with pytest.raises(UsageError, match="lot: the polygon is not simple"):
        build(grammar_file, lot=Polygon([(0, 0), (4, 4), (4, 0), (0, 4)]), formats=())


def test_failed_export_leaves_no_output(grammar_file, tmp_path, monkeypatch):
    out = tmp_path / "out"

    def broken(scene, nodes, out_dir, name):
        (out_dir / f"{name}.broken").write_text("half")
        raise UsageError("exporter failed")

    monkeypatch.setitem(EXPORTERS, "broken", broken)
    with pytest.raises(UsageError):
        build(grammar_file, out_dir=out, formats=("glb", "broken"), quiet=True)
    assert not out.exists() or not any(out.iterdir())
    assert [p.name for p in tmp_path.iterdir() if p.name != "block.grammar"] in ([], ["out"])


def test_strict_fails_on_a_failed_check_and_writes_nothing(grammar_file, tmp_path, monkeypatch):
    class Failed:
        passed = False

        def summary(self):
            return "physics: 0/1 items at rest"

        def to_dict(self):
            return {"passed": False}

    def failing(scene, robot_radius, progress):
        scene.checks["physics"] = Failed()

    monkeypatch.setattr(build_module, "_run_checks", failing)
    scene = build(grammar_file, out_dir=tmp_path / "lenient", quiet=True)
    assert isinstance(scene.checks["physics"], CheckReport)
    assert scene.checks["physics"].passed is False
    with pytest.raises(NoSolutionError, match="physics: 0/1 items at rest"):
        build(grammar_file, out_dir=tmp_path / "strict", strict=True, quiet=True)
    assert not (tmp_path / "strict").exists()


def test_bad_options(grammar_file):
    with pytest.raises(UsageError, match="unknown export format nope; available: glb"):
        build(grammar_file, formats=("nope",))
    with pytest.raises(UsageError, match="--seed"):
        build(grammar_file, seed=-1)
    with pytest.raises(UsageError, match="--units"):
        build(grammar_file, units=0)
    with pytest.raises(ResourceNotFoundError, match="grammar not found"):
        build(grammar_file.with_name("missing.grammar"))


def test_source_errors_carry_the_grammar_text(tmp_path):
    path = tmp_path / "bad.grammar"
    path.write_text("Rules:\nLot --> extrude(h) Body\n")
    with pytest.raises(DerivationError) as info:
        build(path, formats=(), quiet=True)
    text = str(info.value)
    assert text.startswith(f"{path}:2:17: error: undefined variable 'h'")
    assert "   2 | Lot --> extrude(h) Body" in text and "^" in text


def test_summary_dict(grammar_file):
    data = summary_dict(build(grammar_file, seed=1, formats=(), quiet=True), out_dir="o")
    assert data["name"] == "block" and data["seed"] == 1 and data["floors"] == []
    assert data["shapes"] == 5 and data["out_dir"] == "o"
    assert "derive" in data["timings"]
    json.dumps(data)


def test_summary_of_a_floor_plan():
    from cga.operations.floorplan.rectangles import plan_from_rectangles
    from cga.scene import Scene
    from cga.shape import Mass, Shape

    plan = plan_from_rectangles([(0, 0, 6, 10), (6, 0, 14, 10)])
    mass = Mass(plan.footprint, 0, 3)
    shape = Shape(symbol="F", path=("F",), scope=mass.scope(), geometry=mass, plan=plan)
    data = summary_dict(Scene(name="p", seed=0, units=1, terminals=[shape]))
    [floor] = data["floors"]
    assert [(r["id"], r["type"], r["area_m2"]) for r in floor["rooms"]] == [
        (0, None, 60.0), (1, None, 80.0)]
    assert floor["area_m2"] == 140.0 and data["shapes"] == 0
    assert data["materials"] == "neutral" and data["lights"] >= 2  # a light per room at least


def test_cli_build_prints_summary_and_json(grammar_file, tmp_path, capsys):
    assert main(["build", str(grammar_file), "--out", str(tmp_path / "o"), "--seed", "3"]) == 0
    out = capsys.readouterr().out
    assert "block" in out and "seed 3" in out and "derive" in out
    assert (tmp_path / "o" / "block.glb").is_file()
    assert main(["build", str(grammar_file), "--out", str(tmp_path / "o"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["name"] == "block" and data["out_dir"] == str(tmp_path / "o")
    assert main(["build", str(grammar_file), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""


def test_cli_errors_exit_2_without_traceback(tmp_path, capsys):
    path = tmp_path / "typo.grammar"
    path.write_text("Rules:\nLot --> extrud(3) Body\n")
    assert main(["build", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert f"{path}:2:9: error: unknown operation 'extrud'" in err
    assert "did you mean 'extrude'?" in err and "Traceback" not in err
    assert main(["build", str(tmp_path / "missing.grammar")]) == 2
    assert "grammar not found" in capsys.readouterr().err
    assert main(["build", str(path), "--lot", "banana"]) == 2
    assert "expected one of" in capsys.readouterr().err


def test_cli_check(grammar_file, tmp_path, capsys):
    assert main(["check", str(grammar_file)]) == 0
    assert capsys.readouterr().out.strip() == f"{grammar_file}: ok"
    bad = tmp_path / "bad.grammar"
    bad.write_text("Rules:\nLot --> extrude(3) {A, B}\n")
    assert main(["check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:2:" in err and "extrude takes 1 successor, got 2" in err
    assert "1 problem" in err


# -- static checks --------------------------------------------------------------------------

def test_check_reports_every_problem_in_every_branch(tmp_path):
    path = tmp_path / "many.grammar"
    path.write_text(
        "Variables:\n"
        "  height = 6;\n"
        "Rules:\n"
        "Lot --> extrude(height) Body\n"
        "Body --> 50% : repeated_split(\"y\", heigth){A, B}\n"
        "       | else : split(\"q\"){ ~1 : A }\n"
        "A --> type_rooms(\"D:\\\\Rooms\\\\NoSuchTable\") T\n"
        "B --> case scope.sx > 10 : extrude(\"tall\") C | else : comp_split(\"top\"){R}\n")
    problems = check_file(path)
    texts = [str(p) for p in problems]
    assert len(problems) == 5, texts
    assert any(f"{path}:5:" in t and "undefined variable 'heigth'" in t and "did you mean 'height'?"
               in t for t in texts)
    assert any(f"{path}:6:" in t and "argument 'axis' (axis) must be one of" in t for t in texts)
    assert any(f"{path}:7:" in t and "rule table not found: D:\\\\Rooms\\\\NoSuchTable" in t
               for t in texts)
    assert any(f"{path}:8:" in t and "expected a number, got the string \"tall\"" in t
               for t in texts)
    assert any(f"{path}:8:" in t and "unknown operation 'comp_split'" in t for t in texts)
    assert all("^" in t for t in texts)  # excerpts attached


def test_check_reports_syntax_errors_and_lot_problems(tmp_path):
    syntax = tmp_path / "syntax.grammar"
    syntax.write_text("Rules:\nLot --> extrude(3 Body\n")
    [problem] = check_file(syntax)
    assert isinstance(problem, GrammarSyntaxError) and f"{syntax}:2:" in str(problem)
    lot = tmp_path / "lot.grammar"
    lot.write_text("Lot: polygon((0,0),(4,4),(4,0),(0,4))\nRules:\nLot --> extrude(3) B\n")
    [problem] = check_file(lot)
    assert f"{lot}:1:" in str(problem) and "not simple" in str(problem)


def test_check_accepts_shape_dependent_values(tmp_path):
    path = tmp_path / "dyn.grammar"
    path.write_text("Variables:\n  r = [1;2];\nRules:\n"
                    "Lot --> extrude(scope.sx * r) B\n"
                    "B --> split(\"x\"){ ~scope.sx / 3 : C }*\n")
    assert check_file(path) == []


def test_demo_massing_checks_clean():
    from pathlib import Path

    demo = Path(__file__).resolve().parents[3] / "demos" / "massing.grammar"
    assert check_file(demo) == []


def test_cli_batch_builds_each_seed_and_resumes(grammar_file, tmp_path, capsys):
    out = tmp_path / "batch"
    assert main(["batch", str(grammar_file), "-n", "2", "--out", str(out), "--json"]) == 0
    first = json.loads(capsys.readouterr().out)
    assert first["houses"] == 2 and first["built_now"] == 2 and first["errors"] == 0
    assert sorted(p.name for p in out.iterdir()) == [
        ".cga-batch.lock", "manifest.jsonl", "seed_000000", "seed_000001"]
    assert (out / "seed_000001" / "block.glb").is_file()
    assert main(["batch", str(grammar_file), "-n", "3", "--out", str(out), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["houses"] == 3 and again["built_now"] == 1


def test_build_into_the_grammars_own_folder_keeps_the_grammar_and_notes(tmp_path, monkeypatch,
                                                                         capsys):
    """Issue 19, defect 1: `--out .` beside the grammar deleted `house.grammar` and
    `house.notes.txt`; a `*` in the grammar name deleted every file with a dot."""
    monkeypatch.chdir(tmp_path)
    user_files = {"house.grammar": GRAMMAR, "house.notes.txt": "notes", "h*.grammar": GRAMMAR,
                  "plan.v2.txt": "v2", "house.floor9.svg": "a user's drawing"}
    for name, text in user_files.items():
        (tmp_path / name).write_text(text)
    for grammar in ("house.grammar", "h*.grammar", "house.grammar", "h*.grammar"):
        assert main(["build", grammar, "--out", ".", "--no-physics", "--quiet"]) == 0
    for name, text in user_files.items():
        assert (tmp_path / name).read_text() == text
    outputs = {p.name for p in tmp_path.iterdir()} - set(user_files)
    assert outputs == {".cga-house.files.json", ".cga-h*.files.json", "house.glb",
                       "house.scene.json", "h*.glb", "h*.scene.json"}


def test_build_refuses_to_replace_a_file_it_did_not_write(grammar_file, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "block.glb").write_text("someone else's model")
    assert main(["build", str(grammar_file), "--out", str(out), "--quiet"]) == 2
    message = capsys.readouterr().err
    assert "block.glb already exists" in message and "Traceback" not in message
    assert (out / "block.glb").read_text() == "someone else's model"
    assert sorted(p.name for p in out.iterdir()) == ["block.glb"]


def test_api_build_keeps_the_files_of_formats_it_does_not_write(tmp_path):
    """Issue 20: `cga.build()` (glb only) into the folder of a `cga build` that also
    wrote plans and the scene JSON deleted them. A build removes stale files only among
    the formats it writes: a rebuild of the plans still drops a floor's stale plan."""
    grammar = tmp_path / "flat.grammar"
    grammar.write_text('Lot: rectangle(9, 7)\nRules:\nLot --> extrude(6) Body\n'
                       'Body --> repeated_split("y", 3){ Storey }\n'
                       'Storey --> make_floor(2, 0.2, 1>1.2>1.2, 0.9, 2.1, stair = "none") Floor\n')
    out = tmp_path / "out"
    assert main(["build", str(grammar), "--out", str(out), "--no-physics", "--quiet"]) == 0
    names = {p.name for p in out.iterdir()}
    assert {"flat.glb", "flat.scene.json", "flat.floor0.svg", "flat.floor1.png"} <= names
    plans = {n: (out / n).read_bytes() for n in names if ".floor" in n}
    build(grammar, seed=1, out_dir=out, formats=("glb",), physics=False, quiet=True)
    assert {p.name for p in out.iterdir()} == names  # plans and JSON are still there
    assert {n: (out / n).read_bytes() for n in plans} == plans
    # a build that writes plans again replaces them and drops what it no longer writes
    grammar.write_text(grammar.read_text().replace('extrude(6)', 'extrude(3)'))
    build(grammar, out_dir=out, formats=("glb", "plan"), physics=False, quiet=True)
    left = {p.name for p in out.iterdir()}
    assert "flat.floor1.svg" not in left and "flat.floor0.svg" in left
    assert "flat.scene.json" in left
