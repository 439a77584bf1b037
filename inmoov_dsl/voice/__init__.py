"""Sounds for ``say``: a WAV file read into samples (``wav``), text spoken by espeak-ng
(``speak``), and the one way a program hears a ``say`` (``hearing``: where a file is
looked for, what may be spoken, each sound made once)."""
