"""The compiler in the editor: ``gestc lsp``, a language server on standard input and
output (pygls). ``analysis`` (what the compiler makes of a text) and the modules that
answer from it are pure, ``lines`` the one rule for lines and columns; the edges are
``server`` (the requests), ``documents`` (the state), ``protocol`` (pygls's protocol as
the LSP wants it) and ``worker`` (the thread that analyses and answers); ``lexer``
highlights gesture code (Pygments: ``pygmentize -l gest``, ``gestc show``)."""
