"""A small seeded mutation engine: bad input for the compiler, the profile reader and
the compiled-file reader, and the harness that feeds it to them.

Shared by tests/test_fuzz.py (a short run) and benchmarks/fuzz.py (20,000 mutants per
kind). Three kinds of input, each mutated from real files:

- ``gest``: the library's .gest files, compiled like ``gestc check`` does (every
  gesture of the file), then written to a .gestc and read back;
- ``toml``: the built-in profiles, read like ``load_profile`` does, then used to
  compile a gesture that moves every servo;
- ``gestc``: compiled library gestures (``to_json``), read like the player reads them.

``mutate(data, rng, kind)`` applies one to four mutations at byte, line or token level
(flips, deletions, duplications, interesting tokens: huge numbers, NUL, lone
surrogates, deep nesting, repeated lines, tabs, keywords, fan-out of poses...).
``attempt(kind, seed, data)`` runs one input and returns what happened; an input is
fine when it is accepted, or refused with a GestError whose every diagnostic reads
``file:line:col: error: ...``.
"""

from __future__ import annotations

import math
import random
import re
import signal
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

KINDS = ("gest", "toml", "gestc")

# -- interesting tokens -------------------------------------------------------------
NUMBERS = [b"0", b"-0", b"1", b"-1", b"90", b"180", b"181", b"255", b"256", b"1000", b"1001",
           b"65535", b"4294967296", b"9" * 30, b"9" * 400, b"1" * 5000, b"0.5", b".5", b"5.",
           b"1e-09", b"1e308", b"1e999", b"-1e999", b"0" * 50 + b"1", b"+090", b"3.0"]
COMMON = [b"\x00", b"\xff", b"\xc3", b"\xed\xa0\x80", "\u2028".encode(), "\x85".encode(),
          "\ufeff".encode(), b"\t", b"    ", b"\t    ", b"\r", b"\r\n", b"\n", b"\\\n", b"#",
          b":", b",", b'"', b"'", b"=", b"[", b"]", b"{", b"}", b" ", b"\x1b[2J", b"@",
          "\u00e9".encode(), "\U0001f600".encode()]
KEYWORDS = [b"use", b"group", b"pose", b"wait", b"hold", b"repeat", b"over", b"stagger"]
TOKENS = {
    "gest": COMMON + KEYWORDS + [
        b"index", b"middle", b"fingers", b"all", b"fist", b"peace", b"demo", b"s", b"ms",
        b"over 0.001ms", b"over 600s", b"stagger 600s", b"wait 600s", b"repeat 1000:",
        b"repeat 1000: peace", b'use "peace.gest"', b'use "/dev/zero"', b'use ""',
        b'use "../profiles/rhand.toml"', b"pose p: index 9", b"group g: index, middle",
        b"index " + b"9" * 400, b"repeat " + b"9" * 400 + b":",
        b"g: " + b"index 9, " * 200 + b"index 9"],
    "toml": COMMON + KEYWORDS + [
        b"true", b"false", b"nan", b"inf", b"-inf", b"[]", b"{}", b'""', b"[[board]]",
        b"[servo.x]", b"[groups]", b"[[glove]]", b"id", b"baud", b"servos", b"range",
        b"rest", b"max_velocity", b"max_jerk", b"max_acceleration", b"calibration", b"pin",
        b"sensors", b"1979-05-27", b'"""', b"'''", b"a.b.c = 1", b"0x7f", b"1_000",
        b"max_velocity = 1e-09", b"max_jerk = 1e300", b"baud = 300"],
    "gestc": COMMON + [
        b"true", b"false", b"null", b"NaN", b"Infinity", b"-Infinity", b"[]", b"{}",
        b'""', b'"board"', b'"bytes"', b'"times"', b"1000000000000", b"-1e-300",
        b'"format"', b'"version"', b"2"],
}


# -- mutations ----------------------------------------------------------------------
def mutate(data: bytes, rng: random.Random, kind: str) -> bytes:
    """One to four mutations of ``data``, chosen by ``rng``."""
    for _ in range(min(4, 1 + int(rng.expovariate(1.2)))):
        op = rng.choice(_OPS)
        data = op(data, rng, kind)
    return data


