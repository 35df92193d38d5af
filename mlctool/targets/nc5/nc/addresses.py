"""The special relays and registers the virtual NC reads (MLC -> NC: M2cnnn, D2cnnn) and
writes (NC -> MLC: M3cnnn, D3cnnn; HMI: M49cnn, D49cnn), by function.

Each entry is (kind, first digit, function number): ("M", 2, 0) is M2c000, channel c in the
second digit (5.1, L3502); for the HMI rows (49, n) the channel is the third digit (5.1 L3492;
DECISION (notes #3): HMI rows use the third digit, as the HMI tables print them). A per-axis
row is the X axis' number; axis k of the fixed order X Y Z A B C U V W (5.2.1 rows) adds k.
The section cited is where the function is described; the checker's table
(mlctool/targets/nc5/signals.*) has every row, and tests/targets/nc5/ holds the two equal.
"""

from __future__ import annotations

AXIS_ORDER = "XYZABCUVW"  # 5.2.1 per-axis rows: X = +0 ... W = +8 (axes 10-16 have no letter)

# -- MLC -> NC relays (5.2.1)
CYCLE_START = ("M", 2, 0)          # 程式啟動, 5.3.2 / 6.2
FEED_HOLD = ("M", 2, 1)            # 程式停止, 5.3.2 / 6.2
NC_RESET = ("M", 2, 4)             # NC 系統重置(MLC 觸發), 5.2.1
DRY_RUN = ("M", 2, 5)              # 執行空跑, 5.3.2 / 5.2.1
HANDWHEEL_RUN = ("M", 2, 6)        # 手輪模擬: the program's moves by handwheel pulses, 5.3.2 / 6.2
HARD_LIMIT_RELEASE = ("M", 2, 7)   # 硬體極限釋放, 5.3.3 / 6.9
SINGLE_BLOCK = ("M", 2, 8)         # 單節執行, 5.3.2 / 6.2
OPTIONAL_STOP = ("M", 2, 9)        # 選擇停止 (M01 暫停), 5.3.2 / 6.2
BLOCK_SKIP = ("M", 2, 10)          # 單節忽略, 5.3.2 / 6.2
SERVO_ON = ("M", 2, 12)            # Servo On / Off, 5.2.1
EMERGENCY_STOP = ("M", 2, 13)      # MLC 急停觸發, 5.2.1
MST_FINISH = ("M", 2, 16)          # M、S、T 碼執行完成, 5.3.10 / 6.8
MACRO_START = ("M", 2, 25)         # 巨集呼叫啟動, 5.3.8 / 6.12
MACRO_PREPARE = ("M", 2, 32)       # 第 1 巨集呼叫初始準備 (+k: macro 1-16), 5.3.8 / 6.12
MAGAZINE_FORWARD = ("M", 2, 64)    # 刀庫 1 正轉, 5.3.14 / 6.13
MAGAZINE_REVERSE = ("M", 2, 65)    # 刀庫 1 反轉, 5.3.14 / 6.13
TOOL_EXCHANGE = ("M", 2, 66)       # 刀具 1 交換, 5.3.14 / 6.13
MAGAZINE_RESET = ("M", 2, 67)      # 刀庫 1 重置, 5.3.14 / 6.13
SYNC_ON = ("M", 2, 256)            # 同動控制觸發, 5.3.11 / 6.15 / 6.16
TRANSFER_ON = ("M", 2, 257)        # 轉移命令控制觸發, 5.3.12 / 6.15
AXIS_SERVO_OFF = ("M", 2, 272)     # X 軸 Servo Off (+axis), 5.3.3
SYNC_FOLLOW = ("M", 2, 288)        # X 從動軸追隨主動軸 (+axis), 5.3.11 / 6.15 / 6.16
TRANSFER_RECEIVE = ("M", 2, 304)   # X 軸接收主動軸命令 (+axis), 5.3.12 / 6.15
HOME_START = ("M", 2, 320)         # X 軸回原點控制 (+axis), 5.3.4 / 6.7
AXIS_LOCK = ("M", 2, 352)          # X 軸鎖定 (+axis), 5.3.3 / 6.4
SOFT_LIMIT_RELEASE = ("M", 2, 368)  # X 軸第一軟體極限解除 (+axis), 5.3.3 / 6.9
JOG_PLUS = ("M", 2, 384)           # X 軸正向寸動控制 (+axis), 5.3.5 / 6.4
JOG_MINUS = ("M", 2, 400)          # X 軸反向寸動控制 (+axis), 5.3.5 / 6.4
MLC_SPEED_MODE = ("M", 2, 416)     # MLC 軸 X 軸控制模式: On speed, Off position (+axis), 5.3.9 / 6.14
MLC_SWITCH = ("M", 2, 432)         # NC 軸切換 MLC 軸 X 軸 (+axis), 5.3.9 / 6.14
MLC_TRIGGER = ("M", 2, 448)        # X 軸運動觸發(MLC 軸) (+axis), 5.3.9 / 6.14
MLC_INCREMENTAL = ("M", 2, 464)    # MLC 軸 X 軸增量切換 (+axis), 5.3.9 / 6.14
SPINDLE_FORWARD = ("M", 2, 704)    # 第一主軸正轉, 5.3.13 / 6.10
SPINDLE_REVERSE = ("M", 2, 705)    # 第一主軸反轉, 5.3.13 / 6.10
SPINDLE_ORIENT = ("M", 2, 706)     # 第一主軸定位控制, 5.3.13 / 6.10
SPINDLE_SOURCE = ("M", 2, 710)     # 第一主軸命令來源切換, 5.3.13 / 6.10

