"""GX Works2 project files (`.gxw`, FX simple projects) -> the instructions of a program POU.

What is read, each a fact of the public reverse-engineering notes (repository
Arienax/gxworks-agent, commit 8f670605f5843dd681cf6d24acb0f052d03c4926,
docs/process/research/gxw_reverse_engineering.md; docs/formats.md cites the rest):

- the file is a compound file (MS-CFB); its stream `_hdb` is a second compound file holding
  the project's objects as numbered streams. The outer stream `projectdatalist.xml` names
  them (dataset DSPROJECTDATA, rows D_Projectdata: szName the logical name, iID the stream,
  bScrapFlag a deleted row); `history.xml` (DSHISTORY / D_History: iProjectdataID,
  iFileSize, szMD5val = Base64(MD5(stream))) records each object's size and digest. Stream
  numbers differ between projects: a POU is found by its name (`MAIN.Program.pou`), never by
  a number.
- a program POU: a header of 0x4F bytes, the token stream, 24 zero bytes; the u32 at 0x37 and
  again at 0x3B is the token stream's length + 20. Projects saved by GX Works2 in public
  repositories (docs/formats.md, A run over public programs) end in 20 zero bytes with the same
  length fields: the length fields say where the tokens end, and 20 or 24 zero bytes follow.
  Anything else (a structured project's records, another layout) is refused (E917).
- tokens are framed [length payload length]; each instruction is a header token and its
  operand tokens, decoded through the registry mlctool/gxw_tokens.toml (data, each entry
  citing its public source: the notes, the same repository's table of headers harvested from
  GX Works2's conversion DLL, the MC protocol's device codes); a text record (a line statement
  or note) is an Instruction with its text. An unknown token, a bad sentinel, an operand of a
  type the slot does not take is an error with the stream's name and the offset (E918-E921),
  never a guess.
  frames() and decode() serve a GX Developer program body too (mlctool/wpg.py), whose
  instructions are the same tokens: one decoder for both containers.

Device comments (`COMMENT.qcd`) are not read: the notes establish that they live there, not
their record layout. Nothing here writes a project (see docs/formats.md: the notes warn that
the project keeps derived copies, MAIN.res and compiler state, a writer would have to keep
consistent).
"""

from __future__ import annotations

import base64
import dataclasses
import hashlib
import io
import struct
import tomllib
import xml.etree.ElementTree as ET
from functools import cache
from importlib.resources import files

HEADER = 0x4F  # the token stream's offset in a program POU
# Zero bytes after it: 24 in the notes' samples, 20 in projects saved by GX Works2 in public
# repositories (docs/formats.md); the length fields, not the file's size, say where the tokens end.
TRAILERS = (24, 20)
LENGTH_FIELDS = (0x37, 0x3B)  # u32 token length + 20, twice
LENGTH_BIAS = 20
# No GX Works2 project comes near this; a larger file is refused before it is parsed.
MAX_FILE = 64 * 1024 * 1024
_OLE2 = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1"
PROGRAM_SUFFIX = ".Program.pou"


class GxwError(Exception):
    """A project mlctool cannot read: a code of codes.toml, what and where, what to do."""

    def __init__(self, code: str, message: str, *notes: str):
        super().__init__(message)
        self.code, self.message, self.notes = code, message, notes


@dataclasses.dataclass(frozen=True)
class Instruction:
    offset: int  # of the header token in the POU stream
    mnemonic: str  # "" for a line statement or note (`text`)
    operands: tuple[str, ...]  # as FX writes them: X10 (octal), M8000, K-1, H1F
    width: int | None  # the header's stored step count (application, 2-byte headers), None for the others
    text: str | None = None  # a line statement's or note's text (a text record: no instruction, no step)
    note: bool = False  # the text is a note on the instruction before it (else a line statement)
    label: bool = False  # a label (P10:): `operands` holds its pointer


@dataclasses.dataclass(frozen=True)
class Program:
    name: str  # the POU's logical name, MAIN.Program.pou
    stream: str  # its stream in _hdb
    instructions: tuple[Instruction, ...]
    warnings: tuple[tuple[str, str, tuple[str, ...]], ...]  # (code, message, notes)


@dataclasses.dataclass(frozen=True)
class _Slot:
    types: frozenset[int]
    words: int
    numbers: dict[int, tuple[int, int]]  # type byte -> the numbers the slot takes of it (lo, hi)
    digits: frozenset[int]  # the bit devices a digit group [F1 n] may make a word of here (KnM0)
    most_digits: int  # K1-K4 in a 16-bit slot, K1-K8 in a 32-bit one