def _token(rng: random.Random, kind: str) -> bytes:
    return rng.choice(NUMBERS if rng.random() < 0.25 else TOKENS[kind])


def _spot(data: bytes, rng: random.Random) -> int:
    return rng.randrange(len(data) + 1)


def _flip(data: bytes, rng: random.Random, kind: str) -> bytes:
    if not data:
        return bytes([rng.randrange(256)])
    k = rng.randrange(len(data))
    value = rng.randrange(256) if rng.random() < 0.5 else data[k] ^ (1 << rng.randrange(8))
    return data[:k] + bytes([value]) + data[k + 1:]


def _delete(data: bytes, rng: random.Random, kind: str) -> bytes:
    k = _spot(data, rng)
    return data[:k] + data[k + rng.choice((1, 2, 8, 64, 512)):]


def _duplicate(data: bytes, rng: random.Random, kind: str) -> bytes:
    k = _spot(data, rng)
    piece = data[k:k + rng.choice((1, 4, 32, 256))]
    j = _spot(data, rng)
    return data[:j] + piece * rng.choice((1, 2, 100)) + data[j:]


def _insert(data: bytes, rng: random.Random, kind: str) -> bytes:
    k = _spot(data, rng)
    return data[:k] + _token(rng, kind) + data[k:]


_WORD = re.compile(rb"[A-Za-z_][A-Za-z0-9_]*|[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?|\S")


def _replace_token(data: bytes, rng: random.Random, kind: str) -> bytes:
    tokens = list(_WORD.finditer(data[:200_000]))
    if not tokens:
        return _insert(data, rng, kind)
    m = rng.choice(tokens)
    new = rng.choice(NUMBERS) if m.group()[:1].isdigit() else _token(rng, kind)
    return data[:m.start()] + new + data[m.end():]


def _stream_bytes(data: bytes, rng: random.Random, kind: str) -> bytes:
    """Replace one to three numbers of a list of values (a stream's bytes, a pose...)
    with random bytes: a file that still parses, with values a board must not get."""
    numbers = list(re.finditer(rb"(?<=\n)\s*(\d+)(?=,?\n)", data[:2_000_000]))
    if not numbers:
        return _replace_token(data, rng, kind)
    for m in rng.sample(numbers, min(len(numbers), rng.randint(1, 3))):
        value = str(rng.randrange(256)).encode().rjust(len(m.group(1)))
        if len(value) == len(m.group(1)):  # same length: earlier offsets stay valid
            data = data[:m.start(1)] + value + data[m.end(1):]
    return data


def _lines(data: bytes) -> list[bytes]:
    return data.split(b"\n")


def _line_op(data: bytes, rng: random.Random, kind: str) -> bytes:
    lines = _lines(data)
    k = rng.randrange(len(lines))
    op = rng.randrange(5)
    if op == 0:
        del lines[k]
    elif op == 1:
        lines[k:k + 1] = [lines[k]] * rng.choice((2, 3, 10, 1000, 5_000))
    elif op == 2:
        j = rng.randrange(len(lines))
        lines[k], lines[j] = lines[j], lines[k]
    elif op == 3:
        lines[k] = rng.choice((b"\t", b"    ", b" \t", b"\t ", b"        ", b"")) \
            + lines[k].lstrip()
    else:
        lines.insert(k, _token(rng, kind))
    return b"\n".join(lines)


