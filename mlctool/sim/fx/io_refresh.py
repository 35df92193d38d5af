"""I/O refresh (manual 6-7 FNC 50 REF, 51 REFF).

In the simulator every input is read from the stimulus before a scan and every output is
seen after it; there is no hardware image to refresh in mid-scan. DECISION: REF (refresh n
of X/Y from D in mid-scan) and REFF (input filter time n ms) change no device value; they
are accepted (never refused with E905), and REFF's n is checked against the page's 0-60.
"""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.fx.common import op_error
from mlctool.sim.state import Machine


@base._on
def ref(m: Machine, s) -> None:
    """REF D n: the inputs/outputs are already current at the scan level: nothing to do."""


@base._on
def reff(m: Machine, s) -> None:
    """REFF n: the input filter time; pulse trains are counted exactly, so it has no effect."""
    n = s.ops[0].get(m)
    if not 0 <= n <= 60:
        op_error(m, s, f"n = {n} is outside 0-60 ms")


IO_REFRESH_ACTIONS = {"ref": ref, "reff": reff}
