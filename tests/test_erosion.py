"""Shields erode pixel by pixel: the projectile's own image, then its burst, or an alien's
footprint. Expected shields are worked out from the ASCII art alone, independently of masks."""

from __future__ import annotations

from invaders.game import art
from invaders.game.actions import Action
from invaders.game.entities import Bomb, BombType
from invaders.game.events import Event
from invaders.game.world import World
from tests.helpers import active_world, mask_rows, step_until

# A shot fired from x=40 rises into the arch of the first shield (x=32, y=192), meets lit
# pixels at rows 200-203, erases its own 1x4 there, then bursts with its 8x8 picture at
# (37, 198). Checked by hand against art.SHOT_BURST.
AFTER_SHOT = (
    "....##############....",
    "...################...",
    "..##################..",
    ".####################.",
    "######################",
    "######################",
    "#####.###.##.#########",
    "#######.####.#########",
    "######......##########",
    "#####........#########",
    "#####........#########",
    "######......##########",
    "#######.......########",
    "#####..........#######",
    "#####...........######",
    "#####...........######",
)


def _erase(rows: tuple[str, ...], picture: art.Art, ox: int, oy: int) -> tuple[str, ...]:
    """Unlight the picture's lit pixels placed at (ox, oy) in rows."""
    grid = [list(r) for r in rows]
    for x, y in art.lit_cells(picture):
        if 0 <= oy + y < len(grid) and 0 <= ox + x < len(grid[0]):
            grid[oy + y][ox + x] = "."
    return tuple("".join(r) for r in grid)


def _touches(rows: tuple[str, ...], picture: art.Art, ox: int, oy: int) -> bool:
    return any(0 <= oy + y < len(rows) and 0 <= ox + x < len(rows[0])
               and rows[oy + y][ox + x] == "#" for x, y in art.lit_cells(picture))


def _quiet_world() -> World:
    world = active_world()
    world.alien_fire_timer = 10**9
    return world


def test_a_shot_erases_its_image_then_its_burst_shape():
    world = _quiet_world()
    for _ in range(16):
        world.step(Action.RIGHT)
    world.step(Action.FIRE)
    report = step_until(world, lambda r: Event.BUNKER_HIT in r.events, limit=20)
    (contact,) = report.contacts
    assert (contact.bx, contact.by) == (40, 200)
    assert mask_rows(world.bunkers[0].mask) == AFTER_SHOT
    # The shot's picture erased alone would leave the burst's pixels: both really applied.
    assert _erase(art.BUNKER, art.SHOT, 8, 8) != AFTER_SHOT
    assert _erase(_erase(art.BUNKER, art.SHOT, 8, 8), art.SHOT_BURST, 5, 6) == AFTER_SHOT


def _drop_bomb(world: World, btype: BombType, x: int, y: int) -> Bomb:
    bomb = Bomb(world.store.new_id(), btype, x, y)
    world.store.add(bomb)
    world.slots[btype].bomb = bomb
    return bomb


def _fall_until_shield_hit(world: World, bomb: Bomb, bunker) -> tuple[int, int, int, object]:
    """Step until the bomb hits a shield; its x, y and picture frame at the start of that
    tick (it steps, then is tested), and the tick's report."""
    while True:
        x, y, frame = bomb.x, bomb.y, bomb.frame
        report = world.step(0)
        if Event.BUNKER_HIT in report.events:
            return x, y, (frame + 1) % 4, report
        assert bomb.alive and bomb.y < bunker.y + bunker.h, "the bomb went through"


def _expected_after_bomb(rows, picture, x, y0, y1):
    """First row between y0 and y1 (inclusive) at which the picture touches, and the result."""
    for y in range(y0, y1 + 1):
        if _touches(rows, picture, x, y):
            return y, _erase(_erase(rows, picture, x, y), art.BOMB_BURST, x - 2, y + 2)
    raise AssertionError("never touches")


def test_a_bomb_erases_its_image_at_first_contact_then_its_burst_shape():
    world = _quiet_world()
    bunker = world.bunkers[1]
    bomb = _drop_bomb(world, BombType.PLUNGER, bunker.x + 10, bunker.y - 17)
    x, y, frame, report = _fall_until_shield_hit(world, bomb, bunker)
    picture = art.BOMB_PLUNGER[frame]
    hit_y, expected = _expected_after_bomb(art.BUNKER, picture, x - bunker.x, y - bunker.y,
                                           y + 4 - bunker.y)
    assert report.contacts[0].by == bunker.y + hit_y
    assert mask_rows(bunker.mask) == expected


def test_a_bomb_cannot_slip_past_a_one_pixel_remnant():
    world = _quiet_world()
    bunker = world.bunkers[2]
    bunker.mask.clear()
    for col in range(6, 15):
        bunker.mask.set_at((col, 9), 1)  # all that is left: a 1-px ledge across row 9
    rows = mask_rows(bunker.mask)
    bomb = _drop_bomb(world, BombType.SQUIGGLY, bunker.x + 8, bunker.y - 12)
    x, y, frame, _ = _fall_until_shield_hit(world, bomb, bunker)
    picture = art.BOMB_SQUIGGLY[frame]
    _, expected = _expected_after_bomb(rows, picture, x - bunker.x, y - bunker.y,
                                       y + 4 - bunker.y)
    assert mask_rows(bunker.mask) == expected


def test_a_low_alien_clears_its_whole_16x16_footprint():
    world = _quiet_world()
    bunker = world.bunkers[0]
    rack = world.rack
    rack.ref_x, rack.ref_top, rack.cursor = bunker.x, bunker.y + 8, 0
    report = world.step(0)  # draws alien 0 with its footprint over the shield's rows
    assert [(c.a_kind.name, c.b_kind.name) for c in report.contacts] == [("ALIEN", "BUNKER")]
    cleared = tuple("." * 16 + row[16:] for row in art.BUNKER)
    assert mask_rows(bunker.mask) == cleared
    world.step(0)  # alien 1, 16 px to the right, clears the rest
    assert bunker.mask.count() == 0