# -- MLC -> NC registers (5.2.2)
MODE = ("D", 2, 0)                 # NC 模式切換, 5.3.1 / 6.1
FEED_OVERRIDE = ("D", 2, 2)        # 切削進給調整率, 5.3.2 / 6.2
RAPID_OVERRIDE = ("D", 2, 4)       # 快速移動速度調整率, 5.3.2 / 6.6
JOG_SPEED = ("D", 2, 6)            # 寸動進給倍率及試運行速度, 5.3.5 / 6.4
MPG_AXIS = ("D", 2, 8)             # MPG0 手輪軸向選擇, 5.3.6 / 6.3
MPG_SCALE = ("D", 2, 9)            # MPG0 手輪脈波的倍率, 5.3.6 / 6.3
INC_AMOUNT = ("D", 2, 14)          # 增量寸動移動量倍率 (32-bit), 5.3.5 / 6.5
SPINDLE_SPEED = ("D", 2, 24)       # 第一主軸轉速 (透過特 D 寫入), 32-bit (notes #20), 5.3.13 / 6.10
SPINDLE_OVERRIDE = ("D", 2, 26)    # 第一主軸速度調整率, 5.3.13 / 6.10
SPINDLE_GEAR = ("D", 2, 27)        # 第一主軸齒輪比選擇, 5.3.13 / 6.11
MACRO_NAME = ("D", 2, 64)          # 呼叫第 1 巨集檔名稱 (+k: macro 1-16), 5.3.8 / 6.12
MLC_TARGET = ("D", 2, 256)         # X 軸定位命令(MLC 軸), float mm (+2 x axis), 5.3.9 / 6.14
MLC_SPEED = ("D", 2, 288)          # X 軸定位速度(MLC 軸), float mm/min (+2 x axis), 5.3.9 / 6.14

