"""The grey pictures made smaller (`resize`), by area averaging, exactly, for one game or a
batch's games together, in arrays kept between steps: each 8 pixels of a row read as one
number, a table lookup for the columns, blocks of products for the rows (see `Shrink`).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from math import gcd
from typing import NamedTuple

import numpy as np
import pygame

from invaders.env.observations import gel_array
from invaders.game.config import SCREEN_H, SCREEN_W


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
# number, are 255 times the number with a 1 in the lowest bit of each lit byte; that one
# times 0x8040201008040201 has the 8 bits side by side in its top byte (the product's
# other terms land in bits of their own, below it or past the 64th), a number from 0 to
# 255 naming which of the 8 are lit. 255 is odd, so it has an inverse modulo 2**64, and
# numpy's uint64 products are taken modulo 2**64: the canvas's number times GATHER (that
# multiplier over 255) is the same product, in one pass, where a mask to a bit a byte took
# one more (8 games' reads 28 against 37 us, a script).
GROUP = 8
GROUPS = SCREEN_W // GROUP
GATHER = np.uint64(0x8040201008040201 * pow(255, -1, 2**64) % 2**64)
TOP_BYTE = np.uint64(56)


def read_groups(canvas: np.ndarray, out: np.ndarray) -> np.ndarray:
    """Each 8 pixels of a grey canvas's rows (rows, 8 n: contiguous; each byte 0 or 255)
    as the number (0..255) naming the lit ones, in `out` (rows, n) uint64."""
    np.multiply(canvas.view(np.uint64), GATHER, out=out)
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
