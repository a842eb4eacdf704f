"""Command line: parse, call, report. Exit codes: 0 ok, 1 a check failed, 2 bad input or
usage, 3 an internal error; 128 + N when signal N stopped a run or a game."""

from __future__ import annotations

import argparse
import contextlib
import errno
import io
import os
import sys
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple, NoReturn

from invaders import __version__
from invaders.engine.adaptive import BROADPHASES, COMPILED, DEFAULT_BROADPHASE
from invaders.engine.compiled import shadowed_note
from invaders.engine.grid import DEFAULT_CELL
from invaders.lab import choices
from invaders.lab.styles import STYLES
from invaders.quiet import output_to_nothing, say

MAX_TICKS = 100_000_000


class UsageError(Exception):
    """Bad input from the user: reported as one line, exit 2."""


class Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line naming the problem, not a usage block, and
    help or the version that cannot be written is said as any output is (`main`)."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(message)

    def _print_message(self, message: str, file: Any = None) -> None:
        # (argparse's one writer, for help, usage and the version; its own drops the error)
        stream = file if file is not None else sys.stderr
        if message and stream is not None:  # (None without a console: pythonw)
            stream.write(message)

    def exit(self, status: int = 0, message: str | None = None) -> NoReturn:
        if sys.stdout is not None:  # (the help written: flushed where a failure is said)
            sys.stdout.flush()
        super().exit(status, message)


def _int_in(low: int, high: int):
    """A whole number in [low, high] (argparse names the option: "argument --ticks: ...")."""
    def parse(text: str) -> int:
        digits = text.strip().lstrip("+-")
        if digits.isdigit() and len(digits) > 40:  # (no range here is that long)
            raise argparse.ArgumentTypeError(
                f"must be between {low} and {high}, not {_quoted(text)}")
        try:  # decimal first (010 is ten), then 0x.. and 0b.. forms
            value = int(text, 10) if digits.isdigit() else int(text, 0)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"must be a whole number, not {_quoted(text)}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(
                f"must be between {low} and {high}, not {_quoted(text)}")
        return value

    return parse


def _quoted(text: str, most: int = 24) -> str:
    """A value as given, cut to its first characters: a bad value is named, not echoed."""
    return repr(text) if len(text) <= most else f"{text[:most]!r}... ({len(text):,} characters)"


def _named(text: str) -> str:
    """A name (of a file, a folder or an address) that is not empty: an empty one was
    once taken as no option, or as the current folder."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty name")
    return text


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


def _lab_arguments(parser: argparse.ArgumentParser) -> argparse._ArgumentGroup:
    """The lab's choices, the same for a window and a headless run."""
    lab = parser.add_argument_group("the lab", "detect another way than the default, and "
                                    "see what that costs and misses")
    lab.add_argument("--quick", choices=choices.QUICK_TESTS, default=choices.QUICK_TESTS[0],
                     help="the quick test: boxes, or bounding circles")
    lab.add_argument("--thorough", choices=choices.THOROUGH_TESTS,
                     default=choices.THOROUGH_TESTS[0],
                     help="the thorough test: pixel masks, or none (boxes are the shapes)")
    lab.add_argument("--motion", choices=choices.MOTIONS, default=choices.MOTIONS[0],
                     help="per entry as proven (auto), every entry discrete, or swept")
    lab.add_argument("--sample", type=int, choices=choices.SAMPLINGS,
                     default=choices.SAMPLINGS[0], metavar="K",
                     help="detect every K-th tick only (" + _listed(choices.SAMPLINGS) + ")")
    lab.add_argument("--speed-mult", type=int, choices=choices.MULTIPLIERS,
                     default=choices.MULTIPLIERS[0], metavar="N",
                     help="the shot and bombs move N times as far a tick ("
                          + _listed(choices.MULTIPLIERS) + ")")
    return lab


def _listed(options: Sequence[int]) -> str:
    return ", ".join(map(str, options[:-1])) + f" or {options[-1]}"


