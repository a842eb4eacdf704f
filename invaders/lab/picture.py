"""A world drawn into the logical 224x256 picture: the window's and the environment's.

Everything is drawn in white, then tinted by the cabinet's coloured gel strips (red over the
saucer lane, green over the shields and the cannon). No display is needed: the picture is a
plain surface, which the window scales and the environment reads as an array.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pygame

from invaders.engine.compiled import mypyc_attr
from invaders.game import art
from invaders.game.config import SCREEN_H, SCREEN_W
from invaders.game.entities import BOMB_PICTURES, Cannon, CannonState
from invaders.game.players import PROMPT
from invaders.game.rack import pictures_apart
from invaders.game.world import Phase, World
from invaders.lab import font
from invaders.lab.rack_layer import RackLayer, palette_of

WHITE = (255, 255, 255, 255)
BACKGROUND = (0, 0, 0)
RED_GEL = (255, 64, 64)
GREEN_GEL = (64, 255, 64)
# MAME's upright overlay: red over rows 32-61, green over 184-239 and, in the bottom line,
# over x 16-133 (the ships left). UNCERTAIN: read from MAME's artwork, not the cabinet.
GEL_STRIPS = ((RED_GEL, (0, 32, SCREEN_W, 30)), (GREEN_GEL, (0, 184, SCREEN_W, 56)),
              (GREEN_GEL, (16, 240, 118, 16)))


def gel_surface() -> pygame.Surface:
    """Per-row tint: the cabinet's strips of coloured film over a white monitor."""
    gel = pygame.Surface((SCREEN_W, SCREEN_H))
    gel.fill((255, 255, 255))
    for colour, rect in GEL_STRIPS:
        gel.fill(colour, pygame.Rect(rect))
    return gel


TEXTS_KEPT = 256  # lines of text kept drawn (the score bar's change only with the score)


