"""Digests of the game state, for replays and determinism tests.

The state is split into named groups (game, rack, cannon, shot, bombs, saucer, shields,
ground, explosions; the world lists their values), each with its own digest, so that a
replay that goes wrong can say which group went wrong first. The state hash is the digest of
the group digests. Left out: the broad phase's bookkeeping, collision counters, anything
cosmetic.
"""

from __future__ import annotations

from collections.abc import Mapping

try:  # hashlib's own blake2b, without hashlib loading OpenSSL for the others (start-up)
    from _blake2 import blake2b
except ImportError:  # an interpreter without that module
    from hashlib import blake2b

GROUPS = ("game", "rack", "cannon", "shot", "bombs", "saucer", "shields", "ground",
          "explosions")


def digest(value: object) -> str:
    """A short digest of a plain value (bytes as they are, anything else by its repr)."""
    data = value if isinstance(value, bytes) else repr(value).encode()
    return blake2b(data, digest_size=8).hexdigest()


def group_hashes(values: Mapping[str, object]) -> dict[str, str]:
    """A short digest per group, from the groups' plain values."""
    return {name: digest(values[name]) for name in GROUPS}


# The group digests as the state hash lists them: game=...,rack=...,... in GROUPS' order.
LISTED = b",".join(b"%s=%%s" % name.encode() for name in GROUPS)


def combine(groups: Mapping[str, str]) -> str:
    """The state hash (128 bits, hex) from the group digests."""
    return digest_listed(LISTED % tuple(groups[name].encode() for name in GROUPS)).hex()


def digest_listed(listed: bytes) -> bytes:
    """The state hash's 16 bytes from the group digests as LISTED lists them."""
    return blake2b(listed, digest_size=16).digest()
