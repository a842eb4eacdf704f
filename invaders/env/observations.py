"""What an agent sees: the picture as an array, or the game's objects as numbers.

The pixel observations come from the same picture the window shows (`invaders.lab.picture`,
drawn white on black), drawn straight into an array (the picture's surface is made over the
array's memory) and tinted with the cabinet's gel by one numpy operation into an array kept
between steps: every drawn pixel is pure white, so the tinted picture is the gel where the
pixel is lit (255 & g == g) and black elsewhere (0 & g == 0), exactly what the window's
multiply blend gives (a test holds the two equal pixel for pixel).
"""

from __future__ import annotations

import struct

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
    """Draws a world and reads it into a kept array: RGB (256, 224, 3) or grey (256, 224)."""

    def __init__(self, grayscale: bool) -> None:
        self.canvas = np.zeros((SCREEN_H, SCREEN_W, 3), np.uint8)  # what is drawn, untinted
        self.picture = Picture(pygame.image.frombuffer(self.canvas, (SCREEN_W, SCREEN_H), "RGB"))
        gel = _gel_array(self.picture)
        if grayscale:
            weights = np.array(LUMA, dtype=np.uint32)
            self.gel = ((gel.astype(np.uint32) @ weights + 500) // 1000).astype(np.uint8)
            self.out = np.zeros((SCREEN_H, SCREEN_W), np.uint8)
        else:
            self.gel = gel
            self.out = np.zeros((SCREEN_H, SCREEN_W, 3), np.uint8)
        self.grayscale = grayscale

    def observe(self, world: World) -> np.ndarray:
        """The world's picture in `out` (the same array each time: copy it to keep it)."""
        self.picture.draw(world)
        lit = self.canvas[:, :, 0] if self.grayscale else self.canvas
        return np.bitwise_and(lit, self.gel, out=self.out)


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
    """(size_out, size_in): each output pixel the average of the input it covers, pixels cut
    by its edges counted by the part inside (the area interpolation Atari agents use)."""
    scale = size_in / size_out
    weights = np.zeros((size_out, size_in), np.float32)
    for i in range(size_out):
        low, high = i * scale, (i + 1) * scale
        for j in range(int(low), min(size_in, int(np.ceil(high)))):
            weights[i, j] = (min(high, j + 1) - max(low, j)) / scale
    return weights


# Each block of the shrink's products does at most this many multiply-adds (m * n * k):
# under it OpenBLAS, numpy's BLAS, runs a product on the calling thread (interface/gemm.c:
# threads = m * n * k / (65536 * 4)), so the games in a vector's worker processes start no
# BLAS threads to fight over the cores (the whole product at once did: about 6 times slower).
BLOCK_WORK = 2**18
BLOCK_ROWS = 12  # outputs a block (fewer if its work would pass BLOCK_WORK)


def blocks(weights: np.ndarray, across: int) -> list[tuple[slice, slice, np.ndarray]]:
    """The rows of `weights` (out, in) in blocks: each block's outputs, the span of input
    its weights cover (they are zero elsewhere) and its weights there, each block's product
    with `across` columns within BLOCK_WORK."""
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
    return found


class Shrink:
    """A grey picture made smaller by area averaging, in arrays kept between steps: the
    rows, then the columns, a block of outputs at a time against only the inputs they
    cover (the weights are a narrow band: the whole products did 28 times the work), and a
    rounding; nothing allocated."""

    def __init__(self, size: tuple[int, int]) -> None:
        height, width = size
        self.rows = blocks(area_weights(SCREEN_H, height), across=SCREEN_W)
        self.cols = blocks(area_weights(SCREEN_W, width), across=height)
        self._grey = np.zeros((SCREEN_H, SCREEN_W), np.float32)
        self._half = np.zeros((height, SCREEN_W), np.float32)
        self._half_t = np.zeros((SCREEN_W, height), np.float32)  # (the columns as rows)
        self._small_t = np.zeros((width, height), np.float32)
        self.out = np.zeros((height, width), np.uint8)

    def __call__(self, grey: np.ndarray) -> np.ndarray:
        np.copyto(self._grey, grey)
        for outputs, span, weights in self.rows:
            np.matmul(weights, self._grey[span], out=self._half[outputs])
        np.copyto(self._half_t, self._half.T)
        for outputs, span, weights in self.cols:
            np.matmul(weights, self._half_t[span], out=self._small_t[outputs])
        np.add(self._small_t, 0.5, out=self._small_t)  # rounded to nearest, not down
        np.copyto(self.out, self._small_t.T, casting="unsafe")
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