@mypyc_attr(allow_interpreted_subclasses=True)  # (a test's drawn afresh derives from it)
class Picture:
    """The logical screen, its sprites' surfaces and the gel, kept between frames. The
    screen may be given with the array it is made over (`pygame.image.frombuffer`), so
    that every drawing lands in the array: numpy then clears and copies it (SDL fills an
    8-bit surface a byte at a time, 80 us, and blits a 24-bit one at 120 us, where numpy
    fills or copies either in 2). Sprites and texts are made in the screen's pixel format.

    What changes seldom (the score bar, the bottom line, the ground and the shields) is
    the backdrop: drawn when what it shows changes (`backdrop_key`), kept, and put back
    at the start of every other frame; over an array, the rack is kept drawn too, changed
    where it moved (rack_layer.py). A test draws everything afresh in every frame of two
    games and holds the kept pictures to it."""

    def __init__(self, screen: pygame.Surface | None = None,
                 canvas: np.ndarray | None = None) -> None:
        self.screen = screen if screen is not None else pygame.Surface((SCREEN_W, SCREEN_H))
        self.canvas = canvas
        # (a byte a pixel: the screen's palette, as given, for the surfaces made for it)
        self._palette = palette_of(self.screen) if self.screen.get_bitsize() == 8 else None
        self.gel = gel_surface()
        self._sprites: dict[art.Art, pygame.Surface] = {}
        self._texts: dict[str, pygame.Surface] = {}
        # Each rack row's pictures, by frame (looked up 55 times a frame).
        self._aliens = tuple(tuple(map(self.sprite, frames)) for frames in art.ALIEN_BY_ROW)
        self._layers: dict[int, RackLayer] = {}  # each slot's rack, where over an array
        self._apart: tuple[object, bool] = (None, False)  # a config, and pictures_apart's
        # Each slot's backdrop: what it shows, and its pixels (an array or a surface).
        self._backdrops: dict[int, tuple[tuple[object, ...], np.ndarray | pygame.Surface]] = {}

    def clear(self) -> None:
        """The screen all black."""
        if self.canvas is not None:
            self.canvas.fill(0)
        else:
            self.screen.fill(BACKGROUND)

    def sprite(self, picture: art.Art) -> pygame.Surface:
        surface = self._sprites.get(picture)
        if surface is None:
            surface = self._sprites[picture] = self._keyed(art.surface_of(picture, WHITE))
        return surface

    def _keyed(self, picture: pygame.Surface) -> pygame.Surface:
        """A white-on-transparent picture as white on a colour key, in the screen's format:
        the same pixels drawn, and the cheapest blit there is (run-length coded), where
        per-pixel alpha is the dearest."""
        keyed = self._blank(picture.get_size())
        keyed.blit(picture, (0, 0))
        keyed.set_colorkey(BACKGROUND, pygame.RLEACCEL)
        return keyed

    def _blank(self, size: tuple[int, int]) -> pygame.Surface:
        """A surface in the screen's pixel format, with its palette where a pixel is a
        byte: SDL blits between two surfaces of one palette byte for byte, and between
        two palettes through a map of each colour to its nearest, made at each first
        blit (a new line of text onto the grey picture 90 against 1.4 us, a script)."""
        blank = pygame.Surface(size, 0, self.screen)
        if self._palette is not None:
            blank.set_palette(self._palette)
        return blank

    def text(self, message: str, x: int, y: int) -> None:
        """A line of text at (x, y)."""
        self.screen.blit(self.line(message), (x, y))

    def line(self, message: str) -> pygame.Surface:
        """A line of text's picture, its glyphs drawn together once and kept. Kept by its
        message alone: a glyph's picture never changes (the font is constant data), and a
        line is drawn over what is there, its unlit pixels keyed out, as glyph by glyph."""
        line = self._texts.get(message)
        if line is None:
            if len(self._texts) >= TEXTS_KEPT:
                self._texts.clear()
            line = self._blank((max(len(message), 1) * font.ADVANCE, 8))
            for i, ch in enumerate(message):
                line.blit(self.sprite(font.glyph(ch)), (i * font.ADVANCE, 0))
            line.set_colorkey(BACKGROUND, pygame.RLEACCEL)
            self._texts[message] = line
        return line

    def draw(self, world: World, alpha: float = 0.0, slot: int = 0) -> pygame.Surface:
        """The world in white on black (movers `alpha` of a tick on), not yet tinted: the
        backdrop, the playfield's movers and, once the game is over, its message. `slot`:
        the backdrop kept to use (a batch drawing its games in turn gives each its own)."""
        self._draw_backdrop(world, slot)
        self._draw_rack(world, slot)
        self._draw_play(world, alpha)
        if world.phase is Phase.GAME_OVER:
            for message, x, y in game_over_texts(world):
                self.text(message, x, y)
        for message, x, y in turn_texts(world):
            self.text(message, x, y)
        return self.screen

    def _draw_backdrop(self, world: World, slot: int) -> None:
        """The score bar, the bottom line, the ground and the shields: the slot's kept
        ones, or drawn and kept if what they show has changed."""
        shows = backdrop_key(world)
        kept = self._backdrops.get(slot)
        if kept is not None and kept[0] == shows:
            backdrop, canvas = kept[1], self.canvas
            if isinstance(backdrop, pygame.Surface):
                self.screen.blit(backdrop, (0, 0))
            elif canvas is not None:  # (over an array: kept as one)
                np.copyto(canvas, backdrop)
            return
        self.clear()
        self._draw_hud(world)
        self._draw_shields(world)
        pixels = self.canvas.copy() if self.canvas is not None else self.screen.copy()
        self._backdrops[slot] = (shows, pixels)

    def draw_card(self, world: World, texts: list[tuple[str, int, int]],
                  pictures: list[tuple[art.Art, int, int]],
                  prompt: Prompt | None = None) -> pygame.Surface:
        """A screen of the attract cycle (or the prompt before a game): the score bar,
        texts and pictures."""
        self.clear()
        self._draw_hud(world, prompt)
        for message, x, y in texts:
            self.text(message, x, y)
        for picture, x, y in pictures:
            self.screen.blit(self.sprite(picture), (x, y))
        return self.screen

    def tint(self) -> pygame.Surface:
        """The screen under the cabinet's gel, as the player sees it."""
        self.screen.blit(self.gel, (0, 0), special_flags=pygame.BLEND_RGB_MULT)
        return self.screen

    def _draw_hud(self, world: World, prompt: Prompt | None = None) -> None:
        for message, x, y in hud_texts(world, prompt):
            self.text(message, x, y)
        world.ground.to_surface(self.screen, setcolor=WHITE, unsetcolor=None,
                                dest=(0, world.config.geometry.ground_row))
        ships = shown_ships(world)
        cannon = self.sprite(art.CANNON)
        for i in range(min(ships - 1, 6)):
            self.screen.blit(cannon, (24 + 16 * i, 240))

    def _draw_shields(self, world: World) -> None:
        for bunker in world.bunkers:
            bunker.mask.to_surface(self.screen, setcolor=WHITE, unsetcolor=None,
                                   dest=(bunker.x, bunker.y))

    def _draw_rack(self, world: World, slot: int) -> None:
        """The aliens: the slot's kept layer where the picture is over an array and no two
        aliens can share a pixel (rack_layer.py), else each blitted, in one call
        (`fblits`: 14 against 40 us for `blits`)."""
        if self._apart[0] is not world.config:  # (asked once a config: a frame asks)
            self._apart = (world.config, pictures_apart(world.config))
        if self.canvas is not None and self._apart[1]:
            layer = self._layers.get(slot)
            if layer is None:
                layer = self._layers[slot] = RackLayer(self.screen, self.canvas, self._aliens)
            layer.draw(world.rack, self.canvas)
            return
        aliens = self._aliens
        self.screen.fblits([(aliens[alien.row][alien.frame], (alien.x, alien.top))
                            for alien in world.rack.live_aliens()])

    def _draw_play(self, world: World, alpha: float) -> None:
        """The explosions, the cannon, the shot, the bombs and the saucer, in that order,
        in one call (`fblits`: compiled, a step 1.03 times as fast as with a call a sprite,
        RGB or grey, 12 rounds in turn)."""
        sprite = self.sprite
        drawn: list[tuple[pygame.Surface, tuple[int, int]]] = []
        for explosion in world.explosions:
            picture = art.ALIEN_EXPLOSION if explosion.blast.value == "alien" else art.SHOT_BURST
            drawn.append((sprite(picture), (explosion.x, explosion.y)))
        cannon = world.cannon
        if cannon.state is CannonState.ACTIVE:
            drawn.append((sprite(art.CANNON), (cannon.x, cannon.y)))
        elif cannon.state is CannonState.EXPLODING and cannon.timer > 0:  # debris then clears
            drawn.append((sprite(cannon_picture(cannon)), (cannon.x, cannon.y)))
        if world.shot is not None:
            drawn.append((sprite(art.SHOT), _lerp(world.shot, world.tick, alpha)))
        for slot in world.slots:
            if slot.bomb is not None:
                picture = BOMB_PICTURES[slot.btype][slot.bomb.frame]
                drawn.append((sprite(picture), _lerp(slot.bomb, world.tick, alpha)))
            elif slot.burst > 0:
                drawn.append((sprite(art.BOMB_BURST), (slot.burst_x, slot.burst_y)))
        state = world.saucer
        lane = world.config.geometry.saucer_top
        if state.saucer is not None:
            drawn.append((sprite(art.SAUCER), _lerp(state.saucer, world.tick, alpha)))
        elif state.hit_steps > world.config.timing.saucer_boom_until:
            drawn.append((sprite(art.SAUCER_EXPLOSION), (state.hit_x, lane)))
        elif state.hit_steps > 0:
            drawn.append((self.line(str(state.hit_score)), (state.hit_x + 4, lane)))
        self.screen.fblits(drawn)


