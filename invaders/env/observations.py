"""What an agent sees: the picture as an array, or the game's objects as numbers.

The pixel observations come from the same picture the window shows (`invaders.lab.picture`,
drawn white on black), drawn straight into an array (the picture's surface is made over the
array's memory) and tinted with the cabinet's gel by one numpy operation into the array
handed out: every drawn pixel is pure white, so the tinted picture is the gel where the
pixel is lit (255 & g == g) and black elsewhere (0 & g == 0), exactly what the window's
multiply blend gives (a test holds the two equal pixel for pixel).
"""

from __future__ import annotations

import struct
from itertools import accumulate
from typing import Any, Literal

import numpy as np
import pygame

from invaders.game.config import SCREEN_H, SCREEN_W
from invaders.game.entities import FOOTPRINT_ABOVE, Alien, CannonState
from invaders.game.rack import RackWatch
from invaders.game.world import World
from invaders.lab.picture import Picture, gel_surface

ACTIVE = CannonState.ACTIVE
# The movers where the world has them: the window's picture at the end of the last tick
# (its alpha 0 is the tick's start, where they were before it: a tick behind the state).
NOW = 1.0
# ITU-R BT.601 luma, in integers: the grey a monochrome monitor would show for each colour.
LUMA = (299, 587, 114)