def build_parser(command: str | None = None) -> Parser:
    """The whole command line, or with `command` only that command's part: argparse makes
    a parser per command, and a run should not pay for five (start-up time)."""
    parser = Parser(
        prog="invaders",
        description="Space Invaders (1978) at its own 224x256 resolution, and a measured "
                    "laboratory of 2D collision detection: play it in a window, run and check "
                    "its replays headless, time and score the collision methods.",
        epilog="Exit codes: 0 ok, 1 a check failed, 2 bad input or usage, 3 an internal "
               "error (--debug shows its traceback), 128+N stopped by signal N. "
               "With no command, play (with play's options: 'invaders --scale 2'). "
               "'invaders COMMAND --help' tells more.")
    parser.add_argument("--version", action="version", version=f"invaders {__version__}")
    sub = parser.add_subparsers(dest="command", parser_class=Parser)

    for name, entry in COMMANDS.items():
        if command in (None, name):
            entry.add_parser(sub)
    return parser


SEED_HELP = ("seeds the autopilot, and the game's generator, from which the 1978 rules draw "
             "nothing (0 by default)")
BROADPHASE_HELP = (f"the collision pipeline's broad phase ({DEFAULT_BROADPHASE} by default: "
                   "chosen by the scene's size); the state hash is the same with each")


def _add_play(sub: argparse._SubParsersAction) -> None:
    play = sub.add_parser("play", help="play in a window")
    # (--seed, --players, --ticks and --speed default to None, so that one given where it
    # would do nothing is told from one left out: _unused_play_flag.)
    play.add_argument("--seed", type=_int_in(0, 2**63 - 1), help=SEED_HELP)
    play.add_argument("--scale", type=_int_in(1, 8),  # (None: see open_window)
                      help="the window: 224x256 px times this, 1 to 8 (3 by default; at most "
                           "what fits the screen)")
    play.add_argument("--players", type=_int_in(1, 2),
                      help="the game a recording or a screenshot starts with (in the "
                           "window, 1 or 2 starts either)")
    play.add_argument("--broadphase", choices=BROADPHASES, default=DEFAULT_BROADPHASE,
                      help=BROADPHASE_HELP)
    play.add_argument("--screenshot", metavar="FILE", type=_named,
                      help="run headless for --ticks with the autopilot, save the window as PNG")
    play.add_argument("--ticks", type=_int_in(1, MAX_TICKS),
                      help="with --screenshot: how long it plays (600 ticks by default)")
    play.add_argument("--overlay", action="store_true", help="start with the debug overlay on")
    play.add_argument("--mute", action="store_true", help="start with the sound off (M toggles)")
    play.add_argument("--attract", choices=("title", "table", "pull", "insert"),
                      help="with --screenshot: save that moment of the attract cycle instead "
                           "(pull: the alien pulling PLAY's Y; insert: INSERT CCOIN)")
    play.add_argument("--record", metavar="FILE", type=_named,
                      help="record the game as a replay (JSON)")
    play.add_argument("--replay", metavar="FILE", type=_named,
                      help="watch a replay instead of playing")
    play.add_argument("--speed", type=_int_in(1, 64),
                      help="with --replay: its speed multiplier")
    _lab_arguments(play).add_argument(
        "--lab", action="store_true",
        help="open the lab panel beside the playfield (F4 in any game; a lab option opens it)")


def _add_run(sub: argparse._SubParsersAction) -> None:
    run = sub.add_parser("run", help="run headless and print a summary and the state hash")
    run.add_argument("--ticks", type=_int_in(1, MAX_TICKS), default=3600,
                     help="how long it runs, 60 ticks a second of game time (3600 by default)")
    run.add_argument("--seed", type=_int_in(0, 2**63 - 1), default=0,
                     help=SEED_HELP)
    run.add_argument("--players", type=_int_in(1, 2), default=1,
                     help="two take turns at each death, each with their own rack and shields "
                          "(1 by default)")
    run.add_argument("--autopilot", nargs="?", const="hunter", choices=sorted(STYLES),
                     metavar="STYLE",
                     help="let the built-in player play: " + ", ".join(
                         f"{name} (default)" if name == "hunter" else name
                         for name in STYLES))
    run.add_argument("--broadphase", choices=BROADPHASES, default=DEFAULT_BROADPHASE,
                     help=BROADPHASE_HELP)
    run.add_argument("--cell", type=_int_in(1, 1024),  # (None: see _run_world)
                     help="cell size in px of the grid and of the broad phases built on its "
                          f"cells ({DEFAULT_CELL} by default)")
    run.add_argument("--report", metavar="FILE", type=_named,
                     help="per-tick counters, .csv or .jsonl")
    lab = _lab_arguments(run)
    lab.add_argument("--shadow", action="store_true",
                     help="score every tick's contacts against the exact oracle")
    run.add_argument("--record", metavar="FILE", type=_named,
                     help="save the run as a replay (JSON)")