# -- NC -> MLC relays (5.2.1)
MODE_FEEDBACK = ("M", 3, 0)        # M3x000 AUTO ... M3x007 HOME (+mode), 5.3.1; DECISION (notes #1):
#                                    not the M2x288-M2x295 of 6.1's table (those are 5.3.11's followers)
RUNNING = ("M", 3, 16)             # 程序執行中, 5.3.2 / 6.2
PAUSED = ("M", 3, 17)              # 程序暫停, 5.3.2 / 6.2
ESTOP_STATE = ("M", 3, 18)         # NC 系統急停, 5.2.1
RESET_DONE = ("M", 3, 19)          # NC 系統重置動作完成, 5.2.1
LAST_LINE = ("M", 3, 21)           # 最末行程式結束, 5.3.2 / 6.2
M02_END = ("M", 3, 22)             # M02 程式結束, 5.3.2 / 6.2
M30_END = ("M", 3, 23)             # M30 程式結束及回頭, 5.3.2 / 6.2
BLOCK_STOPPED = ("M", 3, 24)       # 單節暫停, 5.3.2 / 6.2
MACRO_RUNNING = ("M", 3, 27)       # 巨集呼叫執行, 5.3.8 / 6.12
MACRO_NEEDS_AUTO = ("M", 3, 28)    # 巨集呼叫需切換自動模式訊號, 5.3.8 / 6.12
MACRO_ERROR = ("M", 3, 29)         # 巨集呼叫錯誤, 5.3.8 / 6.12
MACRO_READY = ("M", 3, 48)         # 第 1 巨集呼叫初始完成 (+k: macro 1-16), 5.3.8 / 6.12
M_STROBE = ("M", 3, 64)            # M 碼執行, 5.3.10 / 6.8
S_STROBE = ("M", 3, 65)            # S 碼執行, 5.3.10 / 6.8
T_STROBE = ("M", 3, 66)            # T 碼執行, 5.3.10 / 6.8
SERVO_STATE = ("M", 3, 272)        # X 軸 Servo On/Off 狀態 (+axis), 5.3.3
HOMED = ("M", 3, 320)              # X 軸完成回原點狀態 (+axis), 5.3.4 / 6.7
HOME_DONE = ("M", 3, 336)          # X 軸原點復歸完成 (+axis), 5.3.4 / 6.7
AT_ORIGIN = ("M", 3, 352)          # X 軸在原點位置 (+axis), 5.3.4
MLC_AXIS_ON = ("M", 3, 432)        # X 軸 NC 軸切換為 MLC 軸完成 (+axis), 5.3.9 / 6.14
MLC_IN_POSITION = ("M", 3, 448)    # X 軸定位完成(MLC 軸): in position / at speed (+axis), 5.3.9 / 6.14
MOVING = ("M", 3, 464)             # X 軸移動中 (+axis), 5.3.3 / 6.4
MOVING_PLUS = ("M", 3, 480)        # X 軸正向移動中 (+axis), 5.3.3 / 6.4
MOVING_MINUS = ("M", 3, 496)       # X 軸反向移動中 (+axis), 5.3.3 / 6.4
SPINDLE_AT_SPEED = ("M", 3, 704)   # 第一主軸到達目標速度, 5.3.13 / 6.10
SPINDLE_ZERO_SPEED = ("M", 3, 705)  # 第一主軸到達零速度, 5.3.13 / 6.10
SPINDLE_ORIENTED = ("M", 3, 706)   # 第一主軸定位完成訊號, 5.3.13 / 6.10

# -- NC -> MLC registers (5.2.2)
SPINDLE_COMMAND = ("D", 3, 24)     # 第一主軸命令速度 (32-bit), 5.3.13 / 6.10
SPINDLE_ACTUAL = ("D", 3, 26)      # 第一主軸實際轉速 (32-bit), 5.3.13 / 6.10
SPINDLE_ANGLE = ("D", 3, 28)       # 第一主軸角度 (32-bit), 5.3.13
SPINDLE_TOOL = ("D", 3, 36)        # 主軸刀號(使用中)刀庫 1, 5.3.14 / 6.13
STANDBY_T = ("D", 3, 37)           # T 碼數據(待命中)刀庫 1, 5.3.14 / 6.13
STANDBY_POT = ("D", 3, 38)         # 刀套(待命中)刀庫 1, 5.3.14 / 6.13
POT_STEPS = ("D", 3, 39)           # T 碼數據(增量移動站號)刀庫 1, 5.3.14 / 6.13
M_CODE = ("D", 3, 48)              # 第一 M 碼數據, 5.3.10 / 6.8
S_CODE = ("D", 3, 50)              # 第一 S 碼數據 (32-bit: D3x052 follows), 5.3.10 / 6.8
T_CODE = ("D", 3, 52)              # 第一 T 碼數據(命令), 5.3.10 / 6.8

