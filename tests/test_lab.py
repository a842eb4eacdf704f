"""The lab, live: switching methods while a game runs, watching each fail against the oracle
in shadow, and reproducing a lab session from its recording. Windows on SDL's dummy driver."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pygame
import pytest

from invaders.app.cli import main
from invaders.app.recording import Recorder, save_replay
from invaders.engine.adaptive import make_broadphase
from invaders.engine.detector import Detector
from invaders.game.actions import Action
from invaders.game.replay import load, run
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from invaders.lab.bench import FramePlayer, detection_round, play_game
from invaders.lab.frames import FrameScene, play_frames, sampled
from invaders.lab.live import Choice, LabDetector, Sampler, install, replay_switch
from invaders.lab.references import prepare
from invaders.lab.runner import FrameRecorder, SceneSpec, record, run_cell, scene_rules, truth
from tests.helpers import active_world, windowed

REPLAYS = Path(__file__).resolve().parents[1] / "replays"
RIGHT, FIRE = int(Action.RIGHT), int(Action.FIRE)


def _key(key: int, shift: bool = False) -> pygame.event.Event:
    return pygame.event.Event(pygame.KEYDOWN, key=key, mod=pygame.KMOD_SHIFT if shift else 0,
                              unicode="", scancode=0)


def _frames(session, clock, n: int) -> None:
    for _ in range(n):
        clock.now += 1 / 60
        session.frame(0)


@pytest.mark.parametrize("key, name", [
    (pygame.K_b, "broad"), (pygame.K_RIGHTBRACKET, "cell"), (pygame.K_LEFTBRACKET, "cell"),
    (pygame.K_q, "quick"), (pygame.K_t, "thorough"), (pygame.K_o, "motion"),
    (pygame.K_k, "sampling"), (pygame.K_EQUALS, "speed")])
def test_each_lab_key_changes_one_choice_and_the_detector_from_the_next_tick(key, name):
    world = World(seed=1)
    session, clock = windowed(world)
    session.handle(_key(pygame.K_F4))
    _frames(session, clock, 30)
    before, detector, state = session.lab.choice, world.detector, world.state_hash()
    session.handle(_key(key))
    after = session.lab.choice
    changed = {f.name for f in dataclasses.fields(Choice)
               if getattr(before, f.name) != getattr(after, f.name)}
    assert changed == {name}
    assert world.state_hash() == state  # nothing else changed: no tick ran
    assert world.detector is not detector and world.detector.choice == after
    _frames(session, clock, 1)
    assert session.report.tick == 30  # the next tick ran with it
    assert session.report.broadphase == after.broad
    assert world.config.speeds.shot == 4 * after.speed


def test_shift_steps_a_choice_back_and_sizes_stop_at_their_ends():
    world = World(seed=1)
    session, _ = windowed(world, lab=Choice(speed=16))
    session.handle(_key(pygame.K_EQUALS))
    assert session.lab.choice.speed == 16
    session.handle(_key(pygame.K_o, shift=True))
    assert session.lab.choice.motion == "swept"  # auto, back round to the last


def test_closing_the_lab_on_the_default_method_gives_the_game_its_own_detector_back():
    world = World(seed=1)
    session, _ = windowed(world)
    session.handle(_key(pygame.K_F4))
    assert isinstance(world.detector, LabDetector)
    session.handle(_key(pygame.K_F4))
    assert type(world.detector) is Detector and world.detector.observers == []


def test_a_detector_put_away_is_fed_no_more():
    """Switching the world from its grid to a sampled method (which detects on a scene of
    its own) or to brute force, and back and forth: the grids put away are fed no moves
    (their buffers stay empty, where they grew every tick before)."""
    for choice in (Choice(sampling=4), Choice(broad="brute")):
        world = World(seed=3)
        for _ in range(200):
            world.step(RIGHT | FIRE)
        old = world.detector.broadphase
        install(world, choice, world.config)
        install(world, Choice(), world.config, shadow=False)  # the game's own, back
        returned = world.detector.broadphase
        install(world, choice, world.config)
        for _ in range(300):
            world.step(RIGHT | FIRE)
        assert old.move_buffer == [] and returned.move_buffer == []
        assert world.store.listener is not old and world.store.listener is not returned


def _shot_through_the_first_shield(choice: Choice):
    """Under the first shield's fifth column, fire once at the choice's speeds."""
    world = active_world()
    detector = install(world, choice, world.config)
    shield = world.bunkers[0]
    column = shield.x + 4
    while world.cannon.x + 8 < column:  # the shot leaves the cannon 8 px from its left
        world.step(RIGHT)
    world.step(FIRE)
    assert world.shot is not None and world.shot.x == column
    pixels = shield.mask.count()
    for _ in range(3):
        world.step(0)
    return world, detector, shield, pixels


def test_at_8x_all_discrete_a_shot_passes_through_a_shield_and_the_miss_is_marked():
    world, detector, shield, pixels = _shot_through_the_first_shield(
        Choice(motion="discrete", speed=8))
    assert shield.mask.count() == pixels  # not a pixel eroded: it went through
    x = world.bunkers[0].x + 4
    # The shot (one pixel wide) going up first touches the column's lowest solid pixel.
    lowest = max(y for y in range(shield.h) if shield.mask.get_at((x - shield.x, y)))
    missed = [m for m in detector.shadow.marks if m.outcome == "missed"]
    assert (missed[0].x, missed[0].y) == (x, shield.y + lowest)
    assert detector.shadow.score.missed >= 1


def test_the_default_method_stops_the_same_shot_at_the_shield_with_no_error():
    _, detector, shield, pixels = _shot_through_the_first_shield(Choice(speed=8))
    score = detector.shadow.score
    assert shield.mask.count() < pixels
    assert (score.true, score.on_time, score.errors) == (1, 1, 0)
    assert list(detector.shadow.marks) == []


def test_the_live_shadow_scores_as_the_study_does_on_the_same_frames():
    """A method that errs at the game's speed, on a recorded game: the lab's live figures
    are the study's for the frames the game showed it."""
    replay = load(REPLAYS / "wave-cleared.json")
    choice = Choice(quick="circle", thorough="none", motion="discrete")
    world = World(replay.seed, replay.config)
    detector = install(world, choice, world.config)
    recorder = FrameRecorder()
    detector.observers.append(recorder)
    for bits, _ in zip(replay.actions(), range(1500), strict=False):
        world.step(bits)
    live = detector.shadow.finish()
    spec = SceneSpec("live", 1500)
    row = run_cell(spec, choice.method, recorder.frames,
                   truth(recorder.frames, world.rules), rules=world.rules)
    assert live.errors > 0
    assert (row["true"], row["on_time"], row["late"], row["missed"], row["false"]) == (
        live.true, live.on_time, live.late, live.missed, live.false)


