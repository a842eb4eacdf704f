"""The lab in the window: switch the collision method while playing, and see what it misses.

`LabControl` owns the lab's side of a game: the choice, putting it into the world (from the
next tick), telling a recording, and the keys. `PanelPainter` paints the panel beside the
playfield at the window's resolution; `draw_marks` rings each error the oracle found where
it should have happened: missed in red, late in orange, false in yellow, fading over a
second. Detection is timed with the clock the window runs on (never the simulation's).
"""

from __future__ import annotations

from collections.abc import Callable

import pygame

from invaders.app.recording import Recorder
from invaders.app.render import View
from invaders.game.config import SCREEN_H, GameConfig
from invaders.game.world import World
from invaders.lab.choices import CELLED
from invaders.lab.live import DEFAULT_CHOICE, MARK_TICKS, Choice, LabDetector, install

# key -> (choice, step): the panel lists them, so any key here is shown to the player
KEYS: dict[int, tuple[str, int]] = {
    pygame.K_b: ("broad", 1),
    pygame.K_LEFTBRACKET: ("cell", -1),
    pygame.K_RIGHTBRACKET: ("cell", 1),
    pygame.K_q: ("quick", 1),
    pygame.K_t: ("thorough", 1),
    pygame.K_o: ("motion", 1),
    pygame.K_k: ("sampling", 1),
    pygame.K_MINUS: ("speed", -1),
    pygame.K_EQUALS: ("speed", 1),
}
MARK_COLOURS = {"missed": (255, 40, 40), "late": (255, 150, 0), "false": (255, 240, 0)}
PANEL_BACKGROUND = (16, 16, 24)
TEXT = (230, 230, 230)
DIM = (140, 140, 150)
PANEL_PX_PER_SCALE = 112  # the panel is half a playfield wide,
PANEL_MIN_PX = 260  # and never too narrow for its lines at the smallest text
PANEL_TEXT_PX = 14  # the text's size at the smallest scales,
MIN_TEXT_PX = 8  # and how small it may get to fit a short window
LEGIBLE_PX = 12  # below this, two columns rather than smaller text
TWO_COLUMNS_PX = 430  # a panel wide enough for two columns of legible text
ONE_COLUMN_MIN_H = 400  # a playfield shorter than this (scale 1) needs the two columns


class LabControl:
    """The lab of one game: its choice, its detector in the world, its keys."""

    def __init__(self, world: World, clock: Callable[[], float], choice: Choice = DEFAULT_CHOICE,
                 recorder: Recorder | None = None, base: GameConfig | None = None) -> None:
        self.world = world
        self.clock = clock
        self.recorder = recorder
        self.base = base or world.config  # the game's speeds; a lab multiplies them
        self.choice = choice
        self.since = world.tick
        self.detector: LabDetector = self._install(choice)
        if recorder is not None and choice != DEFAULT_CHOICE:
            recorder.switch(choice.to_dict())  # the game starts with another method

    def _install(self, choice: Choice) -> LabDetector:
        detector = install(self.world, choice, self.base, shadow=True, clock=self.clock)
        assert isinstance(detector, LabDetector)  # watched: always the lab's detector
        return detector

    def switch(self, choice: Choice, record: bool = True) -> None:
        """Use `choice` from the next tick (a recording notes it); the count starts over."""
        if choice == self.choice:
            return
        self.choice = choice
        self.since = self.world.tick
        self.detector = self._install(choice)
        if record and self.recorder is not None:
            self.recorder.switch(choice.to_dict())

    def key(self, key: int, shift: bool = False) -> bool:
        """A lab key (Shift steps back): whether it was one."""
        entry = KEYS.get(key)
        if entry is None:
            return False
        name, step = entry
        self.switch(self.choice.cycled(name, -step if shift else step))
        return True

    def reopen(self) -> None:
        """Watched and timed again, the count started over."""
        self.since = self.world.tick
        self.detector = self._install(self.choice)

    def close(self) -> None:
        """Back to the game's own detector if the method is the game's own; another method
        stays in force, unwatched and untimed (the lab off costs nothing)."""
        install(self.world, self.choice, self.base, shadow=False)


def panel_width(scale: float) -> int:
    """Half a playfield wide; at the smallest scales, wide enough for two columns."""
    if SCREEN_H * scale < ONE_COLUMN_MIN_H:
        return TWO_COLUMNS_PX
    return max(PANEL_MIN_PX, round(PANEL_PX_PER_SCALE * scale))


