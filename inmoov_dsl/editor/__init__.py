"""The compiler in the editor: ``gestc lsp``, a language server on standard input and
output (pygls). ``analysis`` (what the compiler makes of a text) and the modules that
answer from it are pure, ``lines`` the one rule for lines and columns; the edges are
``server`` (the requests), ``documents`` (the state), ``protocol`` (pygls's protocol as
the LSP wants it), ``worker`` (the thread that analyses and answers) and
``preview_feed`` (the live preview page, fed from the analyses and the cursor: its view
``preview_view``, its robot button ``preview_play``); ``lexer``
highlights gesture code (Pygments: ``pygmentize -l gest``, ``gestc show``)."""
