"""Reading long replays: the block reader for lines in the program's own shape changes
nothing but the speed, replays are kept packed, and a file at the size limit is read in
memory in proportion to what it means, not to its size."""

from __future__ import annotations

import builtins
import contextlib
import itertools
import json
import re
import resource
import sys
from collections.abc import Callable
from pathlib import Path
from unittest import mock

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from invaders.app.readbench import (
    CHILD,
    counts_twice,
    escaped,
    longest_replay,
    order_each_line,
    read_in_fresh_process,
    reading_bench,
    reversed_fields,
)
from invaders.app.recording import record_headless, save_replay
from invaders.game import canonical, json_block, replay_checks, replay_reading
from invaders.game.checkpoint import Checkpoints
from invaders.game.replay import (
    MAX_FILE_BYTES,
    MAX_TICKS,
    Checkpoint,
    ReplayError,
    load,
    segment_line,
)
from invaders.game.runs import Runs
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> Path:
    """A game as the program writes it (its lines in the one shape the block reader reads)."""
    path = tmp_path_factory.mktemp("reading") / "game.json"
    save_replay(path, record_headless(World(seed=7), Autopilot(7), 900))
    return path


def _outcome(path: Path) -> object:
    """What loading gives: the replay, or the one line that refuses it."""
    try:
        return load(path)
    except ReplayError as err:
        return f"refused: {err}"


def _by_json_alone(path: Path) -> object:
    """The same, with both block readers turned off: every line through the JSON parser and
    the field checks, one at a time."""
    with mock.patch.object(canonical, "read_block", return_value=None), mock.patch.object(
            json_block, "read_block", return_value=None):
        return _outcome(path)


def _without_single_lines(path: Path) -> object:
    """What loading gives when no line may be read on its own (an AssertionError if one is)."""
    with mock.patch.object(replay_reading, "_any_line", side_effect=AssertionError("a line")):
        return _outcome(path)


def test_the_programs_own_lines_are_all_read_by_the_block_reader(written):
    with mock.patch.object(json_block, "read_block", side_effect=AssertionError("JSON")):
        replay = _without_single_lines(written)
    assert replay == _by_json_alone(written) and len(replay.checkpoints) == 16


@pytest.mark.parametrize("sort_keys", [False, True])
@pytest.mark.parametrize("separators, end", [((",", ":"), "\n"), ((", ", ": "), "\n"),
                                             ((",", ":"), "\r\n")])
def test_the_shapes_tools_write_are_read_by_the_block_reader_too(written, tmp_path,
                                                                 separators, end, sort_keys):
    """Fields sorted (as `sort_keys=True`, `jq -S` or Go write them) or not, spaced as
    `json.dumps` writes by default, or with Windows' line ends."""
    path = tmp_path / "spaced.json"
    path.write_bytes("".join(json.dumps(json.loads(line), separators=separators,
                                        sort_keys=sort_keys) + end
                             for line in written.read_text().splitlines()).encode())
    with mock.patch.object(json_block, "read_block", side_effect=AssertionError("JSON")):
        assert _without_single_lines(path) == load(written)


SHAPES = {  # how other tools may write the same lines again
    "fields sorted": lambda o: json.dumps(o, sort_keys=True, separators=(",", ":")),
    "fields reversed": lambda o: json.dumps(reversed_fields(o)),
    "wide gaps": lambda o: json.dumps(o, separators=(" \t" * 5 + "," + " " * 9,
                                                     "\r" * 9 + ":" + " \t" * 5)),
    "escaped names": lambda o: json.dumps(o).replace('"tick"', '"\\u0074ick"'),
    "blank lines between": lambda o: json.dumps(o) + "\n \t\n",
    "counts twice": lambda o: counts_twice(json.dumps(o, separators=(",", ":"))),
}


def _spelt(written: Path, path: Path, spelling: Callable[[dict], str]) -> Path:
    """`path`: `written`'s checkpoint lines as `spelling` writes each (the text changed)."""
    header, *lines = written.read_text().splitlines()
    path.write_text(header + "\n" + "".join(spelling(json.loads(line)) + "\n"
                                            for line in lines))
    assert path.read_text() != written.read_text()
    return path


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_lines_in_any_shape_json_allows_are_read_a_block_at_a_time(written, tmp_path, shape):
    """Fields in another order, wide white space, escapes in names, an object twice: the
    JSON block reader takes whole blocks of them (no line is read on its own), the replay
    the same."""
    path = _spelt(written, tmp_path / "other.json", SHAPES[shape])
    with mock.patch.object(canonical, "read_block", return_value=None):
        replay = _without_single_lines(path)
    assert replay == load(written) == _by_json_alone(path)


_SHUFFLED = order_each_line()
HOSTILE = {  # valid lines as only a hostile file would write them (no tool does)
    "an order of fields a line": lambda o: json.dumps(_SHUFFLED(o), separators=(",", ":")),
    "every name and digest escaped": lambda o: escaped(json.dumps(o)),
    "every zero as -0": lambda o: re.sub(r"\b(?<![1-9])0\b", "-0", json.dumps(o)),
    "a field twice on every line": lambda o: json.dumps(o).replace(
        '"wave":', '"wave": 7, "wave":'),  # (JSON keeps the last)
    "an object twice on every line": lambda o: counts_twice(json.dumps(o)),
    "every object twice, the first a part": lambda o: _twice_first_a_part(o),
}


