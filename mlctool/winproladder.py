"""FATEK WinProladder files: a project (`.pdw`) or a ladder resource (`.ldr`) -> the program's
words decoded; and a program's words written into a project saved by WinProladder.

What is read, each a fact of the public reverse-engineering notes of the repository
pormauro/PLC-Tools, FATEK/WinProLadder/docs/ (docs/formats.md cites each page and commit):

- `.pdw`: ASCII "Fatek WinProladder, File Format 1" at 0, the PLC model at 0xA0. From 0x120,
  32 records of 1,280 bytes hold the 20K-word program memory, each XOR-ed with the same
  transform; a record of erased memory (0xFF) gives it, so a record decodes as
  `record ^ erased_record ^ 0xFF` (FORMAT_PDW.md). The image holds "FBS40003" at 2 and
  55 AA at 0x1FE; the program's words start at 0x202; n (their count) at 0x108, 0x4EFF - n
  at 0x10A, 0x202 + 2n at 0x10E and again at 0x110, (sum of the words - 1) & 0xFFFF at 0xCC,
  the byte (0x23 + 4n) & 0xFF at 0xCA (PROGRAM_MEMORY.md). Bytes 0-1 of the image change on
  every save; 0xCB and 0x103 are not identified.
- `.ldr`: ASCII "Fatek Resource File Format 1" at 0; from 0x100 one record per network,
  `12 10, u16 code_len + 5, u16 code_len, code, 5 trailer bytes`, the last network first,
  then FF FF 00 00 00 00 (FORMAT_LDR.md). The networks' code, first to last, is the .pdw's
  program.
- The words: the registry mlctool/winproladder_words.toml (data, each entry citing its
  fixture). Any other word, a device number the notes did not observe, a broken field is an
  error with its offset (E923-E928), never a guess.

The writer is the notes' template-preserving one (MINIMAL_WRITER_VALIDATION.md: its files
opened and passed WinProladder's syntax check): the program's words and the fields that follow
from them go into the image of a project WinProladder saved, the rest of that project is kept
byte for byte. A file made from nothing would lack the project's other resources, which no
note decodes.
"""

from __future__ import annotations

import dataclasses
import re
import tomllib
from functools import cache
from importlib.resources import files

PDW_MAGIC = b"Fatek WinProladder, File Format 1"
LDR_MAGIC = b"Fatek Resource File Format 1"
MODEL_AT = 0xA0
MODEL_SEEN = "FBs-24MC"  # the model of every fixture of the notes
PDW_SIZE_SEEN = 98_871  # the size of every .pdw fixture of the notes
IMAGE_AT, RECORD, RECORDS = 0x120, 1280, 32
IMAGE = RECORD * RECORDS  # 40,960 bytes: 20K words
SIGNATURE_AT, SIGNATURE = 2, b"FBS40003"
MARK_AT, MARK = 0x1FE, b"\x55\xaa"
CODE_AT = 0x202
COUNT_AT, COMPLEMENT_AT, COMPLEMENT_BASE = 0x108, 0x10A, 0x4EFF
END_AT = (0x10E, 0x110)
CHECKSUM_AT, LENGTH_BYTE_AT = 0xCC, 0xCA
MAX_WORDS = COMPLEMENT_BASE  # 0x202 + 2 x 0x4EFF fills the image to its last byte
# the notes' writer stops here: past it (0x23 + 4n) overflows into 0xCB, which is not identified
WRITE_MAX_WORDS = 55
LDR_PAYLOAD_AT, LDR_RECORD_MAGIC, LDR_TRAILER = 0x100, b"\x12\x10", 5
LDR_END = b"\xff\xff\x00\x00\x00\x00"
# No project comes near this (every fixture is 98,871 bytes); a larger file is refused unread.
MAX_FILE = 16 * 1024 * 1024


class FatekError(Exception):
    """A file mlctool cannot read: a code of codes.toml, what and where, what to do."""

    def __init__(self, code: str, message: str, *notes: str):
        super().__init__(message)
        self.code, self.message, self.notes = code, message, notes


@dataclasses.dataclass(frozen=True)
class Item:
    """One decoded form: its words, where they are, what FATEK calls it, the fbs instruction."""

    index: int  # of its first word in the program (a step address of target fbs)
    offset: int  # of its first word in the file
    words: tuple[int, ...]
    fatek: str  # ORG X1, SET M4, timer T0 ... PV 10
    il: str  # the fbs mnemonic; "" none (why says why); ";" no instruction (an empty network)
    operand: str  # X1, M4, or ""
    why: str = ""


