"""Every command the docs show runs as written: each ``gestc``, ``gestplay`` and
``gestsim`` line of a code block in docs/ and the README. One that needs nothing but the
repository (a library gesture, the virtual board ``sim://``, a file it writes) is run,
from a folder of its own beside the repository's gestures, and must end as the docs say
(0, or the error they show under it); one that needs a hand, a file of the reader's, a
terminal or a long-running server is read by the command's own parser, which must take
every option as written; a synopsis (``[--gesture NAME]``) must name only options the
command has."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = sorted((ROOT / "docs").glob("*.md")) + [ROOT / "README.md"]
PROGRAMS = ("gestc", "gestplay", "gestsim")
#: what a command run here may not do: a server, a terminal, a tool that waits for keys
LONG = {"serve", "repl", "teach", "calibrate", "lsp", "record", "upload"}
RUNS = {"gestc": {"check", "show", "list", "compile", "plot", "fmt", "urdf", "export",
                  "preview"},
        "gestplay": {"play", "dump", "send", "relax", "stored"}}


@dataclass(frozen=True)
class Shown:
    """A command as a doc shows it, and the error it shows under it (if any)."""

    doc: str
    line: int
    text: str
    error: str | None = None


def shown_commands() -> list[Shown]:
    """Every command line of the docs' code blocks (indented, or fenced as a shell's),
    with its continuation lines."""
    found = []
    for doc in DOCS:
        lines = doc.read_text(encoding="utf-8").split("\n")
        fenced = False
        for k, row in enumerate(lines):
            if row.startswith("```"):
                fenced = not fenced and row[3:].strip() not in ("", "sh", "console", "bash")
                continue
            command = _command(row)
            if fenced or command is None:
                continue
            end = k
            while command.endswith("\\") and end + 1 < len(lines):
                end += 1
                command = command[:-1] + " " + lines[end].strip()
            after = _command(lines[end + 1], output=True) if end + 1 < len(lines) else None
            error = after.split("error: ", 1)[1] if after and "error: " in after else None
            found.append(Shown(doc.name, k + 1, command, error))
    return found


def _command(row: str, output: bool = False) -> str | None:
    """The command on a code line, or None (``output``: a line the program printed,
    ``gestc: error: ...``, instead)."""
    found = re.match(r"^(?:    |\s*\$ )((?:gestc|gestplay|gestsim)\b.*)$", row)
    if found is None:
        return None
    is_output = re.match(r"^\w+(?: \w+)?: ", found[1]) is not None
    return found[1].strip() if is_output == output else None


def words(shown: Shown) -> list[str]:
    """The command's words, without its comment and what it pipes into or runs after
    (``&& make``)."""
    return shlex.split(re.split(r" (?:\||&&|;) ", shown.text)[0], comments=True)


def is_synopsis(argv: list[str]) -> bool:
    """A command's form (``FILE [--gesture NAME]``), not a command."""
    return any(w.startswith("[") or w.endswith("...") or "|" in w for w in argv[1:])


def parser_of(argv: list[str]):
    """The parser of the command's (sub)command, as the program builds it."""
    from inmoov_dsl.cli import gestc, gestplay, gestsim

    if argv[0] == "gestsim":
        return gestsim.parser()
    if argv[0] == "gestc":
        return gestc.parser(argv[1] if len(argv) > 1 else None)
    return gestplay.parser(gestplay.playing_by_default(argv[1:])[0] if len(argv) > 1
                           else None)


def tool(argv: list[str]) -> str | None:
    """The subcommand of a gestc or gestplay command (``play`` for a gesture)."""
    from inmoov_dsl.cli import gestplay

    if argv[0] == "gestc":
        return argv[1] if len(argv) > 1 else None
    if argv[0] == "gestplay":
        rest = gestplay.playing_by_default(argv[1:])
        return rest[0] if rest else None
    return None


