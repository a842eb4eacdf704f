"""`invaders bench --against REV`: this tree's game speed against another revision's, in one
run, so that a change is judged by what it costs (the speed budget: within 5%).

The other revision is checked out into a temporary git worktree, and each side runs in an
interpreter of its own for the whole bench (neither inherits the other's imports or
caches). Each plays the game once untimed (its inputs kept), then the two take turns: in
each round an autopilot game, then its inputs replayed, timed by the side itself, the order
reversed from one round to the next, so that a slow spell of the machine falls on both.
Figures are medians over the rounds with their spread, each ratio the median of the
per-round ratios.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import invaders

BUDGET = 0.95  # this tree's speed over the other's, at least

# What each side runs: only the interface every revision has (World, Autopilot, step).
# Told "game" or "replay" on a line, it times one and prints the seconds.
CHILD = """
import gc, os, sys, time
if hasattr(os, "sched_setaffinity"):  # both sides on one processor: its slow spells on both
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
sys.path.insert(0, sys.argv[1])
import invaders
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
assert invaders.__file__.startswith(sys.argv[1]), invaders.__file__
ticks, seed = int(sys.argv[2]), int(sys.argv[3])
def game():
    world, pilot, inputs = World(seed=seed), Autopilot(seed), []
    for _ in range(ticks):
        bits = pilot.actions(world)
        world.step(bits)
        inputs.append(bits)
    return world, inputs
def replay():
    world = World(seed=seed)
    for bits in inputs:
        world.step(bits)
    return world
world, inputs = game()
assert replay().state_hash() == world.state_hash()
print(world.state_hash(), flush=True)
gc.collect(); gc.disable()
for line in sys.stdin:
    start = time.perf_counter()
    game() if line.strip() == "game" else replay()
    print(time.perf_counter() - start, flush=True)
"""


class AgainstError(Exception):
    """The other revision could not be had (one line, exit 2)."""


@contextmanager
def worktree(rev: str) -> Iterator[tuple[Path, str]]:
    """The revision checked out in a temporary worktree of this tree's repository, and its
    short name; removed afterwards."""
    here = Path(invaders.__file__).resolve().parents[1]
    if _answer(here, "rev-parse", "--is-inside-work-tree") is None:
        raise AgainstError(f"--against compares with the project's git history, and {here} "
                           "is not in a git checkout (an installed package and a release "
                           "archive have none: run it from the editable install of a clone)")
    named = _answer(here, "rev-parse", "--verify", "--quiet", "--short", f"{rev}^{{commit}}")
    if named is None:
        raise AgainstError(f"--against: {rev!r} names no commit of the repository at {here}")
    with tempfile.TemporaryDirectory(prefix="invaders-against-") as folder:
        path = Path(folder) / "tree"
        _git(here, "worktree", "add", "--detach", "--quiet", str(path), named)
        try:
            yield path, named
        finally:
            _git(here, "worktree", "remove", "--force", str(path))


def _git(where: Path, *args: str) -> str:
    """git's output; its last word as the error if it fails."""
    done = _run_git(where, args)
    if done.returncode != 0:
        problem = (done.stderr.strip().splitlines() or ["git failed"])[-1]
        raise AgainstError(f"--against: {problem}")
    return done.stdout.strip()


def _answer(where: Path, *args: str) -> str | None:
    """git's output, or None where it has no answer (outside a checkout, no such name)."""
    done = _run_git(where, args)
    return done.stdout.strip() if done.returncode == 0 else None


def _run_git(where: Path, args: tuple[str, ...]) -> subprocess.CompletedProcess[str]:
    try:
        return subprocess.run(["git", "-C", str(where), *args], capture_output=True,
                              text=True, check=False)
    except FileNotFoundError:
        raise AgainstError("--against needs git") from None


class Side:
    """One revision's interpreter, playing on request."""

    def __init__(self, root: Path, ticks: int, seed: int) -> None:
        self.root = root
        self.process = subprocess.Popen(
            [sys.executable, "-c", CHILD, str(root), str(ticks), str(seed)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.hash = self._answer()

    def seconds(self, what: str) -> float:
        """Seconds for one `game` or `replay`, as the side timed it."""
        assert self.process.stdin is not None
        self.process.stdin.write(what + "\n")
        self.process.stdin.flush()
        return float(self._answer())

    def _answer(self) -> str:
        assert self.process.stdout is not None
        line = self.process.stdout.readline()
        if not line:
            self.process.kill()
            last = (self.process.communicate()[1].strip().splitlines() or ["no output"])[-1]
            raise AgainstError(f"the game at {self.root} failed: {last}")
        return line.strip()

    def close(self) -> None:
        self.process.kill()
        self.process.communicate()


def against(rev: str, ticks: int, seed: int, rounds: int) -> int:
    """Print both revisions' figures and their ratios; 1 if this tree misses the budget."""
    here = Path(invaders.__file__).resolve().parents[1]
    seconds: dict[tuple[str, str], list[float]] = {}
    with worktree(rev) as (there, name):
        sides = {"this": Side(here, ticks, seed)}
        try:
            sides["other"] = Side(there, ticks, seed)
            for index in range(rounds):
                order = ("this", "other") if index % 2 == 0 else ("other", "this")
                for what in ("game", "replay"):
                    for who in order:
                        seconds.setdefault((who, what), []).append(
                            sides[who].seconds(what))
        finally:
            for side in sides.values():
                side.close()
    print(f"invaders bench --against {rev} ({name}): {ticks}-tick autopilot game, seed "
          f"{seed}, {rounds} interleaved rounds: median (lowest..highest round)")
    missed = 0
    for what, label in (("game", "autopilot game"), ("replay", "its inputs replayed")):
        mine = [ticks / s for s in seconds[("this", what)]]
        theirs = [ticks / s for s in seconds[("other", what)]]
        ratios = [a / b for a, b in zip(mine, theirs, strict=True)]
        ratio = statistics.median(ratios)
        print(f"   {label:<22} this {statistics.median(mine):>7,.0f} ticks/s "
              f"({min(mine):,.0f}..{max(mine):,.0f})   {name} "
              f"{statistics.median(theirs):>7,.0f} ({min(theirs):,.0f}..{max(theirs):,.0f})"
              f"   this/{name} {ratio:.3f}x ({min(ratios):.3f}..{max(ratios):.3f})")
        met = ratio >= BUDGET
        missed += not met
        print(f"   goal {label} within {1 - BUDGET:.0%} of {name}'s speed: "
              f"{'met' if met else 'NOT met'} ({sum(r < BUDGET for r in ratios)} of "
              f"{rounds} rounds missed)")
    same = sides["this"].hash == sides["other"].hash
    print(f"   the same game on both: {'yes' if same else 'no'} (final state hash)")
    return 1 if missed else 0
