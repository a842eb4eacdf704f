"""The cabinet's attract sequence as the ROM runs it, frame by frame (0AEA-0BE7).

One cycle: a second's pause; PLAY typed letter by letter (six frames a letter, 0A93), with
an upside-down Y on every other cycle; SPACE  INVADERS typed; the score advance table, its
pictures at once and its lines typed (1815); on the cycles with the upside-down Y, an alien
walks on, pulls the Y off and pushes a straight one back (0B1E-0B47); the demo (a game of
its own, see `DemoPilot`); then INSERT  COIN and the credit lines, and on the same cycles
INSERT CCOIN, whose extra C an alien shoots off (0BA6, 0BCE-0BD7). Positions are the ROM's
screen addresses turned into the upright screen's pixels.

`Script` says what shows at any frame of a cycle; it knows nothing of pygame or of time.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from invaders.game import art
from invaders.game.actions import Action
from invaders.game.world import World

FPS = 60
LETTER = 6  # frames a typed letter takes (0A93: the delay counter set to 7, waited down to 1)
ONE_SECOND, TWO_SECONDS = 64, 128  # 0AB1, 0AB6: 0x40 and 0x80 frames
UPSIDE_DOWN_Y = "\u028e"  # the font's turned Y


def _flip_left(picture: art.Art, columns: int) -> art.Art:
    """The picture with its first columns upside down (the Y it carries turned over)."""
    flipped = [row[:columns] for row in picture[::-1]]
    return tuple(top + row[columns:] for top, row in zip(flipped, picture, strict=True))


# The alien carrying a Y, two pictures (ROM 1F80 and 1FB0); pulling the upside-down one it is
# the same alien with the Y turned over (UNCERTAIN: 1BB0's picture is not in our notes).
ALIEN_WITH_Y = (
    art.art("..........##....", "#...#....####...", "#...##..######..", ".#.#.####.##.##.",
            "..#...#########.", "..#.....#.##.#..", "..#....#......#.", "..#.....#....#.."),
    art.art("..........##....", ".#...#...####...", ".#...##.######..", "..#.#.###.##.##.",
            "...#..#########.", "...#.....#..#...", "...#....#.##.#..", "...#...#.#..#.#."),
)
ALIEN_PULLING_Y = tuple(_flip_left(picture, 6) for picture in ALIEN_WITH_Y)
SMALL_ALIEN = art.ALIEN_C  # the squid (1C20 and its second picture)


@dataclass(frozen=True)
class Step:
    """One thing the sequence does, for `frames` frames (None: until the demo ends)."""

    kind: str  # "wait", "type", "show", "move", "drop", "clear", "demo", "unshow", "shoot"
    frames: int | None = 0
    texts: tuple[tuple[str, int, int], ...] = ()
    pictures: tuple[tuple[art.Art, int, int], ...] = ()
    path: tuple[int, int, int] = (0, 0, 0)  # a move: x from, x to, y
    frames_of: tuple[art.Art, ...] = ()  # a move's pictures, one after the other each frame


def _blank_left(picture: art.Art) -> int:
    """Columns our picture has before the ROM's first byte (the saucer's box starts 4 early,
    at 1D64; the table draws 16 bytes from 1D68)."""
    return 4 if picture is art.SAUCER else 0


def typed(message: str, x: int, y: int) -> Step:
    return Step("type", LETTER * len(message), texts=((message, x, y),))


def moved(pictures: tuple[art.Art, ...], x0: int, x1: int, y: int) -> Step:
    """A splash sprite moved one pixel a frame from x0 to x1 (the ISR's splash task)."""
    return Step("move", abs(x1 - x0), path=(x0, x1, y), frames_of=pictures)


TABLE = ((art.SAUCER, "=? MYSTERY", 136), (art.ALIEN_C[0], "=30 POINTS", 152),
         (art.ALIEN_B[1], "=20 POINTS", 168), (art.ALIEN_A[0], "=10 POINTS", 184))
CREDITS = (("<1 OR 2 PLAYERS>", 48, 144), ("*1 PLAYER  1 COIN", 48, 168),
           ("*2 PLAYERS 2 COINS", 48, 192))


def cycle(animated: bool) -> list[Step]:
    """One cycle's steps; `animated`: the cycles with the upside-down Y and the extra C."""
    steps = [Step("wait", ONE_SECOND),
             typed("PLA" + (UPSIDE_DOWN_Y if animated else "Y"), 96, 64),
             typed("SPACE  INVADERS", 56, 88), Step("wait", ONE_SECOND),
             Step("show", texts=(("*SCORE ADVANCE TABLE*", 32, 120),),
                  pictures=tuple((picture, 64 - _blank_left(picture), y)
                                 for picture, _, y in TABLE)),
             *(typed(message, 80, y) for _, message, y in TABLE), Step("wait", TWO_SECONDS)]
    if animated:  # (0B1E-0B47: structures 1A95, 1BB0 and 1FC9)
        steps += [moved(SMALL_ALIEN, 222, 126, 64),
                  Step("unshow", texts=((UPSIDE_DOWN_Y, 120, 64),)),
                  moved(ALIEN_PULLING_Y, 120, 223, 64), Step("wait", ONE_SECOND),
                  moved(ALIEN_WITH_Y, 223, 119, 64), Step("wait", ONE_SECOND),
                  Step("drop"), Step("show", pictures=((Y_LEFT_BEHIND, 119, 64),)),
                  Step("wait", TWO_SECONDS)]
    steps += [Step("clear"), Step("demo", None), Step("wait", ONE_SECOND), Step("clear"),
              Step("show", texts=(("INSERT  COIN", 64, 112),
                                  *((("C", 120, 112),) if animated else ())))]
    steps += [typed(*line) for line in CREDITS]
    steps.append(Step("wait", TWO_SECONDS))
    if animated:  # (0BCE-0BD7: structure 1FD5, then the shot at the extra C, 189E)
        steps += [moved(SMALL_ALIEN, 2, 116, 40), Step("shoot", SHOT_FRAMES)]
    return steps


# The straight Y the alien leaves behind once it is cleared (0B41: ten columns from x 125).
Y_LEFT_BEHIND = tuple(row[:6] for row in ALIEN_WITH_Y[0])
# The shot at the extra C: a squiggly bomb from under the alien down to the C's row, 4 px a
# frame, then its burst. UNCERTAIN (189E is not in our notes): the timing is ours.
SHOT_FROM, SHOT_TO, SHOT_X, SHOT_SPEED, BURST_FRAMES = 48, 104, 123, 4, 16
SHOT_FRAMES = (SHOT_TO - SHOT_FROM) // SHOT_SPEED + BURST_FRAMES


@dataclass
class Screen:
    """What the field shows: texts, pictures and the one moving splash sprite (the score
    bar is always there)."""

    texts: list[tuple[str, int, int]] = field(default_factory=list)
    pictures: list[tuple[art.Art, int, int]] = field(default_factory=list)
    sprite: tuple[art.Art, int, int] | None = None

    def drawn(self) -> list[tuple[art.Art, int, int]]:
        return [*self.pictures, *([self.sprite] if self.sprite else [])]


def apply(screen: Screen, step: Step, frame: int) -> None:
    """The step's effect on the screen `frame` frames into it (its whole effect once its
    frames have run)."""
    if step.kind == "clear":
        screen.texts.clear()
        screen.pictures.clear()
        screen.sprite = None
    elif step.kind == "show":
        screen.texts.extend(step.texts)
        screen.pictures.extend(step.pictures)
    elif step.kind == "drop":
        screen.sprite = None
    elif step.kind == "unshow":
        screen.texts[:] = [_without(t, step.texts[0]) for t in screen.texts]
    elif step.kind == "type":
        message, x, y = step.texts[0]
        shown = message[:min(len(message), frame // LETTER + 1)]
        screen.texts.append((shown, x, y))
    elif step.kind == "move":  # a moved sprite stays where it stopped until replaced
        x0, x1, y = step.path
        moved_by = min(frame, step.frames or 0)
        x = x0 + (moved_by if x1 > x0 else -moved_by)
        screen.sprite = (step.frames_of[moved_by % len(step.frames_of)], x, y)
    elif step.kind == "shoot":
        _shoot(screen, frame)


def _without(text: tuple[str, int, int], letter: tuple[str, int, int]) -> tuple[str, int, int]:
    """A line with one letter taken out (the alien pulls the Y of PLAY off)."""
    message, x, y = text
    ch, lx, ly = letter
    at = (lx - x) // 8
    if ly != y or not 0 <= at < len(message) or message[at] != ch:
        return text
    return (message[:at] + " " + message[at + 1:], x, y)


def _shoot(screen: Screen, frame: int) -> None:
    """The squiggly bomb falls on the extra C; at its burst the C is gone."""
    falling = (SHOT_TO - SHOT_FROM) // SHOT_SPEED
    if frame < falling:
        y = SHOT_FROM + SHOT_SPEED * frame
        screen.pictures.append((art.BOMB_SQUIGGLY[frame % 4], SHOT_X, y))
        return
    screen.texts[:] = [t for t in screen.texts if t != ("C", 120, 112)]
    if frame < falling + BURST_FRAMES:
        screen.pictures.append((art.BOMB_BURST, SHOT_X - 2, SHOT_TO + 2))


class Script:
    """A cycle's steps and what shows at a frame of it; the demo step waits for its game."""

    def __init__(self, animated: bool) -> None:
        self.animated = animated
        self.steps = cycle(animated)

    def screen_at(self, index: int, frame: int) -> Screen:
        """The field `frame` frames into step `index` (the steps before it all done)."""
        screen = Screen()
        for number, step in enumerate(self.steps[:index + 1]):
            apply(screen, step, (step.frames or 0) if number < index else frame)
        return screen


class DemoPilot:
    """The ROM's demo player: fires whenever its shot is free, and each time it fires takes
    the next of ten moves from the table at 1F74 (1 right, 2 left, 0 still), which it holds
    until the next shot (1652-1668). UNCERTAIN: our notes do not say where the table's
    pointer starts; we start at its first entry."""

    MOVES = (1, 1, 0, 0, 1, 0, 2, 1, 0, 2)  # the bytes at 1F74-1F7D

    def __init__(self) -> None:
        self.at = -1
        self.move = 0

    def actions(self, world: World) -> int:
        free = world.shot_ready
        fire = 0
        if free and not world.fire_was_down and world.cannon.state == 1:
            self.at = (self.at + 1) % len(self.MOVES)
            self.move = self.MOVES[self.at]
            fire = int(Action.FIRE)
        side = {1: int(Action.RIGHT), 2: int(Action.LEFT)}.get(self.move, 0)
        return fire | side
