"""The autopilot aims by its stated rule and sees the shields' columns as they are."""

from __future__ import annotations

from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st

from invaders.game.config import DEFAULT_CONFIG
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot, ShieldColumns

ALIEN_ROWS = (72, 88, 104, 120)  # tops a target can have


@settings(max_examples=300, deadline=None)
@given(places=st.lists(st.tuples(st.integers(0, 208), st.sampled_from(ALIEN_ROWS)),
                       min_size=1, max_size=11),
       lit=st.frozensets(st.integers(0, 223)), centre=st.integers(8, 200))
def test_the_target_is_the_first_alien_in_the_clear_then_lowest_then_nearest(places, lit,
                                                                             centre):
    """Least by (under a shield, higher up, distance from the cannon's centre), the first
    in column order on a tie: the rule written as a sort key."""
    targets = [SimpleNamespace(x=x, y=y) for x, y in places]
    pilot = Autopilot(0)
    pilot._columns = SimpleNamespace(shooters=lambda world, which: targets)
    pilot._shields = SimpleNamespace(edges=lambda world: frozenset(x - 8 for x in lit))
    world = SimpleNamespace(saucer=SimpleNamespace(saucer=None), config=DEFAULT_CONFIG,
                            cannon=SimpleNamespace(x=centre - 8))
    first = min(range(len(targets)), key=lambda i: (
        targets[i].x + 8 in lit, -targets[i].y, abs(targets[i].x + 8 - centre), i))
    assert pilot._find_target(world) == targets[first].x + 8


def test_the_target_follows_the_cannon_and_an_alien_that_dropped():
    """Worked out each tick: an alien that drops below the rest becomes the target; the
    cannon's moves pick within the row, the first of two as near."""
    targets = [SimpleNamespace(x=16 * i, y=50) for i in range(5)]
    pilot = Autopilot(0)
    pilot._columns = SimpleNamespace(shooters=lambda world, which: targets)
    pilot._shields = SimpleNamespace(edges=lambda world: frozenset({200}))
    cannon = SimpleNamespace(x=0)
    world = SimpleNamespace(saucer=SimpleNamespace(saucer=None), config=DEFAULT_CONFIG,
                            cannon=cannon)
    assert pilot._find_target(world) == 8  # nearest the cannon at the left
    cannon.x = 40
    assert pilot._find_target(world) == 40  # x 32 and 48 as near: the first
    targets[3].y = 58  # dropped
    assert pilot._find_target(world) == 56  # now the lowest


def test_shield_columns_are_those_with_a_lit_pixel_and_follow_erosion():
    world = World(seed=1)
    columns = ShieldColumns()

    def lit_by_pixels() -> set[int]:
        return {bunker.x + cx for bunker in world.bunkers for cx in range(bunker.w)
                if any(bunker.mask.get_at((cx, cy)) for cy in range(bunker.h))}

    pilot = Autopilot(1)  # its targets and shots go by the boxes' left edges, 8 px left
    assert columns.lit(world) == lit_by_pixels()
    assert pilot._shields.edges(world) == {x - 8 for x in lit_by_pixels()}
    bunker = world.bunkers[1]
    for cx in (10, 11, 12):  # three columns of the second shield cleared...
        for cy in range(bunker.h):
            bunker.mask.set_at((cx, cy), 0)
    bunker.mask.set_at((11, 0), 1)  # ...but for a pixel at the top of one
    bunker.mask.set_at((12, bunker.h - 1), 1)  # and one at the bottom of another
    world.erosions += 1  # as the world's erosion counts it
    world.store.tick += 1  # the autopilot looks again on a later tick
    lit = columns.lit(world)
    assert (bunker.x + 10 in lit, bunker.x + 11 in lit, bunker.x + 12 in lit) == (
        False, True, True)
    assert lit == lit_by_pixels()
    assert pilot._shields.edges(world) == {x - 8 for x in lit}


def test_shield_columns_keep_only_the_shields_of_the_wave_in_play():
    """Each wave makes new shields: what was kept of the old ones goes, so a long run's
    memory stays flat (it grew by every wave's shields)."""
    world = World(seed=1)
    columns = ShieldColumns()
    for wave in range(2, 40):
        columns.lit(world)
        assert set(columns._seen) == {bunker.id for bunker in world.bunkers}
        world._start_wave(wave)
    assert columns.lit(world) == {bunker.x + cx for bunker in world.bunkers
                                  for cx in range(bunker.w)
                                  if any(bunker.mask.get_at((cx, cy)) for cy in range(bunker.h))}
