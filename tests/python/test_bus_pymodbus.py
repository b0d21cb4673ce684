# SPDX-License-Identifier: Apache-2.0
"""Interoperability: the C++ actuator driver speaks plain Modbus TCP.

An independent implementation of the register map of docs/actuator-bus.md, written here on top of
pymodbus's server (not libmodbus, not the project's simulator), serves on 127.0.0.1; the C++
program ``dynblur_actuator_ctl`` (found in $DYNBLUR_BUILD_DIR/samples, default /work/main/build,
or at $DYNBLUR_ACTUATOR_CTL) uploads a schedule, starts it and prints its start report.
"""
import asyncio
import os
import pathlib
import re
import socket
import subprocess
import threading
import time

import pytest
from pymodbus.constants import ExcCodes
from pymodbus.server import ModbusTcpServer
from pymodbus.simulator import DataType, SimData, SimDevice

REPO = pathlib.Path(__file__).resolve().parents[2]

# The register map (docs/actuator-bus.md).
IR_MAGIC, IR_VERSION, IR_STATUS, IR_FAULT, IR_MAX_LEVEL, IR_MIN_DWELL_US, IR_CAPACITY = range(7)
IR_CURRENT_LEVEL, IR_START_TIME_US, IR_CLOCK_US, IR_LOADED_CHECKSUM, IR_ENTRY_INDEX, IR_COUNT = 7, 8, 12, 16, 17, 18
HR_COMMAND, HR_LENGTH, HR_INITIAL_LEVEL, HR_CHECKSUM, HR_SAFE_LEVEL, HR_ENTRIES = 100, 101, 102, 103, 104, 200
IDLE, LOADED, RUNNING, DONE, FAULT = range(5)
CMD_LOAD, CMD_START, CMD_STOP, CMD_CLEAR_FAULT = 1, 2, 3, 4
CAPACITY, MAX_LEVEL, MIN_DWELL_US = 64, 16, 1000


def crc16_modbus(words):
    crc = 0xFFFF
    for w in words:
        for byte in ((w >> 8) & 0xFF, w & 0xFF):
            crc ^= byte
            for _ in range(8):
                crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def int16(w):
    return w - 65536 if w >= 32768 else w


class Controller:
    """The device's logic; registers live in pymodbus's block, updated from the action callback."""

    def __init__(self):
        self.state, self.fault, self.level = IDLE, 0, 0
        self.start_us, self.loaded_crc = 0, 0
        self.offsets, self.levels = [], []
        self.started = []            # (offsets, levels) of every start
        self.writes = 0
        self.epoch = time.monotonic() - 5.0  # the controller clock differs from the host's

    def clock_us(self):
        return int((time.monotonic() - self.epoch) * 1e6)

    def advance(self):
        if self.state == RUNNING:
            elapsed = self.clock_us() - self.start_us
            index = max(i for i, off in enumerate(self.offsets) if off <= elapsed)
            self.level = self.levels[index]
            self.index = index
            if index == len(self.offsets) - 1:
                self.state = DONE

    def command(self, code, hr):
        if code == CMD_LOAD:
            n = hr(HR_LENGTH)
            words = [n, hr(HR_INITIAL_LEVEL)] + [hr(HR_ENTRIES + k) for k in range(3 * n)]
            if not 1 <= n <= CAPACITY:
                self.state, self.fault = FAULT, 1
            elif crc16_modbus(words) != hr(HR_CHECKSUM):
                self.state, self.fault = FAULT, 2
            else:
                self.offsets = [(words[2 + 3 * i] << 16) | words[3 + 3 * i] for i in range(n)]
                self.levels = [int16(words[4 + 3 * i]) for i in range(n)]
                self.state, self.fault, self.loaded_crc = LOADED, 0, crc16_modbus(words)
        elif code == CMD_START:
            if self.state != LOADED:
                self.state, self.fault = FAULT, 5
                return
            self.start_us, self.state, self.index = self.clock_us(), RUNNING, 0
            self.level = self.levels[0]
            self.started.append((list(self.offsets), list(self.levels)))
            self.advance()
        elif code == CMD_STOP:
            self.level = int16(hr(HR_SAFE_LEVEL))
            if self.state != FAULT:
                self.state = IDLE
        elif code == CMD_CLEAR_FAULT and self.state == FAULT:
            self.state, self.fault = IDLE, 0

    def fill_inputs(self, reg):
        self.advance()
        values = {IR_MAGIC: 0x4459, IR_VERSION: 0x0100, IR_STATUS: self.state, IR_FAULT: self.fault,
                  IR_MAX_LEVEL: MAX_LEVEL, IR_MIN_DWELL_US: MIN_DWELL_US, IR_CAPACITY: CAPACITY,
                  IR_CURRENT_LEVEL: self.level & 0xFFFF,
                  IR_LOADED_CHECKSUM: self.loaded_crc if self.state == LOADED else 0,
                  IR_ENTRY_INDEX: self.index if self.state in (RUNNING, DONE) else 0xFFFF}
        for k in range(4):
            values[IR_START_TIME_US + k] = (self.start_us >> (16 * (3 - k))) & 0xFFFF
            values[IR_CLOCK_US + k] = (self.clock_us() >> (16 * (3 - k))) & 0xFFFF
        for address, value in values.items():
            reg[address] = value

    async def action(self, function_code, start_address, address, count, registers, set_values):
        def reg_set(a, v):
            registers[a - start_address] = v

        class View(dict):
            def __setitem__(_, a, v):
                reg_set(a, v)

        if function_code == 4 or (function_code == 3 and address < IR_COUNT):
            self.fill_inputs(View())
            return None
        if set_values is None:
            return None
        self.writes += 1
        if address < IR_COUNT:
            return ExcCodes.ILLEGAL_ADDRESS  # input registers are read-only
        end = address + count
        if self.state == LOADED and ((address <= HR_CHECKSUM and end > HR_LENGTH) or end > HR_ENTRIES):
            self.state = IDLE  # a changed schedule must be loaded again
        if address <= HR_COMMAND < end:
            code = set_values[HR_COMMAND - address]
            # The action runs before pymodbus stores the values: apply them first, then the command.
            for k, v in enumerate(set_values):
                registers[address + k - start_address] = v
            self.command(code, lambda a: registers[a - start_address])
            set_values[HR_COMMAND - address] = 0
        return None


