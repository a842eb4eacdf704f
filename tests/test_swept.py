"""Fast things never pass through each other: the swept test against the discrete one."""

from __future__ import annotations

from dataclasses import replace

from hypothesis import given, settings
from hypothesis import strategies as st

from invaders.engine.body import Body
from invaders.engine.broadphase import Brute
from invaders.engine.detector import Detector
from invaders.engine.grid import Grid
from invaders.engine.rules import Motion
from invaders.game import art
from invaders.game.entities import BOMB_MASKS, BombType
from invaders.game.kinds import Kind
from tests.helpers import GAME_RULES, store_of

DISCRETE_RULES = GAME_RULES.map(
    lambda r: r if r.motion is Motion.LANDING else replace(r, motion=Motion.DISCRETE))


def _close(detector: Detector, shot_speed: int, bomb_speed: int, column: int, gap: int,
           btype: BombType, frame: int) -> int | None:
    """Move a shot up and a bomb down until they have passed; the tick they met, or None."""
    bomb = Body(1, Kind.BOMB, 100, 60, BOMB_MASKS[btype][frame])
    lit = [c for c in range(bomb.w) if any(bomb.mask.get_at((c, y)) for y in range(bomb.h))]
    column = lit[column % len(lit)]  # a column the picture lights
    shot = Body(2, Kind.SHOT, 100 + column, bomb.y + bomb.h + gap, art.mask_of(art.SHOT))
    for tick in range(1, 200):
        for body, dy in ((shot, -shot_speed), (bomb, bomb_speed)):
            body.px, body.py, body.moved_tick = body.x, body.y, tick
            body.y += dy
        contacts, _ = detector.detect(store_of([bomb, shot], tick))
        if contacts:
            return tick
        if shot.y + shot.h <= bomb.y:  # the shot is wholly above the bomb: they have passed
            return None
    raise AssertionError("never passed")


@settings(max_examples=300, deadline=None)
@given(shot_speed=st.integers(1, 16), bomb_speed=st.integers(0, 16), column=st.integers(0, 2),
       gap=st.integers(0, 40), btype=st.sampled_from(list(BombType)), frame=st.integers(0, 3))
def test_a_shot_and_a_bomb_closing_at_up_to_16_px_a_tick_always_meet(
        shot_speed, bomb_speed, column, gap, btype, frame):
    for broadphase in (Grid(), Brute()):
        assert _close(Detector(broadphase, GAME_RULES), shot_speed, bomb_speed, column, gap, btype,
                      frame) is not None


def test_the_discrete_test_lets_them_pass_where_steps_exceed_length_plus_thickness():
    # Squiggly's side column is one pixel here; the shot is 4 long: 9 px a tick jumps it.
    discrete = Detector(Brute(), DISCRETE_RULES)
    swept = Detector(Brute(), GAME_RULES)
    misses = [g for g in range(0, 9)
              if _close(discrete, 4, 5, 0, g, BombType.SQUIGGLY, 0) is None]
    assert misses  # some gaps let them pass...
    assert all(_close(swept, 4, 5, 0, g, BombType.SQUIGGLY, 0) for g in misses)  # ...not ours
