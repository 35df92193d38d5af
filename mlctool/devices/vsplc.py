"""A peer Vigor VS PLC on a serial port of the simulated one, for LINK (6-10 FNC 89, a
"VS Computer Link Slave", 7-3-3) and CPUL (FNC 87, a CPU Link station, 7-3-7):

    model vsplc link=CP1 station=2 [baud=19200] [reply=10ms]

No program runs in it: its devices are memory (targets/vs/serial/peers.py) that the stimulus sets and
checks as `CP1#2.D10`, `CP1#2.M5`. Line settings 8N1 at `baud` (7-3-3: 8 bits, no parity,
1 stop bit); a port set otherwise (the stimulus `port` line) does not reach it. `reply`: how
long after a LINK request arrives the answer starts (DECISION: 10 ms, one scan of the peer,
as LINK traffic follows the scans, 6-10 CPUL page; the manual gives no figure).
"""

from __future__ import annotations

from mlctool.devices.base import DeviceModel, ModelIO, ParamError
from mlctool.limits import is_decimal
from mlctool.sim.hardware.seriallink import PORT_NAMES, LineSettings
from mlctool.sim.stimulus.serial_stim import BAUDS
from mlctool.targetapi.model import Target


class VsPlc(DeviceModel):
    kind = "vsplc"

    def __init__(self, params: dict[str, str], target: Target):
        super().__init__(params, target)
        self.port = self._param("link", None).upper()
        if self.port not in PORT_NAMES:
            raise ParamError("link", f"link takes {', '.join(PORT_NAMES)}, not {self.port!r}")
        text = self._param("station", None)
        if not is_decimal(text) or not 0 <= int(text) <= 254:
            raise ParamError("station", f"station takes 0-254 (6-10 LINK/CPUL), not {text!r}")
        self.station = int(text)
        baud = self._param("baud", "19200")
        if not is_decimal(baud) or int(baud) not in BAUDS:
            raise ParamError("baud", f"baud takes one of {', '.join(map(str, BAUDS))} (7-3-3), not {baud!r}")
        self.settings = LineSettings(int(baud))
        self.reply_us = self.time("reply", "10ms")
        self.check_unused()

    def step(self, io: ModelIO, t_us: int, period_us: int) -> None:
        port = io.serial_port(self.port)
        port.attach(id(self), self.settings, None)
        port.stations.setdefault(self.station, {})[id(self)] = self  # two with one number collide

    def answers(self, port) -> bool:
        """The peer hears the PLC (same line settings)."""
        return port.hears(id(self))