class Server:
    def __init__(self):
        self.controller = Controller()
        self.port = None
        self.loop = asyncio.new_event_loop()
        self.thread = threading.Thread(target=self.loop.run_forever, daemon=True)

    def __enter__(self):
        self.thread.start()
        device = SimDevice(
            id=0,
            simdata=[SimData(0, count=IR_COUNT, values=0, datatype=DataType.REGISTERS),
                     SimData(HR_COMMAND, count=5, values=0, datatype=DataType.REGISTERS),
                     SimData(HR_ENTRIES, count=3 * CAPACITY, values=0, datatype=DataType.REGISTERS)],
            action=self.controller.action)
        for _ in range(20):
            with socket.socket() as s:  # a free loopback port
                s.bind(("127.0.0.1", 0))
                port = s.getsockname()[1]

            async def serve():
                server = ModbusTcpServer(device, address=("127.0.0.1", port))  # needs the running loop
                await server.serve_forever(background=True)
                return server

            self.server = asyncio.run_coroutine_threadsafe(serve(), self.loop).result(5)
            if self._listening(port):
                self.port = port
                return self
        raise RuntimeError("the pymodbus server did not start")

    @staticmethod
    def _listening(port):
        deadline = time.monotonic() + 3
        while time.monotonic() < deadline:
            with socket.socket() as s:
                s.settimeout(0.2)
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    return True
            time.sleep(0.02)
        return False

    def __exit__(self, *exc):
        asyncio.run_coroutine_threadsafe(self.server.shutdown(), self.loop).result(5)
        self.loop.call_soon_threadsafe(self.loop.stop)
        self.thread.join(5)


def ctl_path():
    explicit = os.environ.get("DYNBLUR_ACTUATOR_CTL")
    if explicit:
        return pathlib.Path(explicit)
    build = pathlib.Path(os.environ.get("DYNBLUR_BUILD_DIR", REPO / "build"))
    return build / "samples" / "dynblur_actuator_ctl"


def run_ctl(*args):
    tool = ctl_path()
    if not tool.exists():
        pytest.fail(f"{tool} not found: build the dynblur_actuator_ctl target or set DYNBLUR_BUILD_DIR")
    return subprocess.run([str(tool), *args], capture_output=True, text=True, timeout=30)


def write_schedule(path, times, levels, initial=0):
    path.write_text("%YAML:1.0\n---\n"
                    f"times: [ {', '.join(repr(t) for t in times)} ]\n"
                    f"levels: [ {', '.join(str(l) for l in levels)} ]\n"
                    f"initialLevel: {initial}\n")
    return path


def test_driver_uploads_and_starts_on_pymodbus(tmp_path):
    times, levels = [0.0, 0.0113, 0.0262, 0.04], [4, 10, 7, -3]
    schedule = write_schedule(tmp_path / "move.yml", times, levels)
    with Server() as server:
        before = time.monotonic()
        result = run_ctl("--bus", f"tcp://127.0.0.1:{server.port}", "--upload", str(schedule), "--start",
                         "--wait", "2", "--status")
        after = time.monotonic()
        assert result.returncode == 0, result.stderr
        started = server.controller.started
    print(result.stdout)
    assert "protocol 1.0, max level 16" in result.stdout
    assert len(started) == 1
    offsets, got_levels = started[0]
    assert offsets == [round(t * 1e6) for t in times]
    assert got_levels == levels  # the negative level crossed as int16
    m = re.search(r"start: hostStartTime=([\d.]+) uncertainty=([\d.]+)", result.stdout)
    assert m, result.stdout
    host_start, uncertainty = float(m.group(1)), float(m.group(2))
    # The C++ program's steady_clock and Python's monotonic clock are both CLOCK_MONOTONIC.
    assert before <= host_start <= after
    assert 0 < uncertainty < 0.05
    assert "status: DONE, level -3, entry 3" in result.stdout


def test_driver_refuses_unsafe_schedule_without_writing(tmp_path):
    schedule = write_schedule(tmp_path / "bad.yml", [0.0, 0.01], [4, 17])
    with Server() as server:
        writes_after_connect = None
        result = run_ctl("--bus", f"tcp://127.0.0.1:{server.port}", "--upload", str(schedule), "--start")
        writes_after_connect = server.controller.writes
        assert server.controller.started == []
    assert result.returncode == 1
    assert "levels[1] = 17 exceeds" in result.stderr
    assert writes_after_connect == 1  # only connect()'s safe-level write


def test_device_limits_are_honoured(tmp_path):
    # 70 entries > the device's advertised capacity 64: refused on the host, nothing written.
    times = [0.002 * i for i in range(70)]
    schedule = write_schedule(tmp_path / "long.yml", times, [i % 3 for i in range(70)])
    with Server() as server:
        result = run_ctl("--bus", f"tcp://127.0.0.1:{server.port}", "--upload", str(schedule))
        assert server.controller.writes == 1
    assert result.returncode == 1
    assert "device capacity = 64" in result.stderr
