"""The lab's choices and their options, the first of each the game's own: one list the
method matrix, the live lab and the command line share (light enough for the command line
to offer them without loading the lab)."""

from invaders.engine.adaptive import BROADPHASES

BROADS = BROADPHASES  # the engine's, the game's own first
CELLED = ("auto", "rects", "grid", "numpy")  # the broad phases a cell size applies to
CELLS = (4, 8, 16, 32, 64, 128)
QUICK_TESTS = ("rect", "circle")
THOROUGH_TESTS = ("mask", "none")
MOTIONS = ("auto", "discrete", "swept")  # auto: per entry, as proven exact
SAMPLINGS = (1, 2, 4, 8)  # detect every n-th tick
MULTIPLIERS = (1, 2, 4, 8, 16)  # projectile speed

DEFAULT_NARROW = (QUICK_TESTS[0], THOROUGH_TESTS[0], MOTIONS[0], SAMPLINGS[0])
