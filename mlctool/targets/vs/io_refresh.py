"""I/O refresh (manual 6-7 FNC 50 REF, 51 REFF).

A scan is instantaneous at its start time: its inputs are read from the stimulus before it
and its outputs seen after it, so in the main program REF finds the image already current and
changes nothing. Inside an interrupt routine, served at its request's time between scans
(2-12, 2-15), REF X0/X10 n reads the levels the stimulus gives at that time into the image
and REF Y0 n puts the outputs out then (targets/vs/interrupts.py, docs/vs.md "Interrupts").
DECISION: REFF (input filter time n ms) changes no device value (pulse trains are counted
exactly); it is accepted, and its n is checked against the page's 0-60.
"""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine
from mlctool.targets.vs.common import op_error, special


@base._on
def ref(m: Machine, s) -> None:
    """REF D n: in a routine between scans, X read / Y put out at the request's time; in the
    main program the image is already current (nothing to do)."""
    ctl = m.interrupts
    if ctl is None or not ctl.active:
        return
    d, n_ref = s.ops
    n = n_ref.get(m)
    first = d.addr(m, n)
    if d.kind == "X":
        ctl.refresh_inputs(m, first, n)
    else:
        ctl.refresh_outputs(m, first, n)


@base._on
def reff(m: Machine, s) -> None:
    """REFF n: the X0-X7 filter time, n ms, goes to D9020 (the register that sets it, 10 at
    power-on: 6-7 FNC 51's figure). Pulse trains are counted exactly, so the time itself has
    no effect on the simulation."""
    n = s.ops[0].get(m)
    if not 0 <= n <= 60:
        op_error(m, s, f"n = {n} is outside 0-60 ms")
        return
    register = special(m, "input_filter")
    if register is not None:
        m.words["D"][register] = n
        m.writer[("D", register)] = m.pc


IO_REFRESH_ACTIONS = {"ref": ref, "reff": reff}