@dataclasses.dataclass(frozen=True)
class Program:
    kind: str  # "pdw" or "ldr"
    model: str
    items: tuple[Item, ...]
    warnings: tuple[tuple[str, str], ...]  # (code, message)


@dataclasses.dataclass(frozen=True)
class _Family:
    name: str
    base: int
    lo: int
    hi: int


@dataclasses.dataclass(frozen=True)
class Registry:
    family: dict[str, _Family]
    single: dict[int, dict]  # low byte -> entry
    fixed: dict[int, dict]
    edge: dict[int, dict]
    function: dict[int, dict]
    block: dict[int, dict]
    block_why: dict[str, str]


@cache
def registry() -> Registry:
    data = tomllib.loads(files("mlctool").joinpath("winproladder_words.toml").read_text("utf-8"))

    def hexed(table: dict) -> dict[int, dict]:
        return {int(k, 16): v for k, v in table.items()}

    return Registry(
        family={k: _Family(k, v["base"], *v["observed"]) for k, v in data["family"].items()},
        single=hexed(data["single"]), fixed=hexed(data["fixed"]), edge=hexed(data["edge"]),
        function=hexed(data["function"]), block=hexed(data["block"]), block_why=data["block_why"])


def kind_of(head: bytes) -> str | None:
    """"pdw" / "ldr" for a file starting with WinProladder's signature, else None."""
    if head.startswith(PDW_MAGIC):
        return "pdw"
    if head.startswith(LDR_MAGIC):
        return "ldr"
    return None


def read(data: bytes, suffix: str = "") -> Program:
    """The bytes of a .pdw or .ldr -> its program decoded. Raises FatekError."""
    if len(data) > MAX_FILE:
        raise FatekError("E923", f"offset 0: {len(data):,} bytes, larger than any WinProladder file "
                         f"({MAX_FILE // 2**20} MiB are read at most)")
    kind = kind_of(data) or suffix.lower().lstrip(".")
    magic = PDW_MAGIC if kind == "pdw" else LDR_MAGIC
    if not data.startswith(magic):
        shown = data[:len(magic)].decode("latin-1").encode("unicode_escape").decode("ascii")
        raise FatekError("E923", f"offset 0: {shown!r} where a WinProladder {'project' if kind == 'pdw' else 'ladder resource'} "
                         f"starts with {magic.decode('ascii')!r}", _NOT_FATEK)
    if kind == "pdw":
        return read_pdw(data)
    return read_ldr(data)


_NOT_FATEK = ("a damaged file, or no WinProladder project; if WinProladder opens it, export the ladder as text "
              "there and import that (docs/formats.md)")


def _model(data: bytes) -> tuple[str, list[tuple[str, str]]]:
    raw = data[MODEL_AT:MODEL_AT + 16].split(b"\0", 1)[0]
    model = raw.decode("latin-1").strip()
    if model == MODEL_SEEN:
        return model, []
    return model, [("W915", f"offset 0x{MODEL_AT:X}: PLC model {model!r}; the public notes decode the files of an "
                     f"{MODEL_SEEN} only: read as one")]


def image(data: bytes) -> tuple[bytes, int]:
    """A .pdw's program memory image (40,960 bytes) and the key each record is XOR-ed with
    (as an integer of RECORD bytes, little-endian), which the last record, erased memory,
    gives (a program reaching it cannot be decoded, E924). Raises FatekError."""
    if len(data) < IMAGE_AT + IMAGE:
        raise FatekError("E923", f"offset 0x{len(data):X}: the file ends there; a project holds its program memory "
                         f"at 0x{IMAGE_AT:X}-0x{IMAGE_AT + IMAGE - 1:X}", _NOT_FATEK)
    erased = data[IMAGE_AT + IMAGE - RECORD:IMAGE_AT + IMAGE]
    key = int.from_bytes(erased, "little") ^ int.from_bytes(b"\xff" * RECORD, "little")
    out = bytearray()
    for k in range(RECORDS):
        record = data[IMAGE_AT + k * RECORD:IMAGE_AT + (k + 1) * RECORD]
        out += (int.from_bytes(record, "little") ^ key).to_bytes(RECORD, "little")
    return bytes(out), key


def _u16(buf: bytes, at: int) -> int:
    return buf[at] | buf[at + 1] << 8


