#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Writes the seed corpus of fuzz_modbus_reply (fuzz/corpus/modbus_reply/): scripts for the fake
controller of fuzz_modbus_reply.cpp, one reply per request of the driver's sequence
connect / upload / start / status / waitUntilDone(0) / stop. Run it after changing that format:

    python3 fuzz/make_modbus_seeds.py
"""
import os
import struct

OK, OK_INPUT_VALUES, EXCEPTION, FUZZED_PDU, FUZZED_HEADER, RAW, SILENT, CLOSE = range(8)
MAGIC, VERSION, MAX_LEVEL, MIN_DWELL_US, CAPACITY = 0x4459, 0x0100, 16, 1000, 256
IDLE, LOADED, RUNNING, DONE, FAULT = range(5)


def crc16(words):
    crc = 0xFFFF
    for w in words:
        for b in ((w >> 8) & 0xFF, w & 0xFF):
            crc ^= b
            for _ in range(8):
                crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def schedule_registers(n):
    """encodeSchedule of the harness's makeSchedule(n): 2 ms apart, levels ±(1 + i % 16)."""
    regs = [n, 0]
    for i in range(n):
        us = 2000 * i
        level = (1 if i % 2 == 0 else -1) * (1 + i % 16)
        regs += [us >> 16, us & 0xFFFF, level & 0xFFFF]
    return regs


def words(*values):
    return b"".join(struct.pack(">H", v & 0xFFFF) for v in values)


def status(state, crc=0, level=0, start_us=0, clock_us=0, fault=0, entry=0xFFFF):
    """Input registers 2..17 (STATUS .. ENTRY_INDEX)."""
    return words(state, fault, MAX_LEVEL, MIN_DWELL_US, CAPACITY, level,
                 *struct.unpack(">4H", struct.pack(">Q", start_us)),
                 *struct.unpack(">4H", struct.pack(">Q", clock_us)), crc, entry)


def honest(n, overrides=None, retries=0):
    """The script of a controller that does everything right; overrides[i] replaces reply i."""
    crc = crc16(schedule_registers(n))
    chunks = (3 * n + 119) // 120
    replies = [bytes([OK]) + words(MAGIC, VERSION, IDLE, 0, MAX_LEVEL, MIN_DWELL_US, CAPACITY),  # connect: id
               bytes([OK])]                                                                    # safe level
    replies += [bytes([OK]) + status(IDLE)]                                                    # upload: status
    replies += [bytes([OK])] * chunks                                                          # entries
    replies += [bytes([OK]), bytes([OK])]                                                      # head, LOAD
    replies += [bytes([OK])] * (1 + chunks)                                                    # read-back
    replies += [bytes([OK]) + status(LOADED, crc)]                                             # LOADED?
    replies += [bytes([OK]) + status(LOADED, crc), bytes([OK])]                                # start: check, START
    replies += [bytes([OK]) + status(RUNNING, 0, 1, 5_000_000, 5_000_100 + 50 * k, entry=0) for k in range(3)]
    replies += [bytes([OK]) + status(RUNNING, 0, 3, 5_000_000, 5_000_400, entry=1)]            # status
    replies += [bytes([OK]) + status(DONE, 0, 3, 5_000_000, 5_010_000, entry=n - 1)]          # wait
    replies += [bytes([OK])]                                                                   # stop
    for i, r in (overrides or {}).items():
        replies[i] = r
    return bytes([retries, n - 1]) + b"".join(replies)


def main():
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "modbus_reply")
    os.makedirs(out, exist_ok=True)
    n = 3
    crc = crc16(schedule_registers(n))
    seeds = {
        # valid conversations
        "honest_3_entries": honest(3),
        "honest_42_entries_two_chunks": honest(42),
        "silent_once_then_retried": honest(3, {0: bytes([SILENT]) + bytes([OK]) + words(MAGIC, VERSION, IDLE, 0,
                                                                                        MAX_LEVEL, MIN_DWELL_US,
                                                                                        CAPACITY)}, retries=1),
        # broken controllers
        "exception_on_identification": bytes([0, 2, EXCEPTION, 2]),
        "wrong_magic": bytes([0, 2, OK]) + words(0x1234, VERSION, 0, 0, 16, 1000, 256),
        "protocol_2": bytes([0, 2, OK]) + words(MAGIC, 0x0200, 0, 0, 16, 1000, 256),
        "readback_mismatch": honest(n, {6: bytes([OK_INPUT_VALUES]) + words(n, 0, crc ^ 1)}),
        "device_refuses_load": honest(n, {8: bytes([OK]) + status(FAULT, 0, fault=2)}),
        "clock_before_start": honest(n, {11: bytes([OK]) + status(RUNNING, 0, 1, 9_000_000, 1_000, entry=0)}),
        "raw_garbage_reply": bytes([1, 2, RAW, 0, 9]) + b"\x00\x01\x00\x00\x00\x03\xff\x04\x02",
        "fuzzed_pdu_short": bytes([0, 2, FUZZED_PDU, 2, 4, 14]),
        "close_mid_upload": honest(n, {4: bytes([CLOSE])}),
        "wrong_transaction_id": bytes([0, 2, FUZZED_HEADER]) + b"\x77\x77\x00\x00\x00\x11\xff"
                                + words(MAGIC, VERSION, 0, 0, 16, 1000, 256),
    }
    for name, data in seeds.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
    print(f"wrote {len(seeds)} seeds to {out}")


if __name__ == "__main__":
    main()
