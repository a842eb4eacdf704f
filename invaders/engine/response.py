"""Step 4: apply a tick's contacts, earliest first, after every pair has been tested.

Detect first, respond after: nothing is killed or eroded while pairs are still being tested
(eroding mid-loop would let a shot drill through a shield). Contacts come in (time of
impact, low id, high id) order; a body that an earlier contact spent (as its entry says)
takes part in no later contact of that tick, so the earliest contact is the one that happens.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from invaders.engine.body import Body
from invaders.engine.rules import PairRule
from invaders.engine.stats import Contact


def spent_ids(contact: Contact) -> tuple[int, ...]:
    """The ids a contact spends, as its entry says (in a same-kind entry the low id is a)."""
    rule: PairRule = contact.rule  # type: ignore[assignment]
    in_order = contact.a_kind == rule.a
    first = rule.spends_a if in_order else rule.spends_b
    second = rule.spends_b if in_order else rule.spends_a
    if first and second:
        return contact.a_id, contact.b_id
    if first:
        return (contact.a_id,)
    return (contact.b_id,) if second else ()


def first_contacts(contacts: Iterable[Contact]) -> list[Contact]:
    """The contacts that happen: in order, dropping those of bodies already spent."""
    spent: set[int] = set()
    out = []
    for contact in contacts:
        if contact.a_id in spent or contact.b_id in spent:
            continue
        out.append(contact)
        spent.update(spent_ids(contact))
    return out


def respond(contacts: Iterable[Contact], bodies: Mapping[int, Body],
            context: object) -> list[Contact]:
    """Call each happening contact's response with the bodies in its entry's order; skip
    contacts whose bodies are gone. Returns the contacts applied."""
    applied = []
    for contact in first_contacts(contacts):
        a = bodies.get(contact.a_id)
        b = bodies.get(contact.b_id)
        if a is None or b is None or not (a.alive and b.alive):
            continue
        rule: PairRule = contact.rule  # type: ignore[assignment]
        if rule.response is not None:
            if a.kind == rule.a:
                rule.response(context, a, b, contact)
            else:
                rule.response(context, b, a, contact)
        applied.append(contact)
    return applied
