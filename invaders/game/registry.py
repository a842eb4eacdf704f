"""How sim parts add, move and remove bodies without knowing about the broad phase."""

from __future__ import annotations

from typing import Protocol

from invaders.engine.body import Body


class Registry(Protocol):
    """The world's book of bodies: every change goes through it, so the grid hears of it."""

    tick: int

    def new_id(self) -> int: ...

    def add(self, body: Body) -> None: ...

    def move(self, body: Body, x: int, y: int) -> None: ...

    def remove(self, body: Body) -> None: ...
