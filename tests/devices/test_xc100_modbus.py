"""XC100 Modbus (manual 004 ch. 8): the manual's frames as encode/decode vectors through
devices/framing.py (with pymodbus's framers as an independent check of the same frames), the
register map, exceptions and their priority, station and broadcast."""

from __future__ import annotations

import pytest
from pymodbus.framer import FramerAscii, FramerRTU

from mlctool.devices import framing
from mlctool.devices.framing import AsciiReceiver, Frame, RtuReceiver
from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.modbus import handle_pdu
from mlctool.devices.xc100.registers import UNLOCK_KEY, read_words, write_words

# (section, frame as printed, station, PDU). Frame 6 is printed with one "0" missing
# ("002" for "0002"); the corrected frame is the one whose LRC (65) checks.
RTU = [
    ("8.4 read", "01 03 10 00 00 01 80 CA", 1, "03 10 00 00 01"),
    ("8.4 write", "01 06 20 1E 00 03 A2 0D", 1, "06 20 1E 00 03"),
    ("8.4 multi-write", "01 10 20 00 00 02 04 00 00 00 64 6B 85", 1, "10 20 00 00 02 04 00 00 00 64"),
]
ASCII = [
    ("8.5 read", ":010310000001EB", 1, "03 10 00 00 01"),
    ("8.5 write", ":0106201E0003B8", 1, "06 20 1E 00 03"),
    ("8.5 multi-write (corrected)", ":011020000002040000006465", 1, "10 20 00 00 02 04 00 00 00 64"),
    ("8.3 (1) request", ":0104201E0003BA", 1, "04 20 1E 00 03"),
    ("8.3 (1) response", ":0184017A", 1, "84 01"),
    ("8.3 (2) request", ":0190201E00032E", 1, "90 20 1E 00 03"),
    ("8.3 (2) response", ":0190016E", 1, "90 01"),
    ("8.2 write unlock", ":0110999B0004084C7630315479566702", 1,
     "10 99 9B 00 04 08 4C 76 30 31 54 79 56 67"),
]


@pytest.mark.parametrize("name,frame,station,pdu", RTU, ids=[r[0] for r in RTU])
def test_rtu_frames(name, frame, station, pdu):
    raw, body = bytes.fromhex(frame), bytes.fromhex(pdu)
    assert framing.encode("rtu", Frame(station, b""), body) == raw
    assert framing.decode("rtu", raw) == Frame(station, body)
    assert FramerRTU.compute_CRC(raw[:-2]) == int.from_bytes(raw[-2:], "big")  # pymodbus agrees
    assert framing.crc16(raw[:-2]) == int.from_bytes(raw[-2:], "little")


@pytest.mark.parametrize("name,frame,station,pdu", ASCII, ids=[r[0] for r in ASCII])
def test_ascii_frames(name, frame, station, pdu):
    raw, body = frame.encode() + b"\r\n", bytes.fromhex(pdu)
    assert framing.encode("ascii", Frame(station, b""), body) == raw
    assert framing.decode("ascii", raw) == Frame(station, body)
    assert FramerAscii.compute_LRC(bytes.fromhex(frame[1:-2])) == int(frame[-2:], 16)  # pymodbus agrees
    assert framing.lrc(bytes.fromhex(frame[1:-2])) == int(frame[-2:], 16)


def test_damaged_checks_are_not_frames():
    assert framing.decode("rtu", bytes.fromhex("01 03 10 00 00 01 80 CB")) is None
    assert framing.decode("rtu", bytes.fromhex("01 03 80")) is None
    assert framing.decode("ascii", b":010310000001EC\r\n") is None
    assert framing.decode("ascii", b":0103zz0000001EB\r\n") is None
    assert framing.decode("ascii", b":01EB\r\n") is None
    # a stream: junk before ':' and a non-hex line do not eat the good frame behind them
    frames = AsciiReceiver().feed(b"zz:zz\r\n:01:010310000001EB\r\n", 0.0)
    assert frames == [Frame(1, bytes.fromhex("0310000001"))]


def ask(dev, pdu: str, unit: int = 1, station: int = 1) -> str | None:
    reply = handle_pdu(dev, station, unit, bytes.fromhex(pdu))
    return None if reply is None else reply.hex(" ").upper()


