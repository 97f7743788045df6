"""The tests mirror the rooms: one folder of tests/ per room of src/armanim, and file names
that are unique across them (conftest.py puts every folder on sys.path)."""

from __future__ import annotations

from collections import Counter

from conftest import ROOMS, ROOT, TESTS


def test_every_room_has_its_folder_of_tests_and_no_test_is_left_at_the_top():
    rooms = {p.name for p in (ROOT / "src" / "armanim").iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    folders = {p.name for p in TESTS.iterdir() if p.is_dir() and any(p.glob("test_*.py"))}
    assert folders == set(ROOMS) and rooms <= folders, (rooms, folders)
    assert sorted(p.name for p in TESTS.glob("test_*.py")) == []


def test_test_file_names_are_unique_across_the_rooms():
    names = Counter(p.name for p in TESTS.rglob("*.py"))
    assert {name: count for name, count in names.items() if count > 1} == {}
