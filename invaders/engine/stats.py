"""Values the pipeline returns: per-tick counters and contact records (no global state)."""

from __future__ import annotations

from typing import NamedTuple

from invaders.engine.body import Kind


class CollisionStats(NamedTuple):
    """How many pairs each step of one tick's pipeline considered.

    Summed over a run they show the reduction each step buys: naive pairs, then what the rules
    allow, then what the broad phase hands on, then what the quick and thorough tests confirm.
    """

    objects: int = 0
    naive_pairs: int = 0  # n(n-1)/2 over every collidable body
    allowed_pairs: int = 0  # pairs of kinds the rules table tests, inside their zones
    candidates: int = 0  # pairs the broad phase reports
    rect_tests: int = 0  # quick box tests (swept boxes for swept pairs)
    rect_hits: int = 0
    mask_tests: int = 0  # pixel-mask tests at one position
    mask_hits: int = 0
    swept_tests: int = 0  # pixel tests along the relative motion of a tick
    contacts: int = 0


STAT_FIELDS: tuple[str, ...] = CollisionStats._fields


class Contact(NamedTuple):
    """Two bodies touching on a tick: ids in order (low first), where each was at first
    contact (swept contacts may be earlier than the tick's end), and one shared pixel."""

    tick: int
    a_id: int
    b_id: int
    a_kind: Kind
    b_kind: Kind
    ax: int
    ay: int
    bx: int
    by: int
    px: int
    py: int
