"""The recorded games in replays/ show what their names promise (and still replay exactly)."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

from invaders.game.config import DEFAULT_CONFIG
from invaders.game.events import Event
from invaders.game.kinds import Kind
from invaders.game.replay import load
from invaders.game.world import World

REPLAYS = Path(__file__).resolve().parents[1] / "replays"


def _play(name: str) -> tuple[World, Counter, dict]:
    replay = load(REPLAYS / name)
    assert replay.ticks >= 3600  # a minute or more
    world = World(replay.seed, replay.config)
    seen: Counter = Counter()
    notes: dict = {}
    expected = {c.tick: c.hash for c in replay.checkpoints}
    for bits in replay.actions():
        report = world.step(bits)
        for contact in report.contacts:
            seen[frozenset({contact.a_kind, contact.b_kind})] += 1
        for event in report.events:
            seen[event] += 1
            if event is Event.SAUCER_HIT:
                seen[("saucer", world.saucer.hit_score)] += 1
            if event is Event.WAVE_STARTED:
                notes.setdefault("starts", []).append((world.wave, world.rack.ref_top))
            if event is Event.INVASION:
                notes["ships_at_invasion"] = world.ships
            if event is Event.CANNON_HIT:
                notes.setdefault("deaths", []).append(world.tick)
            if event is Event.SHIP_LOST and world.ships > 0:
                notes.setdefault("respawns", []).append(world.tick)
        if world.tick in expected:
            assert world.state_hash() == expected[world.tick], (name, world.tick)
    return world, seen, notes


def test_a_wave_is_cleared():
    _, seen, notes = _play("wave-cleared.json")
    assert seen[Event.WAVE_CLEARED] >= 1
    assert (2, DEFAULT_CONFIG.start_top(2)) in notes["starts"]


def test_the_cannon_dies_and_a_new_one_comes():
    _, seen, notes = _play("cannon-death.json")
    assert seen[frozenset({Kind.CANNON, Kind.BOMB})] >= 1
    assert notes["respawns"]


def test_a_saucer_hit_is_worth_300():
    _, seen, _ = _play("saucer-300.json")
    assert seen[("saucer", 300)] >= 1


def test_shields_are_eroded_by_shots_bombs_and_low_aliens():
    _, seen, _ = _play("shields-eroded.json")
    assert seen[frozenset({Kind.SHOT, Kind.BUNKER})] >= 1
    assert seen[frozenset({Kind.BOMB, Kind.BUNKER})] >= 1
    assert seen[frozenset({Kind.ALIEN, Kind.BUNKER})] >= 1


def test_an_invasion_ends_the_game_with_ships_left():
    _, seen, notes = _play("invasion.json")
    assert seen[Event.INVASION] == 1
    assert notes["ships_at_invasion"] >= 2


@pytest.mark.parametrize("name", ["second-wave.json", "wave-cleared.json"])
def test_the_second_wave_starts_at_its_own_height(name):
    world, _, notes = _play(name)
    assert (2, 152) in notes["starts"]
    assert world.wave == 2


def test_each_replay_is_what_the_command_beside_it_makes(tmp_path, capsys):
    """Byte for byte: a change that plays the autopilot's games differently (or writes
    files differently) shows here, not only in games that happen to replay."""
    import re

    from invaders.app.cli import main

    table = (REPLAYS / "README.md").read_text()
    commands = re.findall(r"`invaders (run [^`]*--record replays/([\w-]+\.json))`", table)
    assert sorted(name for _, name in commands) == sorted(p.name for p in REPLAYS.glob("*.json"))
    for command, name in commands:
        words = command.replace("replays/", f"{tmp_path}/").split()
        assert main(words) == 0
        assert (tmp_path / name).read_bytes() == (REPLAYS / name).read_bytes(), name
    capsys.readouterr()