def _twice_first_a_part(line: dict) -> str:
    """The line with its checkpoint and each object in it written first with one of its
    fields only, then whole (JSON keeps the whole one, the last)."""
    text = json.dumps(line)
    for name, field in (("checkpoint", '"wave": 0'), ("counts", '"shot": 0'),
                        ("groups", f'"game": "{"0" * 16}"')):
        text = text.replace(f'"{name}": {{', f'"{name}": {{{field}}}, "{name}": {{')
    return text


def _checkpoint_twice(line: re.Match[str], dropped: str | None = None) -> str:
    """The checkpoint written twice (JSON keeps the last), the last without the field
    `dropped` (one followed by a comma) if one is named."""
    checkpoint = last = line[1]
    if dropped is not None:
        last = re.sub(rf'"{dropped}":(\{{[^}}]*\}}|[^,{{}}]*),', "", checkpoint, count=1)
    return f'"checkpoint":{checkpoint},"checkpoint":{last}}}'


@pytest.mark.parametrize("shape", sorted(HOSTILE))
def test_lines_only_a_hostile_file_writes_are_read_by_the_regular_expressions(
        written, tmp_path, shape):
    """What JSON lets a file spell many ways (any order of fields on each line, escapes,
    -0, a field written again): the pattern of any order reads them, no line through the
    JSON parser."""
    path = _spelt(written, tmp_path / "hostile.json", HOSTILE[shape])
    with mock.patch.object(json_block, "read_block", side_effect=AssertionError("JSON")):
        assert _without_single_lines(path) == load(written) == _by_json_alone(path)


EDITS = {  # one line changed: what the regular expressions must not read otherwise than JSON
    "a field twice, one missing": (r'"shot":', r'"cannon":', "refused"),
    "a field twice, the last kept": (r'"score":', r'"score":7,"score":', "read"),
    "the inputs twice, the last kept": (r'"inputs":', r'"inputs":[[0,1]],"inputs":', "read"),
    "an object twice, the last whole": (r'("counts":\{[^}]*\})', r'\1,\1', "read"),
    "an object twice, the last a part": (r'"groups":', r'"counts":{"cannon":0},"groups":',
                                         "refused"),
    "an object twice, the first a part": (r'"counts":', r'"counts":{"cannon":0},"counts":',
                                          "read"),
    "an object twice, a field of the last twice, one missing": (
        r'("counts":\{[^}]*\})', r'\1,"counts":{"shot":0,"shot":0,"bomb":0,"alien":55,'
        r'"bunker":4,"saucer":0}', "refused"),
    "the checkpoint twice, the last whole": (
        r'"checkpoint":(\{.*\})\}', _checkpoint_twice, "read"),
    "the checkpoint twice, the last without its counts": (
        r'"checkpoint":(\{.*\})\}', lambda line: _checkpoint_twice(line, "counts"),
        "refused"),
    "the checkpoint twice, the last without its tick": (
        r'"checkpoint":(\{.*\})\}', lambda line: _checkpoint_twice(line, "tick"), "refused"),
    "an escape in a number": (r'"ships":(\d)', r'"ships":\\u003\1', "refused"),
    "an escaped backslash": (r'"hash":"[0-9a-f]', r'"hash":"\\\\u0030', "refused"),
    "an escape of no letter": (r'(?<=[0-9a-f])0(?=[0-9a-f]*")', r'\\u0080', "refused"),
    "a byte of no text": (r'(?<=[0-9a-f])0(?=[0-9a-f]*")', "\x80", "refused"),  # (no UTF-8)
    "a comma before a brace": (r'"saucer":(\d+)}', r'"saucer":\1,}', "refused"),
    "a 19-digit number": (r'"score":\d+', f'"score":{2**63 - 1}', "read"),
    "a run's count past 64 bits": (r'"inputs":\[\[(\d+),\d+\]', r'"inputs":[[\1,' + "9" * 19
                                   + "]", "refused"),
    "a run's count of 63 bits": (r'"inputs":\[\[(\d+),\d+\]', rf'"inputs":[[\1,{2**63 - 1}]',
                                 "refused"),
    "runs past 64 bits, their sum wrapping to the line's 60 ticks": (
        r'"inputs":\[\[.*?\]\],', f'"inputs":[[0,{"9" * 19}],[4,{"9" * 19}],[0,62]],',
        "refused"),
    "a run's bits past 64 bits": (r'"inputs":\[\[\d+,', r'"inputs":[[' + "9" * 19 + ",",
                                  "refused"),
    "one too big": (r'"score":\d+', f'"score":{2**63}', "refused"),
    "a minus": (r'"wave":(\d+)', r'"wave":-\1', "refused"),
    "a minus in a digest": (r'(?<=[0-9a-f])0(?=[0-9a-f]*")', "-0", "refused"),
    "too long a number, then the field again": (r'"score":', f'"score":{10**21},"score":',
                                                 "refused"),
    "a fraction, then the field again": (r'"score":', '"score":0.5,"score":', "refused"),
    "NaN, then the field again": (r'"score":', '"score":NaN,"score":', "refused"),
}


