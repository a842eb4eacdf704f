"""The 5x11 alien rack: one alien redrawn per tick, the reference alien moving at each wrap."""

from __future__ import annotations

import copy
from bisect import bisect_left
from collections.abc import Sequence
from typing import Any, cast

from invaders.engine.body import copied
from invaders.engine.compiled import mypyc_attr
from invaders.engine.store import BodyStore
from invaders.game import art
from invaders.game.config import GameConfig
from invaders.game.entities import ALIEN_MASKS, FOOTPRINT_ABOVE, Alien

ALIEN_HEIGHT = max(len(picture) for pictures in art.ALIEN_BY_ROW for picture in pictures)


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Rack:
    """Aliens sit at (ref_x + 16c, ref_top - 16r) *as of their last draw*.

    The cursor walks live aliens in index order (row * cols + col, bottom-left first), drawing
    one per tick; past the last live one the reference alien steps (dx, and 8 down after an
    edge bump) and the picture frame toggles. N live aliens therefore take N ticks a step.
    A wave starts on an empty field: each alien appears (joins the store) at its first draw,
    so the first pass of the cursor draws the rack one alien a tick (0141, 1B10).
    A kill holds the cursor (`hold`): the ROM spends those ticks' draws on the alien's
    explosion, and on a dead alien the cursor was already set on.
    """

    def __init__(self, config: GameConfig, top: int, store: BodyStore) -> None:
        g = config.geometry
        self.config = config
        self.ref_x = g.rack_left
        self.ref_top = top
        self.dx = config.speeds.rack_step
        self.frame = 0
        self.cursor = 0
        self.aliens: list[Alien | None] = []
        for index in range(g.rows * g.cols):
            row, col = divmod(index, g.cols)
            alien = Alien(store.new_id(), index, row, col, self.ref_x + g.cell * col,
                          top - g.cell * row, 0)
            alien.alive = False  # not drawn yet
            self.aliens.append(alien)
        self.live = len(self.aliens)
        self._live_indices = list(range(self.live))  # in order: the cursor finds the next
        self._extent: tuple[int, int] | None = None  # lit columns' offsets from ref_x
        # Aliens drawn so far, and breaks in the cursor's walk (a kill, the rack hidden):
        # what a RackWatch compares between two looks.
        self.draws = 0
        self.breaks = 0
        self.held = 0  # ticks whose draw is spent before the cursor moves on (`hold`)

    def __deepcopy__(self, memo: dict[int, Any]) -> Rack:
        """A copy with aliens of its own (each copied once, through `memo`); its numbers,
        tuples and config taken as they are."""
        clone = copy.copy(self)
        memo[id(self)] = clone
        clone.aliens = [None if alien is None else cast(Alien, copied(alien, memo))
                        for alien in self.aliens]
        clone._live_indices = list(self._live_indices)
        return clone

    def live_aliens(self) -> list[Alien]:
        """Live aliens on the screen (drawn at least once), in index order."""
        return [a for a in self.aliens if a is not None and a.alive]

    def lowest_in_column(self, col: int) -> Alien | None:
        """The shooter of a column: its lowest live alien, or None if the column is empty."""
        cols = self.config.geometry.cols
        for row in range(self.config.geometry.rows):
            alien = self.aliens[row * cols + col]
            if alien is not None:
                return alien
        return None

    def kill(self, alien: Alien, store: BodyStore) -> None:
        """Take an alien out of the rack (the cursor skips it from now on)."""
        self.aliens[alien.index] = None
        self.live -= 1
        self._live_indices.remove(alien.index)
        self._extent = None
        self.breaks += 1
        store.remove(alien)

    def next_index(self) -> int:
        """The index of the alien the cursor draws next, the first live one if it has
        passed them all (the last one ahead was killed: it wraps at its next draw)."""
        live = self._live_indices
        at = bisect_left(live, self.cursor)
        return live[at] if at < len(live) else live[0]

    def hold(self, ticks: int) -> None:
        """Spend the next `ticks` ticks' draws: the cursor stands still whatever else
        moves (the ROM's DrawAlien runs every frame, 0100, and waits on none of it)."""
        self.held = ticks

    def spend_held(self) -> bool:
        """Spend this tick's draw if it is held; say whether it was."""
        if self.held == 0:
            return False
        self.held -= 1
        return True

    def set_step(self, kept: int) -> None:
        """March with the step a player's page kept, as InitRack sets it at the start of
        their turn or wave (00B1-00C7): a step right of one alien left backed down to the
        usual step, until the next bump at the left edge sets it again."""
        s = self.config.speeds
        self.dx = s.rack_step if kept == s.rack_step_last_right else kept

    def hide(self) -> None:
        """The rack leaves the screen with its player (its aliens taken out of the store):
        they are drawn again, one a tick from the bottom left, when the player comes back."""
        self.cursor = 0
        self.breaks += 1

    def step(self, store: BodyStore) -> Alien | None:
        """Draw the next live alien at its place relative to the reference; wrap if last."""
        if self.live == 0:
            return None
        g = self.config.geometry
        live = self._live_indices
        at = bisect_left(live, self.cursor)  # the next live index from the cursor
        if at == len(live):
            self._wrap()
            at = 0
        index = live[at]
        alien = self.aliens[index]
        assert alien is not None
        row, col = divmod(index, g.cols)
        if not alien.alive:  # its first draw: it appears where it stands
            store.add(alien)
        if alien.frame != self.frame:
            alien.frame = self.frame
            store.reshape(alien, ALIEN_MASKS[row][self.frame])
        store.move(alien, self.ref_x + g.cell * col,
                   self.ref_top - g.cell * row - FOOTPRINT_ABOVE)
        self.cursor = index + 1
        self.draws += 1
        if at == len(live) - 1:  # the last live one
            self._wrap()
        return alien

    def last_drawn(self, count: int) -> list[int]:
        """The indices of the last `count` aliens drawn, newest first. The cursor walks the
        live aliens in index order, so they are the `count` live ones before it (wrapping
        round): true while the walk has not broken since (`breaks`) and `count` is under
        the live count."""
        live = self._live_indices
        at = bisect_left(live, self.cursor)
        return [live[at - back] for back in range(1, count + 1)]  # (a negative index wraps)

    def picture_rows(self) -> tuple[int, int]:
        """The screen rows the live aliens' pictures may cover, from the first to the one
        past the last (none with no live alien). Each was drawn at the reference as it is
        or as it was before its last move (a step, or at an edge a drop): the highest
        live row's may still stand a drop higher, the lowest's is lowest where it is now."""
        live = self._live_indices
        if not live:
            return 0, 0
        cols, cell = self.config.geometry.cols, self.config.geometry.cell
        highest, lowest = live[-1] // cols, live[0] // cols  # (row 0 is the bottom one)
        return (self.ref_top - cell * highest - self.config.speeds.rack_drop,
                self.ref_top - cell * lowest + ALIEN_HEIGHT)

    def _wrap(self) -> None:
        """The reference alien moves: a step, or at an edge a drop and a step back."""
        s = self.config.speeds
        g = self.config.geometry
        left, right = self._lit_extent()
        if self.dx > 0 and right >= g.edge_right:
            self.dx = -s.rack_step
            self.ref_top += s.rack_drop
        elif self.dx < 0 and left <= g.edge_left:
            self.dx = s.rack_step_last_right if self.live == 1 else s.rack_step
            self.ref_top += s.rack_drop
        self.ref_x += self.dx
        self.frame ^= 1
        self.cursor = 0

    def _lit_extent(self) -> tuple[int, int]:
        """Leftmost and rightmost lit screen columns of the live aliens, at the reference
        (their offsets from it change only when an alien is killed, so they are kept)."""
        if self._extent is None:
            cell = self.config.geometry.cell
            left, right = 10**6, -(10**6)
            for alien in self.aliens:
                if alien is None:
                    continue
                lo, hi = art.ALIEN_LIT_COLUMNS[art.ALIEN_BY_ROW[alien.row]]
                left = min(left, cell * alien.col + lo)
                right = max(right, cell * alien.col + hi)
            self._extent = (left, right)
        return self.ref_x + self._extent[0], self.ref_x + self._extent[1]


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class RackWatch:
    """Which of a rack's places (alien indices) may have changed since the last look, for
    an observer that keeps what it made of them: only the aliens drawn since, while the
    same rack has drawn fewer than its live aliens and its walk has not broken; otherwise
    every place (another rack, a kill, the rack hidden, many draws)."""

    def __init__(self) -> None:
        self._rack: Rack | None = None
        self._draws = self._breaks = 0

    def __reduce__(self) -> tuple[type[RackWatch], tuple[()]]:
        """Pickled as a new watch: loaded, the rack it watched is another object, so its
        next look names every place."""
        return RackWatch, ()

    def changed(self, rack: Rack) -> Sequence[int]:
        """The places to look at again, and note the rack as seen now."""
        count = rack.draws - self._draws
        if rack is self._rack and rack.breaks == self._breaks and count < rack.live:
            places: Sequence[int] = rack.last_drawn(count)
        else:
            places = range(len(rack.aliens))
        self._rack, self._draws, self._breaks = rack, rack.draws, rack.breaks
        return places


def pictures_apart(config: GameConfig) -> bool:
    """Whether no two of a rack's aliens can share a lit pixel. Every live alien was drawn
    at the reference as it is or as it was before its last move (a step, or at an edge a
    step back and a drop): a row's aliens are a cell apart, at most a step out of line,
    so the widest picture's lit columns and the largest step must fit in a cell; rows are
    a cell apart, at most a drop out of line, so a picture's height and the drop must."""
    g, s = config.geometry, config.speeds
    widest = max(hi - lo + 1 for lo, hi in art.ALIEN_LIT_COLUMNS.values())
    step = max(s.rack_step, s.rack_step_last_right)
    return widest + step <= g.cell and ALIEN_HEIGHT + s.rack_drop <= g.cell
