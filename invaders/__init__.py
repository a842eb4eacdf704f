"""invaders: Space Invaders (1978) as a measured laboratory of 2D collision detection."""

import os

# pygame prints a banner on import; our last output line must be the state hash.
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

__version__ = "0.1.0"