@pytest.mark.parametrize("edit", sorted(EDITS))
def test_a_line_the_regular_expressions_must_not_misread_is_read_as_json_reads_it(
        written, tmp_path, edit):
    """Each edit to line 6 reads (or is refused) as the JSON parser alone has it (the
    file's bytes ASCII but the one the edit puts, if it puts one)."""
    pattern, replacement, verdict = EDITS[edit]
    lines = written.read_text().splitlines(keepends=True)
    lines[5], edits = re.subn(pattern, replacement, lines[5], count=1)
    path = tmp_path / "edited.json"
    path.write_bytes("".join(lines).encode("latin-1"))
    outcome = _outcome(path)
    assert outcome == _by_json_alone(path) and edits == 1
    assert str(outcome).startswith("refused: ") if verdict == "refused" else (
        len(outcome.checkpoints) == len(lines) - 1)


LEARNT = {  # the same lines as a program written elsewhere may write them all
    "fields reversed": lambda o: json.dumps(reversed_fields(o)),
    "the counts twice": lambda o: counts_twice(json.dumps(o, separators=(",", ":"))),
    "every object twice, the first a part": lambda o: _twice_first_a_part(o),
}


@pytest.mark.parametrize("spelling", sorted(LEARNT))
def test_a_files_own_order_of_fields_is_learnt_from_its_first_block(tmp_path, spelling):
    """Fields in an order no tool of ours writes, the same on every line, names written
    again included (JSON keeps the last): the pattern of any order reads the first block,
    the order as written is learnt, and that order's pattern reads the other blocks."""
    path = tmp_path / "other.json"
    header, *lines = _long_objects(tmp_path)
    path.write_text("\n".join([json.dumps(header), *map(LEARNT[spelling], lines)]) + "\n")
    taken, columns = [], canonical._columns

    def recorded(*args):
        taken.append(columns(*args)[0])  # (the order that read the block)
        return columns(*args)

    with mock.patch.object(json_block, "read_block", side_effect=AssertionError("JSON")
                           ), mock.patch.object(canonical, "_columns", recorded):
        replay = _without_single_lines(path)
    assert replay == _by_json_alone(path) and len(replay.checkpoints) == len(lines) > 400
    written = canonical.order_of(LEARNT[spelling](lines[0]).encode())
    assert written is not None and written not in (canonical.OWN, canonical.SORTED)
    assert taken == [canonical.ANY] + [written] * (len(taken) - 1) and len(taken) > 2


LEARNT_EDITS = {  # one line, after the block an order with the counts twice is learnt from
    "the last counts without a field": (r'\},"counts":\{"cannon":\d+,', '},"counts":{',
                                        "refused"),
    "the first counts a part": (r'"counts":\{[^}]*\},"counts"', '"counts":{"shot":1},"counts"',
                                "read"),
    "the first counts empty": (r'"counts":\{[^}]*\},"counts"', '"counts":{},"counts"', "read"),
    "the first counts with a fraction": (r'"counts":\{"cannon":\d+', '"counts":{"cannon":0.5',
                                         "refused"),
    "the first counts the groups": (r'"counts":\{[^}]*\},"counts"',
                                    '"counts":{"game":"%s"},"counts"' % ("0" * 16), "read"),
    "the groups twice too": (r'("groups":\{[^}]*\})', r'"groups":{"rack":"%s"},\1' % ("1" * 16),
                             "read"),
    "the counts once": (r'"counts":\{[^}]*\},', "", "read"),
}


@pytest.mark.parametrize("edit", sorted(LEARNT_EDITS))
def test_a_line_an_order_learnt_must_not_misread_is_read_as_json_reads_it(tmp_path, edit):
    """A file whose lines write the counts twice teaches that order; one line after is
    edited: it reads (or is refused) as the JSON parser alone has it."""
    pattern, replacement, verdict = LEARNT_EDITS[edit]
    header, *lines = _long_objects(tmp_path)
    texts = [LEARNT["the counts twice"](line) for line in lines]
    texts[300], edits = re.subn(pattern, replacement, texts[300], count=1)
    path = tmp_path / "edited.json"
    path.write_text("\n".join([json.dumps(header), *texts]) + "\n")
    outcome = _outcome(path)
    assert outcome == _by_json_alone(path) and edits == 1
    assert str(outcome).startswith("refused: ") if verdict == "refused" else (
        len(outcome.checkpoints) == len(lines))


class _Pairs(list):
    """A JSON object as (name, value) pairs, so that a name may be written again."""


def _pairs(value: object) -> object:
    if isinstance(value, dict):
        return _Pairs((name, _pairs(item)) for name, item in value.items())
    return value