def _add_replay(sub: argparse._SubParsersAction) -> None:
    check = sub.add_parser("replay", help="run replays headless and check their checkpoints")
    check.add_argument("paths", nargs="+", metavar="PATH", type=_named,
                       help="replay files or folders")
    check.add_argument("--update", action="store_true",
                       help="rewrite the expected checkpoints (after an intended rule change)")
    check.add_argument("--broadphase", choices=BROADPHASES, default=DEFAULT_BROADPHASE,
                       help=BROADPHASE_HELP)


def _add_study(sub: argparse._SubParsersAction) -> None:
    study = sub.add_parser("study", help="speed against accuracy: the method matrix, charts")
    study.add_argument("--quick", action="store_true", help="a smaller matrix (under a minute)")
    study.add_argument("--big", action="store_true",
                       help="also a storm of 30,000 bodies in the scaling chart (minutes more)")
    where = study.add_mutually_exclusive_group()  # (a cluster has its own workers)
    where.add_argument("--jobs", type=_int_in(1, 64), default=1,
                       help="run scenes in this many processes (1 by default)")
    where.add_argument("--scheduler", metavar="ADDRESS", type=_named,
                       help="run scenes on a Dask cluster (the [study] extra)")
    study.add_argument("--out", metavar="FOLDER", default="study", type=_named,
                       help="where study.csv, scaling.csv and the charts go (study by default)")
    study.add_argument("--replays", metavar="FOLDER", default=None, type=_named,
                       help="the replays to study (*.json)")


def _add_bench(sub: argparse._SubParsersAction) -> None:
    bench = sub.add_parser("bench", help="time the pipeline against references, as ratios")
    # (--ticks and --seed default to None, so that one given to a bench that does not play
    # the game is told from one left out: _only_for_the_full_bench.)
    bench.add_argument("--ticks", type=_int_in(60, MAX_TICKS),
                       help="the game the bench plays (3600 ticks by default)")
    bench.add_argument("--seed", type=_int_in(0, 2**63 - 1),
                       help="its seed (7 by default)")
    bench.add_argument("--ale", action="store_true",
                       help="also time the Arcade Learning Environment's emulated Space "
                            "Invaders, and the Gymnasium environment against ALE's (needs "
                            "the compare extra: ale-py)")
    bench.add_argument("--big", action="store_true",
                       help="also time storms of 1,000 and 10,000 bodies: the grid, the numpy "
                            "broad phase, the automatic choice and pymunk")
    bench.add_argument("--largest", type=_int_in(1, 2000), metavar="N",
                       help="section 5's largest group size, sprites a side (default 1,000; "
                            "2,000 with --big)")
    bench.add_argument("--rounds", type=_int_in(3, 100), default=10,
                       help="interleaved rounds, 3 to 100 (10 by default); figures are medians "
                            "over them")
    instead = bench.add_mutually_exclusive_group()  # (one at a time: each runs alone)
    instead.add_argument("--env", action="store_true",
                         help="instead, the Gymnasium environment against ALE's, step for "
                              "step (needs the rl extra; ALE with the compare extra)")
    instead.add_argument("--window", action="store_true",
                         help="instead, a game in a real window: CPU seconds a second "
                              "through SDL's native framebuffer and through a renderer (needs "
                              "a display)")
    instead.add_argument("--reading", action="store_true",
                         help="instead, replay files at the 64 MB size limit read in fresh "
                              "processes (the longest valid one, the same in the other "
                              "shapes a file may take, and four hostile ones): seconds and "
                              "peak memory against the goal of 2 s and 100 MB")
    instead.add_argument("--arcade", action="store_true",
                         help="instead, Arcade's collision checks (spatial hashes, box hit "
                              "boxes) against ours: section 5's boxes, still and moving, and "
                              "section 4's storms (needs the compare extra: arcade)")
    instead.add_argument("--against", metavar="REV",
                         help="instead, this tree's game speed against a git revision's "
                              "(checked out in a temporary worktree), game by game in turn")