def runnable(argv: list[str]) -> bool:
    """Can it run here as written: its subcommand one that ends by itself, every port
    virtual, every file it reads in the repository's gestures?"""
    if tool(argv) not in RUNS.get(argv[0], set()) or "--audio" in argv or speaks(argv):
        return False
    ports = [argv[k + 1] for k, w in enumerate(argv[:-1]) if w == "--port"]
    if any(not all(p.split("=")[-1].startswith("sim://") for p in port.split(","))
           for port in ports):
        return False
    files = [w for w in argv if w.endswith((".gest", ".toml")) and "-o" not in argv[
        max(0, argv.index(w) - 1):argv.index(w)]]
    return all((ROOT / f).exists() for f in files)


def speaks(argv: list[str]) -> bool:
    """Does it play a library gesture whose file says something (a sound output needed)?"""
    from inmoov_dsl.language.library import scan

    entry = scan([ROOT / "gestures"]).entries.get(argv[1]) if len(argv) > 1 else None
    return entry is not None and 'say "' in entry.path.read_text(encoding="utf-8")


COMMANDS = shown_commands()


def test_the_docs_show_commands_of_every_program():
    assert {words(c)[0] for c in COMMANDS} == set(PROGRAMS)
    assert sum(runnable(words(c)) for c in COMMANDS) >= 20


@pytest.mark.parametrize("shown", COMMANDS, ids=lambda c: f"{c.doc}:{c.line}")
def test_each_command_is_one_its_program_takes(shown, capsys):
    """Every option and argument of a command (or, for a synopsis, every option it
    names) is one its program's parser takes."""
    argv = words(shown)
    ap = parser_of(argv)
    if is_synopsis(argv):
        known = set(ap._option_string_actions)
        for sub in (a for a in ap._actions if a.choices and isinstance(a.choices, dict)):
            for each in sub.choices.values():
                known |= set(each._option_string_actions)
        named = {w.strip("[]").split("=")[0] for w in argv if w.lstrip("[").startswith("-")}
        assert named <= known, f"{shown.doc}:{shown.line}: {named - known}"
        return
    rest = argv[1:]
    if argv[0] == "gestplay":
        from inmoov_dsl.cli import gestplay

        rest = gestplay.playing_by_default(rest)
    try:
        ap.parse_args(rest)
    except SystemExit as exc:
        pytest.fail(f"{shown.doc}:{shown.line}: {shown.text}\n{capsys.readouterr().err}"
                    f" (exit {exc.code})")


def _run(shown: Shown, where: Path) -> tuple[Shown, subprocess.CompletedProcess]:
    """Run ``shown`` in a folder of its own (the repository's gestures beside it), with
    a state of its own (what the virtual boards remember)."""
    where.mkdir(parents=True)
    (where / "gestures").symlink_to(ROOT / "gestures")
    env = {**os.environ, "XDG_STATE_HOME": str(where / "state"),
           "XDG_CACHE_HOME": str(where / "cache"), "NO_COLOR": "1"}
    argv = words(shown)
    module = {"gestc": "inmoov_dsl.cli.gestc", "gestplay": "inmoov_dsl.cli.gestplay"}
    done = subprocess.run([sys.executable, "-m", module[argv[0]], *argv[1:]], cwd=where,
                          env=env, capture_output=True, text=True, timeout=300,
                          stdin=subprocess.DEVNULL)
    return shown, done


def test_every_command_that_can_run_here_runs_as_written(tmp_path):
    """Run together (most play on the virtual board in real time): each ends as its
    doc says, 0 or the error shown under it."""
    chosen = [c for c in COMMANDS if not is_synopsis(words(c)) and runnable(words(c))]
    with ThreadPoolExecutor(6) as pool:
        ended = list(pool.map(lambda kc: _run(kc[1], tmp_path / str(kc[0])),
                              enumerate(chosen)))
    wrong = []
    for shown, done in ended:
        if shown.error is not None:
            ok = done.returncode != 0 and shown.error[:40] in done.stderr
        else:
            ok = done.returncode == 0
        if not ok:
            wrong.append(f"{shown.doc}:{shown.line}: {shown.text}: exit {done.returncode}\n"
                         f"{done.stderr[-600:]}")
    assert not wrong, "\n".join(wrong)
