"""`python -m invaders` is `invaders play`."""

import sys

from invaders.app.cli import main

if __name__ == "__main__":
    sys.exit(main(["play", *sys.argv[1:]]))
