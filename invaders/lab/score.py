"""Scoring a method against the oracle, by contact episodes.

An episode is a pair touching on consecutive ticks (in a game one tick, since the response
removes what touched; in a storm with no response, as long as they overlap). A method that
reports the pair during the episode found it: on time if in the window where the episode
began, else late; never, missed. A report with no episode of that pair in its window is
false. Windows let a method that runs every k-th tick be judged on the full-rate truth.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

Pair = tuple[int, int]


@dataclass
class Episode:
    start: int
    end: int
    found_at: int | None = None
    on_time: bool = False


@dataclass
class Score:
    true: int = 0
    on_time: int = 0
    late: int = 0
    missed: int = 0
    false: int = 0
    examples: list[str] = field(default_factory=list)

    @property
    def exact(self) -> bool:
        return self.missed == 0 and self.false == 0 and self.late == 0

    @property
    def errors(self) -> int:
        return self.missed + self.false + self.late

    def note(self, text: str) -> None:
        if len(self.examples) < 5:
            self.examples.append(text)


Judged = tuple[str, Pair, int]  # outcome (on time, late, missed, false), pair, tick it began


class Scorer:
    """Feed `truth(tick, pairs)` for every tick, `reported(start, end, pairs)` for every
    window a method ran over (ticks start+1..end), then `finish()`. With `log`, each
    judgement is also appended to it as it is made (a live lab marks them)."""

    def __init__(self, log: list[Judged] | None = None) -> None:
        self.score = Score()
        self.log = log
        self._active: dict[Pair, Episode] = {}
        self._closed: dict[Pair, list[Episode]] = {}  # ended, still open to a late window

    def truth(self, tick: int, pairs: Iterable[Pair]) -> None:
        pairs = set(pairs)
        for pair in [p for p in self._active if p not in pairs]:
            self._closed.setdefault(pair, []).append(self._active.pop(pair))
        for pair in pairs:
            episode = self._active.get(pair)
            if episode is None:
                self._active[pair] = Episode(tick, tick)
                self.score.true += 1
            else:
                episode.end = tick

    def reported(self, start: int, end: int, pairs: Iterable[Pair]) -> None:
        for pair in sorted(pairs):
            episode = self._episode_in(pair, start, end)
            if episode is None:
                self.score.false += 1
                self.score.note(f"false: {pair} in ticks {start + 1}..{end}")
                if self.log is not None:
                    self.log.append(("false", pair, end))
            elif episode.found_at is None:
                episode.found_at = end
                episode.on_time = episode.start > start
        self._judge(end)

    def _episode_in(self, pair: Pair, start: int, end: int) -> Episode | None:
        active = self._active.get(pair)
        if active is not None and active.start <= end:
            return active
        for episode in self._closed.get(pair, ()):
            if episode.end > start and episode.start <= end:
                return episode
        return None

    def _judge(self, upto: int) -> None:
        """Episodes that ended by `upto` can no longer be found: count them."""
        for pair in list(self._closed):
            keep = []
            for episode in self._closed[pair]:
                if episode.end <= upto:
                    self._count(pair, episode)
                else:
                    keep.append(episode)
            if keep:
                self._closed[pair] = keep
            else:
                del self._closed[pair]

    def _count(self, pair: Pair, episode: Episode) -> None:
        score = self.score
        if episode.found_at is None:
            score.missed += 1
            outcome = "missed"
            score.note(f"missed: {pair} touching in ticks {episode.start}..{episode.end}")
        elif episode.on_time:
            score.on_time += 1
            outcome = "on time"
        else:
            score.late += 1
            outcome = "late"
            score.note(f"late: {pair} began at tick {episode.start}, "
                       f"found at {episode.found_at}")
        if self.log is not None:
            self.log.append((outcome, pair, episode.start))

    def finish(self) -> Score:
        for pair, episode in list(self._active.items()):
            self._closed.setdefault(pair, []).append(episode)
        self._active.clear()
        self._judge(10**18)
        return self.score