def test_manual_requests_get_the_manual_answers():
    dev = c.new_xc100()
    assert ask(dev, "03 10 00 00 01") == "03 02 00 00"  # ActionStatus stopped
    assert ask(dev, "04 20 1E 00 03") == "84 01"  # 8.3 (1)
    assert ask(dev, "90 20 1E 00 03") == "90 01"  # 8.3 (2): >= 80H is echoed
    assert ask(dev, "10 20 00 00 02 04 00 00 00 64") == "10 20 00 00 02"
    assert read_words(dev, 0x2000, 2) == [0, 100]  # high word first: INCamount = 100
    assert ask(dev, "06 20 1E 00 03") == "06 20 1E 00 03"  # homing starts
    assert dev.motion is not None and dev.motion.kind == "home"
    assert ask(dev, "03 10 00 00 01") == "03 02 00 01"


def test_exception_priority_lowest_code_wins():
    dev = c.new_xc100()
    assert ask(dev, "05 10 02 FF FF") == "85 01"  # bad FC beats bad address and value
    assert ask(dev, "03 10 02 00 01") == "83 02"  # gap in the status map
    assert ask(dev, "03 10 00 00 64") == "83 02"  # 100 words run into gaps: address first
    assert ask(dev, "03 90 10 00 00") == "83 03"  # no words: count out of range
    assert ask(dev, "03 10 60 00 32") == "03 64" + " 00" * 100  # the 50-word alarm history
    assert ask(dev, "03 20 1E 00 01") == "83 02"  # 201EH is write-only
    assert ask(dev, "06 10 00 00 01") == "86 02"  # status is read-only
    assert ask(dev, "06 20 1E 00 05") == "86 03"  # MovType 5 is 未開放
    assert ask(dev, "06 20 14 00 65") == "86 03"  # speed 101 %
    assert ask(dev, "06 90 12 00 00") == "86 03"  # half of a 32-bit value
    assert ask(dev, "10 20 00 00 02 04 00 00") == "90 03"  # data shorter than declared
    assert ask(dev, "10 10 00 00 01 02 00 00") == "90 02"  # address error beats data error


def test_station_and_broadcast():
    dev = c.new_xc100()
    assert ask(dev, "03 10 00 00 01", unit=2, station=2) == "03 02 00 00"  # CH 1 -> station 2
    assert ask(dev, "03 10 00 00 01", unit=3, station=2) is None
    assert ask(dev, "06 20 14 00 32", unit=0) is None  # broadcast off (0A03H = 0): ignored
    assert dev.regs.get(0x2014) is None
    dev.params[0x0A03] = 1
    assert ask(dev, "06 20 14 00 32", unit=0) is None  # executed, never answered
    assert dev.regs[0x2014] == 50


def test_parameters_need_the_unlock_frame_and_reboot_flags():
    dev = c.new_xc100()
    assert ask(dev, "06 01 1D 00 0A") == "86 03" and dev.error == 11
    assert write_words(dev, 0x999B, [0x4C76, 0x3031, 0x5479, 0x5668]) == 3  # wrong key
    key = [UNLOCK_KEY[k] << 8 | UNLOCK_KEY[k + 1] for k in range(0, 8, 2)]
    assert write_words(dev, 0x999B, key) == 0 and dev.unlocked
    assert ask(dev, "06 01 1D 00 0A") == "06 01 1D 00 0A" and c.param(dev, "NearZone") == 10
    assert ask(dev, "06 07 03 00 05") == "06 07 03 00 05"  # MOVE -> OUT5: needs a power cycle
    assert dev.error == 6 and dev.boot[0x0703] == 0
    assert ask(dev, "06 99 99 00 00") == "06 99 99 00 00"  # save, then power up
    c.power_up(dev)
    assert dev.boot[0x0703] == 5 and c.param(dev, "NearZone") == 10