# a digit group's modifier token [F1 n], before its bit device: Kn of it (the notes' decoder,
# src/gxw/token_pou.py: "digit_group", n 1-8; MOV K4X0 D0 -> 04 F1 04 04 04 9C 00 04)
DIGITS = 0xF1


@dataclasses.dataclass(frozen=True)
class _Form:
    mnemonic: str
    slots: tuple[str, ...]


@dataclasses.dataclass(frozen=True)
class Registry:
    operand: dict[int, dict]  # type byte -> {device, octal, bits}
    slot: dict[str, _Slot]
    basic: dict[int, _Form]  # opcode
    short: dict[bytes, _Form]  # a 2-byte header's payload [opcode steps]
    application: dict[tuple[int, ...], _Form]  # (family, subtype) or (family, subtype, form byte)
    text: dict[bytes, str]  # a text record's first two payload bytes -> "statement" or "note"
    label: dict[bytes, str]  # a label header's payload -> its pointer's slot


@cache
def registry() -> Registry:
    data = tomllib.loads(files("mlctool").joinpath("gxw_tokens.toml").read_text("utf-8"))

    def form(entry: dict) -> _Form:
        return _Form(entry["mnemonic"], tuple(entry["operands"]))

    def key(text: str) -> tuple[int, ...]:
        return tuple(int(b, 16) for b in text.split())

    return Registry(
        operand={int(k, 16): v for k, v in data["operand"].items()},
        slot={k: _Slot(frozenset(int(t, 16) for t in v["types"]), v.get("words", 0),
                       {int(t, 16): (lo, hi) for t, (lo, hi) in v.get("numbers", {}).items()},
                       frozenset(int(t, 16) for t in v.get("digits", ())), 4 * v.get("words", 0))
              for k, v in data["slot"].items()},
        basic={int(k, 16): form(v) for k, v in data["basic"].items()},
        short={bytes(key(k)): form(v) for k, v in data["short"].items()},
        application={key(k): form(v) for k, v in data["application"].items()},
        text={bytes(key(k)): v["kind"] for k, v in data["text"].items()},
        label={bytes(key(k)): v["operand"] for k, v in data["label"].items()},
    )


def is_compound_file(head: bytes) -> bool:
    return head.startswith(_OLE2)


def read_program(data: bytes, program: str | None = None) -> Program:
    """The bytes of a .gxw -> the program POU named (`MAIN`, else the only one), decoded.
    Raises GxwError."""
    if len(data) > MAX_FILE:
        raise GxwError("E915", f"offset 0: {len(data):,} bytes, larger than any GX Works2 project "
                       f"({MAX_FILE // 2**20} MiB are read at most)")
    outer = _open(data, "the file")
    mapping = _mapping(_stream(outer, "projectdatalist.xml", "the file"))
    hdb = _open(_stream(outer, "_hdb", "the file"), "its stream _hdb")
    name = _choose(mapping, program)
    number = mapping[name]
    pou = _stream(hdb, number, f"_hdb (stream {number}, {name})")
    warnings = []
    if _exists(outer, "history.xml"):
        warnings += _history_check(_stream(outer, "history.xml", "the file"), number, name, pou)
    comments = [n for n in mapping if n.lower().endswith(".qcd") and _exists(hdb, mapping[n])]
    if comments:
        warnings.append(("W912", f"the project's device comments ({', '.join(comments)}) are not read: the public "
                         "notes establish where they are, not their record layout",
                         ("export them from GX Works2 as a device-comment CSV and pass it with --comments "
                          "(docs/formats.md)",)))
    where = f"{name} (_hdb stream {number})"
    return Program(name, number, tuple(decode_pou(pou, where)), tuple(warnings))