def cmd_run(args: argparse.Namespace) -> int:
    from invaders.app.headless import run, use_dummy_drivers

    use_dummy_drivers()
    from invaders.app.outputs import REPLAY_SUFFIXES, REPORT_SUFFIXES, check_output, writing
    from invaders.app.signals import StopSignals

    if args.report is not None:
        check_output(args.report, "report", REPORT_SUFFIXES)
    if args.record is not None:
        check_output(args.record, "replay", REPLAY_SUFFIXES)
    world = _run_world(args)
    base = world.config  # (the lab's speeds change the world's)
    shadow = _install_lab(args, world)
    recorder = _run_recorder(args, world, base)
    with StopSignals() as signals:
        try:
            # (the recording's failures are its own, said by its recorder)
            with writing(args.report, "report") if args.report else contextlib.nullcontext():
                result = run(world, _run_source(args), args.ticks, args.report, recorder,
                             stop=lambda: signals.received is not None, columns=shadow)
        finally:
            if recorder is not None:  # the world is between ticks: a whole replay
                with writing(args.record, "replay"):
                    recorder.save()
    if signals.received is not None:
        saved = (f"; saved {recorder.path} ({recorder.ticks} ticks)" if recorder is not None
                 else "")
        say(f"invaders: stopped by {signals.name} at tick {world.tick}{saved}")
        return signals.exit_code
    _print_run(args, world, result, shadow)
    return 0


def _run_world(args: argparse.Namespace):
    from invaders.game.world import World

    if args.cell is not None and args.broadphase not in choices.CELLED:
        raise UsageError(f"--cell is not used here: the {args.broadphase} broad phase has no "
                         "cells")
    return World(seed=args.seed, broadphase=args.broadphase, cell=args.cell or DEFAULT_CELL,
                 players=args.players)


def _install_lab(args: argparse.Namespace, world):
    """The lab's method put into the world if one is asked for, and the shadow detector
    watching it if asked for: the shadow (else None)."""
    if not (_lab_asked(args) or args.shadow):
        return None
    from invaders.lab.live import install

    detector = install(world, _lab_choice(args), world.config, shadow=args.shadow)
    return getattr(detector, "shadow", None)


def _run_source(args: argparse.Namespace):
    """Where the run's inputs come from: the autopilot, or none pressed."""
    from invaders.app.headless import Idle

    if not args.autopilot:
        return Idle()
    from invaders.lab.autopilot import Autopilot

    return Autopilot(args.seed, args.autopilot)


def _run_recorder(args: argparse.Namespace, world, base):
    """The recorder of the run's replay, if --record asks for one (else None); `base`: the
    game's config, before the lab's speeds."""
    if args.record is None:
        return None
    from invaders.app.recording import Recorder

    recorder = Recorder(world, args.record, save_every=3600, config=base)
    if _lab_asked(args):  # the replay keeps the method, so it plays back as this run went
        recorder.switch(_lab_choice(args).to_dict())
    return recorder


def _print_run(args: argparse.Namespace, world, result, shadow) -> None:
    """The run's summary, the shadow's score if it watched, and the state hash."""
    from invaders.app.summary import summary_lines

    name = f"autopilot {args.autopilot}" if args.autopilot else "none"
    for line in summary_lines(result, args.seed, args.broadphase, name):
        print(line)
    if shadow is not None:
        score = shadow.finish()
        rate = f"{score.errors / score.true:.4f}" if score.true else "-"
        print(f"shadow ({_lab_choice(args).label}): {score.true} true contacts; on time "
              f"{score.on_time}, late {score.late}, missed {score.missed}, false "
              f"{score.false}; {rate} errors per true contact")
    print(world.state_hash())


