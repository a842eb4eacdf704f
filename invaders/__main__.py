"""`python -m invaders` is the `invaders` command (which plays when no command is named);
the command starts here too, so that a Ctrl-C while the program is still loading is one
line, as everywhere else."""

import sys


def run(argv: list[str] | None = None) -> int:
    try:
        from invaders.app.cli import main
    except KeyboardInterrupt:
        print("invaders: interrupted", file=sys.stderr)
        return 130
    return main(argv)


if __name__ == "__main__":
    sys.exit(run())