def _open(data: bytes, what: str):
    """A compound file over bytes; any defect olefile finds is an E915 naming it."""
    import olefile

    if not data.startswith(_OLE2):
        raise GxwError("E915", f"{what}: offset 0: {data[:8].hex(' ') or 'no bytes'} is not the compound-file "
                       "signature d0 cf 11 e0 a1 b1 1a e1", _DAMAGED)
    # GX Works2 may omit the unused tail of the last sector (Arienax/gxworks-agent,
    # src/gxw/container.py's reading of native files): pad it, the stream sizes bound every read
    size = 1 << 9 if len(data) < 512 or data[0x1E] != 12 else 1 << 12
    if len(data) % size:
        data = data + bytes(size - len(data) % size)
    try:
        return olefile.OleFileIO(io.BytesIO(data), raise_defects=olefile.DEFECT_INCORRECT)
    except Exception as e:  # olefile raises OSError, ValueError, IndexError, struct.error ...
        raise GxwError("E915", f"{what}: not a readable compound file: {_said(e)}", _DAMAGED) from None


_DAMAGED = ("a damaged file, or no GX Works2 project; if GX Works2 opens it, write the program to CSV there (Edit > "
            "Write to CSV File) and import that")


def _said(e: Exception) -> str:
    return str(e) or type(e).__name__


def _exists(ole, name: str) -> bool:
    try:
        return bool(ole.exists(name)) and ole.get_type(name) == 2  # a stream
    except Exception:  # a damaged directory
        return False


def _stream(ole, name: str, what: str) -> bytes:
    if not _exists(ole, name):
        raise GxwError("E916", f"{what}: no stream {name!r}: not a GX Works2 project, or a damaged one",
                       "a GX Works2 project holds projectdatalist.xml and _hdb; GX Developer, GX Works3 and "
                       "other OLE2 files are not read (docs/formats.md)")
    try:
        size = ole.get_size(name)
        if size > MAX_FILE:
            raise GxwError("E915", f"{what}: stream {name!r} declares {size:,} bytes, more than a project holds",
                           _DAMAGED)
        data = ole.openstream(name).read()
        _no_loop(ole, name, what)
        return data
    except GxwError:
        raise
    except Exception as e:
        raise GxwError("E915", f"{what}: stream {name!r} cannot be read: {_said(e)}", _DAMAGED) from None


