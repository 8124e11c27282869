"""cga.paths: the text comparisons answer what pathlib answers part by part."""

from __future__ import annotations

from pathlib import PurePosixPath

from hypothesis import given
from hypothesis import strategies as st

from cga.paths import is_below, relative_text

# names that share prefixes with one another, so a sibling can look like a child
names = st.sampled_from(["a", "ab", "a.b", "b", "models", "models2", "models.old", "x y"])
paths = st.lists(names, max_size=4).map(lambda parts: "/" + "/".join(parts))


@given(paths, paths)
def test_is_below_and_relative_text_agree_with_pathlib(path, root):
    below = PurePosixPath(path).is_relative_to(root)
    assert is_below(path, root) == below
    if below:
        assert relative_text(path, root) == PurePosixPath(path).relative_to(root).as_posix()


def test_a_sibling_whose_name_extends_the_folders_is_not_below_it():
    assert not is_below("/work/models2/chair.obj", "/work/models")
    assert is_below("/work/models/chair.obj", "/work/models")
    assert is_below("/anything", "/")
    assert relative_text("/work/models/sub/chair.obj", "/work/models") == "sub/chair.obj"
