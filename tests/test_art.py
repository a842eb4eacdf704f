"""The pictures the original's ROM holds, byte for byte: each written here as the ROM stores
it (one byte a column, left to right; bit 7 the top pixel, bit 0 the bottom, upright view),
decoded, and compared with the game's art."""

from __future__ import annotations

import pytest

from invaders.game import art

ROM = {  # address: (bytes as hex, the picture the game uses)
    "1CEE": ("00fe00", art.BOMB_ROLLING[0]), "1CF1": ("24fe12", art.BOMB_ROLLING[1]),
    "1CF4": ("00fe00", art.BOMB_ROLLING[2]), "1CF7": ("48fe90", art.BOMB_ROLLING[3]),
    "1CE2": ("04fc04", art.BOMB_PLUNGER[0]), "1CE5": ("10fc10", art.BOMB_PLUNGER[1]),
    "1CE8": ("20fc20", art.BOMB_PLUNGER[2]), "1CEB": ("80fc80", art.BOMB_PLUNGER[3]),
    "1CD0": ("44aa10", art.BOMB_SQUIGGLY[0]), "1CD3": ("885422", art.BOMB_SQUIGGLY[1]),
    "1CD6": ("10aa44", art.BOMB_SQUIGGLY[2]), "1CD9": ("225488", art.BOMB_SQUIGGLY[3]),
    "1C10": ("000000781dbe6c3c3c3c6cbe1d780000", art.ALIEN_B[0]),
    "1C40": ("0000000e18be6d3d3c3d6dbe180e0000", art.ALIEN_B[1]),
    "1C70": ("000401130307b30f2f032f4904030001", art.CANNON_DEATH[0]),
    "1C80": ("400805a30a035b0f27270b4b40841148", art.CANNON_DEATH[1]),
    "1D7C": ("002200a54008983db63c361d104862b61d98084290080000", art.SAUCER_EXPLOSION),
    "1D64": ("00000000040c1e373e7c747e7e747c3e371e0c0400000000", art.SAUCER),
    "1C91": ("993c7e3dbc3e7c99", art.SHOT_BURST),
    "1CDC": ("4a15be3f5e25", art.BOMB_BURST),
}


def decode(hex_bytes: str) -> art.Art:
    columns = bytes.fromhex(hex_bytes)
    return tuple("".join("#" if byte >> (7 - row) & 1 else "." for byte in columns)
                 for row in range(8))


@pytest.mark.parametrize("address", sorted(ROM))
def test_each_picture_is_the_roms(address):
    hex_bytes, picture = ROM[address]
    assert picture == decode(hex_bytes)


def test_bombs_light_the_top_of_their_box_and_the_crab_starts_arms_up():
    for pictures in (art.BOMB_ROLLING, art.BOMB_PLUNGER, art.BOMB_SQUIGGLY):
        for picture in pictures:
            assert "#" in picture[0] and picture[7] == "..."
    arms = art.ALIEN_B[0][1]  # frame 0's second row: both arms raised beside the head
    assert arms == "...#..#...#..#.."