def gel_array(grayscale: bool) -> np.ndarray:
    """The cabinet's gel as an upright array: RGB (256, 224, 3), or its grey levels (256,
    224) by LUMA."""
    gel = np.ascontiguousarray(pygame.surfarray.array3d(gel_surface()).transpose(1, 0, 2))
    if not grayscale:
        return gel
    weights = np.array(LUMA, dtype=np.uint32)
    return ((gel.astype(np.uint32) @ weights + 500) // 1000).astype(np.uint8)


class PixelObserver:
    """Draws a world on a kept canvas and tints it into an array: RGB (256, 224, 3) or grey
    (256, 224).
    The grey is drawn a byte a pixel (an 8-bit surface, white its 255): the tint then
    reads the lit pixels end to end, where every third byte of an RGB picture is a slow
    strided read for numpy (4 against 52 us, a script)."""

    def __init__(self, grayscale: bool) -> None:
        shape: tuple[int, ...] = (SCREEN_H, SCREEN_W) if grayscale else (SCREEN_H, SCREEN_W, 3)
        form: Literal["P", "RGB"] = "P" if grayscale else "RGB"
        self.canvas = np.zeros(shape, np.uint8)  # what is drawn, untinted
        screen = pygame.image.frombuffer(  # (numpy's stubs: a buffer from Python 3.12 on)
            self.canvas, (SCREEN_W, SCREEN_H), form)  # type: ignore[arg-type]
        if grayscale:  # (each byte its own grey: the white sprites land as 255)
            screen.set_palette([(level,) * 3 for level in range(256)])
        self.picture = Picture(screen, self.canvas)
        self.gel = gel_array(grayscale)
        self.grayscale = grayscale

    def __reduce__(self) -> tuple[type[PixelObserver], tuple[bool]]:
        """Copied or pickled as a new one: the picture is drawn on a surface over `canvas`,
        which a copy of each would part (the copy drawing on one and reading the other),
        and surfaces cannot be pickled."""
        return PixelObserver, (self.grayscale,)

    def observe(self, world: World, out: np.ndarray | None = None) -> np.ndarray:
        """The world's picture, tinted into a new array or into `out` (of its shape and
        uint8). What is handed out must be the caller's, and a new one costs less than a
        kept one copied (the tint writes it once, a copy reads it all again): an RGB step
        1.08 times as fast (15 rounds in turn, fresh processes)."""
        self.picture.draw(world, NOW)
        return np.bitwise_and(self.canvas, self.gel, out=out)

    def draw(self, world: World, slot: int = 0) -> np.ndarray:
        """The world drawn in `canvas`, untinted (a lit byte 255, any other 0): what a
        shrink reads. `slot`: the picture's backdrop kept for this world (a batch's
        game's number)."""
        self.picture.draw(world, NOW, slot=slot)
        return self.canvas


# The state vector, field by field: (name, how many numbers, what they are).
STATE_FIELDS = (
    ("cannon", 2, "x of the cannon's box, and 1 while it can be hit (0 waiting or exploding)"),
    ("shot", 3, "1 while the player's shot flies, its x and top (0, 0 without one)"),
    ("bombs", 9, "per bomb slot (rolling, plunger, squiggly): 1 if falling, its x and top"),
    ("aliens", 165, "per rack place (row 0 the bottom, col 0 the left): 1 if alive, x, top"),
    ("saucer", 2, "1 while the saucer flies, its x"),
    ("shields", 4, "lit pixels left in each shield, left to right"),
    ("game", 3, "score, ships left, wave"),
)
STATE_SIZE = sum(count for _, count, _ in STATE_FIELDS)
STATE_HIGH = 1e6  # no field is negative; the score is the largest (the counter shows 9999)


NONE3 = (0.0, 0.0, 0.0)
# The vector in three parts, each packed as float32 in native order by one call: the part
# before the aliens (cannon, shot, bombs), the aliens (three numbers a place), the rest.
_STARTS = dict(zip([name for name, _, _ in STATE_FIELDS],  # (and the end: one more start)
                   accumulate((count for _, count, _ in STATE_FIELDS), initial=0),
                   strict=False))
ALIENS_AT, AFTER_AT = _STARTS["aliens"], _STARTS["saucer"]
_BEFORE = struct.Struct(f"={ALIENS_AT}f")
_ALIENS = struct.Struct(f"={AFTER_AT - ALIENS_AT}f")
_PLACE = struct.Struct("=3f")
_AFTER = struct.Struct(f"={STATE_SIZE - AFTER_AT}f")
FLOAT = 4  # bytes


class StateObserver:
    """The game's objects as numbers, in an array kept between steps (`out`, float32,
    STATE_SIZE). The parts before and after the aliens are written afresh each time; of
    the aliens, only the places the rack's watch names (`RackWatch`): those drawn since
    the last look, about one a frame (an alien moves, appears or changes picture only
    when the rack draws it), or all of them after a kill, on another rack or the rack
    hidden. The vector took 5.1 against 9.1 us, a state step 1.12 times as fast (scripts,
    in turn: the same steps; 21 rounds in fresh processes). A test holds every vector of
    whole episodes (restored states, skips of up to 30 frames) to the fields read afresh,
    and the watch's own (tests/test_rack_watch.py) what it names in two-player games."""

    def __init__(self) -> None:
        self.out = np.zeros(STATE_SIZE, np.float32)
        self._watch = RackWatch()

    def observe(self, world: World) -> np.ndarray:
        # (packed into as a buffer: numpy's stubs give an array one from Python 3.12 on)
        out: Any = self.out
        aliens = world.rack.aliens
        _BEFORE.pack_into(out, 0, *_before(world))
        places = self._watch.changed(world.rack)
        if len(places) == len(aliens):
            _ALIENS.pack_into(out, ALIENS_AT * FLOAT, *[
                number for alien in aliens for number in _place(alien)])
        else:
            for index in places:
                _PLACE.pack_into(out, (ALIENS_AT + 3 * index) * FLOAT, *_place(aliens[index]))
        _AFTER.pack_into(out, AFTER_AT * FLOAT, *_after(world))
        return self.out


def _before(world: World) -> list[float]:
    """The cannon, the shot and the bombs."""
    cannon, shot = world.cannon, world.shot
    values = [cannon.x, 1.0 if cannon.state is ACTIVE else 0.0]
    values += (1.0, shot.x, shot.y) if shot is not None else NONE3
    for slot in world.slots:
        bomb = slot.bomb
        values += (1.0, bomb.x, bomb.y) if bomb is not None else NONE3
    return values


def _place(alien: Alien | None) -> tuple[float, ...]:
    """A rack place: 1, x and top while its alien is alive (`top` read as y +
    FOOTPRINT_ABOVE)."""
    if alien is not None and alien.alive:
        return (1.0, alien.x, alien.y + FOOTPRINT_ABOVE)
    return NONE3


def _after(world: World) -> list[float]:
    """The saucer, the shields and the game's numbers."""
    flying = world.saucer.saucer
    values = [1.0, flying.x] if flying is not None else [0.0, 0.0]
    values += [bunker.mask.count() for bunker in world.bunkers]
    values += (world.score, world.ships, world.wave)
    return values


class Stack:
    """The last n frames, oldest first, in one array kept between steps (a reset fills it
    with the first frame, as Gymnasium's FrameStackObservation does)."""

    def __init__(self, n: int, shape: tuple[int, ...]) -> None:
        self.frames = np.zeros((n, *shape), np.uint8)

    def reset(self, frame: np.ndarray) -> np.ndarray:
        self.frames[:] = frame
        return self.frames

    def push(self, frame: np.ndarray) -> np.ndarray:
        self.frames[:-1] = self.frames[1:]
        self.frames[-1] = frame
        return self.frames
