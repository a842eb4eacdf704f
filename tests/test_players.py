"""Two players: turns at each death, each with their own rack, shields, score, ships and wave;
PLAY PLAYER<n> between turns; the replay says how many play; one-player games unchanged."""

from __future__ import annotations

import copy
import itertools
from collections.abc import Callable

import pygame
import pytest

from invaders.game import art
from invaders.game.actions import Action
from invaders.game.events import Event
from invaders.game.players import HOLD, PROMPT, SWITCH_TICKS
from invaders.game.replay import load
from invaders.game.saucer import launch
from invaders.game.world import Phase, World
from invaders.lab.autopilot import Autopilot
from invaders.lab.picture import hud_texts, turn_texts
from tests.helpers import rack_moves, step_until, through_the_prompt


def _lose_a_ship(world: World) -> int:
    """The cannon hit: the tick its ship is lost."""
    world.kill_cannon()
    return step_until(world, lambda r: Event.SHIP_LOST in r.events, limit=200).tick


def test_players_take_turns_at_each_death_each_with_their_own_field():
    world = World(seed=2, players=2)
    step_until(world, lambda r: world.rack.live == 55 and world.cannon.state == 1, limit=400)
    for alien in world.rack.live_aliens()[:5]:  # player 1 shoots five aliens ...
        world.rack.kill(alien, world.store)
    world.add_score(50)
    world.extra_awarded = True  # (as if past 1500)
    world.ground.clear()  # the bottom line chipped away
    world.bunkers[0].mask.clear()  # ... and loses a shield, a saucer flying
    launch(world.saucer, world.store, world.config)
    _lose_a_ship(world)
    assert world.phase is Phase.SWITCH and world.player == 1 and world.ships == 2
    for _ in range(HOLD):  # the field held as it was
        report = world.step(0)
    assert Event.PLAYER_UP in report.events and world.player == 2
    assert (world.score, world.ships, world.wave, world.scores()) == (0, 3, 1, (50, 0))
    assert world.bunkers == [] and not world.rack.live_aliens()  # cleared for the prompt
    assert world.saucer.saucer is None and world.saucer.hit_steps == 0  # (the saucer too)
    assert not world.extra_awarded  # player 2's own
    assert world.ground.count() == art.fresh_mask(art.GROUND).count()  # drawn afresh (0804)
    report = step_until(world, lambda r: Event.TURN_STARTED in r.events, limit=PROMPT)
    assert world.phase is Phase.PLAYING and world.cannon.state == 1  # ready at once
    fresh = art.fresh_mask(art.BUNKER).count()
    assert world.rack.live == 55 and all(b.mask.count() == fresh for b in world.bunkers)
    _lose_a_ship(world)
    step_until(world, lambda r: Event.TURN_STARTED in r.events, limit=SWITCH_TICKS)
    assert (world.player, world.score, world.ships, world.rack.live) == (1, 50, 2, 50)
    assert world.scores() == (50, 0) and world.extra_awarded
    assert world.bunkers[0].mask.count() == 0 and world.bunkers[1].mask.count() == fresh
    drawn = step_until(world, lambda r: len(world.rack.live_aliens()) == 50, limit=60)
    assert drawn.tick - report.tick > 50  # the rack comes back one alien a tick


def test_between_turns_the_field_holds_128_frames_then_the_prompt_176():
    """TwoSecDelay's 0x80 frames after the death (0315), then PLAY PLAYER<n> for 0xB0
    (08A4), then the other player's turn."""
    world = World(seed=2, players=2)
    step_until(world, lambda r: world.cannon.state == 1, limit=400)
    lost = _lose_a_ship(world)
    up = step_until(world, lambda r: Event.PLAYER_UP in r.events, limit=400).tick
    started = step_until(world, lambda r: Event.TURN_STARTED in r.events, limit=400).tick
    assert (up - lost, started - up) == (128, 176)


