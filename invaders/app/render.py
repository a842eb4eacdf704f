"""Draws a World at any integer scale; never writes it. Debug overlay: grid, pairs, counters.

The overlay draws the cells and counters the tick report names and the candidate pairs a
`CandidateWatch` saw (an observer of the detector, attached only while the overlay is on).

Everything is drawn in white on the logical 224x256 screen, tinted by the cabinet's coloured
gel strips (red over the saucer lane, green over the shields and the cannon), then scaled.
The overlay is drawn after scaling so its lines and text stay sharp.
"""

from __future__ import annotations

from collections.abc import Sequence

import pygame

from invaders.app import font
from invaders.engine.broadphase import Pair, Scene
from invaders.engine.stats import CollisionStats, Contact
from invaders.game import art
from invaders.game.config import SCREEN_H, SCREEN_W
from invaders.game.entities import BOMB_PICTURES, CannonState
from invaders.game.kinds import EDGES, Kind
from invaders.game.world import Phase, TickReport, World

WHITE = (255, 255, 255, 255)
BACKGROUND = (0, 0, 0)
RED_GEL = (255, 64, 64)
GREEN_GEL = (64, 255, 64)
GRID_COLOUR = (60, 90, 160)
PAIR_COLOUR = (255, 220, 0)
SCORE_BAR_ROWS = 32  # the score bar's rows, above the playfield
OVERLAY_TEXT_PX = 14  # the overlay's text is never smaller than this, whatever the scale
CONTACT_COLOUR = (255, 0, 255)


