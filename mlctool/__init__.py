"""mlctool: check, build and simulate PLC instruction-list programs.

Belongs here: the stages as packages (syntax, check, asm, sim, ladder), the interface to the
targets (targetapi) and the targets themselves (targets/), plant models (devices), the CLI,
and the few modules every stage shares (diagnostics, config, fileio, program ...).
Does not belong here: code for one controller outside its folder; see docs/architecture.md.
"""

__version__ = "0.1.0"