def _pairs_text(value: object) -> str:
    if isinstance(value, _Pairs):
        return "{" + ",".join(f'"{name}":{_pairs_text(item)}' for name, item in value) + "}"
    return json.dumps(value, separators=(",", ":"))


@st.composite
def _written_again(draw: st.DrawFn, line: dict) -> str:
    """The line with its counts written twice (as the file's other lines), then names
    written again before their last in ways a hostile file might: whole, a part, empty or
    with a fraction; and perhaps the last counts without one of its fields."""
    top = _pairs(line)
    checkpoint = top[1][1]
    counts_at = [name for name, _ in checkpoint].index("counts")
    checkpoint.insert(counts_at, ("counts", _Pairs(checkpoint[counts_at][1])))
    places = {"inputs": top, "checkpoint": top, "tick": checkpoint, "score": checkpoint,
              "counts": checkpoint, "groups": checkpoint}
    for name in draw(st.lists(st.sampled_from(sorted(places)), max_size=3)):
        pairs = places[name]
        value = [item for key, item in pairs if key == name][-1]
        kind = draw(st.sampled_from(["whole", "part", "empty", "fraction"]))
        if isinstance(value, _Pairs) and value:
            kept = draw(st.lists(st.sampled_from(range(len(value))), unique=True))
            earlier = {"whole": _Pairs(value), "empty": _Pairs(), "part": _Pairs(
                value[i] for i in sorted(kept)), "fraction": _Pairs([(value[0][0], 0.5)])}[kind]
        else:
            earlier = 0.5 if kind == "fraction" else value
        pairs.insert(draw(st.integers(0, len(pairs))), (name, earlier))  # (maybe last)
    last = [item for key, item in checkpoint if key == "counts"][-1]
    if last and draw(st.booleans()):
        del last[draw(st.integers(0, len(last) - 1))]
    return _pairs_text(top)


@pytest.fixture(scope="module")
def counts_twice_lines(tmp_path_factory) -> tuple[dict, list[dict]]:
    """A replay's header and 160 lines (decoded): written with the counts twice, two blocks,
    the first of 140 lines or so."""
    header, *lines = _long_objects(tmp_path_factory.mktemp("long"))
    return header, lines[:160]


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_an_order_learnt_with_a_name_written_again_reads_what_json_reads(
        counts_twice_lines, tmp_path, data):
    """The invariant kept where an order is learnt with a name written again: a file whose
    first block teaches the counts written twice, one line after it written again in any
    of these ways, gives the replay or the refusal reading every line as JSON gives."""
    header, lines = counts_twice_lines
    texts = [LEARNT["the counts twice"](line) for line in lines]
    texts[150] = data.draw(_written_again(lines[150]))
    path = tmp_path / "again.json"
    path.write_text("\n".join([json.dumps(header), *texts]) + "\n")
    assert _outcome(path) == _by_json_alone(path)


def test_an_order_naming_more_than_twice_an_objects_fields_is_not_learnt():
    """Each order learnt is a pattern to compile: a line of 256 KB may name a field
    thousands of times (seconds to compile), so an object with more names than twice its
    fields teaches nothing (the pattern of any order reads such lines all the same)."""
    line = json.loads(_checkpoint_line())
    text = json.dumps(line, separators=(",", ":"))
    counts = '"counts":' + json.dumps(line["checkpoint"]["counts"], separators=(",", ":"))
    assert canonical.order_of(text.replace(counts, ",".join([counts] * 8)).encode())
    assert canonical.order_of(text.replace(counts, ",".join([counts] * 9)).encode()) is None


def test_a_file_teaches_only_a_few_orders():
    """Each order learnt is a pattern to compile (a few milliseconds): a file with a new
    order in every block teaches the first few, then the JSON block reader reads it."""
    orders = canonical.Orders()
    line = json.loads(_checkpoint_line())
    for names in itertools.permutations(canonical.OWN[2]):  # the counts' fields reordered
        line["checkpoint"]["counts"] = {name: 0 for name in names}
        orders.learn(json.dumps(line).encode() + b"\n")
    orders.learn(b'{"inputs": []}\n')  # (no checkpoint's line: nothing learnt)
    assert len(orders.orders) == 2 + canonical.Orders.LEARNED
    assert orders.orders[:2] == [canonical.OWN, canonical.SORTED]
    assert len(set(orders.orders)) == len(orders.orders)  # (each once)


def _checkpoint_line() -> str:
    """A checkpoint's line as the program writes it."""
    world = World(seed=1)
    return segment_line([[0, 1]], Checkpoint.of(world))


@pytest.mark.parametrize("ending", ["\n", "\r\n"])
def test_blank_lines_and_windows_line_ends_cost_nothing_but_themselves(written, tmp_path,
                                                                       ending):
    """Each line followed by a blank line (empty, of spaces, of a carriage return, of each
    white space a line may hold and still hold nothing), each ending in \\n or \\r\\n: the
    regular expression of the program's own lines without white space reads every block
    (no other pattern, no JSON block reader, no line on its own), and the replay is the one
    the file without them gives."""
    blanks = itertools.cycle(["", "  ", "\r", " \t\r\x0b\x0c"])
    path = tmp_path / "blank.json"
    path.write_bytes("".join(line + ending + next(blanks) + "\n"
                             for line in written.read_text().splitlines()).encode())
    with mock.patch.object(canonical, "_compiled", wraps=canonical._compiled) as patterns:
        replay, by_json, alone = _read_counting(path)
    assert replay == load(written) and by_json == alone == 0
    assert {call.args for call in patterns.call_args_list} == {(canonical.OWN, b"")}


