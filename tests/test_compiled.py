"""The core runs as it was built: compiled (INVADERS_COMPILE=1, as CI sets it for its second
run, on a build of the same commit) or interpreted (every other run), never quietly the
other. What the compiled build changes of the code is tested by the rest of the suite, run
on both. A compiled build that sources imported in front of it would leave unused is said."""

from __future__ import annotations

import importlib
import os
import sys
from importlib.machinery import EXTENSION_SUFFIXES
from pathlib import Path

import pytest

import invaders.env
from invaders.engine import body, detector, store
from invaders.engine.adaptive import COMPILED
from invaders.engine.compiled import shadowed_build, shadowed_note
from invaders.game import rack, world


def test_the_core_is_compiled_exactly_when_built_so():
    compiled = os.environ.get("INVADERS_COMPILE") == "1"
    for module in (body, detector, store, rack, world):
        assert module.__file__.endswith(".py") is not compiled, module.__file__


def _a_build_in(folder: Path) -> Path:
    """A compiled build's trace in `folder`, as pip installs one: the core's modules as
    extensions (one stands for them all; its content is never read)."""
    engine = folder / "invaders" / "engine"
    engine.mkdir(parents=True)
    (engine / f"adaptive{EXTENSION_SUFFIXES[0]}").write_bytes(b"")
    return folder / "invaders"


def test_a_compiled_build_behind_the_sources_imported_is_found_and_said(tmp_path,
                                                                         monkeypatch):
    build = _a_build_in(tmp_path / "site-packages")
    (tmp_path / "elsewhere" / "invaders").mkdir(parents=True)  # (sources: no extension)
    path = [str(tmp_path / "elsewhere"), str(tmp_path / "site-packages")]
    assert shadowed_build(path) == (None if COMPILED else build)
    assert shadowed_build(path[:1]) is None
    (tmp_path / "archive.zip").write_bytes(b"")  # (entries no folder is under: no build)
    assert shadowed_build([str(tmp_path / "archive.zip"), str(tmp_path / "gone"), ""]) is None
    monkeypatch.setattr(sys, "path", path)  # (every module needed is imported)
    note = shadowed_note()
    if COMPILED:  # (the compiled core imported: nothing stands in front of it)
        assert note is None
        return
    assert note is not None and str(build) in note and "docs/compiled.md" in note
    with pytest.warns(RuntimeWarning, match="compiled build behind them"):
        importlib.reload(invaders.env)


def test_nothing_is_said_without_a_compiled_build_on_the_path(tmp_path, monkeypatch, recwarn):
    (tmp_path / "invaders" / "engine").mkdir(parents=True)  # (sources: no extension)
    monkeypatch.setattr(sys, "path", [str(tmp_path)])  # (every module needed is imported)
    assert shadowed_build() is None and shadowed_note() is None
    importlib.reload(invaders.env)
    assert not [w for w in recwarn if "compiled build" in str(w.message)]