def test_register_map_reads():
    dev = c.new_xc100()
    words = read_words(dev, 0x10E0, 3)
    assert bytes(b for w in words for b in (w >> 8, w & 0xFF)).rstrip(b"\0") == b"XC100"
    assert read_words(dev, 0x10F0, 1) == [0x0100]
    assert read_words(dev, 0x100E, 1) == [0xFFFF]  # StepNo -1: never run
    assert read_words(dev, 0x9010, 14) == [0, 0, 0, 100, 1000, 0, 0, 0, 0, 0, 300, 300, 0, 0xFFFF]
    assert read_words(dev, 0x97FD, 1) == [0xFFFF]  # P127's last word (9010H + 10H*126 + DH)
    assert read_words(dev, 0x901E, 1) == 2  # between points
    assert read_words(dev, 0x1020, 1) == [c.output_pins(dev)]
    assert read_words(dev, 0x0108, 2) == [0, 100]  # FullCountValue, 32-bit


def test_point_table_written_by_fc10_then_started():
    dev = c.new_xc100(params={0x051B: 0})
    # P2: ABS to 20000 pulses, 100 %: mode, position (2 words), speed
    assert ask(dev, "10 90 20 00 04 08 00 01 00 00 4E 20 00 64") == "10 90 20 00 04"
    assert dev.points[2].mode == 1 and dev.points[2].position == 20000
    assert ask(dev, "10 90 20 00 01 02 00 05") == "90 03"  # mode 5 is not open
    assert c.start_point(dev, 2)
    c.advance(dev, 2_000_000)
    assert dev.motion is None and round(dev.act) == 20000
    assert read_words(dev, 0x1008, 2) == [0, 20000]


@pytest.mark.parametrize("name,frame,station,pdu", RTU + ASCII, ids=[r[0] for r in RTU + ASCII])
def test_manual_frames_through_the_server_stream_receivers(name, frame, station, pdu):
    """The manual's frames (8.3-8.5) through `mlc device serve`'s own receivers, both ways."""
    receiver = AsciiReceiver() if frame.startswith(":") else RtuReceiver()
    raw = frame.encode() + b"\r\n" if frame.startswith(":") else bytes.fromhex(frame)
    assert receiver.feed(raw, 0.0) == [Frame(station, bytes.fromhex(pdu))]
    assert receiver.encode(Frame(station, b""), bytes.fromhex(pdu)) == raw


def _unlocked() -> c.Xc100:
    dev = c.new_xc100()
    dev.unlocked = True
    return dev


def test_rtu_is_8_data_bits_only():
    """8.1 通訊規格: "資料長度 | 7、8 BIT | 8 BIT" (ASCII mode 7 or 8 data bits, RTU mode
    8 only) and "停止位元 | 1 BIT". 5.8: 0A01H DataSize 0 = 8bit, 1 = 7bit; 0A04H Protocol
    0 = ASCII, 1 = RTU. The pair 7 bit + RTU is refused like a value out of range (10.3
    上下限錯誤 = ErrorStatus 2), whichever is written last; the status says why."""
    dev = _unlocked()
    assert ask(dev, "06 0A 01 00 01") == "06 0A 01 00 01"  # 7-bit ASCII: allowed
    assert ask(dev, "06 0A 04 00 01") == "86 03"  # ... then RTU: refused
    assert dev.error == c.ERR_RANGE and "8.1" in dev.refused and dev.params[0x0A04] == 0
    dev = _unlocked()
    assert ask(dev, "06 0A 04 00 01") == "06 0A 04 00 01"  # 8-bit RTU: allowed
    assert ask(dev, "06 0A 01 00 01") == "86 03"  # ... then 7 bit: refused
    assert dev.params[0x0A01] == 0 and dev.error == 2
    dev = _unlocked()
    assert ask(dev, "10 0A 00 00 05 0A 00 01 00 01 00 00 00 00 00 01") == "90 03"  # all at once
    assert dev.params[0x0A00] == 1 and dev.params[0x0A01] == 0  # nothing of it was written
    # and back to 8 bits with RTU in one request is fine
    assert ask(dev, "10 0A 00 00 05 0A 00 01 00 00 00 00 00 00 00 01")[:2] == "10"
    assert dev.params[0x0A04] == 1


def test_parameter_out_of_range_sets_error_2():
    """10.3 故障排除: "上下限錯誤 | 在參數裡設定超出範圍的數值" (a parameter set outside its range)."""
    dev = _unlocked()
    assert ask(dev, "06 0A 00 00 05") == "86 03"  # 0A00H BaudRate 0~4 (5.8)
    assert dev.error == 2 and "0A00H" in dev.refused and dev.params[0x0A00] == 1