def _lab_asked(args: argparse.Namespace) -> bool:
    """Whether the lab options ask for another method or speed than the game's own (told
    without importing the lab, which a plain run does not need)."""
    return ((args.quick, args.thorough, args.motion, args.sample) != choices.DEFAULT_NARROW
            or args.speed_mult != choices.MULTIPLIERS[0])


def _lab_choice(args: argparse.Namespace):
    """The run's collision method and projectile speed, as the lab names them."""
    from invaders.engine.grid import DEFAULT_CELL
    from invaders.lab.live import Choice

    return Choice(args.broadphase, getattr(args, "cell", None) or DEFAULT_CELL, args.quick,
                  args.thorough, args.motion, args.sample, args.speed_mult)


def cmd_play(args: argparse.Namespace) -> int:
    from invaders.app.outputs import PICTURE_SUFFIXES, REPLAY_SUFFIXES, check_output
    from invaders.app.play import DEFAULT_SCALE, play, screenshot

    unused = _unused_play_flag(args)
    if unused is not None:
        raise UsageError(unused)
    seed, players = args.seed or 0, args.players or 1
    lab = _lab_choice(args) if args.lab or _lab_asked(args) else None
    if args.screenshot:
        check_output(args.screenshot, "screenshot", PICTURE_SUFFIXES)
        return screenshot(args.screenshot, seed=seed, ticks=args.ticks or 600,
                          scale=args.scale or DEFAULT_SCALE, overlay=args.overlay,
                          broadphase=args.broadphase,
                          attract=args.attract, lab=lab, players=players)
    replay = None
    if args.replay:
        from invaders.app.replay_check import check_switches
        from invaders.game.replay import ReplayError, load

        try:
            replay = load(args.replay)
            check_switches(replay)
        except ReplayError as err:
            raise UsageError(f"{args.replay}: {err}") from None
    if args.record:
        check_output(args.record, "replay", REPLAY_SUFFIXES)
        if args.replay and _same_file(args.replay, args.record):
            raise UsageError(f"--record {args.record} is the replay being watched: recording "
                             "would overwrite it")
    import pygame

    try:
        return play(seed=seed, scale=args.scale, broadphase=args.broadphase,
                    overlay=args.overlay, record=args.record, replay=replay,
                    speed=args.speed or 1, mute=args.mute, lab=lab, players=players)
    except pygame.error as err:
        raise UsageError(f"cannot open a window ({err}); without a display, run the game "
                         "headless with 'invaders run'") from None


def _unused_play_flag(args: argparse.Namespace) -> str | None:
    """The first flag given that this way of playing would leave unused, and why (a flag
    that does nothing without a word is a surprise); None if every one given is used."""
    unused: tuple[str, ...]
    if args.screenshot:
        mode, unused = "--screenshot plays a game of its own", ("replay", "record", "speed")
    elif args.replay:
        mode, unused = "--replay plays the game it holds", ("seed", "players", "ticks",
                                                             "attract")
    else:
        mode, unused = "they are for --screenshot or --replay", ("ticks", "attract", "speed")
    flag = next((name for name in unused if getattr(args, name) is not None), None)
    return None if flag is None else f"--{flag} is not used here: {mode}"


def cmd_replay(args: argparse.Namespace) -> int:
    from invaders.app.headless import use_dummy_drivers

    use_dummy_drivers()
    from invaders.app.replay_check import check_all

    return check_all(args.paths, update=args.update, broadphase=args.broadphase)


