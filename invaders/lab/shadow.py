"""Shadow scoring: the oracle runs beside a pipeline on the very states it sees.

Detection only: the game goes on with the pipeline's contacts and response. Episodes are
scored as in `score.py`: on time, late, missed, or false.
"""

from __future__ import annotations

from invaders.engine.detector import Detector
from invaders.lab.oracle import true_contacts
from invaders.lab.score import Score, Scorer


class ShadowDetector:
    """Stands in for a world's detector: passes the pipeline's answer on, scores it."""

    def __init__(self, inner: Detector) -> None:
        self.inner = inner
        self.broadphase = inner.broadphase
        self.scorer = Scorer()

    @property
    def last_pairs(self):
        return self.inner.last_pairs

    def detect(self, scene):
        contacts, stats = self.inner.detect(scene)
        self.scorer.truth(scene.tick, ((c.a_id, c.b_id) for c in true_contacts(scene)))
        self.scorer.reported(scene.tick - 1, scene.tick, ((c.a_id, c.b_id) for c in contacts))
        return contacts, stats

    def finish(self) -> Score:
        return self.scorer.finish()
