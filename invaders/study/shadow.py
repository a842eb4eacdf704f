"""Shadow scoring: the oracle runs beside a pipeline on the very states it sees.

Detection only: the game goes on with the pipeline's contacts and response. Per pair, a
contact the oracle finds and the pipeline does not is pending; found by the pipeline on a
later tick it is late, never found it is missed; one the pipeline reports that the oracle
does not is false.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from invaders.collision.pipeline import Detector
from invaders.study.oracle import true_contacts


@dataclass
class Score:
    ticks: int = 0
    true: int = 0
    found: int = 0
    missed: int = 0
    false: int = 0
    late: int = 0
    examples: list[str] = field(default_factory=list)

    @property
    def exact(self) -> bool:
        return self.missed == 0 and self.false == 0 and self.late == 0

    def note(self, text: str) -> None:
        if len(self.examples) < 5:
            self.examples.append(text)


class ShadowDetector:
    """Stands in for a world's detector: passes the pipeline's answer on, scores it."""

    def __init__(self, inner: Detector) -> None:
        self.inner = inner
        self.broadphase = inner.broadphase
        self.score = Score()
        self._pending: dict[tuple[int, int], int] = {}  # pair -> tick the oracle saw it

    @property
    def last_pairs(self):
        return self.inner.last_pairs

    def detect(self, scene):
        contacts, stats = self.inner.detect(scene)
        score = self.score
        score.ticks += 1
        truth = {(c.a_id, c.b_id) for c in true_contacts(scene)}
        ours = {(c.a_id, c.b_id) for c in contacts}
        score.true += len(truth)
        score.found += len(ours)
        for pair in sorted(ours):
            if pair in self._pending:  # the oracle saw it on an earlier tick
                score.late += 1
                score.note(f"late: {pair} at tick {scene.tick}, true at {self._pending[pair]}")
                del self._pending[pair]
            elif pair not in truth:
                score.false += 1
                score.note(f"false: {pair} at tick {scene.tick}")
        for pair in sorted(truth - ours):
            self._pending.setdefault(pair, scene.tick)
        return contacts, stats

    def finish(self) -> Score:
        """Pairs still pending at the end were never found: missed."""
        for pair, tick in sorted(self._pending.items()):
            self.score.missed += 1
            self.score.note(f"missed: {pair} at tick {tick}")
        self._pending.clear()
        return self.score
