"""Shields erode pixel by pixel: the projectile's own image, then its burst, or an alien's
footprint. Expected shields are worked out from the ASCII art alone, independently of masks."""

from __future__ import annotations

from invaders.game import art
from invaders.game.actions import Action
from invaders.game.entities import Bomb, BombType
from invaders.game.events import Event
from invaders.game.kinds import Kind
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
    "#######.###.##########",
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
    """Step until the bomb hits a shield; where it was drawn that tick (it steps, is drawn,
    and only then tested, as the original does), its picture frame, and the tick's report."""
    while True:
        report = world.step(0)
        if Event.BUNKER_HIT in report.events:
            (contact,) = [c for c in report.contacts if bomb.id in (c.a_id, c.b_id)]
            assert {contact.a_kind, contact.b_kind} == {Kind.BOMB, Kind.BUNKER}
            if contact.a_id == bomb.id:
                return contact.ax, contact.ay, bomb.frame, report
            return contact.bx, contact.by, bomb.frame, report
        assert bomb.alive and bomb.y < bunker.y + bunker.h, "the bomb went through"


def _after_bomb(rows, picture, x: int, y: int):
    """The shield after a bomb drawn at (x, y): its own picture erased, then its burst at
    (x - 2, y + 2) (the original's 6x8 burst at Xr-2, Yr-2)."""
    return _erase(_erase(rows, picture, x, y), art.BOMB_BURST, x - 2, y + 2)


def test_a_bomb_erases_its_image_where_it_was_drawn_then_its_burst_shape():
    world = _quiet_world()
    bunker = world.bunkers[1]
    bomb = _drop_bomb(world, BombType.PLUNGER, bunker.x + 10, bunker.y - 17)
    x, y, frame, report = _fall_until_shield_hit(world, bomb, bunker)
    picture = art.BOMB_PLUNGER[frame]
    assert _touches(art.BUNKER, picture, x - bunker.x, y - bunker.y)  # where it landed
    assert not _touches(art.BUNKER, picture, x - bunker.x, y - 4 - bunker.y)  # not before
    assert report.contacts[0].time == 1  # a landing entry: tested where it is drawn
    assert mask_rows(bunker.mask) == _after_bomb(art.BUNKER, picture, x - bunker.x,
                                                 y - bunker.y)


def test_a_bomb_on_a_remnant_is_judged_where_it_lands():
    world = _quiet_world()
    bunker = world.bunkers[2]
    bunker.mask.clear()
    for col in range(6, 15):
        bunker.mask.set_at((col, 9), 1)  # all that is left: a 1-px ledge across row 9
    rows = mask_rows(bunker.mask)
    bomb = _drop_bomb(world, BombType.SQUIGGLY, bunker.x + 8, bunker.y - 12)
    x, y, frame, _ = _fall_until_shield_hit(world, bomb, bunker)
    picture = art.BOMB_SQUIGGLY[frame]
    assert _touches(rows, picture, x - bunker.x, y - bunker.y)
    assert mask_rows(bunker.mask) == _after_bomb(rows, picture, x - bunker.x, y - bunker.y)


def test_one_bomb_on_a_fresh_shield_removes_11_to_29_pixels_4_to_8_rows_deep():
    craters = []
    for btype in BombType:
        for offset in range(2, 18, 3):
            world = _quiet_world()
            bunker = world.bunkers[3]
            before = bunker.mask.count()
            bomb = _drop_bomb(world, btype, bunker.x + offset, bunker.y - 20)
            _fall_until_shield_hit(world, bomb, bunker)
            lost_rows = [y for y in range(bunker.h)
                         if mask_rows(bunker.mask)[y] != art.BUNKER[y]]
            craters.append((before - bunker.mask.count(), len(lost_rows)))
    assert all(11 <= pixels <= 29 and 4 <= depth <= 8 for pixels, depth in craters), craters
    assert len({pixels for pixels, _ in craters}) > 1  # the crater depends on type and place


def test_a_low_alien_clears_its_whole_16x16_footprint():
    world = _quiet_world()
    bunker = world.bunkers[0]
    rack = world.rack
    rack.ref_x, rack.ref_top, rack.cursor = bunker.x, bunker.y + 8, 0
    report = world.step(0)  # draws alien 0 with its footprint over the shield's rows
    assert [(c.a_kind, c.b_kind) for c in report.contacts] == [(Kind.ALIEN, Kind.BUNKER)]
    cleared = tuple("." * 16 + row[16:] for row in art.BUNKER)
    assert mask_rows(bunker.mask) == cleared
    world.step(0)  # alien 1, 16 px to the right, clears the rest
    assert bunker.mask.count() == 0
