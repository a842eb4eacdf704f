"""The config's fields, defaults and valid ranges as a Markdown table, made from the config
itself (docs/replays.md carries it, and a test keeps the two the same)."""

from __future__ import annotations

import dataclasses

from invaders.game.config import GameConfig


def ranges_table(config: GameConfig | None = None) -> str:
    """One row per field: its path as replay files name it, its default and its range."""
    config = config or GameConfig()
    rows = ["| field | default | valid |", "| --- | --- | --- |"]

    def walk(section: object, path: str) -> None:
        for field in dataclasses.fields(section):  # type: ignore[arg-type]
            value = getattr(section, field.name)
            name = f"{path}.{field.name}"
            if dataclasses.is_dataclass(value):
                walk(value, name)
                continue
            low, high = field.metadata["range"]
            if isinstance(value, tuple):
                shortest, longest = field.metadata["length"]
                shown = ", ".join(map(str, value))
                valid = f"{shortest} to {longest} values, each {low}..{high}"
            else:
                shown, valid = str(value), f"{low}..{high}"
            rows.append(f"| `{name}` | {shown} | {valid} |")

    walk(config, "config")
    return "\n".join(rows) + "\n"