def gel_surface() -> pygame.Surface:
    """Per-row tint: the cabinet's strips of coloured film over a white monitor."""
    gel = pygame.Surface((SCREEN_W, SCREEN_H))
    gel.fill((255, 255, 255))
    gel.fill(RED_GEL, pygame.Rect(0, 32, SCREEN_W, 32))
    gel.fill(GREEN_GEL, pygame.Rect(0, 184, SCREEN_W, 56))
    gel.fill(GREEN_GEL, pygame.Rect(24, 240, 112, 16))
    return gel


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
    """Keeps sprite surfaces and the gel; `draw` paints one frame onto a target surface."""

    def __init__(self, scale: int = 3) -> None:
        self.scale = scale
        self.screen = pygame.Surface((SCREEN_W, SCREEN_H))
        self.gel = gel_surface()
        self._sprites: dict[art.Art, pygame.Surface] = {}
        self._font: pygame.font.Font | None = None
        self._font_size = 0

    def sprite(self, picture: art.Art) -> pygame.Surface:
        surface = self._sprites.get(picture)
        if surface is None:
            surface = self._sprites[picture] = art.surface_of(picture, WHITE)
        return surface

    def text(self, message: str, x: int, y: int) -> None:
        for i, ch in enumerate(message):
            self.screen.blit(self.sprite(font.glyph(ch)), (x + i * font.ADVANCE, y))

    def draw(self, target: pygame.Surface, world: World, alpha: float = 0.0,
             overlay: bool = False, report: TickReport | None = None,
             pairs: Sequence[tuple[int, int]] = (), paused: bool = False,
             replay_verdict: str | None = None) -> View:
        """Paint the world (movers interpolated by `alpha` of a tick) onto `target`; with
        `overlay`, the last tick's cells, candidate `pairs` and counters over it. Returns
        where the screen sits in the target, for whatever is drawn over it."""
        screen = self.screen
        screen.fill(BACKGROUND)
        self._draw_hud(world)
        self._draw_play(world, alpha)
        if world.phase is Phase.GAME_OVER:
            for message, x, y in game_over_texts():
                self.text(message, x, y)
        if paused:
            self.text("PAUSED", 88, 152)
        if replay_verdict is not None:
            for i, line in enumerate(("REPLAY ENDED", replay_verdict, "ENTER PLAYS  ESC QUITS")):
                self.text(line, (SCREEN_W - 8 * len(line)) // 2, 88 + 16 * i)
        view = self._present(target)
        if overlay:
            self._draw_overlay(target, view, world, report, pairs)
        return view

    def draw_card(self, target: pygame.Surface, world: World, texts: list[tuple[str, int, int]],
                  pictures: list[tuple[art.Art, int, int]]) -> None:
        """A still screen of the attract cycle: the score bar, texts and pictures."""
        self.screen.fill(BACKGROUND)
        self._draw_hud(world)
        for message, x, y in texts:
            self.text(message, x, y)
        for picture, x, y in pictures:
            self.screen.blit(self.sprite(picture), (x, y))
        self._present(target)

    def _present(self, target: pygame.Surface) -> View:
        """Tint the logical screen with the gel and show it in the target, its aspect kept."""
        screen = self.screen
        screen.blit(self.gel, (0, 0), special_flags=pygame.BLEND_RGB_MULT)
        view = View.of(target.get_size())
        if target.get_size() == screen.get_size():
            target.blit(screen, (0, 0))
        else:  # the game's aspect kept, black borders around it
            target.fill(BACKGROUND)
            size = (round(SCREEN_W * view.scale), round(SCREEN_H * view.scale))
            target.blit(pygame.transform.scale(screen, size), (view.x, view.y))
        return view

    def _draw_hud(self, world: World) -> None:
        for message, x, y in hud_texts(world):
            self.text(message, x, y)
        for x in range(SCREEN_W):
            if world.ground.get_at((x, 0)):
                self.screen.set_at((x, world.config.geometry.ground_row), WHITE)
        ships = max(world.ships, 0)
        cannon = self.sprite(art.CANNON)
        for i in range(min(ships - 1, 6)):
            self.screen.blit(cannon, (24 + 16 * i, 240))

    def _draw_play(self, world: World, alpha: float) -> None:
        blit = self.screen.blit
        for bunker in world.bunkers:
            surface = bunker.mask.to_surface(setcolor=WHITE, unsetcolor=(0, 0, 0, 0))
            blit(surface, (bunker.x, bunker.y))
        for alien in world.rack.live_aliens():
            pictures = art.ALIEN_BY_ROW[alien.row]
            blit(self.sprite(pictures[alien.frame]), (alien.x, alien.top))
        for explosion in world.explosions:
            picture = art.ALIEN_EXPLOSION if explosion.blast.value == "alien" else art.SHOT_BURST
            blit(self.sprite(picture), (explosion.x, explosion.y))
        cannon = world.cannon
        if cannon.state is CannonState.ACTIVE:
            blit(self.sprite(art.CANNON), (cannon.x, cannon.y))
        elif cannon.state is CannonState.EXPLODING and cannon.timer > 0:  # debris then clears
            frame = (cannon.timer // world.config.timing.cannon_death_swap) % 2
            blit(self.sprite(art.CANNON_DEATH[frame]), (cannon.x, cannon.y))
        if world.shot is not None:
            blit(self.sprite(art.SHOT), _lerp(world.shot, world.tick, alpha))
        for slot in world.slots:
            if slot.bomb is not None:
                picture = BOMB_PICTURES[slot.btype][slot.bomb.frame]
                blit(self.sprite(picture), _lerp(slot.bomb, world.tick, alpha))
            elif slot.burst > 0:
                blit(self.sprite(art.BOMB_BURST), (slot.burst_x, slot.burst_y))
        state = world.saucer
        lane = world.config.geometry.saucer_top
        if state.saucer is not None:
            blit(self.sprite(art.SAUCER), _lerp(state.saucer, world.tick, alpha))
        elif state.hit_steps > world.config.timing.saucer_boom_until:
            blit(self.sprite(art.SAUCER_EXPLOSION), (state.hit_x, lane))
        elif state.hit_steps > 0:
            self.text(str(state.hit_score), state.hit_x + 4, lane)

    def _draw_overlay(self, target: pygame.Surface, view: View, world: World,
                      report: TickReport | None, pairs: Sequence[tuple[int, int]]) -> None:
        """Cells, candidate pairs and counters, at the window's resolution; the lines stay
        in the playfield's rows, off the score bar and the bottom line."""
        ground = world.config.geometry.ground_row
        top, bottom = view.to_window(0, SCORE_BAR_ROWS)[1], view.to_window(0, ground)[1]
        if report is not None and report.cell:
            for x in range(0, SCREEN_W + 1, report.cell):
                wx = view.to_window(x, 0)[0]
                pygame.draw.line(target, GRID_COLOUR, (wx, top), (wx, bottom))
            first = -(-SCORE_BAR_ROWS // report.cell) * report.cell
            for y in range(first, ground + 1, report.cell):
                wy = view.to_window(0, y)[1]
                pygame.draw.line(target, GRID_COLOUR, (view.x, wy),
                                 (view.to_window(SCREEN_W, 0)[0], wy))
        by_id = world.store.by_id
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
        size = max(OVERLAY_TEXT_PX, round(7 * view.scale))
        if self._font is None or self._font_size != size:
            pygame.font.init()
            self._font = pygame.font.Font(None, size)
            self._font_size = size
        labels = [self._font.render(line, True, (255, 255, 255))
                  for line in overlay_lines(world.tick, report)]
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


def game_over_texts() -> list[tuple[str, int, int]]:
    """GAME OVER and how to start again, centred in the rows just below the saucer's lane:
    the rack never rises above its first rows, so nothing is drawn over it however low it
    has come. UNCERTAIN: our notes do not give the original's place for the text."""
    return [("GAME OVER", (SCREEN_W - 8 * 9) // 2, 48),
            ("PRESS ENTER", (SCREEN_W - 8 * 11) // 2, 56)]


def hud_texts(world: World) -> list[tuple[str, int, int]]:
    """The score bar and the bottom line as the original lays them out: the header with both
    players' scores, the high score (which changes only when a game ends, 166D-1695), the
    ships left, and the credit count; no wave label."""
    return [
        ("SCORE<1> HI-SCORE SCORE<2>", 8, 8),
        (f"{world.score:04d}", 24, 24),
        (f"{world.hi_score:04d}", 88, 24),
        ("0000", 168, 24),
        (str(max(world.ships, 0)), 8, 240),
        ("CREDIT 00", 136, 240),
    ]


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


def _lerp(body, tick: int, alpha: float) -> tuple[int, int]:
    """Between the previous tick's position and the current one, `alpha` of the way: the
    render runs up to one tick behind, but never shows a place the simulation did not."""
    px, py = body.start_of_tick(tick - 1)
    return round(px + (body.x - px) * alpha), round(py + (body.y - py) * alpha)


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
