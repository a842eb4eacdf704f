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
from collections.abc import Callable
from functools import partial
from itertools import accumulate
from math import gcd
from typing import Any, Literal, NamedTuple

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
BLOCK_ROWS = 4  # outputs a block (fewer if its work would pass BLOCK_WORK)


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
        period_out, period_in = weights.shape
        return cls(common, period_in, period_out, tuple(found))


# A grey canvas read 8 pixels at a time: its bytes are 0 or 255, so 8 of them, one 64-bit
# number, masked to a bit a byte and multiplied by GATHER, have their bits side by side in
# the top byte (the product's other terms land in bits of their own, below it or past the
# 64th), a number from 0 to 255 naming which of the 8 are lit.
GROUP = 8
GROUPS = SCREEN_W // GROUP
LOW_BITS = np.uint64(0x0101010101010101)
GATHER = np.uint64(0x8040201008040201)
TOP_BYTE = np.uint64(56)


def read_groups(canvas: np.ndarray, out: np.ndarray) -> np.ndarray:
    """Each 8 pixels of a grey canvas's rows (rows, 8 n: contiguous) as the number
    (0..255) naming the lit ones, in `out` (rows, n) uint64."""
    np.bitwise_and(canvas.view(np.uint64), LOW_BITS, out=out)
    np.multiply(out, GATHER, out=out)
    return np.right_shift(out, TOP_BYTE, out=out)


def _padded(weights: np.ndarray, outputs: int) -> np.ndarray:
    """Weights (outputs by inputs) with rows of zeros added to make `outputs` rows."""
    pads = np.zeros((outputs - weights.shape[0], weights.shape[1]), weights.dtype)
    return np.concatenate([weights, pads])


