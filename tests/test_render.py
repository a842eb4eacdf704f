"""Rendering reads the world and never writes it; sprites land on exact pixels at any scale."""

from __future__ import annotations

import numpy as np
import pygame

from invaders.app.cli import main
from invaders.app.render import Renderer
from invaders.game import art
from invaders.game.config import GameConfig, Speeds
from invaders.game.events import Event
from invaders.game.rack import ALIEN_HEIGHT, pictures_apart
from invaders.game.world import Phase, World
from invaders.lab.autopilot import Autopilot
from invaders.lab.picture import Picture
from tests.helpers import active_world


def _lit(surface: pygame.Surface, x: int, y: int) -> bool:
    return surface.get_at((x, y))[:3] != (0, 0, 0)


def test_the_cannon_is_drawn_pixel_for_pixel_and_scaled_as_blocks():
    world = active_world()
    cannon = world.cannon
    flat = pygame.Surface((224, 256))
    Renderer().draw(flat, world)
    for y, row in enumerate(art.CANNON):
        for x, ch in enumerate(row):
            assert _lit(flat, cannon.x + x, cannon.y + y) == (ch == "#"), (x, y)
    big = pygame.Surface((224 * 3, 256 * 3))
    Renderer().draw(big, world)
    for y, row in enumerate(art.CANNON):
        for x, ch in enumerate(row):
            for dy in range(3):
                for dx in range(3):
                    px, py = (cannon.x + x) * 3 + dx, (cannon.y + y) * 3 + dy
                    assert _lit(big, px, py) == (ch == "#")


def test_drawing_with_the_overlay_does_not_change_the_world():
    world = active_world(seed=2)
    for _ in range(200):
        world.step(4 if world.tick % 20 == 0 else 0)
    before = world.state_hash()
    target = pygame.Surface((224 * 2, 256 * 2))
    report = world.step(0)
    after_step = world.state_hash()
    assert after_step != before
    Renderer().draw(target, world, 0.5, overlay=True, report=report)
    assert world.state_hash() == after_step


def test_screenshot_writes_a_png_of_the_scaled_window(tmp_path, capsys):
    """The file is the window's picture of the game after those ticks, pixel for pixel:
    the same as the renderer draws of a world played as far by the autopilot."""
    from invaders.game.world import World
    from invaders.lab.autopilot import Autopilot

    path = tmp_path / "shot.png"
    assert main(["play", "--screenshot", str(path), "--ticks", "300", "--scale", "2",
                 "--seed", "4"]) == 0
    image = pygame.image.load(str(path))
    assert image.get_size() == (448, 512)
    assert not list(tmp_path.glob(".*"))
    world, pilot = World(seed=4), Autopilot(4)
    for _ in range(300):
        world.step(pilot.actions(world))
    expected = pygame.Surface((448, 512))
    Renderer().draw(expected, world)
    assert pygame.image.tobytes(image, "RGB") == pygame.image.tobytes(expected, "RGB")


def test_the_score_bar_is_the_originals_and_the_high_score_waits_for_game_over():
    from invaders.app.render import hud_texts
    from invaders.game.world import World

    world = World(seed=0)
    world.score = 120  # a game under way
    texts = {message: (x, y) for message, x, y in hud_texts(world)}
    assert texts["SCORE<1> HI-SCORE SCORE<2>"] == (8, 8)
    assert texts["0120"] == (24, 24) and texts["0000"] in ((88, 24), (168, 24))
    assert texts["CREDIT 00"] == (136, 240) and texts["3"] == (8, 240)
    assert not any(message.startswith("WAVE") for message in texts)
    world._game_over()
    assert ("0120", 88, 24) in hud_texts(world)  # now it is the high score


