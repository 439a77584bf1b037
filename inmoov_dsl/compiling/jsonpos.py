"""Places in a JSON text, for error messages: ``json.loads`` keeps no positions.

Pure scans of the text's tokens, run only when there is an error to point at. A place
is ``(line, column, width)``, line and column counting from 1.
"""

from __future__ import annotations

import re

_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[{}\[\]:,]|[^\s{}\[\]:,"]+')


def locate(text: str, path: tuple) -> tuple[int, int, int]:
    """The place of ``path`` (object keys and list indices) in ``text``: a key's name, a
    list element's value, or the deepest part of the path there is."""
    at, width, found = 0, 1, 0
    keys: list = []  # per open container: its current key or index
    kinds: list[str] = []
    expect_key = False
    for m in _TOKEN.finditer(text):
        tok = m.group()
        if tok == ":":
            continue
        if tok == ",":
            if kinds and kinds[-1] == "[":
                keys[-1] += 1
            else:
                expect_key = True
            continue
        if tok in ("}", "]"):
            if kinds:
                kinds.pop()
                keys.pop()
            expect_key = False
            continue
        if expect_key:
            keys[-1] = tok[1:-1]
            expect_key = False
        depth = len(keys)
        if depth > found and tuple(keys) == path[:depth]:
            at, width, found = m.start(), len(tok), depth
            if depth == len(path):
                break
        if tok in ("{", "["):
            kinds.append(tok)
            keys.append(0 if tok == "[" else None)
            expect_key = tok == "{"
    line, column, _ = position(text, at)
    return line, column, max(1, min(width, 40))


def position(text: str, offset: int) -> tuple[int, int, int]:
    """The place of the character at ``offset`` in ``text``, one character wide."""
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1, 1


def nested_deeper(text: str, depth: int) -> int:
    """The offset where arrays and objects first nest deeper than ``depth`` (0 if they
    never do)."""
    level = 0
    for m in _TOKEN.finditer(text):
        tok = m.group()
        if tok in "{[":
            level += 1
            if level > depth:
                return m.start()
        elif tok in "}]":
            level -= 1
    return 0
