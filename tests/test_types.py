"""The package type-checks: its annotations say what its code does, so a reader and, for
what the compiled build compiles (the engine, the game and the picture's drawing:
setup.py), the compiler (mypyc, docs/compiled.md) can trust them. The check is tried on a
wrong annotation first, so a pass means something."""

from __future__ import annotations

from pathlib import Path

from mypy import api

ROOT = Path(__file__).resolve().parents[1]


def type_errors(paths: list[str], cache: Path) -> list[str]:
    """mypy's error lines for the paths, with the project's settings (pyproject.toml)."""
    out, err, _ = api.run([*paths, "--config-file", str(ROOT / "pyproject.toml"),
                           "--cache-dir", str(cache)])
    assert not err, err
    return [line for line in out.splitlines() if ": error:" in line]


def test_the_check_finds_an_annotation_the_code_breaks(tmp_path):
    wrong = tmp_path / "wrong.py"
    wrong.write_text("def half(n: int) -> int:\n    return n / 2\n")
    errors = type_errors([str(wrong)], tmp_path / "cache")
    assert len(errors) == 1 and "wrong.py:2: error: Incompatible return value" in errors[0]


def test_the_package_type_checks(tmp_path):
    """Everything, the compiled core (setup.py's) with the rest."""
    assert type_errors([str(ROOT / "invaders")], tmp_path / "cache") == []