def test_game_over_is_written_clear_of_the_rack_and_the_dead_cannon_is_cleared():
    from invaders.app.render import Renderer, game_over_texts
    from invaders.game.config import DEFAULT_CONFIG
    from invaders.game.entities import CannonState
    from invaders.game.world import Phase, World
    from tests.helpers import step_until

    world = World(seed=1)
    # The top row's pictures at the highest start of any wave: the rack only comes down.
    highest_ever = min(DEFAULT_CONFIG.start_top(w) for w in range(1, 12)) - 16 * 4
    world._game_over()
    typed = []
    while world.phase_timer > 0:
        (text,) = game_over_texts(world)
        typed.append(text)
        world.step(0)
    assert typed[0] == ("G", 72, 56) and typed[6] == ("GA", 72, 56)  # six frames a letter
    assert typed[-1] == ("GAME OVER", 72, 56) and typed.count(typed[-1]) > 60
    assert typed[-1][2] + 8 <= highest_ever  # above every row the rack can reach
    world = World(seed=1)
    world.kill_cannon()
    world.ships = 1
    step_until(world, lambda r: world.phase is Phase.GAME_OVER, limit=200)
    assert world.cannon.state is CannonState.EXPLODING and world.cannon.timer <= 0
    target = pygame.Surface((224, 256))
    Renderer().draw(target, world)
    cannon = world.cannon
    area = target.subsurface((cannon.x, cannon.y, 16, 8))
    assert all(area.get_at((x, y))[:3] == (0, 0, 0) for x in range(16) for y in range(8))


def test_a_window_of_another_shape_shows_the_game_unstretched_between_black_borders():
    from invaders.app.render import View

    world = active_world()
    target = pygame.Surface((800, 600))
    Renderer().draw(target, world, overlay=True)
    view = View.of((800, 600))
    assert view.scale == 600 / 256 and (view.x, view.y) == (138, 0)  # 525 px wide, centred
    for x in (0, 137, 663, 799):
        assert all(target.get_at((x, y))[:3] == (0, 0, 0) for y in range(0, 600, 7))
    inside = {target.get_at((x, y))[:3] for x in range(138, 662, 5) for y in range(0, 600, 5)}
    assert len(inside) > 2  # the game is drawn there


def test_the_overlay_text_is_legible_at_scale_1_and_its_lines_stay_off_the_hud():
    world = active_world()
    target = pygame.Surface((224, 256))
    Renderer().draw(target, world, overlay=True, report=world.step(0))
    plain = pygame.Surface((224, 256))
    Renderer().draw(plain, world, overlay=False, report=None)
    for y in list(range(0, 31)) + list(range(241, 256)):  # the score bar and bottom line
        assert all(target.get_at((x, y)) == plain.get_at((x, y)) for x in range(224)), y