def test_one_out_of_ships_the_other_plays_on_alone_then_the_game_ends():
    world = World(seed=3, players=2)
    world.ships = 1
    world.add_score(30)
    _lose_a_ship(world)  # player 1's last ship: GAME OVER PLAYER<1>, then player 2
    assert world.out and world.phase is Phase.SWITCH
    assert world.hi_score == 30  # (taken when a player is out, as at the game's end)
    assert turn_texts(world) == [("GAME OVER PLAYER<1>", 32, 224)]
    step_until(world, lambda r: Event.TURN_STARTED in r.events, limit=SWITCH_TICKS)
    assert world.player == 2 and world.waiting.out
    _lose_a_ship(world)  # player 2 has ships left: no turn for player 1, play on
    assert world.phase is Phase.PLAYING and world.player == 2 and world.ships == 2
    world.ships = 1
    world.add_score(120)
    world.kill_cannon()
    step_until(world, lambda r: Event.GAME_OVER in r.events, limit=200)
    assert world.hi_score == 120


def test_a_one_player_game_is_what_it_always_was():
    one, default = World(seed=6, players=1), World(seed=6)
    pilot_a, pilot_b = Autopilot(6), Autopilot(6)
    for _ in range(2000):
        one.step(pilot_a.actions(one))
        default.step(pilot_b.actions(default))
    assert one.state_hash() == default.state_hash() and one.scores()[1] is None


def test_the_two_player_start_button_begins_a_game_of_two_after_game_over():
    world = World(seed=1)
    world.ships = 1
    _lose_a_ship(world)
    assert world.phase is Phase.GAME_OVER
    report = step_until(world, lambda r: Event.NEW_GAME in r.events, actions=int(Action.START2))
    assert world.players == 2 and world.waiting is not None and report.tick > 0


def test_a_two_player_game_recorded_replays_and_says_so_in_its_header(tmp_path, capsys):
    from invaders.app.cli import main

    path = tmp_path / "two.json"
    assert main(["run", "--autopilot", "--players", "2", "--seed", "1", "--ticks", "3000",
                 "--record", str(path)]) == 0
    replay = load(path)
    assert replay.players == 2 and '"players":2' in path.read_text().splitlines()[0]
    assert main(["replay", str(path)]) == 0
    world, pilot = World(seed=1, players=2), Autopilot(1)
    seen = set()
    for _ in range(3000):
        seen.update(world.step(pilot.actions(world)).events)
    assert Event.PLAYER_UP in seen and world.state_hash() == replay.checkpoints[-1].hash
    capsys.readouterr()


@pytest.mark.parametrize("players", [0, 3, "2", None])
def test_a_header_with_a_wrong_number_of_players_is_refused(tmp_path, players, capsys):
    from invaders.app.cli import main

    path = tmp_path / "one.json"
    assert main(["run", "--ticks", "60", "--record", str(path)]) == 0
    header, *rest = path.read_text().splitlines(keepends=True)
    bad = tmp_path / "bad.json"
    bad.write_text(header.replace('"seed"', f'"players":{_json(players)},"seed"') + "".join(rest))
    assert main(["replay", str(bad)]) == 2
    assert "players must be 1 or 2" in capsys.readouterr().err


def _json(value) -> str:
    import json

    return json.dumps(value)


def test_the_score_bar_shows_both_scores_and_the_prompt_flashes_the_player_ups():
    one = World(seed=0)
    assert [t for t in hud_texts(one) if t[1:] == (168, 24)] == []  # SCORE<2> blank
    world = World(seed=0, players=2)
    world.add_score(30)
    _lose_a_ship(world)
    assert turn_texts(world) == []  # held: player 1 still has ships
    for _ in range(HOLD):
        world.step(0)
    assert turn_texts(world) == [("PLAY PLAYER<2>", 56, 112)]
    shown = []
    for _ in range(16):
        texts = {(x, y): m for m, x, y in hud_texts(world)}
        shown.append(texts.get((168, 24)))
        assert texts[(24, 24)] == "0030"
        world.step(0)
    assert set(shown) == {"0000", None}  # player 2's score flashes, 4 frames on, 4 off