def test_a_carriage_return_inside_a_line_is_white_space_on_the_json_path_too(written,
                                                                            tmp_path):
    """What the fuzzer found: fields in another order (so the JSON parser reads every line)
    with carriage returns between tokens; lines end at a newline alone, as JSON has it."""
    path = tmp_path / "sorted.json"
    path.write_bytes("".join(json.dumps(json.loads(line), separators=("\r,", ":\r"),
                                        sort_keys=True) + "\n"
                             for line in written.read_text().splitlines()).encode())
    assert _outcome(path) == _by_json_alone(path) == load(written)


def _long_objects(tmp_path: Path) -> list[dict]:
    """The lines of a valid replay of 430 lines (the header first), decoded."""
    longest_replay(tmp_path / "long.json", tmp_path, size=200_000)
    return [json.loads(line) for line in (tmp_path / "long.json").read_text().splitlines()]


def _switched(objects: list[dict], lines: range) -> str:
    """The lines, each of `lines` with a lab switch at its first tick, as the program
    writes them."""
    for index in lines:
        objects[index]["lab"] = [[objects[index - 1]["checkpoint"]["tick"], {"speed": 1}]]
    return "".join(_json_line(o) for o in objects)


def _json_line(data: dict) -> str:
    """A line with its fields in the order they came (the program's, for its own lines)."""
    return json.dumps(data, separators=(",", ":")) + "\n"


def _read_counting(path: Path) -> tuple[object, int, int]:
    """What loading gives, and how many blocks the JSON block reader and lines the
    line-by-line reader were given."""
    with mock.patch.object(replay_reading, "_any_line", wraps=replay_reading._any_line
                           ) as alone, mock.patch.object(
            json_block, "read_block", wraps=json_block.read_block) as by_json:
        return _outcome(path), by_json.call_count, alone.call_count


@pytest.mark.parametrize("escaped", [False, True])
def test_lines_with_lab_switches_are_read_with_their_blocks(tmp_path, escaped):
    """A lab switch every 50 lines, its name written plainly (cut out of its line, the
    block read whole by the regular expressions) or escaped (which no cut takes: the block
    read whole by the JSON block reader): no line is read on its own, and the replay is
    the one the JSON parser alone reads."""
    objects = _long_objects(tmp_path)
    text = _switched(objects, range(50, len(objects), 50))
    path = tmp_path / "switched.json"
    path.write_text(text.replace('"lab"', '"\\u006cab"') if escaped else text)
    replay, by_json, alone = _read_counting(path)
    assert replay == _by_json_alone(path) and len(objects) > 400
    assert [tick for tick, _ in replay.switches] == [60 * n - 60 for n in range(50, 430, 50)]
    assert alone == 0 and (by_json > 0) == escaped


def test_a_run_of_lines_with_lab_switches_is_read_by_the_regular_expressions(tmp_path):
    """A hundred lines in a row each with a lab switch (the most a replay may hold is
    10,000), each cut out of its line: the blocks are read whole by the regular
    expressions, neither by the JSON block reader nor a line at a time; the replay is the
    one the JSON parser alone reads."""
    path = tmp_path / "switched.json"
    path.write_text(_switched(_long_objects(tmp_path), range(100, 200)))
    replay, by_json, alone = _read_counting(path)
    assert replay == _by_json_alone(path) and len(replay.switches) == 100
    assert by_json == alone == 0


# A line's lab switches written as a tool or a hostile file might: where the member sits,
# with white space, written twice, inside the checkpoint, with what JSON refuses around it
# or in it. In each line, I is the line's inputs, C its checkpoint (K without its last
# brace) and L its lab member, of the value given (%d: the tick at the line's start).
SWITCH = '[[%d,{"speed":1}]]'
LAB_LINES = {
    "first": ("{L,I,C}", SWITCH),
    "between": ("{I,L,C}", SWITCH),
    "last": ("{I,C,L}", SWITCH),
    "spaced": ("{ I , L\r,\tC }", SWITCH),
    "spaced last": ("{I,C ,\t L }", SWITCH),
    "a word with an escape": ("{I,L,C}", '[[%d,{"broad":"gr\\u0069d"}]]'),
    "twice": ("{I,L,L,C}", SWITCH),
    "twice, once escaped": ('{I,"\\u006cab":[],L,C}', SWITCH),
    "a word not ASCII": ("{I,L,C}", '[[%d,{"broad":"gr\u00efd"}]]'),
    "in the checkpoint": ("{I,K,L}}", SWITCH),
    "as a value": ('{I,C,"x":"lab"}', SWITCH),
    "alone": ("{L}", SWITCH),
    "no comma before": ("{I,C L}", SWITCH),
    "no comma after": ("{I,L C}", SWITCH),
    "a comma too many": ("{I,,L,C}", SWITCH),
    "a comma at the end": ("{I,C,L,}", SWITCH),
    "a comma first": ("{,L,I,C}", SWITCH),
    "its comma after it, not before": ("{I,C L,}", SWITCH),
    "its comma before it twice, not after": ("{I,,L C}", SWITCH),
    "its value cut short": ("{I,L,C}", '[[%d,{"speed":1}]'),
    "a fraction": ("{I,L,C}", '[[%d,{"speed":1.5}]]'),
    "NaN": ("{I,L,C}", '[[%d,{"speed":NaN}]]'),
    "a long number": ("{I,L,C}", '[[%d,{"speed":1' + "0" * 30 + "}]]"),
}
VALID = ("first", "between", "last", "spaced", "spaced last", "a word with an escape", "twice",
         "twice, once escaped", "a word not ASCII")  # (JSON keeps a name's last value)
