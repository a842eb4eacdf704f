"""What an agent sees: the picture as an array, or the game's objects as numbers.

The pixel observations come from the same picture the window shows (`invaders.lab.picture`,
drawn white on black), drawn straight into an array (the picture's surface is made over the
array's memory) and tinted with the cabinet's gel by one numpy operation into an array kept
between steps: every drawn pixel is pure white, so the tinted picture is the gel where the
pixel is lit (255 & g == g) and black elsewhere (0 & g == 0), exactly what the window's
multiply blend gives (a test holds the two equal pixel for pixel).
"""

from __future__ import annotations

import functools
import struct
from math import gcd
from typing import NamedTuple

import numpy as np
import pygame

from invaders.game.config import SCREEN_H, SCREEN_W
from invaders.game.entities import FOOTPRINT_ABOVE, CannonState
from invaders.game.world import World
from invaders.lab.picture import Picture

ACTIVE = CannonState.ACTIVE
# ITU-R BT.601 luma, in integers: the grey a monochrome monitor would show for each colour.
LUMA = (299, 587, 114)


def _gel_array(picture: Picture) -> np.ndarray:
    """The gel as an upright (256, 224, 3) array."""
    return np.ascontiguousarray(pygame.surfarray.array3d(picture.gel).transpose(1, 0, 2))


