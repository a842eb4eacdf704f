"""The text a headless run prints: the game, the counters per pipeline step, the hash last."""

from __future__ import annotations

from invaders.app.headless import RunResult
from invaders.engine.stats import STAT_FIELDS

LABELS = {
    "objects": "objects",
    "naive_pairs": "naive pairs n(n-1)/2",
    "allowed_pairs": "1 reduce: rules allow",
    "candidates": "1 reduce: broad phase",
    "rect_tests": "2 quick: rect tests",
    "rect_hits": "2 quick: rect hits",
    "mask_tests": "3 thorough: mask tests",
    "mask_hits": "3 thorough: mask hits",
    "swept_tests": "3 thorough: swept tests",
    "contacts": "4 respond: contacts",
}


def _share(part: float, whole: float) -> str:
    return "-" if whole == 0 else f"{100.0 * part / whole:.2f}%"


def summary_lines(result: RunResult, seed: int, broadphase: str, source: str) -> list[str]:
    """Human-readable summary; the state hash is the caller's last line."""
    world = result.world
    totals = result.table.totals()
    medians = result.table.medians()
    ev = result.events
    lines = [
        f"ran {result.table.count} ticks, seed {seed}, broad phase {broadphase}, input {source}",
        f"score {world.score}  hi-score {world.hi_score}  "
        f"aliens killed {world.aliens_killed}  ships {world.ships}  wave {world.wave}  "
        f"games {world.games}  phase {world.phase.name.lower()}",
        f"events: saucer hits {ev['SAUCER_HIT']}, cannon hits {ev['CANNON_HIT']}, "
        f"shield hits {ev['BUNKER_HIT']}, waves cleared {ev['WAVE_CLEARED']}, "
        f"invasions {ev['INVASION']}",
        f"{'pipeline step':<28}{'total':>12}{'median/tick':>13}",
    ]
    for name in STAT_FIELDS:
        lines.append(f"  {LABELS[name]:<26}{totals[name]:>12}{medians[name]:>13g}")
    naive = medians["naive_pairs"]
    lines.append(
        f"median broad-phase candidates are {_share(medians['candidates'], naive)} of the "
        f"median naive pairs; rules keep {_share(totals['allowed_pairs'], totals['naive_pairs'])}"
        f" of all pairs, the broad phase {_share(totals['candidates'], totals['allowed_pairs'])}"
        " of those")
    return lines
