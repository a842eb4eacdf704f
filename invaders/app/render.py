"""Draws a World into a window of any size; never writes it. Debug overlay: grid, pairs, counters.

The overlay draws the cells and counters the tick report names and the candidate pairs a
`CandidateWatch` saw (an observer of the detector, attached only while the overlay is on).

The picture itself is `invaders.lab.picture`'s (the environment's too): the logical 224x256
screen in white under the cabinet's gel strips. Here it is scaled into the window, and the
overlay drawn after scaling so its lines and text stay sharp.
"""

from __future__ import annotations

from collections.abc import Sequence

import pygame

from invaders.engine.broadphase import Pair, Scene
from invaders.engine.stats import CollisionStats, Contact
from invaders.game import art
from invaders.game.config import SCREEN_H, SCREEN_W
from invaders.game.kinds import EDGES, Kind
from invaders.game.world import TickReport, World
from invaders.lab.picture import BACKGROUND, Picture, Prompt, game_over_texts, hud_texts

__all__ = ["CandidateWatch", "Renderer", "View", "game_over_texts", "hud_texts"]

GRID_COLOUR = (60, 90, 160)
PAIR_COLOUR = (255, 220, 0)
SCORE_BAR_ROWS = 32  # the score bar's rows, above the playfield
OVERLAY_TEXT_PX = 14  # the overlay's text is never smaller than this, whatever the scale
CONTACT_COLOUR = (255, 0, 255)


class CandidateWatch:
    """Observes the detector: the last detection's candidate pairs, as ids."""

    def __init__(self) -> None:
        self.pairs: list[tuple[int, int]] = []

    def before(self, scene: Scene) -> None:
        pass

    def after(self, scene: Scene, candidates: Sequence[Pair], contacts: Sequence[Contact],
              stats: CollisionStats) -> None:
        self.pairs = [(a.id, b.id) for a, b, _ in candidates]