def program_words(img: bytes) -> list[int]:
    """The image's program words, every field that depends on them checked (E924, E925)."""
    where = f"offset 0x{IMAGE_AT + SIGNATURE_AT:X}"
    if img[SIGNATURE_AT:SIGNATURE_AT + len(SIGNATURE)] != SIGNATURE or img[MARK_AT:MARK_AT + 2] != MARK:
        raise FatekError("E924", f"{where}: the program memory decodes to {img[SIGNATURE_AT:SIGNATURE_AT + 8]!r} ... "
                         f"{img[MARK_AT:MARK_AT + 2].hex(' ')} at 0x{IMAGE_AT + MARK_AT:X}, not {SIGNATURE!r} ... 55 aa: "
                         "another PLC's or another version's layout, or a damaged file", _NOT_FATEK)
    n = _u16(img, COUNT_AT)
    field = f"program memory offset 0x{IMAGE_AT:X} + "

    def bad(at: int, what: str, found: int, expected: int) -> FatekError:
        return FatekError("E925", f"offset 0x{IMAGE_AT + at:X} ({field}0x{at:X}): {what} is 0x{found:04X} where "
                          f"{n} program words give 0x{expected:04X}", "a damaged file, or one changed by another tool")

    if n > MAX_WORDS:
        raise FatekError("E925", f"offset 0x{IMAGE_AT + COUNT_AT:X}: {n} program words, more than the {MAX_WORDS} the "
                         "program memory holds", "a damaged file")
    if _u16(img, COMPLEMENT_AT) != COMPLEMENT_BASE - n:
        raise bad(COMPLEMENT_AT, "the free-word count", _u16(img, COMPLEMENT_AT), COMPLEMENT_BASE - n)
    end = CODE_AT + 2 * n
    for at in END_AT:
        if _u16(img, at) != end:
            raise bad(at, "the end of the program", _u16(img, at), end)
    if end > IMAGE - RECORD:
        raise FatekError("E924", f"offset 0x{IMAGE_AT + COUNT_AT:X}: {n} program words reach the last record of the "
                         "program memory, which the notes' method needs erased to decode the others")
    words = [_u16(img, CODE_AT + 2 * k) for k in range(n)]
    total = (sum(words) - 1) & 0xFFFF
    if _u16(img, CHECKSUM_AT) != total:
        raise bad(CHECKSUM_AT, "the checksum", _u16(img, CHECKSUM_AT), total)
    if img[LENGTH_BYTE_AT] != (0x23 + 4 * n) & 0xFF:
        raise bad(LENGTH_BYTE_AT, "the length byte", img[LENGTH_BYTE_AT], (0x23 + 4 * n) & 0xFF)
    rest = img[end:]
    if rest.count(0xFF) != len(rest):
        at = end + next(k for k, b in enumerate(rest) if b != 0xFF)
        raise FatekError("E924", f"offset 0x{IMAGE_AT + at:X}: program memory after the program's {n} words is not "
                         "erased (0xFF): content the notes do not describe, or a damaged file")
    return words


def read_pdw(data: bytes) -> Program:
    model, warnings = _model(data)
    if len(data) != PDW_SIZE_SEEN:
        warnings.append(("W914", f"the file has {len(data):,} bytes, every project of the public notes "
                         f"{PDW_SIZE_SEEN:,}: only its program memory is read"))
    words = program_words(image(data)[0])
    placed = [(IMAGE_AT + CODE_AT + 2 * k, w) for k, w in enumerate(words)]
    return Program("pdw", model, tuple(decode(placed)), tuple(warnings))


