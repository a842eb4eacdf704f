"""Objects that hold pygame masks, through pickle (pygame's masks have no pickling of their
own): a world handed to another process, an environment's state kept on disk.

Such an object's `__reduce__` returns `reduce_with_masks(self)`: its class and fields,
pickled by a pickler of their own that writes each mask either as the call that makes it
again (a shared picture's mask, registered with `remade_by`: loaded in any process, it is
that process's shared mask) or as its size and pixels (a mask of its own, such as a shield
that erodes, loaded as a new one). Pickle's memo keeps what shared a mask sharing it.
"""

from __future__ import annotations

import copyreg
import io
import pickle
from collections.abc import Callable
from typing import Any, TypeVar

import pygame

from invaders.engine.compiled import fields

T = TypeVar("T")
Recipe = tuple[Callable[..., pygame.mask.Mask], tuple[Any, ...]]
_recipes: dict[pygame.mask.Mask, Recipe] = {}  # (masks hash by identity)


def remade_by(mask: pygame.mask.Mask, make: Callable[..., pygame.mask.Mask],
              *args: Any) -> pygame.mask.Mask:
    """Pickle `mask` as the call `make(*args)`, which gives this same mask again (a cached
    function found by its name, of arguments that pickle); returns the mask."""
    _recipes[mask] = (make, args)
    return mask


def forget_recipe(mask: pygame.mask.Mask) -> None:
    """`mask` pickles as its pixels again (its maker lets it go: kept here, it would be
    kept for the process)."""
    _recipes.pop(mask, None)


def mask_bytes(mask: pygame.mask.Mask) -> bytes:
    """The mask's pixels, one byte each (255 lit, 0 not), row by row."""
    surface = mask.to_surface(setcolor=(255, 255, 255, 255), unsetcolor=(0, 0, 0, 255))
    return pygame.image.tobytes(surface, "RGB")[::3]


def mask_from_bytes(size: tuple[int, int], pixels: bytes) -> pygame.mask.Mask:
    """A new mask of `size` with the pixels `mask_bytes` gave."""
    mask = pygame.mask.Mask(size)
    width = size[0]
    for at, lit in enumerate(pixels):
        if lit:
            mask.set_at((at % width, at // width))
    return mask


def _reduce_mask(mask: pygame.mask.Mask) -> Recipe:
    recipe = _recipes.get(mask)
    return recipe if recipe is not None else (mask_from_bytes,
                                              (mask.get_size(), mask_bytes(mask)))


def reduce_with_masks(obj: object) -> tuple[Callable[[bytes], Any], tuple[bytes]]:
    """What `obj.__reduce__` returns for an object whose fields hold masks (see above)."""
    buffer = io.BytesIO()
    pickler = pickle.Pickler(buffer, pickle.HIGHEST_PROTOCOL)
    pickler.dispatch_table = {**copyreg.dispatch_table, pygame.mask.Mask: _reduce_mask}
    pickler.dump((type(obj), fields(obj)))
    return _with_fields, (buffer.getvalue(),)


def _with_fields(pickled: bytes) -> Any:
    """The object `reduce_with_masks` pickled."""
    cls, values = pickle.loads(pickled)
    return with_fields(cls, values)


def with_fields(cls: type[T], values: dict[str, Any]) -> T:
    """A new object of `cls`, its `__init__` not called, its fields set by name: how an
    object pickled as its fields by name is loaded, by either build (docs/compiled.md)."""
    obj = cls.__new__(cls)
    for name, value in values.items():
        setattr(obj, name, value)
    return obj
