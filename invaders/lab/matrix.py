"""The method matrix: each cell a way to detect collisions, built as a Detector.

Dimensions: broad phase (brute force, grid with a cell of 4 to 128 px or chosen from the
scene, sort-and-sweep, the numpy broad phase, the cell rects, the engine's automatic
choice), quick test (rect, circle), thorough test (none: boxes are taken as the shapes;
mask), motion (discrete, swept, or auto: per entry, the cheapest proven exact for the
scene's speeds), and temporal sampling (detection every 1, 2, 4 or 8 original frames).
Every broad phase gives the same contacts (the contract), so accuracy depends only on the
other dimensions, and speed on all of them.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from invaders.engine.adaptive import make_broadphase
from invaders.engine.detector import Detector
from invaders.engine.grid import DEFAULT_CELL
from invaders.engine.rules import Motion, RuleTable, Shape
from invaders.game.config import DEFAULT_CONFIG, GameConfig
from invaders.game.rules import make_rules
from invaders.game.tuning import cheapest_rules
from invaders.lab.choices import CELLS, DEFAULT_NARROW, SAMPLINGS
from invaders.lab.methods import QUICK_TESTS


@dataclass(frozen=True)
class Method:
    broad: str = "grid"  # brute | grid | sweep | numpy | rects | auto
    cell: int = DEFAULT_CELL  # grid cell in px; 0: chosen from the scene
    quick: str = "rect"  # rect | circle
    thorough: str = "mask"  # none | mask
    motion: str = "auto"  # discrete | swept | auto
    sampling: int = 1  # detect every n-th original frame

    @property
    def label(self) -> str:
        broad = self.broad if self.broad != "grid" else f"grid{self.cell or 'auto'}"
        return f"{broad}/{self.quick}/{self.thorough}/{self.motion}/every{self.sampling}"

    @property
    def is_default(self) -> bool:
        return (self.quick, self.thorough, self.motion, self.sampling) == DEFAULT_NARROW


DEFAULT = Method()


def rules_for(method: Method, multiplier: int = 1,
              config: GameConfig = DEFAULT_CONFIG) -> RuleTable:
    """The game's rules table as the method models it (LANDING entries stay as they are:
    where things land is their definition); `config` has the projectiles' speeds at 1x."""
    if method.motion == "auto":
        rules = cheapest_rules(multiplier * method.sampling, config)
    else:
        motion = Motion.SWEPT if method.motion == "swept" else Motion.DISCRETE
        rules = make_rules(config).map(
            lambda r: r if r.motion is Motion.LANDING else replace(r, motion=motion))
    if method.thorough == "none":
        rules = rules.map(lambda r: replace(r, a_shape=Shape.BOX, b_shape=Shape.BOX))
    return rules


def detector_for(method: Method, multiplier: int = 1, cell: int | None = None,
                 rules: RuleTable | None = None,
                 config: GameConfig = DEFAULT_CONFIG) -> Detector:
    """A Detector for the method; `cell` replaces an automatic cell size once chosen, and
    `rules` (a scene's own zones) the game's table before the method models it."""
    size = method.cell or cell or DEFAULT_CELL
    quick = None if method.quick == "rect" else QUICK_TESTS[method.quick]
    table = rules_for(method, multiplier, config)
    if rules is not None:
        zones = {(r.a, r.b): r.zone for r in rules}
        table = table.map(lambda r: replace(r, zone=zones[(r.a, r.b)]))
    return Detector(make_broadphase(method.broad, size), table, quick)


def accuracy_matrix(quick: bool) -> list[Method]:
    """Narrow-phase cells, all on the default broad phase (it does not change contacts)."""
    samplings = (1, 2, 4) if quick else SAMPLINGS
    return [Method(quick=q, thorough=t, motion=m, sampling=s)
            for q in ("rect", "circle") for t in ("none", "mask")
            for m in ("discrete", "swept", "auto") for s in samplings]


def broad_matrix(quick: bool) -> list[Method]:
    """Broad-phase cells with the default narrow phase."""
    cells = (8, 16, 32, 64) if quick else CELLS
    return ([Method(broad="brute"), Method(broad="sweep"), Method(broad="numpy"),
             Method(broad="rects"), Method(broad="auto"), Method(cell=0)]
            + [Method(cell=c) for c in cells])
