"""Resource lookup: as written, absolute, shipped, by name (Windows paths), then a full error."""

import pytest

from cga.errors import ResourceNotFoundError
from cga.resources import resolve_resource, shipped_dir


@pytest.fixture
def grammar_dir(tmp_path):
    folder = tmp_path / "grammars"
    (folder / "tables").mkdir(parents=True)
    (folder / "tables" / "types.csv").write_text("Type;Size\n")
    (folder / "TestConfig.csv").write_text("local\n")
    (folder / "placement").mkdir()
    (folder / "placement" / "TestConfig.csv").write_text("placement\n")
    return folder


def test_relative_to_grammar_folder(grammar_dir):
    found = resolve_resource("tables/types.csv", "rules", base_dir=grammar_dir)
    assert found == grammar_dir / "tables" / "types.csv"


def test_absolute_path(grammar_dir, tmp_path):
    elsewhere = tmp_path / "elsewhere.csv"
    elsewhere.write_text("x")
    assert resolve_resource(str(elsewhere), "rules", base_dir=grammar_dir) == elsewhere


@pytest.mark.parametrize("written", [
    "D:\\\\Rooms\\\\TestConfig.csv",      # doubled backslashes as a grammar string may keep them
    "D:\\Rooms\\TestConfig",              # no suffix: .csv is tried
    "D:/Rooms/testconfig.CSV",            # case differs (Windows ignores case)
])
def test_foreign_path_found_by_name(grammar_dir, written):
    found = resolve_resource(written, "rules", base_dir=grammar_dir)
    assert found.read_text() == "local\n"


def test_longest_tail_wins_for_same_file_names(grammar_dir):
    written = "D:\\RoomsProjekt\\processor\\placement\\TestConfig.csv"
    assert resolve_resource(written, "rules", base_dir=grammar_dir).read_text() == "placement\n"


def test_shipped_rules_found_by_name(tmp_path, monkeypatch):
    shipped = tmp_path / "shipped"
    shipped.mkdir()
    (shipped / "house_types.csv").write_text("shipped\n")
    monkeypatch.setattr("cga.resources.shipped_dir", lambda package: shipped)
    found = resolve_resource("C:\\Users\\me\\house_types", "rules", base_dir=tmp_path / "g")
    assert found == shipped / "house_types.csv"


def test_missing_lists_every_place(grammar_dir):
    with pytest.raises(ResourceNotFoundError) as info:
        resolve_resource("D:\\Rooms\\Nowhere", "rules", base_dir=grammar_dir)
    text = str(info.value)
    assert text.startswith("rule table not found: D:\\Rooms\\Nowhere")
    assert str(grammar_dir / "D:\\Rooms\\Nowhere") in text
    assert "Nowhere.csv" in text
    rules_dir = shipped_dir("cga.rules")
    if rules_dir is not None:
        assert str(rules_dir) in text
    assert len(info.value.searched) >= 3


def test_model_kind_tries_obj_suffix(tmp_path):
    (tmp_path / "chair.obj").write_text("v 0 0 0\n")
    assert resolve_resource("chair", "model", base_dir=tmp_path) == tmp_path / "chair.obj"


def test_file_kind_has_no_shipped_fallback(tmp_path):
    with pytest.raises(ResourceNotFoundError) as info:
        resolve_resource("lot.geojson", "file", base_dir=tmp_path)
    assert not any("(shipped" in place for place in info.value.searched)
    assert len(info.value.searched) == 2


def test_unknown_kind_is_a_programming_error(tmp_path):
    with pytest.raises(ValueError, match="unknown resource kind"):
        resolve_resource("x", "texture", base_dir=tmp_path)
