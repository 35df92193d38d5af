"""`mlc lsp`: a language server over stdio (pygls), a thin front end over the library.

Belongs here: the editor's view of a project (project.py: which mlc.toml a file belongs to,
the open buffers checked together with the project's other sources, an index of symbols,
labels and their uses), the features as plain functions of that view (features.py: hover,
completion, definition, references, rename, symbols, formatting, code actions) and the pygls
wiring (server.py). The checking itself is mlctool.check, the formatter mlctool.fmt,
the manual tables mlctool.targetapi.

Does not belong here: deciding what a program means (rules, tables, layout), any one
editor's settings (editors/vscode/).
"""
