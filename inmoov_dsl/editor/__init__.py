"""The compiler in the editor: ``gestc lsp``, a language server on standard input and
output (pygls): ``diagnose`` (pure: a text's errors and warnings, as ``gestc check``
tells them) and ``server`` (the LSP edge); and ``lexer``, gesture code highlighted
(Pygments: ``pygmentize -l gest``, ``gestc show``)."""