def test_key_2_in_the_attract_cycle_starts_a_game_of_two(monkeypatch):
    from invaders.app.play import App
    from tests.helpers import FakeClock

    clock = FakeClock()
    app = App(World(seed=4), pygame.Surface((224, 256)), clock)
    app.step([pygame.event.Event(pygame.KEYDOWN, key=pygame.K_2)], 0)
    assert app.mode == "prompt" and app.session.world.players == 2
    through_the_prompt(app, clock)
    clock.now += 1 / 60
    app.step([], 0)
    assert app.session.world.tick > 0


def test_before_a_new_game_play_player_1_flashes_the_new_games_score_not_the_last_ones():
    from invaders.lab.picture import Prompt

    world = World(seed=0)
    world.score, world.hi_score = 450, 900  # the last game's
    on = {(x, y): m for m, x, y in hud_texts(world, Prompt(players=1, left=8))}
    off = {(x, y): m for m, x, y in hud_texts(world, Prompt(players=1, left=4))}
    assert on[(24, 24)] == "0000" and (24, 24) not in off and on[(88, 24)] == "0900"
    assert (168, 24) not in on  # one player: SCORE<2> blank
    two = {(x, y): m for m, x, y in hud_texts(world, Prompt(players=2, left=4))}
    assert two[(168, 24)] == "0000" and (24, 24) not in two



def _march(world: World, done: Callable[[World], bool]) -> list[int]:
    """The rack's steps across until `done(world)`."""
    return [dx for dx, _ in rack_moves(world, done)]


def _one_alien_left(world: World) -> None:
    step_until(world, lambda r: world.rack.live == 55 and world.cannon.state == 1, limit=400)
    for alien in world.rack.live_aliens()[1:]:
        world.rack.kill(alien, world.store)


def _round_the_turns(world: World) -> None:
    """Player 1 dies, player 2 plays and dies, and player 1's turn starts again."""
    for _ in range(2):
        _lose_a_ship(world)
        step_until(world, lambda r: Event.TURN_STARTED in r.events, limit=SWITCH_TICKS + 10)
    assert world.player == 1


def test_a_turn_starts_the_last_aliens_3_pixel_step_right_back_at_2():
    """InitRack (00C2) backs a kept step of 3 down to 2 at the start of a player's turn,
    until the next bump at the left edge sets it again."""
    world = World(seed=2, players=2)
    _one_alien_left(world)
    _march(world, lambda w: w.rack.dx == 3)  # bumped at the right edge, then the left
    _round_the_turns(world)
    assert world.rack.dx == 2
    steps = _march(world, lambda w: w.rack.dx == 3)  # right, left, and the left bump again
    assert [step for step, _ in itertools.groupby(steps)] == [2, -2, 3]


def test_a_players_new_wave_marches_with_the_step_they_left_their_last_turn_with():
    """The page keeps the step saved when its player last left for the other's turn, and
    InitRack starts each of their waves with it (09EF, 0814): a wave cleared after a turn
    left going left starts going left. A game of one saves none: right, as ever."""
    for players, first in ((2, -2), (1, 2)):
        world = World(seed=2, players=players)
        _one_alien_left(world)
        _march(world, lambda w: w.rack.dx < 0)  # turned at the right edge
        if players == 2:
            _round_the_turns(world)
            assert world.rack.dx == -2
            twin = copy.deepcopy(world)  # (the step kept decides the future: in the hash)
            twin.kept_dx = 2
            assert twin.state_hash() != world.state_hash()
        _march(world, lambda w: w.rack.dx > 0)  # going right again
        last = world.rack.live_aliens()[0]
        world.kill_alien(last, last.x + 8)
        step_until(world, lambda r: Event.WAVE_STARTED in r.events, limit=400)
        assert world.rack.dx == first and world.rack.ref_x == world.config.geometry.rack_left
        assert _march(world, lambda w: w.rack.ref_x != w.config.geometry.rack_left) == [first]
