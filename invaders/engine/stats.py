"""Values the detector returns: per-tick counters and contact records (no global state)."""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:  # made only when a contact is: importing fractions (and with it decimal)
    from fractions import Fraction  # is a tenth of the program's own start-up


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


@lru_cache(maxsize=4096)
def impact_time(step: int, steps: int) -> Fraction:
    """The time of substep `step` of `steps` within the tick, in the one time base of every
    contact: 0 is the tick's first instant (`impact_time(0, 0)`), 1 its last, where things
    land (`impact_time(1, 1)`). Kept per pair of numbers, the latest 4,096 (a Fraction
    costs a microsecond or two to make; they are immutable, so one serves every contact)."""
    from fractions import Fraction

    return Fraction(step, steps) if steps else Fraction(0)


class Contact(NamedTuple):
    """Two bodies touching on a tick: the time of first touch within it (an exact fraction,
    0 to 1), ids in order (low first), where each was at contact (for a swept entry the
    first touch, for the others where they landed), one shared pixel, and the rules entry
    that found it."""

    tick: int
    time: Fraction
    a_id: int
    b_id: int
    a_kind: int
    b_kind: int
    ax: int
    ay: int
    bx: int
    by: int
    px: int
    py: int
    rule: object  # the PairRule (typed loosely: rules.py builds on this module)


def contact_time(contact: Contact) -> float:
    """A contact's time as a float, which orders as the fractions do (see `contact_order`):
    enough to sort contacts already in (low id, high id) order, as a stable sort keeps it."""
    time = contact.time
    return time.numerator / time.denominator


def contact_order(contact: Contact) -> tuple[float, int, int]:
    """The order contacts are applied in: earliest first, ties by (low id, high id).

    The time is compared as a float, which orders exactly as the fractions do: a time's
    denominator is a tick's step count (a few hundred at most), and two fractions whose
    denominators are under 2**26 differ by more than a float's spacing between 0 and 1, so
    distinct times never round to one float and equal ones always do. (Comparing the
    fractions themselves costs several times more in a storm's thousands of contacts.)"""
    return contact_time(contact), contact.a_id, contact.b_id
