"""The compiled engines: a program's steps generated as Python functions (compile.py with
compile_layout.py, compile_ops.py, codegen.py; compiled in parts by pycompile.py), run on
the Machine by the Scanner (engine.py, with the reference interpreter of scan.py as its
fallback), kept on disk between runs (codecache.py), and built into a C extension by Cython
(native.py).

Belongs here: generating, compiling, caching and running a program's code on one Machine,
with the interpreter's semantics exactly (tools/dump_compiled.py prints what is generated).
Imports the machine only. Does not belong here: the semantics themselves (semantics.py,
scan.py), stimulus and runs (stimulus/, run/), the batch lanes (campaign/: they run many
scenarios and read the run's results).
"""
