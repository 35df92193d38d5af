"""GX Developer program bodies (`.wpg`, FX CPUs) -> the instructions of the program.

No public description of the file was found (docs/formats.md). What is read is the layout the
public GX Developer projects show (docs/formats.md, "GX Developer program bodies": their
repositories and commits), each part checked, and the instruction tokens of a GX Works2
program POU, which the body holds unchanged and which mlctool/gxw.py decodes through its
registry (each entry citing its public source): one decoder for both containers.

- 0x00: u16 0x0040, the header's length (the program's frames start 4 bytes after it), then
  22 01: together the signature checked (E932);
- 0x26: u16, the CPU type: the number the project's Gppw.gps stores as lCpuType, whose name
  its Gppw.gpj gives as CpuType; the FX CPUs are read (mlctool/gxdeveloper.py, the table the
  comment reader uses too), another is refused (E933), never read as FX;
- the rest of the header (a 32-byte title of spaces at 0x04, bytes not identified, FF fill) is
  not read;
- 0x40: 04 00 FF FF (every public body; E932 otherwise), then the program's frames
  [length payload length] to the file's end: the instructions up to END, then `02 02`
  frames (an empty payload), one per unused step of the program memory: a program of S
  steps in a memory of C steps is followed by C - S of them (each of the 105 public FX bodies:
  2,000, 8,000, 16,000 or 64,000 steps; docs/formats.md). An empty frame within the program is a NOP too (DECISION: the same frame,
  the same step). Anything after END that is not an empty frame is E921, as in a POU.

Nothing here writes a body (no `mlc export --to wpg`): the project around it (Gppw.gpj, the
parameters, the comments) is not described, and GX Works2 reads the CSV mlc export writes.
"""

from __future__ import annotations

import dataclasses

from mlctool.gxdeveloper import CPU_AT, FX_CPUS, HEADER, SIGNATURE, cpu_type
from mlctool.gxw import GxwError, Instruction, decode, frames

BODY_MARK = b"\x04\x00\xff\xff"  # at HEADER, before the first frame
TOKENS = HEADER + len(BODY_MARK)
NOP_FRAME = 2  # `02 02`: an empty payload
# the program memory sizes of FX CPUs, in steps: the NOP fill makes the program this long
CAPACITIES = (2000, 4000, 8000, 16000, 32000, 64000)
# No program body comes near this (64,000 steps of the longest tokens); a larger file is refused unread.
MAX_FILE = 4 * 1024 * 1024

# CPUs of other series seen in public bodies: their programs are no FX programs (hexadecimal
# X/Y, M9000/D9000 or SM/SD specials, other step counts).
OTHER_CPUS = {
    0x0092: ("Q06UDEH (MELSEC-Q)", "HellerkoreaCSCho/PLC_PCO520L2 c96dfa3 (Gppw.gpj CpuType \"Q06UDEH\", Gppw.gps "
             "lCpuType 146)"),
    0x0106: ("A1N (MELSEC-A)", "autoinst578/Canvas_Cleaner-PLC 6609c03 (Gppw.gpj CpuType \"A1N\", Gppw.gps lCpuType "
             "262)"),
    0x010A: ("A3N (MELSEC-A)", "autoinst578/Winder_MHI-PLC defce74 (Gppw.gpj CpuType \"A3N\", Gppw.gps lCpuType 266)"),
}


@dataclasses.dataclass(frozen=True)
class Program:
    cpu: str  # the CPU's name (gxdeveloper.FX_CPUS)
    instructions: tuple[Instruction, ...]  # END last; an empty frame within the program is a NOP
    fill: int  # the empty frames after END: the program memory's unused steps
    fill_offset: int  # of the first of them (the file's end if none)


_NOT_READ = ("write the program as CSV from GX Developer (or open the project in GX Works2 and write it to CSV) "
             "and import that (docs/formats.md)")


def read_program(data: bytes, where: str = "the program body") -> Program:
    """The bytes of a .wpg -> its program, decoded. Raises GxwError (E918-E921 as for a GX
    Works2 POU; E932 the layout, E933 the CPU)."""
    if len(data) > MAX_FILE:
        raise GxwError("E932", f"{where}: offset 0: {len(data):,} bytes, larger than any GX Developer program body "
                       f"({MAX_FILE // 2**20} MiB are read at most)")
    if not data:
        raise GxwError("E932", f"{where}: offset 0: an empty file, no GX Developer program body", _NOT_READ)
    if len(data) < TOKENS:
        raise GxwError("E932", f"{where}: offset 0x{len(data):X}: the file ends inside the 0x{TOKENS:X}-byte header",
                       _NOT_READ)
    if data[:len(SIGNATURE)] != SIGNATURE:
        raise GxwError("E932", f"{where}: offset 0: {data[:4].hex(' ')} where a GX Developer program body starts "
                       f"{SIGNATURE.hex(' ')} (u16 0x0040, the header's length, then 22 01)", _NOT_READ)
    cpu = cpu_type(data)
    if cpu not in FX_CPUS:
        name = OTHER_CPUS.get(cpu, ("", ""))[0]
        said = (f"a program for the {name}, no FX CPU: its X/Y are hexadecimal, its specials and step counts "
                "another series'" if name else
                f"no FX CPU (FX: 0x0201-0x020A, {FX_CPUS[0x0201]} to {FX_CPUS[0x020A]})")
        raise GxwError("E933", f"{where}: offset 0x{CPU_AT:X}: CPU type 0x{cpu:04X}: {said}",
                       "rewrite the program for the target" if name else
                       "if GX Developer names an FX CPU for it, " + _NOT_READ)
    if data[HEADER:TOKENS] != BODY_MARK:
        raise GxwError("E932", f"{where}: offset 0x{HEADER:X}: {data[HEADER:TOKENS].hex(' ')} where every GX "
                       f"Developer program body has {BODY_MARK.hex(' ')} before its first frame", _NOT_READ)
    toks = frames(data, TOKENS, len(data), where, least=NOP_FRAME)
    instructions, rest = decode(toks, where, TOKENS, nop=True)
    for at, payload in toks[rest:]:
        if payload:
            raise GxwError("E921", f"{where}: offset 0x{at:X}: token [{payload.hex(' ').upper()}] after END, where "
                           "only the empty frames 02 02 of the unused program memory follow it")
    fill_offset = toks[rest][0] if rest < len(toks) else len(data)
    return Program(FX_CPUS[cpu], tuple(instructions), len(toks) - rest, fill_offset)