def cmd_bench(args: argparse.Namespace) -> int:
    from invaders.app.headless import use_dummy_drivers

    _only_for_the_full_bench(args)
    ticks, seed = args.ticks or 3600, 7 if args.seed is None else args.seed
    if args.window:  # (before the dummy drivers: this one needs the real display)
        from invaders.app.windowbench import NoWindow, window_bench

        try:
            print("\n".join(window_bench(args.rounds)))
        except NoWindow as err:
            raise UsageError(str(err)) from None
        return 0

    use_dummy_drivers()
    print(f"core: {'compiled' if COMPILED else 'interpreted'} (docs/compiled.md)")
    if (note := shadowed_note()) is not None:
        print(note)
    if args.reading:
        from invaders.app.readbench import reading_bench

        lines, met = reading_bench(args.rounds)
        print("\n".join(lines))
        return 0 if met else 1
    from invaders.lab.bench import BenchFailure, bench

    if args.against is not None:
        from invaders.lab.against import AgainstError, against

        try:
            return against(args.against, ticks, seed, args.rounds)
        except AgainstError as err:
            raise UsageError(str(err)) from None
    if args.env:
        return _env_table(args.rounds)
    if args.arcade:
        return _arcade_table(args.rounds)
    if args.ale:
        from invaders.lab.ale import available

        if not available():
            raise UsageError("--ale needs ale-py: pip install '.[compare]'")
    try:
        code = bench(ticks=ticks, seed=seed, rounds=args.rounds, ale=args.ale,
                     big=args.big, largest=args.largest)
    except BenchFailure as err:
        say(f"invaders: bench: {err}")
        return 1
    if args.ale:  # the environment against ALE's own, as section 6
        code = max(code, _env_table(args.rounds, section=True))
    return code


def _only_for_the_full_bench(args: argparse.Namespace) -> None:
    """--ale, --big and --largest add to the full bench, and --ticks and --seed set the game
    it and --against play: each refused beside a bench that would leave it unused without a
    word."""
    instead = next((f"--{name}" for name in ("env", "window", "reading", "arcade", "against")
                    if getattr(args, name) not in (False, None)), None)
    added = next((flag for flag, given in (("--ale", args.ale), ("--big", args.big),
                                           ("--largest", args.largest is not None)) if given),
                 None)
    if instead and added:
        raise UsageError(f"{added} adds to the full bench; {instead} runs instead of it")
    game = next((flag for flag, given in (("--ticks", args.ticks), ("--seed", args.seed))
                 if given is not None), None)
    if instead not in (None, "--against") and game:
        raise UsageError(f"{game} sets the game the full bench and --against play; "
                         f"{instead} plays none")


def _arcade_table(rounds: int) -> int:
    """Arcade's collision checks against ours (bench --arcade)."""
    try:
        import arcade  # noqa: F401
    except ImportError:
        raise UsageError("--arcade needs arcade: pip install '.[compare]'") from None
    from invaders.lab.bench_arcade import arcade_table

    return arcade_table(rounds)


def _env_table(rounds: int, section: bool = False) -> int:
    """The Gymnasium environment's table (bench --env, or section 6 of bench --ale)."""
    try:
        from invaders.env.speed import env_table
    except ImportError:
        if section:
            print("6. the Gymnasium environment: skipped (install the rl extra: gymnasium)")
            return 0
        raise UsageError("--env needs gymnasium: pip install '.[rl]'") from None
    return env_table(rounds, section)


SCHEDULER_TIMEOUT = 5.0  # seconds to reach a Dask scheduler before calling it bad input


def _reach_scheduler(address: str) -> None:
    """UsageError unless a Dask scheduler answers at `address` (before anything is made)."""
    try:
        from dask.distributed import Client
    except ImportError:
        raise UsageError("--scheduler needs Dask: pip install 'invaders[study]'") from None
    try:
        with Client(address, timeout=SCHEDULER_TIMEOUT):
            pass
    except (OSError, TimeoutError, ValueError) as err:
        reason = str(err).splitlines()[0][:120] if str(err) else type(err).__name__
        raise UsageError(f"--scheduler {_quoted(address, 60)}: no Dask scheduler answers "
                         f"there within {SCHEDULER_TIMEOUT:g} s ({reason})") from None


def cmd_study(args: argparse.Namespace) -> int:
    from pathlib import Path

    from invaders.app.headless import use_dummy_drivers

    use_dummy_drivers()
    # (by default ./replays, as in a checkout; elsewhere the storms alone)
    folder = Path(args.replays if args.replays is not None else "replays")
    replays: Path | None = folder
    if not folder.is_dir() or not any(folder.glob("*.json")):
        if args.replays is not None:
            raise UsageError(f"--replays {args.replays!r}: no folder of replay files (*.json)")
        print("study: no ./replays folder here: studying the storms only "
              "(--replays FOLDER adds recorded games)")
        replays = None
    if args.scheduler is not None:
        _reach_scheduler(args.scheduler)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError(f"--out {args.out!r} is a file, not a folder")
    from invaders.app.outputs import check_output, writing

    made = out  # the study makes the folder and any missing above it: check the first that is
    while not made.exists() and made != made.parent:
        made = made.parent
    check_output(str(made / "study.csv"), "study", (".csv",), named=args.out)
    from invaders.lab.plan import study

    return study(out, replays, quick=args.quick, jobs=args.jobs, scheduler=args.scheduler,
                 big=args.big, saving=lambda: writing(out, "the study into"))