def test_a_detector_that_looks_every_kth_tick_sees_what_the_study_samples():
    world = World(seed=3)
    recorder = FrameRecorder()
    world.detector.observers.append(recorder)
    pilot = Autopilot(3)
    for _ in range(400):
        world.step(pilot.actions(world))
    frames = recorder.frames
    for k in (2, 4, 8):
        sampler, scene = Sampler(k), FrameScene()
        views = []
        for frame in frames:
            scene.load(frame)
            if sampler.due(frame.tick):
                view = sampler.view(scene.store)
                views.append(sorted((b.id, b.x, b.y, *b.start_of_tick(view.tick))
                                    for b in view.by_id.values()))
        expected = [sorted((row[0], row[1], row[2], *((row[3], row[4]) if row[5] == n
                                                     else (row[1], row[2])))
                           for rows in f.bodies.values() for row in rows)
                    for n, f in enumerate(sampled(frames, k))]
        assert views == expected


def test_a_lab_session_plays_back_from_its_recording(tmp_path):
    world = World(seed=3)
    recorder = Recorder(world)
    session, clock = windowed(world, recorder=recorder, pilot=Autopilot(3))
    session.handle(_key(pygame.K_F4))
    _frames(session, clock, 200)
    switched = [world.tick] * 4
    for key in (pygame.K_o, pygame.K_EQUALS, pygame.K_EQUALS, pygame.K_EQUALS):
        session.handle(_key(key))  # all discrete, then 8x
    _frames(session, clock, 800)
    switched.append(world.tick)
    session.handle(_key(pygame.K_k))
    _frames(session, clock, 400)
    assert session.lab.detector.shadow.score.missed > 0  # it did fail, and the game went on
    path = tmp_path / "lab.json"
    save_replay(path, recorder.finished())
    replay = load(path)
    assert [t for t, _ in replay.switches] == switched
    result, _ = run(replay, switch=replay_switch(replay.config))
    assert result.mismatch is None and result.final.hash == world.state_hash()
    assert main(["replay", str(path)]) == 0
    watched = World(replay.seed, replay.config)
    viewer, clock = windowed(watched, replay=replay)
    _frames(viewer, clock, replay.ticks + 5)
    assert viewer.replay_verdict() == "CHECKPOINTS MATCHED"
    assert viewer.lab_open and viewer.lab.choice == session.lab.choice