def read_ldr(data: bytes) -> Program:
    model, warnings = _model(data)
    networks: list[list[tuple[int, int]]] = []
    at = LDR_PAYLOAD_AT
    while True:
        if data[at:] == LDR_END:
            break
        head = data[at:at + 6]
        if len(head) < 6 or head[:2] != LDR_RECORD_MAGIC:
            if data[at:at + 6] == LDR_END:
                raise FatekError("E929", f"offset 0x{at + 6:X}: {len(data) - at - 6} bytes after the end mark "
                                 "FF FF 00 00 00 00")
            raise FatekError("E929", f"offset 0x{at:X}: {head.hex(' ') or 'the end of the file'} where a network "
                             "record (12 10 ...) or the end mark (FF FF 00 00 00 00) is", _NOT_FATEK)
        envelope, size = _u16(head, 2), _u16(head, 4)
        if envelope != size + LDR_TRAILER or size < 2 or size % 2:
            raise FatekError("E929", f"offset 0x{at + 2:X}: record lengths {envelope} and {size}: the code is an even "
                             f"number of bytes (2 or more) and the first length is the code's + {LDR_TRAILER}")
        if at + 6 + size + LDR_TRAILER > len(data):
            raise FatekError("E929", f"offset 0x{at:X}: a record of {size} code bytes runs past the file's end "
                             f"(0x{len(data):X})")
        networks.append([(at + 6 + 2 * k, _u16(data, at + 6 + 2 * k)) for k in range(size // 2)])
        at += 6 + size + LDR_TRAILER
    if not networks:
        raise FatekError("E929", f"offset 0x{LDR_PAYLOAD_AT:X}: no network record")
    items: list[Item] = []
    base = 0
    for net in reversed(networks):  # the last network is stored first
        items += decode(net, base)
        base += len(net)
    return Program("ldr", model, tuple(items), tuple(warnings))


def _device(reg: Registry, family: str, word: int, at: int, form: str) -> str:
    fam = reg.family[family]
    number = (word >> 8) - fam.base
    if not fam.lo <= number <= fam.hi:
        said = f"{family}{number} by the {family} rule" if number >= 0 else f"high byte {word >> 8:02X} below the " \
            f"{family} family's base {fam.base:02X}"
        raise FatekError("E928", f"offset 0x{at:X}: word {word:04X}: {form} {said}; the public notes observed "
                         f"{family}{fam.lo}-{family}{fam.hi} only", _FORMS_NOTE)
    return f"{family}{number}"


_FORMS_NOTE = ("mlctool decodes the words of mlctool/winproladder_words.toml only (docs/formats.md); export the ladder "
               "as text from WinProladder and write it as IL")


def decode(placed: list[tuple[int, int]], base: int = 0) -> list[Item]:
    """[(file offset, word)] -> the forms, in order; `base` the program index of the first word.
    Raises FatekError at the first word that is not a form of the registry."""
    reg = registry()
    out: list[Item] = []
    k = 0
    while k < len(placed):
        at, word = placed[k]
        ahead = [w for _, w in placed[k + 1:k + 4]]

        def item(words: int, fatek: str, il: str, operand: str = "", why: str = "", k: int = k, at: int = at) -> Item:
            return Item(base + k, at, tuple(w for _, w in placed[k:k + words]), fatek, il, operand, why)

        if word in reg.fixed:
            e = reg.fixed[word]
            out.append(item(1, e["fatek"], e["il"], why=e.get("why", "")))
        elif word in reg.edge:
            e = reg.edge[word]
            nxt = ahead[0] if ahead else None
            form = e["forms"].get(f"{nxt & 0xFF:02X}") if nxt is not None else None
            if form is None:
                got = f"{nxt:04X}" if nxt is not None else "the end of the program"
                raise FatekError("E926", f"offset 0x{at:X}: edge word {word:04X} followed by {got}; the notes establish "
                                 f"it before an ORG / ORG NOT {e['family']} word only", _FORMS_NOTE)
            device = _device(reg, e["family"], nxt, at + 2, form[0])
            out.append(item(2, f"{form[0]} {device}", form[1], device))
        elif word in reg.function:
            e = reg.function[word]
            nxt = ahead[0] if ahead else None
            if nxt is None or nxt & 0xFF != e["operand_low"]:
                got = f"{nxt:04X}" if nxt is not None else "the end of the program"
                raise FatekError("E926", f"offset 0x{at:X}: {e['fatek']} ({word:04X}) with operand word {got}; the notes "
                                 f"establish a {e['family']} operand (low byte {e['operand_low']:02X}) only", _FORMS_NOTE)
            device = _device(reg, e["family"], nxt, at + 2, f"{e['fatek']} operand")
            out.append(item(2, f"{e['fatek']} {device}", e["il"], device, e.get("why", "")))
        elif word in reg.block:
            e = reg.block[word]
            size = 2 + len(e["tail"])
            if len(ahead) < size - 1 or ahead[1:size - 1] != e["tail"]:
                got = " ".join(f"{w:04X}" for w in ahead[:size - 1]) or "the end of the program"
                tail = " ".join(f"{w:04X}" for w in e["tail"])
                raise FatekError("E926", f"offset 0x{at:X}: {e['fatek']} ({word:04X}) followed by {got}; the notes "
                                 f"establish a preset word then {tail}", _FORMS_NOTE)
            preset = (ahead[0] >> 8) | (ahead[0] & 0xFF) << 8  # its bytes in big-endian order
            out.append(item(size, f"{e['fatek']}, PV {preset}", "", why=reg.block_why[e["kind"]]))
        elif word & 0xFF in reg.single:
            e = reg.single[word & 0xFF]
            device = _device(reg, e["family"], word, at, e["fatek"])
            out.append(item(1, f"{e['fatek']} {device}", e["il"], device, e.get("why", "")))
        else:
            raise FatekError("E926", f"offset 0x{at:X}: word {word:04X} is no form the public notes establish",
                             _FORMS_NOTE)
        k += len(out[-1].words)
    return out


def encode(mnemonic: str, operand: str) -> list[int] | None:
    """An fbs instruction -> its words, by the registry read backwards; None if the registry
    holds no form of it (or the device number is one the notes did not observe)."""
    reg = registry()
    m = re.fullmatch(r"([A-Z]+)([0-9]+)", operand)
    fam = reg.family.get(m[1]) if m else None
    if fam is None or not fam.lo <= int(m[2]) <= fam.hi:
        return None
    family, number = m[1], int(m[2])
    high = (fam.base + number) << 8
    for low, e in reg.single.items():
        if e["il"] == mnemonic and e["family"] == family:
            return [high | low]
    for word, e in reg.edge.items():
        for low, (_, il) in e["forms"].items():
            if il == mnemonic and e["family"] == family:
                return [word, high | int(low, 16)]
    for word, e in reg.function.items():
        if e["il"] == mnemonic and e["family"] == family:
            return [word, high | e["operand_low"]]
    return None


def write_pdw(template: bytes, words: list[int]) -> bytes:
    """A project WinProladder saved, with its program replaced by `words` (the notes' writer:
    the fields that follow from the words are set, every other byte of the project kept).
    Raises FatekError: a template that is no readable project, or one whose program is empty
    (byte 0x103 of the image differs between the notes' empty and non-empty projects and is
    not identified: it is kept from the template) or longer than the writer's limit."""
    if not template.startswith(PDW_MAGIC):
        raise FatekError("E931", f"the template: offset 0: not a WinProladder project (it starts "
                         f"{template[:8].hex(' ') or 'empty'})", _TEMPLATE_NOTE)
    try:
        img, key = image(template)
        old = program_words(img)
    except FatekError as e:
        raise FatekError("E931", f"the template: {e.message}", _TEMPLATE_NOTE) from None
    if not 1 <= len(old) <= WRITE_MAX_WORDS:
        raise FatekError("E931", f"the template's program has {len(old)} words; the writer needs a template of 1 to "
                         f"{WRITE_MAX_WORDS}", _TEMPLATE_NOTE)
    if len(words) > WRITE_MAX_WORDS:
        raise FatekError("E931", f"the program is {len(words)} words; the notes' writer is validated up to "
                         f"{WRITE_MAX_WORDS} (past it the length byte at 0xCA carries into 0xCB, not identified)")
    new = bytearray(img)
    n = len(words)
    new[CODE_AT:CODE_AT + 2 * len(old)] = b"\xff" * (2 * len(old))
    for k, w in enumerate(words):
        new[CODE_AT + 2 * k:CODE_AT + 2 * k + 2] = w.to_bytes(2, "little")
    for at, value in ((COUNT_AT, n), (COMPLEMENT_AT, COMPLEMENT_BASE - n), (END_AT[0], CODE_AT + 2 * n),
                      (END_AT[1], CODE_AT + 2 * n), (CHECKSUM_AT, (sum(words) - 1) & 0xFFFF)):
        new[at:at + 2] = value.to_bytes(2, "little")
    new[LENGTH_BYTE_AT] = (0x23 + 4 * n) & 0xFF
    out = bytearray(template)
    record = int.from_bytes(bytes(new[:RECORD]), "little") ^ key
    out[IMAGE_AT:IMAGE_AT + RECORD] = record.to_bytes(RECORD, "little")
    return bytes(out)


_TEMPLATE_NOTE = ("save a project in WinProladder holding any short program (one rung, e.g. X0 -> Y0) and give it "
                  "with --template: the program is written into it, the rest of the project kept (docs/formats.md)")