class Renderer:
    """The picture, scaled into a window; `draw` paints one frame onto a target surface."""

    def __init__(self) -> None:
        self.picture = Picture()
        self._font: pygame.font.Font | None = None
        self._font_size = 0

    def draw(self, target: pygame.Surface, world: World, alpha: float = 0.0,
             overlay: bool = False, report: TickReport | None = None,
             pairs: Sequence[tuple[int, int]] = (), paused: bool = False,
             replay_verdict: str | None = None) -> View:
        """Paint the world (movers interpolated by `alpha` of a tick) onto `target`; with
        `overlay`, the last tick's cells, candidate `pairs` and counters over it. Returns
        where the screen sits in the target, for whatever is drawn over it."""
        picture = self.picture
        picture.draw(world, alpha)
        if paused:
            self._message(["PAUSED"], 152)
        if replay_verdict is not None:
            self._message(["REPLAY ENDED", replay_verdict, "ENTER PLAYS  ESC QUITS"], 88)
        view = self._present(target)
        if overlay:
            self._draw_overlay(target, view, world, report, pairs)
        return view

    def _message(self, lines: list[str], top: int) -> None:
        """Lines centred from row `top`, 16 rows apart, on a band cleared across the
        playfield (from 4 rows above the first to 4 below the last), so that they read
        whatever is drawn behind them."""
        band = pygame.Rect(0, top - 4, SCREEN_W, 16 * len(lines))
        self.picture.screen.fill(BACKGROUND, band)
        for i, line in enumerate(lines):
            self.picture.text(line, (SCREEN_W - 8 * len(line)) // 2, top + 16 * i)

    def draw_card(self, target: pygame.Surface, world: World, texts: list[tuple[str, int, int]],
                  pictures: list[tuple[art.Art, int, int]], prompt: Prompt | None = None,
                  ) -> None:
        """A screen of the attract cycle (or the prompt before a game): the score bar,
        texts and pictures."""
        self.picture.draw_card(world, texts, pictures, prompt)
        self._present(target)

    def _present(self, target: pygame.Surface) -> View:
        """Tint the logical screen with the gel and show it in the target, its aspect kept."""
        screen = self.picture.tint()
        view = View.of(target.get_size())
        if target.get_size() == screen.get_size():
            target.blit(screen, (0, 0))
        else:  # the game's aspect kept, black borders around it
            place = pygame.Rect(view.x, view.y, round(SCREEN_W * view.scale),
                                round(SCREEN_H * view.scale))
            if place.size != target.get_size():
                target.fill(BACKGROUND)
            pygame.transform.scale(screen, place.size, target.subsurface(place))  # in place
        return view

    def _draw_overlay(self, target: pygame.Surface, view: View, world: World,
                      report: TickReport | None, pairs: Sequence[tuple[int, int]]) -> None:
        """Cells, candidate pairs and counters, at the window's resolution; the lines stay
        in the playfield's rows, off the score bar and the bottom line."""
        ground = world.config.geometry.ground_row
        top, bottom = view.to_window(0, SCORE_BAR_ROWS)[1], view.to_window(0, ground)[1]
        if report is not None and report.cell:
            _draw_cells(target, view, report.cell, ground, (top, bottom))
        _draw_pairs(target, view, world.store.by_id, pairs)
        self._draw_counters(target, view, overlay_lines(world.tick, report), top)

    def _draw_counters(self, target: pygame.Surface, view: View, lines: list[str],
                       top: int) -> None:
        """The counters' lines on a dark panel in the playfield's top right corner."""
        size = max(OVERLAY_TEXT_PX, round(7 * view.scale))
        if self._font is None or self._font_size != size:
            pygame.font.init()
            self._font = pygame.font.Font(None, size)
            self._font_size = size
        labels = [self._font.render(line, True, (255, 255, 255)) for line in lines]
        pad = max(2, size // 7)
        width = max(label.get_width() for label in labels) + 2 * pad
        height = sum(label.get_height() for label in labels) + 2 * pad
        panel = pygame.Surface((width, height), pygame.SRCALPHA)
        panel.fill((0, 0, 0, 170))
        y = pad
        for label in labels:
            panel.blit(label, (pad, y))
            y += label.get_height()
        right = view.to_window(SCREEN_W, 0)[0]
        target.blit(panel, (right - width - pad, top + pad))


def _draw_cells(target: pygame.Surface, view: View, cell: int, ground: int,
                rows: tuple[int, int]) -> None:
    """The broad phase's cells as lines, from the score bar down to the ground (`rows`:
    those two in the window's pixels)."""
    top, bottom = rows
    for x in range(0, SCREEN_W + 1, cell):
        wx = view.to_window(x, 0)[0]
        pygame.draw.line(target, GRID_COLOUR, (wx, top), (wx, bottom))
    first = -(-SCORE_BAR_ROWS // cell) * cell
    for y in range(first, ground + 1, cell):
        wy = view.to_window(0, y)[1]
        pygame.draw.line(target, GRID_COLOUR, (view.x, wy), (view.to_window(SCREEN_W, 0)[0], wy))


def _draw_pairs(target: pygame.Surface, view: View, by_id: dict,
                pairs: Sequence[tuple[int, int]]) -> None:
    """Each candidate pair: a line between the two bodies and their boxes; a body and an
    edge, a line from the body to the edge's line, drawn across."""
    for a_id, b_id in pairs:
        a, b = by_id.get(a_id), by_id.get(b_id)
        if a is None or b is None:
            continue
        if a.kind in EDGES:  # an edge (ids below every thing's: always a): its line
            line = a.y + a.h - 1 if a.kind is Kind.TOP else a.y
            x, y = view.centre(b)
            edge_y = view.to_window(0, line)[1]
            pygame.draw.line(target, PAIR_COLOUR, (x, y), (x, edge_y), 2)
            pygame.draw.line(target, PAIR_COLOUR, (view.x, edge_y),
                             (view.to_window(SCREEN_W, 0)[0], edge_y), 1)
            pygame.draw.rect(target, PAIR_COLOUR, view.box(b), 1)
            continue
        pygame.draw.line(target, PAIR_COLOUR, view.centre(a), view.centre(b), 2)
        for body in (a, b):
            pygame.draw.rect(target, PAIR_COLOUR, view.box(body), 1)


def overlay_lines(tick: int, report: TickReport | None) -> list[str]:
    """The counters as a few short lines: each pipeline step, what it considered."""
    if report is None:
        return [f"tick {tick}"]
    stats = report.stats
    lines = [f"tick {tick}  {report.broadphase}" + (f" {report.cell}px" if report.cell else "")]
    if stats is not None:
        lines += [
            f"objects {stats.objects}  naive {stats.naive_pairs}",
            f"rules {stats.allowed_pairs}  broad {stats.candidates}",
            f"rect {stats.rect_hits}/{stats.rect_tests}  mask {stats.mask_hits}/{stats.mask_tests}",
            f"swept {stats.swept_tests}  contacts {stats.contacts}",
        ]
    return lines


class View:
    """Where the 224x256 screen sits in a window of any size: scaled as large as fits with
    its aspect kept, centred, black around it."""

    def __init__(self, x: int, y: int, scale: float) -> None:
        self.x, self.y, self.scale = x, y, scale

    @classmethod
    def of(cls, size: tuple[int, int]) -> View:
        w, h = size
        scale = min(w / SCREEN_W, h / SCREEN_H)
        return cls(round((w - SCREEN_W * scale) / 2), round((h - SCREEN_H * scale) / 2),
                   scale)

    def to_window(self, x: float, y: float) -> tuple[int, int]:
        return round(self.x + x * self.scale), round(self.y + y * self.scale)

    def box(self, body) -> pygame.Rect:
        x0, y0 = self.to_window(body.x, body.y)
        x1, y1 = self.to_window(body.x + body.w, body.y + body.h)
        return pygame.Rect(x0, y0, x1 - x0, y1 - y0)

    def centre(self, body) -> tuple[int, int]:
        return self.to_window(body.x + body.w / 2, body.y + body.h / 2)