def cannon_picture(cannon: Cannon) -> art.Art:
    """The hit cannon's picture: its own, held through the blow-up delay, then the debris
    it shows (`Cannon.debris`), @1C80 first (0296-03A5)."""
    return art.CANNON if cannon.debris < 0 else art.CANNON_DEATH[cannon.debris]


GAME_OVER_LETTER = 6  # frames a letter of GAME OVER takes to type (0A93)


def game_over_texts(world: World) -> list[tuple[str, int, int]]:
    """GAME OVER alone, typed a letter every six frames at the ROM's place (72, 56: 16C9),
    in the rows just below the saucer's lane, which the rack never reaches. The window goes
    back to the attract cycle when it has shown (Enter waits for that)."""
    shown = (world.config.timing.game_over_pause - world.phase_timer) // GAME_OVER_LETTER + 1
    return [("GAME OVER"[:max(0, min(9, shown))], 72, 56)]


def hud_texts(world: World, prompt: Prompt | None = None) -> list[tuple[str, int, int]]:
    """The score bar and the bottom line as the original lays them out: the header with both
    players' scores (player 2's blank in a one-player game, 08E4; the player up's flashing
    while PLAY PLAYER<n> shows, 08A9-08CE), the high score (which changes only when a game
    ends, 166D-1695), the ships left, and the credit count; no wave label. `prompt`: the
    window's PLAY PLAYER<1> before a new game, whose scores are not the world's yet."""
    texts = [("SCORE<1> HI-SCORE SCORE<2>", 8, 8), (f"{world.hi_score:04d}", 88, 24)]
    if prompt is None:
        scores, up, flashing = world.scores(), world.player, up_flashing(world)
    else:
        scores, up = (0, 0 if prompt.players == 2 else None), 1
        flashing = _flash_hides(prompt.left)
    for number, (score, x) in enumerate(zip(scores, (24, 168), strict=True), 1):
        if score is not None and not (flashing and number == up):
            texts.append((f"{score:04d}", x, 24))
    return [*texts, (str(shown_ships(world)), 8, 240), ("CREDIT 00", 136, 240)]


