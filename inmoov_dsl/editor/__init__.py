"""The compiler in the editor: ``gestc lsp``, a language server on standard input and
output (pygls). ``analysis`` (what the compiler makes of a text) and the modules that
answer from it are pure; ``server`` is the LSP edge; ``lexer`` highlights gesture code
(Pygments: ``pygmentize -l gest``, ``gestc show``)."""
