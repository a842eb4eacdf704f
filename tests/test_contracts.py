"""Contracts of the design: the simulation reads no clock, draws nothing, has one RNG;
README's test command is what CI runs."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FORBIDDEN = re.compile(
    r"import time|from time|perf_counter|monotonic|pygame\.display|pygame\.time|"
    r"random\.(random|randint|choice|seed)\(|import render")


def test_the_simulation_and_the_pipeline_read_no_clock_and_touch_no_display():
    for folder in ("game", "engine"):
        for path in (ROOT / "invaders" / folder).glob("*.py"):
            for number, line in enumerate(path.read_text().splitlines(), 1):
                assert not FORBIDDEN.search(line), f"{path.name}:{number}: {line.strip()}"


def test_the_world_owns_the_only_generator():
    text = (ROOT / "invaders" / "game" / "world.py").read_text()
    assert "random.Random(self.seed)" in text
    for path in (ROOT / "invaders" / "game").glob("*.py"):
        if path.name != "world.py":
            assert "import random" not in path.read_text(), path.name


def test_ci_runs_exactly_the_readme_test_command():
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```(?:sh|bash)?\n(.*?)```", readme, re.S)
    assert len(blocks) >= 2
    test_command = blocks[1].strip()
    assert "pytest" in test_command
    assert test_command in (ROOT / ".ci" / "run").read_text()