def panel_lines(control: LabControl) -> list[tuple[str, tuple[int, int, int]]]:
    """The panel's text, top to bottom, each line with its colour."""
    c = control.choice
    d = control.detector
    lines = [("LAB   F4 closes", TEXT), ("with Shift: a step back", DIM)]
    rows = [("B", "broad phase", c.broad),
            ("[ ]", "grid cell", f"{c.cell} px" if c.broad in CELLED else "-"),
            ("Q", "quick test", c.quick),
            ("T", "thorough", c.thorough),
            ("O", "motion", "as proven" if c.motion == "auto" else f"all {c.motion}"),
            ("K", "sampling", f"every {c.sampling} tick" + ("s" if c.sampling > 1 else "")),
            ("- =", "speed", f"x{c.speed}")]
    lines += [(f"{key:<4}{name:<12}{value}", TEXT) for key, name, value in rows]
    lines.append((f"since tick {control.since}" + ("  (default)" if c.is_default else ""),
                  DIM))
    score = d.shadow.score if d.shadow is not None else None
    if score is not None:
        # A contact is counted true when it begins and judged when it ends: the counts
        # shown are the judged ones (true = on time + late + missed, always), with those
        # still touching beside them.
        judged = score.on_time + score.late + score.missed
        still = score.true - judged
        rate = f"{score.errors / judged:.3f}" if judged else "-"
        lines += [(f"true {judged:<6} on time {score.on_time}"
                   + (f"  +{still} now" if still else ""), TEXT),
                  (f"missed {score.missed}", MARK_COLOURS["missed"]),
                  (f"late   {score.late}", MARK_COLOURS["late"]),
                  (f"false  {score.false}", MARK_COLOURS["false"]),
                  (f"errors per true contact {rate}", TEXT)]
    last, mid, ratio = d.timings()
    lines += [(f"detection  {last * 1e6:8.1f} us", TEXT),
              (f"1 s median {mid * 1e6:8.1f} us", TEXT),
              (f"vs default {'1.00x' if ratio is None else f'{ratio:.2f}x':>8}", TEXT)]
    s, m = d.stats, d.counter_medians()
    lines.append((f"{'counters':<11}{'last':>6}{'1 s':>7}", DIM))
    lines += [(f"{name:<11}{getattr(s, field):>6}{getattr(m, field):>7g}", TEXT)
              for name, field in (("objects", "objects"), ("rules", "allowed_pairs"),
                                  ("broad", "candidates"), ("rect tests", "rect_tests"),
                                  ("mask tests", "mask_tests"), ("swept", "swept_tests"),
                                  ("contacts", "contacts"))]
    return lines


class PanelPainter:
    """Keeps the panel's fonts by size."""

    def __init__(self) -> None:
        self._fonts: dict[int, pygame.font.Font] = {}

    def font(self, size: int) -> pygame.font.Font:
        font = self._fonts.get(size)
        if font is None:
            pygame.font.init()
            font = self._fonts[size] = (pygame.font.SysFont("monospace", size)
                                        or pygame.font.Font(None, size))
        return font

    def draw(self, target: pygame.Surface, area: pygame.Rect, control: LabControl,
             scale: float) -> list[tuple[str, pygame.Rect, int]]:
        """The panel in `area`, its text as large as the scale asks and small enough for
        every line to fit, across and down (in two columns where one would need text below
        legible). Returns each line, where it went, and the text's size."""
        target.fill(PANEL_BACKGROUND, area)
        lines = panel_lines(control)
        size, columns = self._layout([text for text, _ in lines], area, scale)
        font = self.font(size)
        pad = max(4, size // 2)
        per_column = -(-len(lines) // columns)
        width = (area.w - pad) // columns
        placed = []
        for number, (text, colour) in enumerate(lines):
            column, row = divmod(number, per_column)
            at = (area.x + pad + column * width, area.y + pad + row * font.get_linesize())
            rendered = font.render(text, True, colour)
            target.blit(rendered, at)
            placed.append((text, rendered.get_rect(topleft=at), size))
        return placed

    def _layout(self, texts: list[str], area: pygame.Rect, scale: float) -> tuple[int, int]:
        """The text size and how many columns: the largest size that fits in one column,
        or, if that is below legible, in two."""
        best = (MIN_TEXT_PX, 1)
        for columns in (1, 2):
            per_column = -(-len(texts) // columns)
            widest = max(texts, key=len)
            size = max(PANEL_TEXT_PX, round(4.2 * scale))
            while size > MIN_TEXT_PX:
                font = self.font(size)
                pad = max(4, size // 2)
                if (font.get_linesize() * per_column + 2 * pad <= area.h
                        and columns * (font.size(widest)[0] + pad) + pad <= area.w):
                    break
                size -= 1
            if size >= LEGIBLE_PX:
                return size, columns
            best = max(best, (size, columns))
        return best


def draw_marks(target: pygame.Surface, view: View, control: LabControl) -> None:
    """A ring where each error the shadow found should have happened, fading as it ages."""
    shadow = control.detector.shadow
    if shadow is None:
        return
    now = control.world.tick
    radius = max(4, round(5 * view.scale))
    width = max(2, round(view.scale))
    for mark in shadow.marks:
        left = 1 - (now - mark.tick) / MARK_TICKS
        if left <= 0:
            continue
        colour = tuple(round(c * left) for c in MARK_COLOURS[mark.outcome])
        pygame.draw.circle(target, colour, view.to_window(mark.x + 0.5, mark.y + 0.5), radius,
                           width)