CUT = VALID[:6]  # (the member written once, plainly, at the top level between delimiters)


@pytest.mark.parametrize("shape", list(LAB_LINES))
def test_a_lab_switch_in_any_shape_is_read_as_json_reads_it(tmp_path, shape):
    """Each shape above in one line of a long replay: the replay, or the refusal, that the
    JSON parser alone gives; a member the cut takes is cut out (no JSON block reader, no
    line on its own), any other leaves its block to them."""
    objects = _long_objects(tmp_path)
    template, value = LAB_LINES[shape]
    checkpoint = '"checkpoint":' + json.dumps(objects[200]["checkpoint"], separators=(",", ":"))
    members = {"I": '"inputs":' + json.dumps(objects[200]["inputs"], separators=(",", ":")),
               "C": checkpoint, "K": checkpoint[:-1],
               "L": '"lab":' + value % objects[199]["checkpoint"]["tick"]}
    lines = [_json_line(o) for o in objects]
    lines[200] = re.sub("[ICKL]", lambda found: members[found[0]], template) + "\n"
    path = tmp_path / "lab.json"
    path.write_text("".join(lines))
    outcome, by_json, alone = _read_counting(path)
    assert outcome == _by_json_alone(path)
    assert isinstance(outcome, str) == (shape not in VALID)
    assert (by_json == alone == 0) == (shape in CUT), (by_json, alone)


def test_a_run_of_lines_too_full_of_lab_switches_is_refused_as_json_alone_refuses_it(
        tmp_path):
    """Two lines in a row each with 300 switches to empty choices (each valid): more
    objects than a line of that length may hold, so the line-by-line reader refuses the
    first before parsing it, and the JSON block reader must not take the run."""
    objects = _long_objects(tmp_path)
    for index in (100, 101):
        objects[index]["lab"] = [[objects[index - 1]["checkpoint"]["tick"], {}]] * 300
    path = tmp_path / "full.json"
    path.write_text("".join(json.dumps(o, separators=(",", ":")) + "\n" for o in objects))
    refused = _outcome(path)
    assert refused == _by_json_alone(path) == "refused: line 101 holds more objects than a " \
        "replay can"


def test_a_bad_line_costs_only_itself_the_block_reader(tmp_path):
    """One bad line among 430 (its lab switch after its span): its block is read again by
    halves, so a few dozen blocks take the lines before it, not each alone, and the line
    read on its own is refused as the JSON parser alone refuses it."""
    objects = _long_objects(tmp_path)
    objects[200]["lab"] = [[objects[200]["checkpoint"]["tick"], {"speed": 1}]]
    path = tmp_path / "bad.json"
    path.write_text("".join(json.dumps(o, separators=(",", ":")) + "\n" for o in objects))
    read_by_json = []

    def counted(line, where, *rest):
        read_by_json.append(where)
        return _any_line(line, where, *rest)

    _any_line = replay_reading._any_line
    with mock.patch.object(replay_reading, "_any_line", counted), mock.patch.object(
            canonical, "read_block", wraps=canonical.read_block) as blocks:
        refused = _outcome(path)
    assert read_by_json == ["line 201"]
    assert blocks.call_count < 40, blocks.call_count  # (one a line: over 200)
    assert refused == _by_json_alone(path) and "line 201 lab switch 0 tick" in str(refused)


@pytest.mark.parametrize("block_bytes", [1, 7, 460, 4096])
def test_blocks_cut_anywhere_in_a_line_read_the_same(written, block_bytes):
    whole = load(written)
    with mock.patch.object(replay_reading, "BLOCK_BYTES", block_bytes):
        assert load(written) == whole


EDGES = [0, 1, -1, 31, 32, 2**63 - 1, 2**63, 10**18 - 1, 10**18, MAX_TICKS, MAX_TICKS + 1,
         1.5, "a", None, [], {}]