def up_flashing(world: World) -> bool:
    """Whether the score of the player up is hidden now: it flashes while PLAY PLAYER<n>
    shows between turns (08A9-08CE)."""
    return world.phase is Phase.SWITCH and _flash_hides(world.phase_timer)


def _flash_hides(left: int) -> bool:
    """Hidden while the prompt shows and bit 2 of its delay is set (08B1)."""
    return left <= PROMPT and bool(left & 4)


class Prompt(NamedTuple):
    """PLAY PLAYER<1> before a new game: how many play, and the frames it has left."""

    players: int
    left: int


def turn_texts(world: World) -> list[tuple[str, int, int]]:
    """Between two players' turns: GAME OVER PLAYER<n> under the field of one who is out
    (1698-16B7), then PLAY PLAYER<n> for the one up (088D)."""
    if world.phase is not Phase.SWITCH:
        return []
    if world.phase_timer > PROMPT:
        return [(f"GAME OVER PLAYER<{world.player}>", 32, 224)] if world.out else []
    return [(f"PLAY PLAYER<{world.player}>", 56, 112)]


def backdrop_key(world: World) -> tuple[object, ...]:
    """What the backdrop shows, in values that change whenever it does: what the score
    bar's and the bottom line's texts are made from (`hud_texts`: the scores, the player
    up and whether theirs flashes off, the ships shown, whose icons follow their count),
    the ground and its lit pixels (a mask that only loses pixels until a wave draws a new
    one), the shields' list (a new field's is a new one) and their erosions
    (World.erosions counts every change to their pixels). Numbers, not the texts
    themselves: compiled, an RGB step 1.07 times as fast and a grey one 1.09 (12 rounds in
    turn, fresh processes); tests/test_render.py changes each of them."""
    return (world.hi_score, world.scores(), world.player, up_flashing(world),
            shown_ships(world), world.ground, world.ground.count(), world.bunkers,
            world.erosions)


def shown_ships(world: World) -> int:
    """The ships the bottom line shows: none once the rack has landed (the ROM erases the
    icons and prints 0, 16FF), whatever the count still holds."""
    return 0 if world.invaded else world.ships


def _lerp(body, tick: int, alpha: float) -> tuple[int, int]:
    """Between the previous tick's position and the current one, `alpha` of the way: the
    render runs up to one tick behind, but never shows a place the simulation did not."""
    px, py = body.start_of_tick(tick - 1)
    return round(px + (body.x - px) * alpha), round(py + (body.y - py) * alpha)
