"""Shadow scoring: the oracle runs beside a detector on the very states it sees.

An observer of the detector: after each detection, before any response, it asks the oracle
for the tick's true first contacts and scores the detector's (the ones that happen, as the
response would take them) against them by episodes, as in `score.py`: on time, late,
missed, or false. The game goes on with the detector's answer.
"""

from __future__ import annotations

from collections.abc import Sequence

from invaders.engine.broadphase import Pair, Scene
from invaders.engine.response import first_contacts
from invaders.engine.rules import RuleTable
from invaders.engine.stats import CollisionStats, Contact
from invaders.lab.oracle import true_contacts
from invaders.lab.score import Score, Scorer


class Shadow:
    """Scores every detection of the detector it observes against the oracle."""

    def __init__(self, rules: RuleTable) -> None:
        self.rules = rules
        self.scorer = Scorer()

    def before(self, scene: Scene) -> None:
        pass

    def after(self, scene: Scene, candidates: Sequence[Pair], contacts: Sequence[Contact],
              stats: CollisionStats) -> None:
        tick = scene.tick
        self.scorer.truth(tick, ((c.a_id, c.b_id) for c in true_contacts(scene, self.rules)))
        self.scorer.reported(tick - 1, tick,
                             ((c.a_id, c.b_id) for c in first_contacts(contacts)))

    def finish(self) -> Score:
        return self.scorer.finish()