def test_the_end_of_a_replay_reads_on_a_band_cleared_of_the_rack_behind_it():
    """Its three lines are drawn where the rack is: behind them, only the letters."""
    from invaders.game.world import World
    from invaders.lab.picture import Picture

    world = World(seed=1)
    for _ in range(400):  # the rack drawn and marching
        world.step(0)
    target = pygame.Surface((224, 256))
    lines = ["REPLAY ENDED", "CHECKPOINTS MATCHED", "ENTER PLAYS  ESC QUITS"]
    Renderer().draw(target, world, replay_verdict=lines[1])
    letters = Picture()  # the same lines alone, on black
    for i, line in enumerate(lines):
        letters.text(line, (224 - 8 * len(line)) // 2, 88 + 16 * i)
    letters.tint()
    band = pygame.Rect(0, 84, 224, 48)
    drawn, alone = target.subsurface(band), letters.screen.subsurface(band)
    assert all(drawn.get_at((x, y)) == alone.get_at((x, y))
               for x in range(band.w) for y in range(band.h))
    rack_rows = {alien.top + dy for alien in world.rack.live_aliens() for dy in range(8)}
    assert rack_rows & set(range(84, 132))  # there was rack to clear


def test_a_kept_line_of_text_lights_exactly_its_glyphs_pixels_first_time_and_again():
    """Lines of text are kept by their message: drawn from the cache, again after the cache
    is emptied, and over pixels already lit, they light exactly the glyphs' own pixels."""
    from invaders.game.art import lit_cells
    from invaders.lab import font, picture

    pic = picture.Picture()
    message, x, y = "SCORE<1> 0420", 9, 20
    expected = {(x + i * font.ADVANCE + cx, y + cy) for i, ch in enumerate(message)
                for cx, cy in lit_cells(font.glyph(ch))}
    for attempt in range(3):
        pic.screen.fill((0, 0, 0))
        pic.screen.set_at((x + 1, y + 7), (255, 255, 255))  # lit before: stays lit
        if attempt == 2:
            pic._texts.clear()
        pic.text(message, x, y)
        lit = {(px, py) for px in range(224) for py in range(16, 32)
               if pic.screen.get_at((px, py))[:3] == (255, 255, 255)}
        assert lit == expected | {(x + 1, y + 7)}


def test_on_a_grey_picture_lines_and_sprites_take_its_palette_and_light_its_white():
    """Surfaces made for a picture of a byte a pixel take its palette, so SDL blits them
    byte for byte (between two palettes it maps every colour to its nearest at a surface's
    first blit: a new line of text 90 us); what they draw is the same, white as 255."""
    from invaders.game.art import lit_cells
    from invaders.lab import font

    pic = _canvas_picture(grey=True)
    palette = pic.screen.get_palette()
    message, x, y = "0420", 9, 20
    assert pic.line(message).get_palette() == palette
    for picture in (art.CANNON, art.SHOT, art.SAUCER, font.glyph("4")):
        assert pic.sprite(picture).get_palette() == palette
    pic.text(message, x, y)
    pic.screen.blit(pic.sprite(art.CANNON), (100, 200))
    expected = {(x + i * font.ADVANCE + cx, y + cy) for i, ch in enumerate(message)
                for cx, cy in lit_cells(font.glyph(ch))}
    expected |= {(100 + cx, 200 + cy) for cx, cy in lit_cells(art.CANNON)}
    rows, cols = np.nonzero(pic.canvas)
    assert set(zip(cols.tolist(), rows.tolist(), strict=True)) == expected
    assert set(pic.canvas[rows, cols].tolist()) == {255}


def test_the_hit_cannon_is_held_for_five_frames_then_shows_the_1c80_debris_first():
    from invaders.game.config import DEFAULT_CONFIG
    from invaders.lab.picture import cannon_picture

    timing = DEFAULT_CONFIG.timing
    world = active_world()
    world.kill_cannon()
    shown = []
    for _ in range(timing.cannon_death):
        shown.append(cannon_picture(world.cannon))
        assert world.cannon.mask is art.mask_of(shown[-1])  # (what bombs meet: the drawn)
        world.step(0)
    cannon, c70, c80 = art.CANNON, art.CANNON_DEATH[0], art.CANNON_DEATH[1]
    assert shown[:5] == [cannon] * 5
    assert shown[5:25] == [c80] * 5 + [c70] * 5 + [c80] * 5 + [c70] * 5
    flat = pygame.Surface((224, 256))
    world = active_world()
    world.kill_cannon()
    for _ in range(7):  # the 8th frame since the hit: the first debris picture
        world.step(0)
    Renderer().draw(flat, world)
    x, y = world.cannon.x, world.cannon.y
    for row, line in enumerate(c80):
        for col, ch in enumerate(line):
            assert _lit(flat, x + col, y + row) == (ch == "#"), (col, row)


def test_after_an_invasion_the_bottom_line_shows_no_ships_left():
    from invaders.app.render import hud_texts

    world = active_world()
    world.invaded = True  # the rack has landed; the count still holds 3
    assert ("0", 8, 240) in hud_texts(world)
    flat = pygame.Surface((224, 256))
    Renderer().draw(flat, world)
    icons = flat.subsurface((24, 240, 112, 8))
    assert not any(_lit(icons, x, y) for x in range(112) for y in range(8))
    world.invaded = False
    Renderer().draw(flat, world)
    assert any(_lit(icons, x, y) for x in range(112) for y in range(8))


def test_the_gel_is_mames_overlay_red_rows_32_to_61_green_below_and_x_16_to_133():
    from invaders.lab.picture import GREEN_GEL, RED_GEL, gel_surface

    gel = gel_surface()
    assert [gel.get_at((100, y))[:3] == RED_GEL for y in (31, 32, 61, 62)] == [
        False, True, True, False]
    assert gel.get_at((0, 183))[:3] == (255, 255, 255) and gel.get_at((0, 184))[:3] == GREEN_GEL
    assert [gel.get_at((x, 245))[:3] == GREEN_GEL for x in (15, 16, 133, 134)] == [
        False, True, True, False]


def test_a_screenshot_of_the_attract_cycle_is_its_still_pixel_for_pixel_and_says_so(
        tmp_path, capsys):
    from invaders.app.attract import card
    from invaders.game.world import World

    path = tmp_path / "pull.png"
    capsys.readouterr()
    assert main(["play", "--screenshot", str(path), "--attract", "pull", "--scale", "1"]) == 0
    assert capsys.readouterr().out == f"saved {path}: the attract cycle's pull\n"
    texts, pictures = card("pull")
    expected = pygame.Surface((224, 256))
    Renderer().draw_card(expected, World(seed=0), texts, pictures)
    image = pygame.image.load(str(path))
    assert pygame.image.tobytes(image, "RGB") == pygame.image.tobytes(expected, "RGB")


def test_each_live_alien_is_drawn_in_its_own_frames_picture_pixel_for_pixel():
    world = active_world(seed=3)
    while len({alien.frame for alien in world.rack.live_aliens()}) < 2:  # (mid-march)
        world.step(0)
    flat = pygame.Surface((224, 256))
    Renderer().draw(flat, world)
    for alien in world.rack.live_aliens():
        picture = art.ALIEN_BY_ROW[alien.row][alien.frame]
        for y, row in enumerate(picture):
            for x, ch in enumerate(row):
                assert _lit(flat, alien.x + x, alien.top + y) == (ch == "#"), (alien.index, x, y)


class _DrawnAfresh(Picture):
    """The backdrop drawn anew in every frame: nothing kept."""

    def _draw_backdrop(self, world, slot) -> None:
        self.clear()
        self._draw_hud(world)
        self._draw_shields(world)


def _canvas_picture(grey: bool = False) -> Picture:
    """A picture over an array, as the environment's: RGB, or a byte a pixel (grey)."""
    if grey:
        canvas = np.zeros((256, 224), np.uint8)
        screen = pygame.image.frombuffer(canvas, (224, 256), "P")
        screen.set_palette([(level,) * 3 for level in range(256)])
        return Picture(screen, canvas)
    canvas = np.zeros((256, 224, 3), np.uint8)
    return Picture(pygame.image.frombuffer(canvas, (224, 256), "RGB"), canvas)


def test_the_kept_backdrop_and_rack_are_the_picture_drawn_afresh_in_every_frame_of_two_games():
    # (The kept backdrop relies on its key: what the texts are made of, the ground only
    # losing pixels while it is the same mask, a new field's shields being a new list and
    # World.erosions counting every change to their pixels; the kept rack of a picture
    # over an array on the rack's watch and its aliens never sharing a pixel. Each game
    # has its pictures, a plain one and two over an array as the environment's, RGB and
    # grey; one more draws both games in turn, each with a slot of its own, as a batch of
    # games does, and two more in one slot.)
    worlds = [(World(seed=1, players=2), Autopilot(1)), (World(seed=7), Autopilot(7))]
    own = [(Picture(), _canvas_picture(), _canvas_picture(grey=True)) for _ in worlds]
    shared, afresh = _canvas_picture(), _DrawnAfresh()
    one_slot = (Picture(), _canvas_picture())
    events, wears, grounds = set(), set(), set()
    for _ in range(3000):
        for slot, (world, pilot) in enumerate(worlds):
            events.update(world.step(pilot.actions(world)).events)
            wears.add(world.erosions)
            grounds.add((id(world.ground), world.ground.count()))
            expected = pygame.image.tobytes(afresh.draw(world), "RGB")
            for drawn in (*(picture.draw(world) for picture in (*own[slot], *one_slot)),
                          shared.draw(world, slot=slot)):
                assert pygame.image.tobytes(drawn, "RGB") == expected, world.tick
    assert {Event.PLAYER_UP, Event.TURN_STARTED, Event.BUNKER_HIT, Event.BOMB_BURST,
            Event.ALIEN_KILLED, Event.SHIP_LOST} <= events
    assert len(wears) > 20 and len(grounds) > 20
    assert all(len(picture._layers) == 1 for picture in (*own[0][1:], one_slot[1]))
    kept, over_array, _ = own[1]
    for shield in (0, 3):  # two new worlds' shields, each worn once, in another place
        other = World(seed=6)
        bunker = other.bunkers[shield]
        other.erode(art.mask_of(art.SHOT_BURST), bunker.x + 4, bunker.y)
        assert other.erosions == 1
        expected = pygame.image.tobytes(afresh.draw(other), "RGB")
        assert pygame.image.tobytes(kept.draw(other), "RGB") == expected
        assert pygame.image.tobytes(over_array.draw(other), "RGB") == expected
    for change in (_high_score_beaten, _other_player_up):  # (seldom in the games above)
        other = World(seed=6, players=2)
        other.phase, other.phase_timer = Phase.SWITCH, 4  # the score up flashed off
        kept.draw(other), over_array.draw(other)
        change(other)
        expected = pygame.image.tobytes(afresh.draw(other), "RGB")
        assert pygame.image.tobytes(kept.draw(other), "RGB") == expected, change
        assert pygame.image.tobytes(over_array.draw(other), "RGB") == expected, change


def _high_score_beaten(world: World) -> None:
    world.hi_score = 120  # (as a game's end sets it)


def _other_player_up(world: World) -> None:
    world.player = 2  # (player 2's score is the one flashing off now)


def _aliens_share_a_pixel(world: World) -> bool:
    lit = pygame.mask.Mask((224, 256))
    for alien in world.rack.live_aliens():
        picture = art.mask_of(art.ALIEN_BY_ROW[alien.row][alien.frame])
        if lit.overlap(picture, (alien.x, alien.top)):
            return True
        lit.draw(picture, (alien.x, alien.top))
    return False


def test_the_rows_a_rack_may_cover_hold_every_live_alien_within_a_drop_each_way():
    """The kept rack is laid over the rows `Rack.picture_rows` gives: every drawn alien's
    picture lies in them at every tick of whole games (waves, kills, deaths, two
    players), and once the whole rack is drawn the band is the aliens' own rows, or a
    drop more: above, while the top row stands where the reference is (it allows for its
    being a drop higher), or below, at the end of a pass that dropped the reference,
    before the bottom row is drawn there."""
    slacks: set[tuple[int, int]] = set()
    for seed in range(2):
        world, pilot = World(seed=seed, players=2), Autopilot(seed, "expert")
        drop = world.config.speeds.rack_drop
        for _ in range(12000):
            world.step(pilot.actions(world))
            drawn, (top, bottom) = world.rack.live_aliens(), world.rack.picture_rows()
            if not drawn:
                continue
            highest = min(alien.top for alien in drawn)
            lowest = max(alien.top for alien in drawn) + ALIEN_HEIGHT
            assert top <= highest and lowest <= bottom, world.tick
            if len(drawn) == world.rack.live:
                slacks.add((highest - top, bottom - lowest))
    assert slacks == {(0, 0), (drop, 0), (0, drop)}


def test_the_rows_a_rack_may_cover_reach_a_top_row_alien_alone_in_its_row():
    """Two aliens left, the bottom-left and the top-right: the band runs from the top
    one's row (a drop higher) to the bottom one's, through their steps and drops."""
    world = active_world()
    for alien in world.rack.live_aliens():
        if alien.index not in (0, 54):
            world.rack.kill(alien, world.store)
    tops = set()
    for _ in range(600):
        world.alien_fire_timer = 10**9  # (no bomb: the cannon lives, the rack marches)
        world.step(0)
        top, bottom = world.rack.picture_rows()
        for alien in world.rack.live_aliens():
            assert top <= alien.top and alien.top + ALIEN_HEIGHT <= bottom, world.tick
        tops.add(world.rack.ref_top)
    assert len(tops) > 2  # (two drops at least)


def test_a_racks_aliens_share_no_pixel_exactly_where_pictures_apart_says_so():
    """Over an array the rack is kept drawn, aliens taken out and put in, which needs no
    two to share a pixel: the default rack's never do through its steps and drops, nor one
    stepping 4 pixels (the widest picture's lit columns and the step fill a cell); one
    stepping 5 does, is said not to be apart, and is drawn alien by alien (its picture is
    the one drawn afresh)."""
    for speeds, apart in ((Speeds(), True), (Speeds(rack_step=4), True),
                          (Speeds(rack_step=5), False)):
        config = GameConfig(speeds=speeds)
        assert pictures_apart(config) is apart
        world, over_array, afresh = World(seed=3, config=config), _canvas_picture(), _DrawnAfresh()
        shared, tops = False, set()
        for _ in range(4000):
            world.step(0)
            shared |= _aliens_share_a_pixel(world)
            tops.add(world.rack.ref_top)
            expected = pygame.image.tobytes(afresh.draw(world), "RGB")
            assert pygame.image.tobytes(over_array.draw(world), "RGB") == expected
        assert shared is not apart and len(tops) > 2
        assert len(over_array._layers) == apart