@st.composite
def compact_mutants(draw, path: Path) -> str:
    """A file in the program's own shape (no spaces) with one change: any value anywhere
    in a checkpoint's line or in an input run (numbers at every edge, a fraction or a truth
    value equal to the number there, a digest a digit short or long), one character, a run
    split in two (the same inputs, unless a part is empty), a line's fields reordered, an
    object's fields shuffled, a field written twice (an object, whole or short of a field,
    too) or named as another, a character written as JSON's escape of it (in a string or
    not), a zero as -0, a blank line, white space put between a line's tokens, or a lab
    switch."""
    objects = [json.loads(line) for line in path.read_text().splitlines()]
    index = draw(st.integers(2, len(objects) - 1))  # (line 2 has no input runs)
    how = draw(st.sampled_from(["value", "run", "char", "split", "reorder", "shuffle",
                                "twice", "rename", "escape", "minus", "blank", "spaced",
                                "lab"]))
    if how == "run":
        run = draw(st.sampled_from(objects[index]["inputs"]))
        run[draw(st.integers(0, 1))] = draw(st.sampled_from([0, 32, 2**63, MAX_TICKS + 1]))
    elif how == "value":
        parent = objects[index]
        while True:
            key = draw(st.sampled_from(list(parent) if isinstance(parent, dict)
                                       else range(len(parent))))
            child = parent[key]
            if not (isinstance(child, dict | list) and child) or draw(st.booleans()):
                break
            parent = child
        twins = ([float(child), bool(child)] if type(child) is int  # (equal to it)
                 else [child[:-1], child + "0"] if type(child) is str else [])
        parent[key] = draw(st.one_of(st.sampled_from(EDGES + twins), st.integers()))
    elif how == "split":
        runs = objects[index]["inputs"]
        at = draw(st.integers(0, len(runs) - 1))
        bits, count = runs[at]
        part = draw(st.integers(0, count))  # (a part of 0 ticks: no file may hold one)
        runs[at:at + 1] = [[bits, part], [bits, count - part]]
    elif how == "lab":  # a switch, its tick inside the line's span or just outside it,
        start = objects[index - 1]["checkpoint"]["tick"]  # anywhere among the line's fields
        tick = draw(st.integers(start - 1, objects[index]["checkpoint"]["tick"]))
        line = dict(objects[index], lab=[[tick, {"speed": draw(st.integers(0, 2))}]])
        objects[index] = {name: line[name] for name in draw(st.permutations(list(line)))}
    elif how == "reorder":
        objects[index] = dict(reversed(objects[index].items()))
    elif how == "shuffle":
        checkpoint = objects[index]["checkpoint"]
        parent = draw(st.sampled_from([objects, checkpoint, checkpoint]))
        key = index if parent is objects else draw(st.sampled_from(["counts", "groups"]))
        names = draw(st.permutations(list(parent[key])))
        parent[key] = {name: parent[key][name] for name in names}
    text = [json.dumps(o, separators=(",", ":")) + "\n" for o in objects]
    line = text[index]
    if how == "char":  # put in place of one, or before it
        at = draw(st.integers(0, len(line) - 2))
        text[index] = line[:at] + draw(st.sampled_from('0123456789abcdefAF",:[]{} -\\')) + line[
            at + draw(st.integers(0, 1)):]
    elif how == "escape":  # (its code's hex digits in capitals or not)
        at = draw(st.integers(0, len(line) - 2))
        escape = draw(st.sampled_from(["\\u%04x", "\\u%04X"])) % ord(line[at])
        text[index] = line[:at] + escape + line[at + 1:]
    elif how == "minus":
        zeros = [at for at in range(1, len(line)) if line[at - 1:at + 2] in (":0,", ":0}", "[0,")]
        at = draw(st.sampled_from(zeros or [0]))
        text[index] = line[:at] + "-" + line[at:]
    elif how == "twice":  # a field written again before any field (JSON: the last counts)
        name = draw(st.sampled_from(sorted(set(re.findall(r'"(\w+)":', line)))))
        at = draw(st.sampled_from([found.start() for found in re.finditer(r'"\w+":', line)]))
        value = draw(st.sampled_from(["7", '{"cannon":0}', '"0"', "[]", "0.5", "NaN",
                                      str(10**21), str(2**63), *_objects_named(
                                          objects[index], name, draw(st.integers(0, 8)))]))
        text[index] = line[:at] + f'"{name}":{value},' + line[at:]
    elif how == "rename":  # a field named as another (of its object: one twice, one missing)
        name = draw(st.sampled_from(re.findall(r'"(\w+)":', line)))
        at = draw(st.sampled_from([found.start() for found in re.finditer(r'"\w+":', line)]))
        text[index] = line[:at] + f'"{name}"' + line[line.index(":", at):]
    elif how == "blank":
        text.insert(index, " " * draw(st.integers(0, 2)) + "\n")
    elif how == "spaced":  # white space where JSON allows it, a little or a lot
        gap = st.sampled_from(["", " ", "\t", " " * 8, " " * 9, "\r"])
        text[index] = draw(gap) + json.dumps(objects[index], separators=(
            draw(gap) + "," + draw(gap), draw(gap) + ":" + draw(gap))) + draw(gap) + "\n"
    return "".join(text)


