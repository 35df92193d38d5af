"""Reading source text: files and encodings (source.py), the IL grammar and parsers
(parser.py, lark_parser.py, statements.py), operand syntax (operands.py).

Belongs here: what can be said about a text without a target's instruction table.
Does not belong here: anything that knows a target's instructions (check/), formatting
(mlctool/fmt.py reads labels through the checker).
"""
