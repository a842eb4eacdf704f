"""The attract sequence as the ROM runs it: texts typed at six frames a letter at the ROM's
places, the alien that straightens PLAY's Y, INSERT CCOIN's extra C shot off, every other
cycle; the demo played by the ROM's moves, scoring nothing."""

from __future__ import annotations

from invaders.app.attract import demo_world
from invaders.app.splash import (
    ALIEN_PULLING_Y,
    ALIEN_WITH_Y,
    UPSIDE_DOWN_Y,
    Y_LEFT_BEHIND,
    DemoPilot,
    Script,
)
from invaders.game.events import Event


def _at(script: Script, frame: int):
    """The screen at a frame of the cycle, counted from its start (before the demo)."""
    for index, step in enumerate(script.steps):
        assert step.frames is not None, "past the demo: count from after it"
        if frame < step.frames:
            return script.screen_at(index, frame)
        frame -= step.frames
    raise AssertionError("past the cycle")


def test_the_title_is_typed_six_frames_a_letter_after_a_second():
    script = Script(animated=False)
    assert _at(script, 63).texts == []
    assert _at(script, 64).texts == [("P", 96, 64)]
    assert _at(script, 64 + 6).texts == [("PL", 96, 64)]
    assert _at(script, 64 + 23).texts == [("PLAY", 96, 64)]
    assert _at(script, 88 + 6 * 6).texts[-1] == ("SPACE  ", 56, 88)
    assert ("PLA" + UPSIDE_DOWN_Y, 96, 64) in _at(Script(animated=True), 88).texts


def test_the_score_table_shows_its_pictures_at_once_and_types_its_lines():
    screen = _at(Script(animated=False), 242)  # 64 + 24 + 90 + 64
    assert ("*SCORE ADVANCE TABLE*", 32, 120) in screen.texts
    assert [(x, y) for _, x, y in screen.drawn()] == [(60, 136), (64, 152), (64, 168), (64, 184)]
    assert screen.texts[-1] == ("=", 80, 136)
    done = _at(Script(animated=False), 242 + 4 * 60)
    assert [t for t in done.texts if t[1] == 80] == [
        ("=? MYSTERY", 80, 136), ("=30 POINTS", 80, 152), ("=20 POINTS", 80, 168),
        ("=10 POINTS", 80, 184)]


def test_an_alien_walks_to_the_upside_down_y_pulls_it_off_and_pushes_a_straight_one_back():
    script = Script(animated=True)
    start = 242 + 240 + 128  # the table typed, two seconds
    walking = _at(script, start + 10)
    assert walking.sprite[1:] == (212, 64)  # from x 222, a pixel a frame to the left
    pulling = _at(script, start + 96 + 20)
    assert ("PLA ", 96, 64) in pulling.texts  # the Y goes with the alien
    assert pulling.sprite == (ALIEN_PULLING_Y[0], 140, 64)
    pushing = _at(script, start + 96 + 103 + 64 + 50)
    assert pushing.sprite[0] in ALIEN_WITH_Y and pushing.sprite[1:] == (173, 64)
    after = _at(script, start + 96 + 103 + 64 + 104 + 64)
    assert after.sprite is None and (Y_LEFT_BEHIND, 119, 64) in after.pictures
    assert not any(step.kind == "move" for step in Script(animated=False).steps[:19])


def test_insert_ccoin_loses_its_extra_c_to_an_aliens_shot_on_the_same_cycles():
    script = Script(animated=True)
    after_demo = script.steps.index(next(s for s in script.steps if s.kind == "demo")) + 1
    shown = [script.screen_at(i, 0) for i in range(after_demo, len(script.steps))]
    assert ("INSERT  COIN", 64, 112) in shown[3].texts and ("C", 120, 112) in shown[3].texts
    last = len(script.steps) - 1
    assert script.steps[last].kind == "shoot"
    falling = script.screen_at(last, 5)
    assert ("C", 120, 112) in falling.texts and falling.sprite[1:] == (116, 40)
    hit = script.screen_at(last, script.steps[last].frames - 1)
    assert ("C", 120, 112) not in hit.texts
    plain = Script(animated=False)
    assert all(("C", 120, 112) not in plain.screen_at(i, 0).texts
               for i in range(len(plain.steps)) if plain.steps[i].kind != "demo")
    credits = [t for t in shown[-1].texts if t[1] == 48]
    assert credits == [("<1 OR 2 PLAYERS>", 48, 144), ("*1 PLAYER  1 COIN", 48, 168),
                       ("*2 PLAYERS 2 COINS", 48, 192)]


def test_the_demo_moves_by_the_roms_table_a_move_a_shot_and_scores_nothing():
    world, pilot = demo_world("auto")
    moves = []
    for _ in range(3000):
        bits = pilot.actions(world)
        report = world.step(bits)
        if Event.SHOT_FIRED in report.events:
            moves.append(pilot.move)
        if Event.CANNON_HIT in report.events:
            break
    assert len(moves) > 10 and moves == [DemoPilot.MOVES[i % 10] for i in range(len(moves))]
    assert world.score == 0 and world.aliens_killed > 0