def _entries(group_weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What each 8 pixels add to their outputs of the columns (`group_weights`, outputs by
    8 pixels), for every set of them lit under every 8 levels of the gel there are: a table
    of 256 entries each 8 levels, each entry those outputs' float32s as one item; and where
    each group's 8 levels' entries begin, (SCREEN_H, GROUPS) uint64."""
    lit = np.array([[255 * (n >> (GROUP - 1 - i) & 1) for i in range(GROUP)]
                    for n in range(256)], np.uint8)  # (256 sets of 8 lit or not)
    codes = read_groups(lit, np.zeros((256, 1), np.uint64))[:, 0]
    levels, which = np.unique(gel_array(grayscale=True).reshape(-1, GROUP), axis=0,
                              return_inverse=True)
    table = np.zeros((len(levels), 256, len(group_weights)), np.float32)
    for i, level in enumerate(levels):
        table[i, codes] = np.minimum(lit, level) @ group_weights.T
    item = np.dtype(f"V{table.itemsize * len(group_weights)}")
    first = (which.reshape(SCREEN_H, GROUPS) * 256).astype(np.uint64)
    return table.reshape(-1).view(item), first


def _pads_dropped(with_pads: np.ndarray, out: np.ndarray, per_group: int, padded: int
                  ) -> Callable[[], object]:
    """The copy of `with_pads` (games, rows, groups of `padded` bytes: `per_group` outputs,
    then pads) into `out` without the pads. Three outputs and a pad are a pixel of SDL's
    RGBX format, and three outputs one of its RGB format: SDL's blit from the one to the
    other copies each channel's byte as it is and leaves the fourth (8 games at 84x84: 5.6
    against 27 us for numpy's take of the kept places, a script). Other paddings: the take
    (a copy of the floats into `out` through strides that skip the pads took 51 against
    28 us)."""
    if (per_group, padded) == (3, 4):
        size = (with_pads.shape[2] // padded, with_pads.shape[0] * with_pads.shape[1])
        source = pygame.image.frombuffer(with_pads, size, "RGBX")  # type: ignore[arg-type]
        target = pygame.image.frombuffer(out, size, "RGB")  # type: ignore[arg-type]
        return partial(target.blit, source, (0, 0))
    kept = np.array([group * padded + i for group in range(with_pads.shape[2] // padded)
                     for i in range(per_group)])
    return partial(np.take, with_pads, kept, axis=2, mode="clip", out=out)


class Shrink:
    """Grey pictures, one a game, made smaller by area averaging, exactly, together, in
    arrays kept between steps, from the canvases drawn (`read`: lit bytes 255, under the
    cabinet's grey gel). Each 8 pixels of a row are read as one number (which are lit),
    which picks what they add to the columns' outputs from a table (every set of 8 lit
    under every 8 levels of the gel): where 8 columns make whole outputs (widths 28, 56,
    84, ..., 224: 3 outputs for 84), the table holds those outputs' sums, so it does the
    columns' shrink; otherwise it holds the 8 tinted pixels and products do it (as the
    rows' below). An entry is padded with zeros to a power of two floats (4 for 84),
    which the lookup copies fastest; the pads go along to the end and are left out there.
    One lookup of numpy's takes every game's groups. Then the rows: their
    weights repeat every `rows.period_in` rows, so a product multiplies a block of a
    period's outputs' weights by the rows they cover, in every period of every game at
    once; then a division and a rounding half up; nothing allocated. (The native batch of
    8 games, 84x84 grey stacked 4, took 132 against 151 us a game's step interpreted and
    102 against 115 compiled, where the tinted picture was made float32 and shrunk by
    products both ways: the median of three processes each, in turn, 5 rounds each; a
    single game about as fast either way.)

    Exact, whatever the order the products add in: the weights are whole numbers, so every
    sum is a whole number, at most 255 times the weights' total D (the rows' period of
    inputs times 8 where the table does the columns, else times the columns' period: at
    most 256 * 224 = 57344; every sum under 2**24, so exact in float32). D is even (no
    output is 256 rows tall, so the rows' period of inputs is 256 over a power of two
    below it), so `sum + D / 2` is whole; a float32 division rounds the quotient (under
    256) by at most 2**-17, less than any fraction it can have (a multiple of 1 / D), so
    dropping the fraction gives the rounding half up."""

    def __init__(self, size: tuple[int, int], games: int = 1) -> None:
        height, width = size
        periods = gcd(SCREEN_H, height)
        folded = GROUP * width % SCREEN_W == 0  # (the table makes the columns' outputs)
        per_group = GROUP * width // SCREEN_W if folded else GROUP
        # A group's outputs in the table padded with zeros to a power of two: numpy's
        # lookup copies an item of 4, 8, 16 or 32 bytes as one number, and any other size
        # by a call for each (8 games' lookup, 3 outputs a group: 31 against 99 us, a
        # script). The pads are shrunk with the rest and left out at the end.
        padded = 1 << (per_group - 1).bit_length()
        self.table, self._first = _entries(_padded(
            area_weights(GROUP, per_group) if folded else np.eye(GROUP, dtype=np.float32),
            padded))
        self._codes = np.zeros((games, SCREEN_H, GROUPS), np.uint64)
        self._read = np.zeros((games * periods, SCREEN_H // periods, GROUPS * padded),
                              np.float32)  # (each game's rows as their periods)
        self.cols = None if folded else Axis.of(SCREEN_W, width, across=1)
        self._narrow = self._read if folded else np.zeros(
            (*self._read.shape[:2], width), np.float32)
        wide = self._narrow.shape[-1]  # (the outputs and any pads)
        self.rows = Axis.of(SCREEN_H, height, across=wide)
        self._small = np.zeros((games * periods, self.rows.period_out, wide), np.float32)
        self.total = self.rows.period_in * (GROUP if self.cols is None
                                            else self.cols.period_in)
        self.out = np.zeros((games, height, width), np.uint8)
        # Where there are pads: the outputs as bytes, pads and all, and the copy of them
        # into `out` that leaves the pads out.
        self._unpadding: tuple[np.ndarray, Callable[[], object]] | None = None
        if padded != per_group:
            with_pads = np.zeros((games, height, wide), np.uint8)
            self._unpadding = (with_pads, _pads_dropped(with_pads, self.out, per_group, padded))
        self.column_products = self._column_products()
        self.row_products = [(weights, self._narrow[:, span], self._small[:, outputs])
                             for outputs, span, weights in self.rows.blocks]

    def __reduce__(self) -> tuple[type[Shrink], tuple[tuple[int, int], int]]:
        """Copied or pickled as a new one: its products hold views of its arrays, which a
        copy would part (and it keeps nothing from one step to the next)."""
        games, height, width = self.out.shape
        return Shrink, ((height, width), games)

    def _column_products(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Where the table leaves the columns whole: each block of the columns' weights
        (transposed: the columns are on the right) times every row's periods of columns,
        as many rows at once as BLOCK_WORK allows."""
        if self.cols is None:
            return []
        read = self._read.reshape(-1, self.cols.period_in)
        narrow = self._narrow.reshape(-1, self.cols.period_out)
        found = []
        for outputs, span, weights in self.cols.blocks:
            each = max(1, BLOCK_WORK // weights.size)
            found += [(weights.T, read[first:first + each, span],
                       narrow[first:first + each, outputs])
                      for first in range(0, read.shape[0], each)]
        return found

    def read(self, canvas: np.ndarray, game: int = 0) -> None:
        """Game `game`'s picture, as drawn (a grey canvas: a lit byte 255, any other 0),
        read as its groups' entries in the table."""
        codes = read_groups(canvas, self._codes[game])
        np.add(codes, self._first, out=codes)

    def shrink(self) -> np.ndarray:
        """Every game's picture read made smaller, in `out` (games, height, width). (The
        lookup's indices are in the table by how they are made, so numpy is told not to
        check them: `clip`, which then changes none, takes half the time, and writes
        straight into the array kept, where `raise` fills a buffer first.)"""
        np.take(self.table, self._codes.reshape(-1).view(np.int64), mode="clip",
                out=self._read.reshape(-1).view(self.table.dtype))
        for weights, inputs, outputs in self.column_products:
            np.matmul(inputs, weights, out=outputs)
        for weights, inputs, outputs in self.row_products:
            np.matmul(weights, inputs, out=outputs)
        np.add(self._small, self.total // 2, out=self._small)
        np.divide(self._small, self.total, out=self._small)
        if self._unpadding is None:
            np.copyto(self.out, self._small.reshape(self.out.shape), casting="unsafe")
        else:
            with_pads, drop_pads = self._unpadding
            np.copyto(with_pads, self._small.reshape(with_pads.shape), casting="unsafe")
            drop_pads()
        return self.out  # (the copy dropped the fraction)


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