class PixelObserver:
    """Draws a world and reads it into a kept array: RGB (256, 224, 3) or grey (256, 224).
    The grey is drawn a byte a pixel (an 8-bit surface, white its 255): the tint then
    reads the lit pixels end to end, where every third byte of an RGB picture is a slow
    strided read for numpy (4 against 52 us, a script)."""

    def __init__(self, grayscale: bool) -> None:
        shape, form = ((SCREEN_H, SCREEN_W), "P") if grayscale else ((SCREEN_H, SCREEN_W, 3), "RGB")
        self.canvas = np.zeros(shape, np.uint8)  # what is drawn, untinted
        screen = pygame.image.frombuffer(self.canvas, (SCREEN_W, SCREEN_H), form)
        if grayscale:  # (each byte its own grey: the white sprites land as 255)
            screen.set_palette([(level,) * 3 for level in range(256)])
        self.picture = Picture(screen, clear=functools.partial(self.canvas.fill, 0))
        gel = _gel_array(self.picture)
        if grayscale:
            weights = np.array(LUMA, dtype=np.uint32)
            gel = ((gel.astype(np.uint32) @ weights + 500) // 1000).astype(np.uint8)
        self.gel, self.out = gel, np.zeros(shape, np.uint8)
        self.grayscale = grayscale

    def observe(self, world: World) -> np.ndarray:
        """The world's picture in `out` (the same array each time: copy it to keep it)."""
        self.picture.draw(world)
        return np.bitwise_and(self.canvas, self.gel, out=self.out)


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
_PACKED = struct.Struct(f"={STATE_SIZE}f")  # the vector, as float32 in native order


def observe_state(world: World, out: np.ndarray) -> np.ndarray:
    """The game's objects as numbers, written into `out` (float32, STATE_SIZE): one list
    built in field order, then packed into the array's memory in one call (numpy's own
    conversion of a list takes about twice as long)."""
    cannon, shot, flying = world.cannon, world.shot, world.saucer.saucer
    values = [cannon.x, 1.0 if cannon.state is ACTIVE else 0.0]
    values += (1.0, shot.x, shot.y) if shot is not None else NONE3
    for slot in world.slots:
        bomb = slot.bomb
        values += (1.0, bomb.x, bomb.y) if bomb is not None else NONE3
    for alien in world.rack.aliens:  # (`top` read as y + FOOTPRINT_ABOVE: 55 a step)
        values += (1.0, alien.x, alien.y + FOOTPRINT_ABOVE) if (
            alien is not None and alien.alive) else NONE3
    values += (1.0, flying.x) if flying is not None else (0.0, 0.0)
    values += [bunker.mask.count() for bunker in world.bunkers]
    values += (world.score, max(world.ships, 0), world.wave)
    _PACKED.pack_into(out, 0, *values)
    return out


def area_weights(size_in: int, size_out: int) -> np.ndarray:
    """(size_out, size_in) whole numbers: output i covers inputs i * size_in / size_out to
    (i + 1) * size_in / size_out, and input j's weight is the length it has inside that
    span, counted in 1/size_out of a pixel (so every output's weights add up to size_in).
    Whole numbers, so sums of them times pixels are exact in float32 (see Shrink)."""
    outputs = np.arange(size_out)[:, None] * size_in
    inputs = np.arange(size_in)[None, :] * size_out
    overlap = (np.minimum(outputs + size_in, inputs + size_out)
               - np.maximum(outputs, inputs))
    return np.maximum(overlap, 0).astype(np.float32)


# Each product the shrink makes does at most this many multiply-adds (m * n * k): under it
# OpenBLAS, numpy's BLAS, runs a product on the calling thread (interface/gemm.c: threads =
# m * n * k / (65536 * 4)), so the games in a vector's worker processes start no BLAS
# threads to fight over the cores (a whole product at once did: about 6 times slower).
BLOCK_WORK = 2**18
BLOCK_ROWS = 12  # outputs a block (fewer if its work would pass BLOCK_WORK)


class Axis(NamedTuple):
    """The shrink of one axis, from `size_in` to `size_out` pixels. The weights repeat
    every `period_in` inputs (every `period_out` outputs: the sizes over their greatest
    common divisor), so one period's weights serve all `periods`; they are cut into blocks
    of outputs, each with the span of inputs its weights cover (a narrow band)."""

    periods: int
    period_in: int
    period_out: int
    blocks: tuple[tuple[slice, slice, np.ndarray], ...]  # outputs, inputs, their weights

    @classmethod
    def of(cls, size_in: int, size_out: int, across: int) -> Axis:
        """`across`: the pixels each weight multiplies in one product (for BLOCK_WORK)."""
        common = gcd(size_in, size_out)
        weights = area_weights(size_in // common, size_out // common)
        found, start = [], 0
        while start < weights.shape[0]:
            for rows in range(BLOCK_ROWS, 0, -1):
                stop = min(weights.shape[0], start + rows)
                used = np.flatnonzero(weights[start:stop].any(axis=0))
                span = slice(int(used[0]), int(used[-1]) + 1)
                if rows * (span.stop - span.start) * across <= BLOCK_WORK:
                    break
            found.append((slice(start, stop), span,
                          np.ascontiguousarray(weights[start:stop, span])))
            start = stop
        return cls(common, *reversed(weights.shape), tuple(found))


class Shrink:
    """A grey picture made smaller by area averaging, exactly, in arrays kept between
    steps: the rows, then the columns, each a block of a period's outputs at a time against
    only the inputs they cover, for every period in one product; then a division and a
    rounding half up; nothing allocated.

    Exact, whatever the order the products add in: the weights are whole numbers, so every
    sum is a whole number, at most 255 times the weights' total D (the two periods of
    inputs multiplied, at most 256 * 224 = 57344: every sum under 2**24, so exact in
    float32). D is even (no output is 256 rows tall, so the rows' period of inputs is 256
    over a power of two below it), so `sum + D / 2` is whole; a float32 division rounds the
    quotient (under 256) by at most 2**-17, less than any fraction it can have (a multiple
    of 1 / D), so dropping the fraction gives the rounding half up."""

    def __init__(self, size: tuple[int, int]) -> None:
        height, width = size
        self.rows = Axis.of(SCREEN_H, height, across=SCREEN_W)
        self.cols = Axis.of(SCREEN_W, width, across=height * gcd(SCREEN_W, width))
        self.total = self.rows.period_in * self.cols.period_in
        self._grey = np.zeros((SCREEN_H, SCREEN_W), np.float32)
        self._half = np.zeros((height, SCREEN_W), np.float32)
        self._small = np.zeros((height, width), np.float32)
        self.out = np.zeros((height, width), np.uint8)

    def __call__(self, grey: np.ndarray) -> np.ndarray:
        np.copyto(self._grey, grey)
        rows, cols = self.rows, self.cols
        # The rows: each period of inputs (a stack of row bands) times the weights' blocks.
        grey3 = self._grey.reshape(rows.periods, rows.period_in, SCREEN_W)
        half3 = self._half.reshape(rows.periods, rows.period_out, SCREEN_W)
        for outputs, span, weights in rows.blocks:
            np.matmul(weights, grey3[:, span], out=half3[:, outputs])
        # The columns: every row's periods of columns times the blocks' weights
        # (transposed: the columns are on the right).
        height = self._half.shape[0]
        half2 = self._half.reshape(height * cols.periods, cols.period_in)
        small2 = self._small.reshape(height * cols.periods, cols.period_out)
        for outputs, span, weights in cols.blocks:
            np.matmul(half2[:, span], weights.T, out=small2[:, outputs])
        np.add(self._small, self.total // 2, out=self._small)
        np.divide(self._small, self.total, out=self._small)
        np.copyto(self.out, self._small, casting="unsafe")  # (drops the fraction)
        return self.out


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