class Command(NamedTuple):
    """A command: how its parser is built (only the one a run asks for), and its body."""

    add_parser: Callable[[argparse._SubParsersAction], None]
    run: Callable[[argparse.Namespace], int]


COMMANDS = {"play": Command(_add_play, cmd_play), "run": Command(_add_run, cmd_run),
            "replay": Command(_add_replay, cmd_replay), "study": Command(_add_study, cmd_study),
            "bench": Command(_add_bench, cmd_bench)}  # in the order `--help` lists them


def _with_command(argv: list[str]) -> list[str]:
    """The line with its command: `play` where it starts with none (`invaders` alone, or
    `invaders --scale 2`, play's options), but for the program's own `--help` and
    `--version`; a word that is no command is left for the parser to refuse."""
    if not argv or (argv[0].startswith("-") and argv[0] not in ("-h", "--help", "--version")):
        return ["play", *argv]
    return argv


def main(argv: Sequence[str] | None = None) -> int:
    """Run one command; exit codes: 0 ok, 1 a check failed, 2 bad input or usage, 3 an
    internal error (one line; `--debug` anywhere on the line prints the traceback)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    for stream in (sys.stdout, sys.stderr):  # a name the output's encoding lacks, escaped
        if isinstance(stream, io.TextIOWrapper):  # (as Python's own stderr does)
            stream.reconfigure(errors="backslashreplace")
    debug = "--debug" in argv
    argv = [arg for arg in argv if arg != "--debug"]
    try:
        from invaders.app.outputs import OutputError
        from invaders.app.processing import current
    except KeyboardInterrupt:  # (Ctrl-C while the program is still loading)
        say("invaders: interrupted")
        return 130
    current.clear()
    try:
        argv = _with_command(argv)
        args = build_parser(argv[0] if argv[0] in COMMANDS else None).parse_args(argv)
        code = COMMANDS[args.command].run(args)
        if sys.stdout is not None:  # (None without a console: pythonw on Windows)
            sys.stdout.flush()  # (here, where a failure is said in one line, not at the exit)
        return code
    except (UsageError, OutputError) as err:
        say(f"invaders: error: {err}")
        return 2
    except KeyboardInterrupt:
        say("invaders: interrupted")
        return 130
    except BrokenPipeError:  # the reader went away (| head): stop quietly
        output_to_nothing()
        return 0
    except Exception as err:  # the last guard: one line, never a bare traceback
        if isinstance(err, OSError) and (_output_failed() or err.errno in FULL):
            from invaders.app.outputs import reason

            # (a named file's failures are said as OutputErrors: one unnamed is the output's,
            # or a library's scratch file's, where the output is not buffered to tell)
            say(f"invaders: error: cannot write the output: {reason(err)}")
            return 2
        if debug:
            import traceback

            traceback.print_exc()
        where = f" while processing {current[-1]}" if current else ""
        text = " ".join(f"{type(err).__name__}: {err}".split())[:300]
        say(f"invaders: internal error{where}: {text} (run it again with --debug for the "
             "traceback)")
        return 3


FULL = (errno.ENOSPC, errno.EDQUOT)  # a write's failures that no bug of ours causes


def _output_failed() -> bool:
    """Whether standard output cannot take what was written to it (redirected to a full
    disk, say); if so, it is pointed at nothing, so that Python's last flush says nothing
    more when the program ends."""
    try:
        if sys.stdout is not None:
            sys.stdout.flush()
    except OSError:
        output_to_nothing()
        return True
    return False


if __name__ == "__main__":
    sys.exit(main())
