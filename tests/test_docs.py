"""The README and docs/ stay true: every `invaders` command they show is run, in the order
shown, in a folder of its own (with a copy of the replays), and a command's output shown
just below it is what the program prints.

Commands that open a window run on SDL's dummy driver with a scripted player (Enter, a few
frames, then the window closed); `study` and `bench`, which take minutes, run at their
smallest size: `study --quick` (the session's one quick study, which the study's own
tests share), `bench` for three rounds of 60 ticks."""

from __future__ import annotations

import inspect
import re
import shlex
import shutil
import subprocess
from pathlib import Path

import pygame
import pytest

from invaders.app.cli import build_parser, main
from invaders.env.space_invaders import SpaceInvadersEnv

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BLOCK = re.compile(r"```(\w*)\n(.*?)```", re.S)
# Whether this tree has its git history, which `bench --against` reads (a release archive
# has none: there the command is refused, in words, tests/test_cli.py).
IN_CHECKOUT = shutil.which("git") is not None and subprocess.run(
    ["git", "-C", str(ROOT), "rev-parse"], capture_output=True, check=False).returncode == 0
INSTEAD = {"--env", "--window", "--reading", "--arcade", "--against"}  # (benches without sections)
TIMED = ("bench", "study")  # their output is timings: the pages show one run of it


def shown(page: Path) -> list[tuple[list[str], str | None]]:
    """The page's `invaders` commands in order, the last of a block with its output: the
    plain block after it, when one paragraph ending in a colon is all that stands between
    (compared for every command but those that print timings)."""
    text = page.read_text()
    blocks = list(BLOCK.finditer(text))
    found = []
    for place, block in enumerate(blocks):
        if block.group(1) not in ("sh", "bash"):
            continue
        output = None
        if place + 1 < len(blocks) and blocks[place + 1].group(1) == "":
            between = text[block.end():blocks[place + 1].start()].strip()
            if between.endswith(":") and "\n\n" not in between:
                output = blocks[place + 1].group(2)
        commands = [words for line in block.group(2).splitlines()
                    for words in _invocations(line)]
        for number, words in enumerate(commands):
            found.append((words, output if number == len(commands) - 1 else None))
    return found


def _invocations(line: str) -> list[list[str]]:
    words = shlex.split(line, comments=True)
    parts, part = [], []
    for word in [*words, "&&"]:
        if word == "&&":
            parts.append(part)
            part = []
        else:
            part.append(word)
    return [p[1:] for p in parts if p and p[0].endswith("bin/invaders")]


def test_the_pages_show_commands_and_every_one_parses():
    counted = 0
    for page in PAGES:
        for words, _ in shown(page):
            build_parser().parse_args(words)  # a stale flag fails here, naming itself
            counted += 1
    assert counted >= 10


class ScriptedPlayer:
    """pygame's event queue as a player who presses Enter, waits, then closes the window."""

    def __init__(self, frames: int = 20) -> None:
        self.calls = 0
        self.frames = frames

    def __call__(self, *args, **kwargs) -> list[pygame.event.Event]:
        self.calls += 1
        if self.calls == 2:
            return [pygame.event.Event(pygame.KEYDOWN, key=pygame.K_RETURN, mod=0,
                                       unicode="\r", scancode=0)]
        if self.calls >= self.frames:
            return [pygame.event.Event(pygame.QUIT)]
        return []


@pytest.mark.parametrize("page", [p for p in PAGES if shown(p)], ids=lambda p: p.name)
def test_every_command_on_the_page_runs_and_prints_what_the_page_shows(
        page, tmp_path, monkeypatch, capsys, quick_study):
    commands = shown(page)
    shutil.copytree(ROOT / "replays", tmp_path / "replays")
    monkeypatch.chdir(tmp_path)
    for words, output in commands:
        command = words[0]
        capsys.readouterr()
        if command == "study":  # the study's smallest run, shared
            code, printed, _ = quick_study
        else:
            if command == "bench":  # --ale and --big take minutes (their own tests)
                words = [w for w in words if w not in ("--ale", "--big")] + ["--rounds", "3"]
                instead = INSTEAD.intersection(words)
                if not instead - {"--against"}:  # (a game: the full bench's and --against's)
                    words += ["--ticks", "60"]
                if not instead:
                    words += ["--largest", "100"]  # (section 5's: the full bench's alone)
            monkeypatch.setattr(pygame.event, "get", ScriptedPlayer())
            code = main(words)
            printed = capsys.readouterr().out
            if "--against" in words and not IN_CHECKOUT:  # (a release archive: no history)
                assert code == 2
                continue
        assert code in (0, 1) if command == "bench" else code == 0, (words, printed)
        if output is not None and command not in TIMED:
            shown_lines = output.strip().splitlines()
            if len(shown_lines) == 1:  # one line of the output, quoted among the rest
                assert shown_lines[0] in printed.splitlines(), (words, printed)
            else:
                assert printed.strip() == output.strip(), words


PYTHON = [(page, block) for page in PAGES
          for block in re.findall(r"```python\n(.*?)```", page.read_text(), re.S)]


@pytest.mark.parametrize("page, code", PYTHON, ids=[f"{p.name}-{i}" for i, (p, _) in
                                                     enumerate(PYTHON)])
def test_every_python_example_on_the_pages_runs_and_prints_what_its_comments_say(
        page, code, capsys):
    exec(compile(code, page.name, "exec"), {})
    printed = capsys.readouterr().out.splitlines()
    said = re.findall(r"print\(.*\)\s+# (.+)$", code, re.M)  # what a print says it prints
    assert printed == said


def test_the_environments_options_table_names_every_option_it_takes():
    """docs/env.md's table of options, against the environment's own: one it takes and the
    page leaves out (or one the page names that it refuses) fails here."""
    table = (ROOT / "docs" / "env.md").read_text().split("## Options", 1)[1].split("\n\n")[2]
    named = {name for row in table.splitlines()[2:]
             for name in re.findall(r"`(\w+)`", row.split(" | ")[0])}
    taken = set(inspect.signature(SpaceInvadersEnv).parameters)
    assert named == taken