# -- HMI registers (5.2.2, 5.3.15): D49c00 ... in the third digit
PARTS_DONE = ("D", 49, 0)          # 完成加工數 (32-bit), 5.3.15
PARTS_TARGET = ("D", 49, 2)        # 目標加工數 (32-bit), 5.3.15
TOTAL_TIME = ("D", 49, 4)          # 總加工時間 (32-bit, s), 5.3.15
CYCLE_TIME = ("D", 49, 6)          # 單一加工時間 (32-bit, s), 5.3.15
SYSTEM_TIME = 49000                # D49000-D49002 系統時間 年月, 日時, 分秒: the system's, no channel, 5.3.15


# How the model uses them (tests/targets/nc5/test_nc5_addresses.py holds them to the signal table):
# it reads groups 2 (MLC -> NC) and 59 (HMI -> MLC) and writes 3 (NC -> MLC) and 49 (-> HMI);
WIDE = (INC_AMOUNT, SPINDLE_SPEED, SPINDLE_COMMAND, SPINDLE_ACTUAL, SPINDLE_ANGLE, S_CODE, PARTS_DONE,
        PARTS_TARGET, TOTAL_TIME, CYCLE_TIME, MLC_TARGET, MLC_SPEED)  # 32-bit: low word at n, high at n + 1
PER_AXIS = (AXIS_SERVO_OFF, HOME_START, AXIS_LOCK, SOFT_LIMIT_RELEASE, JOG_PLUS, JOG_MINUS, SERVO_STATE,
            HOMED, HOME_DONE, AT_ORIGIN, MOVING, MOVING_PLUS, MOVING_MINUS, SYNC_FOLLOW, TRANSFER_RECEIVE,
            MLC_SPEED_MODE, MLC_SWITCH, MLC_TRIGGER, MLC_INCREMENTAL, MLC_AXIS_ON,
            MLC_IN_POSITION)  # + axis 0-8 (X ... W)
PER_AXIS_PAIRS = (MLC_TARGET, MLC_SPEED)  # + 2 x axis (two words each)
RUNS = {MODE_FEEDBACK: 8, MACRO_PREPARE: 16, MACRO_READY: 16, MACRO_NAME: 16}  # rows n ... n + count - 1


def entries() -> dict[str, tuple[str, int, int]]:
    """Every address of this module by its name (CYCLE_START ...)."""
    return {k: v for k, v in globals().items()
            if k.isupper() and isinstance(v, tuple) and len(v) == 3 and isinstance(v[0], str)}


def number(entry: tuple[str, int, int], channel: int, axis: int = 0) -> int:
    """The device number of `entry` on `channel` (1-8), plus `axis` for a per-axis row:
    ("M", 2, 0) on channel 1 -> 21000; ("D", 49, 0) on channel 1 -> 49100."""
    _, group, function = entry
    if group == 49:
        return 49000 + 100 * channel + function + axis
    return group * 10000 + channel * 1000 + function + axis


def name(entry: tuple[str, int, int]) -> str:
    """The manual's spelling with the channel digit as x: M2x000, D49x00."""
    kind, group, function = entry
    return f"{kind}49x{function:02d}" if group == 49 else f"{kind}{group}x{function:03d}"
