"""Running the matrix: scenes as recorded frames, the oracle's truth, one row per cell.

A scene is recorded once (a replay played with the default pipeline, or a storm) and every
method is played the very same frames, sampled as the method asks; the oracle's truth is
taken at the full rate, so a method that looks less often is judged on what it missed.
"""

from __future__ import annotations

import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from invaders.engine.broadphase import Pair, Scene
from invaders.engine.response import first_contacts
from invaders.engine.rules import RuleTable
from invaders.engine.stats import CollisionStats, Contact
from invaders.game.config import DEFAULT_CONFIG
from invaders.game.replay import load
from invaders.game.rules import make_rules
from invaders.lab.frames import Frame, FrameScene, play_frames, sampled, snapshot
from invaders.lab.matrix import Method, detector_for
from invaders.lab.oracle import true_contacts
from invaders.lab.score import Scorer
from invaders.lab.storm import Storm, storm_rules

AUTO_CHOICES = (Method(broad="brute"), Method(broad="sweep"), Method(broad="numpy"),
                Method(broad="rects"), Method(cell=8), Method(cell=16),
                Method(cell=32), Method(cell=64))


@dataclass(frozen=True)
class SceneSpec:
    """What to record: a replay file (its first `ticks`), or a storm of `bodies`."""

    name: str
    ticks: int
    replay: str | None = None
    bodies: int = 0
    multiplier: int = 1
    seed: int = 0

    @classmethod
    def of_replay(cls, path: str | Path, ticks: int) -> SceneSpec:
        return cls(f"replay:{Path(path).stem}", ticks, replay=str(path))

    @classmethod
    def storm(cls, bodies: int, ticks: int, multiplier: int = 1, seed: int = 0) -> SceneSpec:
        return cls(f"storm{bodies}x{multiplier}", ticks, bodies=bodies, multiplier=multiplier,
                   seed=seed)


class FrameRecorder:
    """Observes a detector: snapshots every frame it is shown, with the contacts found."""

    def __init__(self) -> None:
        self.frames: list[Frame] = []

    def before(self, scene: Scene) -> None:
        pass

    def after(self, scene: Scene, candidates: Sequence[Pair], contacts: Sequence[Contact],
              stats: CollisionStats) -> None:
        self.frames.append(snapshot(scene, contacts))


def scene_rules(spec: SceneSpec) -> RuleTable:
    """The game's rules for the scene: a replay's config, or a storm's lane in every tile."""
    if spec.replay is not None:
        return make_rules(load(spec.replay).config)
    return storm_rules(make_rules(DEFAULT_CONFIG), spec.bodies)


def record(spec: SceneSpec) -> list[Frame]:
    """The scene's frames, from tick 0 (a replay as the default detector saw it)."""
    if spec.replay is not None:
        replay = load(spec.replay)
        world = replay.world()
        recorder = FrameRecorder()
        world.detector.observers.append(recorder)
        for n, bits in enumerate(replay.actions()):
            if n >= spec.ticks:
                break
            world.step(bits)
        return recorder.frames
    storm = Storm(spec.bodies, spec.seed, spec.multiplier)
    frames = [snapshot(storm.store)]
    for _ in range(spec.ticks - 1):
        storm.advance()
        frames.append(snapshot(storm.store))
    return frames


def truth(frames: list[Frame], rules: RuleTable) -> list[set[tuple[int, int]]]:
    """The oracle's first contacts of every frame, as pairs."""
    scene = FrameScene()
    out = []
    for frame in frames:
        scene.load(frame)
        out.append({(c.a_id, c.b_id) for c in true_contacts(scene.store, rules)})
    return out


BRUTE_TRIAL_LIMIT = 400  # bodies: brute force (and in C, the rects) not tried on bigger scenes


def choose_broadphase(frames: list[Frame], multiplier: int, rules: RuleTable) -> Method:
    """The fastest broad phase on the scene's first frames (all give the same contacts):
    brute force where the scene is too small for anything else to pay."""
    bodies = sum(len(v) for v in frames[0].bodies.values())
    probe = 40 if bodies <= 1000 else 4
    best = None
    for method in AUTO_CHOICES:
        if method.broad in ("brute", "rects") and bodies > BRUTE_TRIAL_LIMIT:
            continue
        seconds = _play(method, frames[:probe], multiplier, rules)[0]
        if best is None or seconds < best[0]:
            best = (seconds, method)
    assert best is not None
    return best[1]


def _play(method: Method, frames: list[Frame], multiplier: int, rules: RuleTable):
    """Seconds, the contacts that happen (as pairs) per frame, and the counters summed."""
    seconds, found, totals = play_frames(detector_for(method, multiplier, rules=rules), frames)
    return seconds, [{(c.a_id, c.b_id) for c in first_contacts(contacts)}
                     for contacts in found], totals


def run_cell(spec: SceneSpec, method: Method, frames: list[Frame],
             truths: list[set[tuple[int, int]]], repeat: int = 1,
             rules: RuleTable | None = None) -> dict:
    """Time (the median of `repeat` plays) and score one method on one scene: a CSV row."""
    rules = rules if rules is not None else scene_rules(spec)
    chosen = method
    if method.broad == "grid" and method.cell == 0:
        chosen = choose_broadphase(frames, spec.multiplier, rules)
    k = method.sampling
    play = sampled(frames, k)
    concrete = Method(chosen.broad, chosen.cell, method.quick, method.thorough, method.motion, k)
    seconds, reported, totals = _play(concrete, play, spec.multiplier, rules)
    if repeat > 1:  # the median of the plays, never the best of them
        plays = [seconds] + [_play(concrete, play, spec.multiplier, rules)[0]
                             for _ in range(repeat - 1)]
        seconds = statistics.median(plays)
    scorer = Scorer()
    for n, pairs in enumerate(reported):
        last = n * k + k - 1
        for t in range(last - k + 1, last + 1):
            scorer.truth(t, truths[t])
        scorer.reported(last - k, last, pairs)
    score = scorer.finish()
    ticks = len(play) * k
    bodies = sum(sum(len(v) for v in f.bodies.values()) for f in frames) / len(frames)
    row = {
        "scene": spec.name, "bodies": round(bodies, 1), "multiplier": spec.multiplier,
        "method": method.label, "broad": chosen.broad,
        "cell": chosen.cell if chosen.broad == "grid" else "",
        "quick": method.quick, "thorough": method.thorough, "motion": method.motion,
        "sampling": k, "ticks": ticks, "detections": len(play),
        "us_per_detection": round(1e6 * seconds / max(1, len(play)), 3),
        "us_per_tick": round(1e6 * seconds / max(1, ticks), 3),
        "true": score.true, "on_time": score.on_time, "late": score.late,
        "missed": score.missed, "false": score.false,
        "error_rate": round(score.errors / score.true, 6) if score.true else 0.0,
    }
    names = ("objects", "naive_pairs", "allowed_pairs", "candidates", "rect_tests",
             "rect_hits", "mask_tests", "mask_hits", "swept_tests", "contacts")
    row.update({name: value for name, value in zip(names, totals, strict=True)
                if name in ("candidates", "rect_tests", "mask_tests", "swept_tests")})
    return row


def run_scene(spec: SceneSpec, methods: list[Method], repeat: int = 1) -> list[dict]:
    """Record a scene once and run every method on it (one unit of parallel work)."""
    frames = record(spec)
    rules = scene_rules(spec)
    truths = truth(frames, rules)
    return [run_cell(spec, method, frames, truths, repeat, rules) for method in methods]
