"""The autopilot's styles, apart from the autopilot, so the command line can list them
without loading it."""

STYLES = {
    # name: (chance to notice a bomb, rack columns it shoots at: all, the middle one (which
    # a defender clears, then hides under) or none, keeps the 300 shot for saucers)
    "hunter": (0.85, "all", False),
    "expert": (0.98, "all", True),
    "defender": (0.995, "middle", False),
    "pacifist": (0.995, "none", False),
}