def _long_line(data: bytes, rng: random.Random, kind: str) -> bytes:
    lines = _lines(data)
    k = rng.randrange(len(lines))
    piece = rng.choice((b"index 9, ", b"9", b"x", b"# ", b" ", b"a", b"[1, ", b"p, "))
    lines[k] += piece * rng.choice((1_000, 10_000, 200_000, 1_800_000 // len(piece)))
    return b"\n".join(lines)


def _nest(data: bytes, rng: random.Random, kind: str) -> bytes:
    """Deep nesting: brackets for JSON and TOML; for .gest, poses and gestures built
    from each other (a fan-out whose expansion doubles per level) and nested repeats."""
    depth = rng.choice((20, 40, 101, 1_000, 100_000))
    k = _spot(data, rng)
    if kind == "gest":
        shape = rng.randrange(4)
        if shape == 0:  # pose p_i: p_{i-1}, p_{i-1}
            lines = ["pose q0: index 9"] + [f"pose q{i}: q{i - 1}, q{i - 1}"
                                            for i in range(1, min(depth, 2_000))]
        elif shape == 1:  # gesture g_i calls g_{i-1} twice
            lines = ["h0: index 9"] + [f"h{i}:\n    h{i - 1}\n    h{i - 1}"
                                       for i in range(1, min(depth, 2_000))]
        elif shape == 2:  # repeat blocks nested inside each other
            n = min(depth, 500)
            lines = ["r:"] + ["    " * (i + 1) + "repeat 2:" for i in range(n)] \
                + ["    " * (n + 1) + "index 9"]
        else:  # a pose of many poses
            lines = ["pose w0: index 9"] + [f"pose w{i}: " + ", ".join(
                f"w{j}" for j in range(max(0, i - 8), i)) for i in range(1, min(depth, 500))]
        block = ("\n" + "\n".join(lines) + "\n").encode()
        k = data.rfind(b"\n", 0, k) + 1  # at the start of a line
        return data[:k] + block + data[k:]
    if kind == "toml":
        return data[:k] + b"\nx = " + b"[" * depth + b"]" * depth + b"\n" + data[k:]
    return data[:k] + b"[" * depth + b"]" * depth + data[k:]


def _many(data: bytes, rng: random.Random, kind: str) -> bytes:
    """Many small things at once: one-line gestures, [servo] tables, stream pairs."""
    n = rng.choice((10, 100, 1_000))
    if kind == "gest":
        extra = "".join(f"m{i}: index {i % 181}, middle 90 over 0.5s\n" for i in range(n))
        return data + b"\n" + extra.encode()
    if kind == "toml":
        extra = "".join(f"[servo.z{i}]\nid = {i % 181}\n" for i in range(n))
        return data + b"\n" + extra.encode()
    k = data.find(b'"bytes": [')
    if k < 0:
        return _insert(data, rng, kind)
    k += len(b'"bytes": [')
    return data[:k] + b"1, 2, " * n + data[k:]


_OPS: list[Callable[[bytes, random.Random, str], bytes]] = [
    _flip, _flip, _delete, _duplicate, _insert, _insert, _replace_token, _replace_token,
    _stream_bytes, _line_op, _line_op, _long_line, _nest, _many]


# -- seeds --------------------------------------------------------------------------
@dataclass(frozen=True)
class Seed:
    kind: str
    name: str  #: the file it stands for (errors name it)
    data: bytes
    profile: str  #: the profile it is compiled or played on


def seeds() -> dict[str, list[Seed]]:
    """The inputs to mutate: the library's .gest files, the built-in profiles, and a few
    compiled library gestures."""
    from inmoov_dsl.compiling.compiled import to_json
    from inmoov_dsl.compiling.compiler import compile_program
    from inmoov_dsl.errors import GestError
    from inmoov_dsl.language.load import load
    from inmoov_dsl.resources import library_dir, profiles_dir

    gest = []
    for path in sorted(library_dir().glob("*.gest")):
        program = load(str(path), search=[str(library_dir())])
        for profile in ("rhand", "inmoov"):
            try:
                for name in program.own:
                    compile_program(program, name, profile)
            except GestError:
                continue
            gest.append(Seed("gest", str(path), path.read_bytes(), profile))
            break
    toml = [Seed("toml", str(p), p.read_bytes(), p.stem)
            for p in sorted(profiles_dir().glob("*.toml"))]
    gestc = []
    for name, profile in (("peace", "rhand"), ("count", "rhand"), ("wiggle", "lhand"),
                          ("hello", "inmoov"), ("shrug", "inmoov"),
                          ("wave", "rhand-maestro"), ("peace", "rhand-pca9685")):
        program = load(str(library_dir() / _file_of(name)), search=[str(library_dir())])
        compiled, _ = compile_program(program, name, profile)
        gestc.append(Seed("gestc", f"{name}.gestc", to_json(compiled).encode(), profile))
    return {"gest": gest, "toml": toml, "gestc": gestc}


def _file_of(gesture: str) -> str:
    from inmoov_dsl.language.library import load_library

    return Path(load_library()[gesture]).name


# -- running one input --------------------------------------------------------------
class Hang(BaseException):
    """An input took longer than its time bound (a BaseException: no ``except
    Exception`` in the code under test can swallow it)."""


@dataclass(frozen=True)
class Outcome:
    status: str  #: "accepted", "refused" (a proper GestError), "bad-error", "uncaught", "hang"
    seconds: float
    detail: str = ""


FORMAT = re.compile(r"[^\n]+:\d+:\d+: (error|warning): ")


def attempt(seed: Seed, data: bytes, limit: float = 5.0) -> Outcome:
    """Run one input through the part of the toolchain its kind is for, within
    ``limit`` seconds, and say what happened."""
    from inmoov_dsl.errors import GestError

    run = {"gest": _gest, "toml": _toml, "gestc": _gestc}[seed.kind]
    t0 = time.perf_counter()
    try:
        warnings = within(limit, lambda: run(seed, data))
    except GestError as exc:
        seconds = time.perf_counter() - t0
        bad = [d.format() for d in exc.diagnostics if not FORMAT.match(d.format())]
        if bad or not exc.diagnostics:
            return Outcome("bad-error", seconds, bad[0] if bad else "no diagnostic")
        return Outcome("refused", seconds, exc.diagnostics[0].message)
    except Hang:
        return Outcome("hang", time.perf_counter() - t0)
    except (Exception, RecursionError) as exc:  # noqa: BLE001 - what we are looking for
        return Outcome("uncaught", time.perf_counter() - t0, f"{type(exc).__name__}: {exc}"
                       [:500])
    seconds = time.perf_counter() - t0
    bad = [w.format() for w in warnings if not FORMAT.match(w.format())]
    if bad:
        return Outcome("bad-error", seconds, bad[0])
    return Outcome("accepted", seconds)


def within(seconds: float, fn: Callable[[], object]):
    """``fn()``, or Hang after ``seconds`` of this process's CPU time (a busy machine
    does not stretch it; a loop that hangs spends it) or ten times as long by the wall
    clock (a wait that hangs): timer signals in the main thread (which interrupt Python
    code wherever it loops), a watchdog thread elsewhere (which cannot stop ``fn``, but
    does not wait for it)."""
    if hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread():
        def alarm(signum, frame):
            raise Hang

        old = {sig: signal.signal(sig, alarm) for sig in (signal.SIGPROF, signal.SIGALRM)}
        signal.setitimer(signal.ITIMER_PROF, seconds)
        signal.setitimer(signal.ITIMER_REAL, 10 * seconds)
        try:
            return fn()
        finally:
            signal.setitimer(signal.ITIMER_PROF, 0)
            signal.setitimer(signal.ITIMER_REAL, 0)
            for sig, handler in old.items():
                signal.signal(sig, handler)
    box: list = []

    def work():
        try:
            box.append((True, fn()))
        except BaseException as exc:  # noqa: BLE001 - handed to the caller
            box.append((False, exc))

    worker = threading.Thread(target=work, daemon=True)
    worker.start()
    worker.join(seconds)
    if not box:
        raise Hang
    ok, value = box[0]
    if not ok:
        raise value
    return value


def _gest(seed: Seed, data: bytes):
    """Like ``gestc check``: read, parse with imports, compile every gesture of the file;
    then each compiled gesture must read back from its .gestc. A mutant read as bytes
    goes through the file reader's decoding; one in three is given as text that keeps
    undecodable bytes as lone surrogates (as a caller of compile_source may)."""
    from inmoov_dsl.compiling.compiled import to_json
    from inmoov_dsl.compiling.compiled_reader import from_json
    from inmoov_dsl.compiling.compiler import compile_program
    from inmoov_dsl.errors import decode_utf8
    from inmoov_dsl.language.load import load
    from inmoov_dsl.resources import library_dir

    if len(data) % 3 == 0:
        text = data.decode("utf-8", "surrogateescape")
    else:
        text = decode_utf8(data, seed.name)
    program = load(seed.name, text, search=[str(library_dir())])
    warnings = []
    for k, name in enumerate(program.own):
        compiled, _ = compile_program(program, name, seed.profile)
        warnings += compiled.warnings
        if k < 3:  # the first few: enough to test the writer and the reader together
            again = from_json(to_json(compiled), f"{name}.gestc")
            assert [s.data for s in again.streams] == [s.data for s in compiled.streams]
            check_compiled(again)
    return warnings


def _toml(seed: Seed, data: bytes):
    """Like ``load_profile``: decode, parse, check; then compile a gesture moving every
    servo on it, and read the result back and against the profile."""
    from inmoov_dsl.compiling.compiled import to_json
    from inmoov_dsl.compiling.compiled_reader import from_json
    from inmoov_dsl.compiling.compiler import compile_source
    from inmoov_dsl.compiling.playable import check_profile
    from inmoov_dsl.errors import decode_utf8
    from inmoov_dsl.profiles.profile import parse_profile

    profile = parse_profile(decode_utf8(data, seed.name), seed.name)
    lo = max(s.lo for s in profile.servos)
    hi = min(s.hi for s in profile.servos)
    if lo > hi:  # no value every servo takes: each to its own range's ends
        source = "g:\n    " + ", ".join(f"{s.name} {s.hi}" for s in profile.servos) + \
            " over 0.3s\n    " + ", ".join(f"{s.name} {s.lo}" for s in profile.servos) + "\n"
    else:
        source = f"g:\n    all {hi} over 0.3s\n    all {lo} stagger 10ms\n"
    compiled = compile_source(source, profile=profile, file="fuzz.gest")
    again = from_json(to_json(compiled), "fuzz.gestc")
    check_compiled(again)
    check_profile(again, profile)
    return compiled.warnings


def _gestc(seed: Seed, data: bytes):
    """Like the player: read the file (as bytes, or as text for even lengths), check
    what it accepts against the rules of the protocol, then against the profile."""
    from inmoov_dsl.compiling.compiled_reader import from_json
    from inmoov_dsl.compiling.playable import check_profile
    from inmoov_dsl.profiles.profile import load_profile

    if len(data) % 2 == 0:
        text = data.decode("utf-8", "surrogateescape")
        compiled = from_json(text, seed.name)
    else:
        compiled = from_json(data, seed.name)
    check_compiled(compiled)
    check_profile(compiled, load_profile(seed.profile))
    return ()


def check_compiled(c) -> None:
    """What a board and the player rely on in every compiled gesture, checked from the
    protocol (not from the reader's code): AssertionError when one rule is broken."""
    assert c.streams
    assert len(c.start) == len(c.final) == len(c.servos) >= 1
    assert all(0 <= v <= 180 for v in (*c.start, *c.final))
    assert math.isfinite(c.duration) and 0 <= c.duration <= 3600
    owner: dict[int, int] = {}
    for s in c.streams:
        data, times = list(s.data), s.times.tolist()
        tau = 10 / s.baud
        if s.kind != "rig":  # whole commands of the kind, in time, within the gesture
            from inmoov_dsl.boards import fault

            assert fault(s.kind, s.data) is None and len(data) == len(times)
            assert all(math.isfinite(t) and t >= 0 for t in times)
            assert all(b >= a for a, b in zip(times, times[1:], strict=False))
            assert not times or times[-1] <= c.duration + 0.04 + 1e-6
            continue
        assert 181 <= s.board <= 247 and len(data) == len(times) and len(data) % 2 == 1
        assert data[0] == 255 and times[0] == 0
        assert all(b <= 180 for b in data[1:]), "a servo ID or value above 180"
        assert all(math.isfinite(t) for t in times)
        assert all(b - a >= tau - 2e-9 for a, b in zip(times, times[1:], strict=False))
        assert times[-1] <= c.duration + 0.04 + 1e-6
        for sid in data[1::2]:
            assert owner.setdefault(sid, s.board) == s.board, "a servo ID on two boards"