def _no_loop(ole, name: str, what: str) -> None:
    """E915 where a stream's sector chain comes back to a sector it passed ([MS-CFB] 2.3: a
    chain ends in ENDOFCHAIN): olefile reads such a stream with its sectors repeated, bounded
    by the declared size, without a word."""
    entry = ole.root.kids_dict[name.lower()]
    small = entry.size < ole.minisectorcutoff
    table, unit = (ole.minifat, ole.minisectorsize) if small else (ole.fat, ole.sectorsize)
    seen: set[int] = set()
    sector = entry.isectStart
    for _ in range(-(-entry.size // unit)):
        if sector in seen:
            raise GxwError("E915", f"{what}: the {'mini ' if small else ''}sector chain of stream {name!r} loops "
                           f"back to sector {sector}", _DAMAGED)
        seen.add(sector)
        sector = table[sector] if 0 <= sector < len(table) else sector


def _rows(raw: bytes, dataset: str, row: str, what: str) -> list[dict[str, str]]:
    """The current rows of an ADO.NET dataset XML (the dataset is the root or a child of it, as
    under a diffgram, whose `before` copies are no current rows)."""
    if b"<!DOCTYPE" in raw or b"<\x00!\x00D\x00O\x00C\x00" in raw:
        raise GxwError("E916", f"{what}: a DOCTYPE declaration: no GX Works2 metadata has one")
    try:
        root = ET.fromstring(raw)
    except ET.ParseError as e:
        raise GxwError("E916", f"{what}: not well-formed XML: {e}") from None

    def local(el) -> str:
        return el.tag.rsplit("}", 1)[-1] if isinstance(el.tag, str) else ""

    sets = [root] if local(root) == dataset else [c for c in root if local(c) == dataset]
    if len(sets) != 1:
        raise GxwError("E916", f"{what}: {len(sets)} {dataset} datasets, expected one")
    return [{local(f): (f.text or "").strip() for f in r} for r in sets[0] if local(r) == row]


def _mapping(raw: bytes) -> dict[str, str]:
    """projectdatalist.xml -> {logical name: stream name in _hdb}."""
    what = "projectdatalist.xml"
    out: dict[str, str] = {}
    for r in _rows(raw, "DSPROJECTDATA", "D_Projectdata", what):
        if r.get("bScrapFlag", "false").lower() in ("true", "1"):
            continue
        name, number = r.get("szName", ""), r.get("iID", "")
        if not name or not number.isdigit():
            raise GxwError("E916", f"{what}: a D_Projectdata row without szName or a numeric iID ({name!r}, {number!r})")
        if name in out or number in out.values():
            raise GxwError("E916", f"{what}: {name!r} / stream {number} named twice: the mapping is ambiguous")
        out[name] = number
    return out


def _choose(mapping: dict[str, str], program: str | None) -> str:
    programs = sorted(n for n in mapping if n.endswith(PROGRAM_SUFFIX))
    listed = ", ".join(n.removesuffix(PROGRAM_SUFFIX) for n in programs) or "none"
    if program is not None:
        name = program if program.endswith(PROGRAM_SUFFIX) else program + PROGRAM_SUFFIX
        if name not in mapping:
            raise GxwError("E916", f"projectdatalist.xml: no program POU {program!r} (the project's: {listed})")
        return name
    if len(programs) == 1:
        return programs[0]
    if not programs:
        raise GxwError("E916", "projectdatalist.xml names no program POU (*.Program.pou)")
    raise GxwError("E922", f"the project has {len(programs)} program POUs ({listed}); the order in which the CPU "
                   "runs them is set in the project's parameters, which no public note decodes",
                   "import one with --program NAME (each gives its own IL file)")


def _history_check(raw: bytes, number: str, name: str, pou: bytes) -> list[tuple[str, str, tuple[str, ...]]]:
    """W913 where history.xml's size or digest of the POU is not the stream's: changed
    outside GX Works2, or damaged. The stream is read as it is."""
    rows = [r for r in _rows(raw, "DSHISTORY", "D_History", "history.xml") if r.get("iProjectdataID") == number]
    out = []
    for r in rows[:1]:
        size, digest = r.get("iFileSize", ""), r.get("szMD5val", "")
        said = []
        if size.isdigit() and int(size) != len(pou):
            said.append(f"iFileSize {size} where the stream holds {len(pou)} bytes")
        actual = base64.b64encode(hashlib.md5(pou).digest()).decode("ascii")
        if digest and digest != actual:
            said.append(f"szMD5val {digest} where the stream's is {actual}")
        if said:
            out.append(("W913", f"history.xml records {name} (stream {number}) otherwise: {'; '.join(said)}",
                        ("the project was changed outside GX Works2 or is damaged; the stream is read as it is",)))
    return out


def tokens(pou: bytes, where: str) -> list[tuple[int, bytes]]:
    """The POU's token stream -> [(offset, payload)], every frame's sentinels checked."""
    if len(pou) < HEADER + min(TRAILERS):
        raise GxwError("E917", f"{where}: {len(pou)} bytes, shorter than the {HEADER + min(TRAILERS)} of an empty "
                       "program POU's header and trailer", _LAYOUT_NOTE)
    first, again = (struct.unpack_from("<I", pou, at)[0] for at in LENGTH_FIELDS)
    if first != again:
        raise GxwError("E917", f"{where}: offset 0x{LENGTH_FIELDS[0]:X}: length field {first} where the one at "
                       f"0x{LENGTH_FIELDS[1]:X} says {again}", _LAYOUT_NOTE)
    length = first - LENGTH_BIAS
    trailer = len(pou) - HEADER - length
    if trailer not in TRAILERS:
        raise GxwError("E917", f"{where}: offset 0x{LENGTH_FIELDS[0]:X}: length field {first} (a program of "
                       f"{length} token bytes) leaves {trailer} bytes after the tokens, where a program POU has "
                       f"{' or '.join(map(str, TRAILERS))} zero bytes", _LAYOUT_NOTE)
    tail = pou[HEADER + length:]
    if any(tail):
        at = HEADER + length + next(k for k, b in enumerate(tail) if b)
        raise GxwError("E917", f"{where}: offset 0x{at:X}: the {trailer}-byte trailer is not zero", _LAYOUT_NOTE)
    return frames(pou, HEADER, HEADER + length, where)


def frames(data: bytes, start: int, end: int, where: str, least: int = 3) -> list[tuple[int, bytes]]:
    """The frames [length payload length] of data[start:end] -> [(offset, payload)], every
    frame's sentinels checked (E918). `least`: the shortest frame the container holds (3, an
    opcode's; a GX Developer program body's NOP frame `02 02` is 2)."""
    out = []
    at = start
    while at < end:
        n = data[at]
        if n < least:
            raise GxwError("E918", f"{where}: offset 0x{at:X}: token length {n}, the least is {least} "
                           "([length payload length])")
        if at + n > end:
            raise GxwError("E918", f"{where}: offset 0x{at:X}: a token of {n} bytes runs past the token stream's "
                           f"end at 0x{end:X}")
        if data[at + n - 1] != n:
            raise GxwError("E918", f"{where}: offset 0x{at + n - 1:X}: closing sentinel {data[at + n - 1]:#04x} "
                           f"where the token opened at 0x{at:X} says {n:#04x}")
        out.append((at, data[at + 1:at + n - 1]))
        at += n
    return out


_LAYOUT_NOTE = ("the public notes describe a simple project's ladder POU (header 0x4F bytes, token stream, 24 zero "
                "bytes; 20 in public projects); a structured project or another layout is not read: write the program to CSV from GX "
                "Works2 and import that (docs/formats.md)")


def decode_pou(pou: bytes, where: str) -> list[Instruction]:
    toks = tokens(pou, where)
    out, rest = decode(toks, where, HEADER)
    if rest < len(toks):
        raise GxwError("E921", f"{where}: offset 0x{toks[rest][0]:X}: tokens after END ({len(toks) - rest} of them)")
    return out


def decode(toks: list[tuple[int, bytes]], where: str, start: int, nop: bool = False
           ) -> tuple[list[Instruction], int]:
    """Tokens (of a GX Works2 POU or a GX Developer program body) -> the instructions up to END
    and the index of the first token after it: each instruction a header token and its operand
    tokens, decoded through the registry. `nop`: an empty frame is a NOP (a GX Developer
    program body's). E919/E920 for what the registry does not establish, E921 without END
    (`start`: the offset the tokens begin at, for an empty stream)."""
    reg = registry()
    out: list[Instruction] = []
    k = 0
    while k < len(toks):
        at, payload = toks[k]
        if nop and not payload:
            out.append(Instruction(at, "NOP", (), None))
            k += 1
            continue
        if payload[:2] in reg.text and len(payload) > 2:
            out.append(Instruction(at, "", (), None, _text(payload[2:]), note=reg.text[payload[:2]] == "note"))
            k += 1
            continue
        if payload in reg.label:
            if k + 1 >= len(toks):
                raise GxwError("E920", f"{where}: offset 0x{at:X}: a label lacks its pointer: the token stream ends")
            slot = reg.label[payload]
            pointer = _operand(reg, toks[k + 1], reg.slot[slot], slot, "a label", where)
            out.append(Instruction(at, "", (pointer,), None, label=True))
            k += 2
            continue
        form, width = _header(reg, at, payload, where)
        operands = []
        j = k + 1  # the next operand token
        for n, slot_name in enumerate(form.slots, 1):
            slot = reg.slot[slot_name]
            if j >= len(toks):
                raise GxwError("E920", f"{where}: offset 0x{at:X}: {form.mnemonic} lacks its operand {n} of "
                               f"{len(form.slots)}: the token stream ends")
            group = toks[j][1]
            if group and group[0] == DIGITS and slot.digits:  # [F1 n] then its bit device: KnM0
                operands.append(_digit_group(reg, toks, j, slot, slot_name, form.mnemonic, where))
                j += 2
                continue
            operands.append(_operand(reg, toks[j], slot, slot_name, form.mnemonic, where))
            j += 1
        if width is not None and len(payload) >= 3:  # an application header (a 2-byte one: its steps)
            words = sum(reg.slot[s].words for s in form.slots)
            if width != 1 + 2 * words:
                raise GxwError("E919", f"{where}: offset 0x{at:X}: {form.mnemonic} header width {width}, where its "
                               f"{words} word slots give {1 + 2 * words} (width = 1 + 2 x word slots)")
        out.append(Instruction(at, form.mnemonic, tuple(operands), width))
        k = j
        if form.mnemonic == "END":
            return out, k
    end = toks[-1][0] if toks else start
    raise GxwError("E921", f"{where}: offset 0x{end:X}: the program does not end with END")


def _text(raw: bytes) -> str:
    """A text record's bytes -> the text. DECISION: the body does not say its code page (the
    public texts are ASCII but for two Latin-1 words), so a byte outside printable ASCII is
    written as \\xNN: kept, never guessed."""
    return "".join(chr(b) if 0x20 <= b < 0x7F and b != 0x5C else f"\\x{b:02X}" for b in raw)


def _header(reg: Registry, at: int, payload: bytes, where: str) -> tuple[_Form, int | None]:
    if len(payload) == 1 and payload[0] in reg.basic:
        return reg.basic[payload[0]], None
    if payload in reg.short:
        return reg.short[payload], payload[1]
    if len(payload) in (3, 4) and (payload[0], *payload[2:]) in reg.application:
        return reg.application[payload[0], *payload[2:]], payload[1]
    shown = payload.hex(" ").upper()
    if len(payload) == 1:
        why = f"basic instruction opcode {payload[0]:02X}, not one the public sources establish"
    elif len(payload) == 2 and payload[0] < 0x80:
        why = f"instruction {payload[0]:02X} of {payload[1]} steps, not a form the public sources establish"
    elif len(payload) in (3, 4) and any(f[0] == payload[0] for f in reg.application):
        why = (f"application family {payload[0]:02X} subtype {payload[2]:02X}"
               + (f" form {payload[3]:02X}" if len(payload) == 4 else "") + ", not one the public sources establish")
    elif payload and payload[0] in reg.operand:
        why = "an operand where an instruction was expected"
    else:
        why = "no instruction token the public sources establish"
    raise GxwError("E919", f"{where}: offset 0x{at:X}: token [{shown}]: {why}",
                   "mlctool decodes the instructions of mlctool/gxw_tokens.toml only; write the program to CSV "
                   "from GX Works2 and import that (docs/formats.md)")


def _operand(reg: Registry, token: tuple[int, bytes], slot: _Slot, slot_name: str, mnemonic: str,
             where: str) -> str:
    at, payload = token
    kind = reg.operand.get(payload[0]) if payload else None
    if kind is None or payload[0] not in slot.types:
        taken = ", ".join(dict.fromkeys(_type_name(reg, t) for t in sorted(slot.types)))
        got = f"type {payload[0]:02X}" + (f" ({_type_name(reg, payload[0])})" if kind else "") if payload else "empty"
        raise GxwError("E920", f"{where}: offset 0x{at:X}: {mnemonic}'s {slot_name.replace('_', '/')} operand is {got}; "
                       f"the registry takes {taken} there")
    value = payload[1:]
    limit = kind.get("bits", 32) // 8
    if not 1 <= len(value) <= limit:
        raise GxwError("E920", f"{where}: offset 0x{at:X}: {kind['device']} operand of {len(value)} value bytes "
                       f"(1 to {limit})")
    number = int.from_bytes(value, "little")
    device = kind["device"]
    lo, hi = slot.numbers.get(payload[0], (0, number))
    if not lo <= number <= hi:
        raise GxwError("E920", f"{where}: offset 0x{at:X}: {mnemonic} {device}{number}: the registry takes "
                       f"{device}{lo}-{device}{hi} in its {slot_name.replace('_', '/')} operand")
    if device == "K":
        if len(value) == limit and number >> (8 * limit - 1):
            number -= 1 << (8 * limit)  # full width: two's complement
        return f"K{number}"
    if device == "H":
        return f"H{number:X}"
    return f"{device}{number:o}" if kind.get("octal") else f"{device}{number}"


def _digit_group(reg: Registry, toks: list[tuple[int, bytes]], j: int, slot: _Slot, slot_name: str, mnemonic: str,
                 where: str) -> str:
    """A digit group [F1 n] [bit device] in a word slot -> KnM0 (n digits of 4 bits from the device)."""
    at, payload = toks[j]
    if len(payload) != 2 or not 1 <= payload[1] <= slot.most_digits:
        raise GxwError("E920", f"{where}: offset 0x{at:X}: {mnemonic}'s digit group {payload[1:].hex(' ') or 'empty'}: "
                       f"K1-K{slot.most_digits} in its {slot_name.replace('_', '/')} operand")
    if j + 1 >= len(toks):
        raise GxwError("E920", f"{where}: offset 0x{at:X}: {mnemonic}'s digit group lacks its device: the token "
                       "stream ends")
    bits = _Slot(slot.digits, 0, {}, frozenset(), 0)
    return f"K{payload[1]}{_operand(reg, toks[j + 1], bits, slot_name, mnemonic, where)}"


def _type_name(reg: Registry, t: int) -> str:
    kind = reg.operand.get(t)
    if kind is None:
        return f"{t:02X}"
    return f"{kind['device']}{kind['bits']}" if kind["device"] == "K" else kind["device"]