def test_a_replay_with_a_switch_the_lab_cannot_make_is_refused_in_one_line(tmp_path, capsys):
    world = World(seed=3)
    recorder = Recorder(world)
    recorder.switch({"motion": "teleport"})
    for _ in range(120):
        world.step(0)
        recorder.tick(0)
    path = tmp_path / "bad.json"
    save_replay(path, recorder.finished())
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "lab switch at tick 0: lab choice motion must be one of" in err[0]


def test_a_recording_stops_at_the_lab_switch_limit_and_the_file_replays(tmp_path, capsys,
                                                                         monkeypatch):
    """The limit lowered to 5 switches (10,000 in the program): the checkpoint whose line
    would hold the sixth is not written, recording stops with one line, and the file (4
    switches) replays; two switches more in the file are refused by its reader."""
    from invaders.game import recording, replay_checks

    for module in (recording, replay_checks):
        monkeypatch.setattr(module, "MAX_SWITCHES", 5)
    world, path = World(seed=3), tmp_path / "switched.json"
    recorder = Recorder(world, path, save_every=60)
    choices, apply = [Choice(speed=speed).to_dict() for speed in (1, 2)], replay_switch(
        world.config)
    for tick in range(1, 600):
        if tick % 50 == 0:  # as the lab's panel does
            apply(world, choices[tick // 50 % 2])
            recorder.switch(choices[tick // 50 % 2])
        world.step(0)
        recorder.tick(0)
    recorder.save()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "recording stopped at tick 240" in err[0] and "5 lab" in err[0]
    replay = load(path)  # (the line to 300 would have held switches 249 and 299)
    assert [tick for tick, _ in replay.switches] == [49, 99, 149, 199]
    assert run(replay, switch=replay_switch(replay.config))[0].mismatch is None
    lines = path.read_text().splitlines()
    extra = json.loads(lines[-1])
    extra["lab"] += [[extra["checkpoint"]["tick"] - 1, choices[0]]] * 2
    path.write_text("\n".join([*lines[:-1], json.dumps(extra)]) + "\n")
    assert main(["replay", str(path)]) == 2
    assert "more than 5 lab switches" in capsys.readouterr().err


def test_run_reports_the_shadows_running_score_in_its_columns(tmp_path, capsys):
    report = tmp_path / "r.csv"
    assert main(["run", "--autopilot", "--ticks", "1500", "--seed", "3", "--motion",
                 "discrete", "--speed-mult", "8", "--shadow", "--report", str(report)]) == 0
    printed = next(line for line in capsys.readouterr().out.splitlines()
                   if line.startswith("shadow ("))
    header, *rows = report.read_text().splitlines()
    names = header.split(",")
    last = dict(zip(names, rows[-1].split(","), strict=True))
    true, on_time, missed = (int(last[f"shadow_{n}"]) for n in ("true", "on_time", "missed"))
    assert missed > 0 and f"{true} true contacts; on time {on_time}" in printed


def test_the_panel_shows_each_counter_last_and_as_its_median_over_a_second():
    import statistics

    from invaders.app.labpanel import panel_lines

    world = World(seed=3)
    session, clock = windowed(world, pilot=Autopilot(3), lab=Choice())
    objects = []
    for _ in range(200):
        clock.now += 1 / 60
        session.frame(0)
        objects.append(session.report.stats.objects)
    detector = session.lab.detector
    assert detector.counter_medians().objects == statistics.median(objects[-60:])
    line = next(text for text, _ in panel_lines(session.lab) if text.startswith("objects"))
    assert line.split()[1:] == [str(objects[-1]), f"{statistics.median(objects[-60:]):g}"]


def test_watching_and_timing_the_default_method_changes_nothing_in_the_game():
    import time

    plain, watched = World(seed=5), World(seed=5)
    detector = install(watched, Choice(), watched.config, shadow=True, clock=time.perf_counter)
    pilots = Autopilot(5), Autopilot(5)
    for _ in range(1500):
        for world, pilot in zip((plain, watched), pilots, strict=True):
            world.step(pilot.actions(world))
    assert detector.shadow.score.true > 0 and detector.timings()[1] > 0
    assert watched.state_hash() == plain.state_hash()


def test_the_bench_playing_storm_frames_by_turns_finds_what_a_whole_playback_finds():
    spec = SceneSpec.storm(300, 6, multiplier=4)
    frames, rules = record(spec), scene_rules(spec)
    _, expected, _ = play_frames(Detector(make_broadphase("brute"), rules), frames, untimed=1)
    assert sum(map(len, expected)) > 20
    players = [FramePlayer(name, frames, rules) for name in ("grid", "rects", "numpy", "auto")]
    for index in range(1, len(frames)):
        for player in players if index % 2 else players[::-1]:  # turns, as the bench takes
            player.frame_seconds(index)
    for player in players:
        assert player.found == expected


def test_the_bench_times_ours_and_groupcollide_by_turns_and_each_finds_the_games_contacts():
    frames = play_game(900, 3, "grid", record=True)[2]
    seconds, ours, theirs = detection_round(frames, prepare(frames), 1)
    assert set(seconds) == {"ours", "grid", "naive", "careful"}
    assert ours == [frame.contacts for frame in frames]
    pairs = [{(c.a_id, c.b_id) for c in frame.contacts} for frame in frames]
    assert theirs["naive"] == theirs["careful"] == pairs
    assert any(pairs)


def test_the_bench_holds_group_collide_to_pygames_answer_and_a_wrong_one_misses_its_goal(
        capsys):
    """Section 5's GroupCollide rows: a row for each size and motion where the answer is
    pygame's (swept: holds pygame's), and a collider that finds nothing is told apart at
    10 a side, where pygame finds a touch in each motion, and fails the goal."""
    from invaders.lab.bench import Goals
    from invaders.lab.bench_sprites import COLLIDER_MOTIONS, collider_table

    goal = Goals(3)
    collider_table(3, goal, largest=10)
    printed = capsys.readouterr().out
    assert "WARNING" not in printed
    for n in (1, 5, 10):
        for motion in COLLIDER_MOTIONS:
            assert f"{n:>5} a side  {motion:<6} GroupCollide" in printed
    wrong = Goals(3)
    collider_table(3, wrong, largest=10, make=lambda: lambda a, b: {})
    printed = capsys.readouterr().out
    for motion in COLLIDER_MOTIONS:
        assert f"WARNING 10 a side, {motion}, GroupCollide: a different result" in printed
    assert wrong.missed == 1 and "goal GroupCollide faster" in printed


def test_the_labs_broad_phases_are_the_engines_and_the_cell_applies_where_it_is_used():
    from invaders.engine.adaptive import BROADPHASES, DEFAULT_BROADPHASE
    from invaders.lab.choices import BROADS, CELLED

    assert BROADS == BROADPHASES and BROADS[0] == DEFAULT_BROADPHASE
    for name in BROADS:
        assert (make_broadphase(name, 48).cell == 48) == (name in CELLED), name


def test_the_panels_counts_add_up_while_contacts_are_still_touching():
    """true = on time + late + missed on every frame: a contact that has begun but not
    ended is shown as touching now, not as a true one yet unjudged (it once showed
    'true 1, on time 0' with nothing missed, late or false)."""
    from invaders.app.labpanel import panel_lines

    world = World(seed=4)
    session, clock = windowed(world, pilot=Autopilot(4), lab=Choice())
    seen_touching = False
    for _ in range(900):
        clock.now += 1 / 60
        session.frame(0)
        lines = [text for text, _ in panel_lines(session.lab)]
        head = next(line for line in lines if line.startswith("true")).split()
        true, on_time = int(head[1]), int(head[4])
        count = {line.split()[0]: int(line.split()[1]) for line in lines
                 if line.split()[0] in ("missed", "late")}
        assert true == on_time + count["missed"] + count["late"]
        seen_touching |= "now" in head
    assert seen_touching and true > 5


@pytest.mark.parametrize("scale", [1, 2, 3])
def test_every_line_of_the_panel_shows_whole_and_legible_at_every_scale(scale):
    import time

    from invaders.app.labpanel import LEGIBLE_PX, LabControl, PanelPainter, panel_lines, panel_width

    world = World(seed=1)
    control = LabControl(world, time.perf_counter)
    area = pygame.Rect(224 * scale, 0, panel_width(scale), 256 * scale)
    target = pygame.Surface((area.right, area.h))
    placed = PanelPainter().draw(target, area, control, scale)
    assert [text for text, _, _ in placed] == [text for text, _ in panel_lines(control)]
    assert all(area.contains(rect) for _, rect, _ in placed)
    assert min(size for _, _, size in placed) >= LEGIBLE_PX
    rows: dict[int, list[pygame.Rect]] = {}
    for _, rect, _ in placed:  # side by side in a row, never over one another
        rows.setdefault(rect.top, []).append(rect)
    assert all(not a.colliderect(b) for row in rows.values() for i, a in enumerate(row)
               for b in row[i + 1:])
    assert len(rows) * max(len(row) for row in rows.values()) >= len(placed)
