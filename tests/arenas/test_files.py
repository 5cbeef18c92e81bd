"""The strict reader of user files (arenas.files)."""

import os

import pytest

from arenas import ArenaError
from arenas.files import MAX_EXPANDED_NODES, check_output, load_yaml, parse_yaml, read_text


@pytest.mark.parametrize("text, match", [
    ("a: 1\na: 2\n", "duplicate key 'a'"),
    ("a: {b: 1, b: 2}\n", "duplicate key 'b'"),
    ("x: " + "[" * 40 + "]" * 40, "nested deeper"),
    ("a: [1\n", "not valid YAML"),
    ("a: !!python/object:os.system {}\n", "not valid YAML"),
])
def test_bad_yaml_is_refused_in_one_line(text, match):
    with pytest.raises(ArenaError, match=match) as exc:
        parse_yaml(text, "f")
    assert "\n" not in str(exc.value)


def test_alias_bombs_are_refused_small_aliases_pass():
    bomb = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join(['*' + chr(97 + i)] * 9)}]\n" for i in range(8))
    with pytest.raises(ArenaError, match=f"more than {MAX_EXPANDED_NODES} values"):
        parse_yaml(bomb, "bomb")
    assert parse_yaml("a: &x [1, 2]\nb: *x\n", "ok") == {"a": [1, 2], "b": [1, 2]}


def test_merge_keys_may_override():
    assert parse_yaml("base: &b {x: 1}\nc:\n  <<: *b\n  x: 2\n", "m")["c"] == {"x": 2}


def test_files_that_are_not_text_are_refused(tmp_path):
    (tmp_path / "bin.yaml").write_bytes(b"a: 1\x00\x01")
    (tmp_path / "latin.yaml").write_bytes("a: caf\xe9".encode("latin-1"))
    (tmp_path / "big.yaml").write_text("a: " + "x" * 2_000_000)
    for name, match in [("bin.yaml", "binary"), ("latin.yaml", "not UTF-8"), ("big.yaml", "bytes"),
                        ("missing.yaml", "cannot read")]:
        with pytest.raises(ArenaError, match=match):
            load_yaml(tmp_path / name, name)
    with pytest.raises(ArenaError, match="is a folder"):
        read_text(tmp_path, "dir")
    if os.path.exists("/dev/zero"):
        with pytest.raises(ArenaError, match="not a regular file"):
            read_text("/dev/zero", "zero")


def test_check_output_creates_nothing(tmp_path):
    (tmp_path / "f").write_text("x")
    assert check_output(tmp_path / "a" / "b" / "c.json", "--json") == tmp_path / "a" / "b" / "c.json"
    assert check_output(tmp_path / "new", "--out", folder=True) == tmp_path / "new"
    for path, folder, match in [(tmp_path, False, "is a folder"), (tmp_path / "f", True, "is a file"),
                                (tmp_path / "f" / "x.json", False, "no folder can be made")]:
        with pytest.raises(ArenaError, match=match):
            check_output(path, "--x", folder=folder)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f"]