def _objects_named(line: dict, name: str, dropped: int) -> list[str]:
    """The line's objects of that name (its checkpoint, counts or groups), as they are and
    without their field number `dropped` (if they have one)."""
    found = [line[name]] if name in line else [line["checkpoint"][name]] if name in (
        "counts", "groups") else []
    return [json.dumps(part, separators=(",", ":")) for value in found if type(value) is dict
            for part in (value, {key: item for number, (key, item) in
                                 enumerate(value.items()) if number != dropped})]


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_the_block_reader_gives_what_the_json_parser_gives(written, tmp_path, data):
    """The invariant the block reader keeps: whatever a file holds, it gives the very
    replay, or the very refusal, that reading every line as JSON gives."""
    path = tmp_path / "mutant.json"
    path.write_text(data.draw(compact_mutants(written)))
    assert _outcome(path) == _by_json_alone(path)


@pytest.mark.parametrize("limit, value", [("MAX_RUNS", 40), ("MAX_TICKS", 500),
                                          ("MAX_LINE_BYTES", 500)])
def test_each_limit_refuses_the_same_through_either_reader(written, limit, value):
    with contextlib.ExitStack() as patched:
        for module in (replay_checks, replay_reading):  # (each has the limit as its own name)
            if hasattr(module, limit):
                patched.enter_context(mock.patch.object(module, limit, value))
        refused = _outcome(written)
        assert refused == _by_json_alone(written) and str(refused).startswith("refused: ")


def test_a_run_split_across_lines_or_within_one_is_stored_once():
    runs = Runs([(4, 2)])
    runs.extend([4, 4, 0, 1, 1, 4], [1, 3, 2, 5, 1, 1])
    assert list(runs) == [(4, 6), (0, 2), (1, 6), (4, 1)] and runs.ticks == 15
    one_at_a_time = Runs([(4, 2)])
    for bits, count in zip([4, 4, 0, 1, 1, 4], [1, 3, 2, 5, 1, 1], strict=True):
        one_at_a_time.add(bits, count)
    assert runs == one_at_a_time and list(runs.actions())[:7] == [4] * 6 + [0]


def test_checkpoints_come_back_from_their_packing_field_for_field(written):
    listed = [json.loads(line)["checkpoint"] for line in written.read_text().splitlines()[1:]]
    packed = load(written).checkpoints
    assert isinstance(packed, Checkpoints) and len(packed) == len(listed)
    assert [vars(c) for c in packed] == listed  # every number and digest, in the file's order
    assert packed[-1] == packed[len(listed) - 1] and packed[1:3] == list(packed)[1:3]
    with pytest.raises(IndexError):
        packed[len(listed)]


def test_a_replay_at_the_size_limit_is_read_in_memory_in_proportion_to_its_meaning(
        tmp_path):
    """64 MB of checkpoints, 8.7 million ticks: the file's text is never held, only its
    numbers and digests packed (about 160 bytes a checkpoint, 16 an input run), where
    reading it as text and objects took 520 MB."""
    path = tmp_path / "long.json"
    ticks = longest_replay(path, tmp_path)
    assert MAX_FILE_BYTES - 2**20 < path.stat().st_size <= MAX_FILE_BYTES
    _, megabytes, read = read_in_fresh_process(path)
    assert read == ticks > 8_000_000 and megabytes < 100  # (the interpreter and imports: 34)


@pytest.mark.parametrize("platform, per_megabyte", [("linux", 2**10), ("darwin", 2**20)])
def test_without_proc_the_peak_is_getrusages_in_its_platforms_unit(
        monkeypatch, capsys, platform, per_megabyte):
    """Where there is no /proc (macOS), the reading process's peak is getrusage's, which
    counts bytes on macOS and KiB elsewhere: either way the same megabytes."""
    real_open = builtins.open

    def no_proc(file, *args, **kwargs):
        if str(file).startswith("/proc/"):
            raise FileNotFoundError(file)
        return real_open(file, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", no_proc)
    monkeypatch.setattr(sys, "platform", platform)
    monkeypatch.setattr(sys, "argv", ["-c", str(ROOT / "replays" / "saucer-300.json")])
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # (KiB: this is Linux)
    exec(CHILD, {})
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    _, megabytes, ticks = json.loads(capsys.readouterr().out)
    assert ticks == 3600 and before <= megabytes * per_megabyte <= after


def test_the_reading_bench_reads_the_valid_files_and_refuses_the_hostile_ones():
    """`bench --reading` at 2 MB: each of its files read or refused as it says, a line each,
    every figure under the goal at this size."""
    lines, met = reading_bench(rounds=1, size=2**21)
    rows = [line.split() for line in lines[1:]]
    verdicts = [row[row.index("s") - 2] for row in rows]  # (the word before the seconds)
    assert lines[0].startswith("reading files at the size limit (2,097,152 bytes), 1 rounds")
    assert verdicts == ["read"] * 12 + ["refused"] * 4 and met, lines
    assert [row[-1] for row in rows] == ["met"] * 16
