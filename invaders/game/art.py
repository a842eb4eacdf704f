"""Sprite bitmaps written as ASCII art ('#' lit), turned into masks and surfaces.

The bombs, the crab, the saucer, the cannon's death, the saucer's explosion and both bursts
are the ROM's pictures (decoded from its bytes, one byte a column, bit 7 the top pixel; a
test holds them to those bytes); the others are drawn at the sizes the reference gives
(section 3). What matters to the game is each sprite's box, its lit extent and where its
pixels are, since collision is tested pixel by pixel. No image files are needed.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import pygame

from invaders.engine.pickling import remade_by

Art = tuple[str, ...]


def art(*rows: str) -> Art:
    """Check that a picture is rectangular and made of '.' and '#' only."""
    width = len(rows[0])
    for row in rows:
        if len(row) != width or set(row) - {".", "#"}:
            raise ValueError(f"bad art row {row!r}")
    return tuple(rows)


def pad(picture: Art, left: int, width: int) -> Art:
    """Place a picture in a wider box, `left` blank columns before it."""
    right = width - left - len(picture[0])
    return tuple("." * left + row + "." * right for row in picture)


def lit_cells(picture: Art) -> list[tuple[int, int]]:
    """The (x, y) of every lit pixel."""
    return [(x, y) for y, row in enumerate(picture) for x, ch in enumerate(row) if ch == "#"]


@cache
def mask_of(picture: Art) -> pygame.mask.Mask:
    """The collision mask of a picture (shared: never erase a mask from here; pickled as
    this call, so that loaded it is the shared one again)."""
    mask = pygame.mask.Mask((len(picture[0]), len(picture)))
    for x, y in lit_cells(picture):
        mask.set_at((x, y), 1)
    return remade_by(mask, mask_of, picture)


def fresh_mask(picture: Art) -> pygame.mask.Mask:
    """A mask of its own, for things that erode (bunkers, the ground)."""
    return mask_of(picture).copy()


def surface_of(picture: Art, colour: Sequence[int]) -> pygame.Surface:
    """A transparent surface with the lit pixels in `colour`."""
    surface = pygame.Surface((len(picture[0]), len(picture)), pygame.SRCALPHA)
    for x, y in lit_cells(picture):
        surface.set_at((x, y), colour)
    return surface


# Aliens: 16x8 boxes. Rows 0-1 (10 pts) are 12 lit columns at box cols 2-13,
# rows 2-3 (20 pts) 11 at cols 3-13, row 4 (30 pts) 8 at cols 4-11. Two pictures each.
ALIEN_A = (
    pad(art("....####....", ".##########.", "############", "###..##..###",
            "############", "...##..##...", "..##.##.##..", "##........##"), 2, 16),
    pad(art("....####....", ".##########.", "############", "###..##..###",
            "############", "..###..###..", ".##..##..##.", "..##....##.."), 2, 16),
)
ALIEN_B = (  # the crab, rows 2-3: ROM frame 0 @1C10, frame 1 @1C40
    art(".....#.....#....", "...#..#...#..#..", "...#.#######.#..", "...###.###.###..",
        "...###########..", "....#########...", ".....#.....#....", "....#.......#..."),  # @1C10
    art(".....#.....#....", "......#...#.....", ".....#######....", "....##.###.##...",
        "...###########..", "...#.#######.#..", "...#.#.....#.#..", "......##.##....."),  # @1C40
)
ALIEN_C = (
    pad(art("...##...", "..####..", ".######.", "##.##.##",
            "########", "..#..#..", ".#.##.#.", "#.#..#.#"), 4, 16),
    pad(art("...##...", "..####..", ".######.", "##.##.##",
            "########", ".#.##.#.", "#......#", ".#....#."), 4, 16),
)
# Picture by rack row, bottom row first (reference: offset (row & 0xFE) * 8).
ALIEN_BY_ROW = (ALIEN_A, ALIEN_A, ALIEN_B, ALIEN_B, ALIEN_C)
ALIEN_LIT_COLUMNS = {ALIEN_A: (2, 13), ALIEN_B: (3, 13), ALIEN_C: (4, 11)}

ALIEN_EXPLOSION = pad(art(
    "....#...#....", ".#...#.#...#.", "..#.......#..", "...#.....#...",
    "##.........##", "...#.....#...", "..#..#.#..#..", ".#..#...#..#."), 1, 16)

CANNON = pad(art(
    "......#......", ".....###.....", ".....###.....", ".###########.",
    "#############", "#############", "#############", "#############"), 2, 16)
CANNON_DEATH = (  # ROM, swapped every 5 frames
    art("......#.........", "...........#....", "......#.#.#.....", "...#..#.........",
        ".......##.##....", ".#...#.##.#.#...", "...########..#..", "..##########.#.#"),  # @1C70
    art("...#.........#..", "#.....#....##..#", "...#....##......", "......#.......#.",
        ".#..#.##..##...#", "..#....###...#..", "...#########....", "..##.#######..#."),  # @1C80
)

SHOT = art("#", "#", "#", "#")  # the lit 1x4 of the 1x8 box
SHOT_BURST = art(  # ROM @1C91
    "#...#..#",
    "..#...#.",
    ".######.",
    "########",
    "########",
    ".######.",
    "..#..#..",
    "#..#...#",
)

# Bombs: 3x8 boxes, four pictures each, the lit rows at the top of the box (ROM, one byte a
# column: rolling @1CEE, plunger @1CE2, squiggly @1CD0): lit heights 7, 6 and 7.
BOMB_ROLLING = (
    art(".#.", ".#.", ".#.", ".#.", ".#.", ".#.", ".#.", "..."),  # @1CEE
    art(".#.", ".#.", "##.", ".##", ".#.", "##.", ".##", "..."),  # @1CF1
    art(".#.", ".#.", ".#.", ".#.", ".#.", ".#.", ".#.", "..."),  # @1CF4
    art(".##", "##.", ".#.", ".##", "##.", ".#.", ".#.", "..."),  # @1CF7
)
BOMB_PLUNGER = (
    art(".#.", ".#.", ".#.", ".#.", ".#.", "###", "...", "..."),  # @1CE2
    art(".#.", ".#.", ".#.", "###", ".#.", ".#.", "...", "..."),  # @1CE5
    art(".#.", ".#.", "###", ".#.", ".#.", ".#.", "...", "..."),  # @1CE8
    art("###", ".#.", ".#.", ".#.", ".#.", ".#.", "...", "..."),  # @1CEB
)
BOMB_SQUIGGLY = (
    art(".#.", "#..", ".#.", "..#", ".#.", "#..", ".#.", "..."),  # @1CD0
    art("#..", ".#.", "..#", ".#.", "#..", ".#.", "..#", "..."),  # @1CD3
    art(".#.", "..#", ".#.", "#..", ".#.", "..#", ".#.", "..."),  # @1CD6
    art("..#", ".#.", "#..", ".#.", "..#", ".#.", "#..", "..."),  # @1CD9
)
BOMB_BURST = art(  # ROM @1CDC
    "..#...",
    "#...#.",
    "..##.#",
    ".####.",
    "#.###.",
    ".#####",
    "#.###.",
    ".#.#.#",
)

SAUCER = art(  # ROM @1D64: the lit rows are the box's lower seven
    "........................",
    ".........######.........",
    ".......##########.......",
    "......############......",
    ".....##.##.##.##.##.....",
    "....################....",
    "......###..##..###......",
    ".......#........#.......",
)
SAUCER_EXPLOSION = art(  # ROM @1D7C
    "...#..#.#......#.#..#...",
    "....#........##....#....",
    ".#.#...####...##........",
    "......#######..###..#...",
    ".....###.#.#.#..###..#..",
    "...#...#####...##.......",
    ".#......#.#...##...#....",
    "...#...#...#....#.......",
)

BUNKER = art(
    "....##############....",
    "...################...",
    "..##################..",
    ".####################.",
    "######################",
    "######################",
    "######################",
    "######################",
    "######################",
    "######################",
    "######################",
    "######################",
    "#######.......########",
    "######.........#######",
    "#####...........######",
    "#####...........######",
)

GROUND = ("#" * 224,)
