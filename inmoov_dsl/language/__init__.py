"""The language: the syntax tree (``syntax``), parsing a text and wording its errors
(``parse``, ``indent``, ``parse_errors``), a program and its loading with ``use``
(``program``, ``load``), a typed line (``snippet``), the canonical layout (``fmt``) and
the gesture library along its search path (``library``). Nothing here knows a
profile."""
