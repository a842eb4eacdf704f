"""`python -m invaders` is the `invaders` command (which plays when no command is named);
the command starts here too, so that a Ctrl-C while the program is still loading is one
line, as everywhere else."""

import os
import sys

# The window's class, by which window managers group windows and match them to a launcher:
# the program's name however it was started (pygame gives its import's `argv[0]`, which
# is '__main__.py' under `python -m`). Set before pygame is imported; one given is kept.
os.environ.setdefault("SDL_VIDEO_X11_WMCLASS", "invaders")


def run(argv: list[str] | None = None) -> int:
    try:
        from invaders.app.cli import main
    except KeyboardInterrupt:
        print("invaders: interrupted", file=sys.stderr)
        return 130
    return main(argv)


if __name__ == "__main__":
    sys.exit(run())
