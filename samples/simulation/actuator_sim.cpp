// SPDX-License-Identifier: Apache-2.0
#include "actuator_sim.hpp"

#include <modbus/modbus.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <pty.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <fstream>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

namespace dynblur_samples {

using namespace cv::dynblur;
using namespace cv::dynblur::busmap;

namespace {

int16_t asInt16(uint16_t w) { return static_cast<int16_t>(w); }

void setU64(uint16_t* regs, uint64_t v)
{
    for (int i = 3; i >= 0; --i)
    {
        regs[i] = static_cast<uint16_t>(v & 0xFFFF);
        v >>= 16;
    }
}

}  // namespace

const char* simFaultName(int kind)
{
    switch (kind)
    {
    case SIM_FAULT_DROP_REQUEST: return "drop request";
    case SIM_FAULT_DROP_REPLY: return "drop reply";
    case SIM_FAULT_DELAY: return "delay";
    case SIM_FAULT_EXCEPTION: return "exception reply";
    case SIM_FAULT_GARBAGE: return "garbage reply";
    case SIM_FAULT_SHORT: return "short reply";
    default: return "unknown";
    }
}

struct ActuatorSim::Impl
{
    SimConfig cfg;
    modbus_mapping_t* map = nullptr;
    mutable std::mutex mtx;
    std::atomic<bool> running{false};
    std::thread serverThread, plantThread;
    int listenFd = -1, port = 0;
    int ptyMaster = -1, ptySlave = -1;
    std::string ptyName;
    modbus_t* rtuCtx = nullptr;
    struct Client
    {
        int fd;
        modbus_t* ctx;
    };
    std::vector<Client> clients;
    std::chrono::steady_clock::time_point epoch = std::chrono::steady_clock::now();

    // Controller state (guarded by mtx).
    int state = ACTUATOR_IDLE, fault = FAULT_NONE, level = 0, entryIndex = -1;
    uint64_t startUs = 0;
    int loadedCrc = 0, loadedInitial = 0;
    std::vector<uint32_t> offsets;  // loaded schedule, µs from start
    std::vector<int> levels;
    SwitchSchedule history;         // every level change, controller seconds
    double logUntil = -1, lastLogT = -1;

    void logRow(double t)
    {
        if (!csv.is_open() || t <= lastLogT)
            return;
        csv << cv::format("%.6f,%.9f,%d\n", t, thetaAt(t), level);
        lastLogT = t;
    }
    std::ofstream csv;
    int starts = 0, requests = 0;
    SimFaults faults;
    int faultBase = 0;              // requests counted before setFaults()
    std::mt19937 rng{12345};        // garbage bytes
    std::mt19937 faultRng{1};       // random fault decisions (seeded by setFaults)
    SimFaultCounts counts;
    std::deque<SimStartRecord> startLog;
    double historyHorizon = -1;     // s after which a switch no longer moves θ (< 1e-12); -1: keep all

    uint64_t clockUs() const
    {
        return static_cast<uint64_t>(
                   std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - epoch).count()) +
               1000000;  // the controller's clock does not start at 0
    }

    void applyLevel(int newLevel, double tSec)
    {
        if (newLevel == level)
            return;
        if (!history.times.empty() && tSec <= history.times.back())
            tSec = history.times.back() + 1e-6;
        history.times.push_back(tSec);
        history.levels.push_back(newLevel);
        level = newLevel;
        pruneHistory(tSec);
    }

    // θ is only evaluated from now on, where a switch older than the horizon contributes less than
    // e^-28 of its step: fold such switches into the initial level so that the history (and the
    // cost of thetaAt) stays bounded however long the simulator runs.
    void pruneHistory(double nowSec)
    {
        if (historyHorizon <= 0 || history.times.size() < 64)
            return;
        size_t k = 0;  // entries [0, k) are older than the horizon
        while (k + 1 < history.times.size() && history.times[k] < nowSec - historyHorizon)
            ++k;
        if (k < 32)
            return;
        history.initialLevel = history.levels[k - 1];
        history.times.erase(history.times.begin(), history.times.begin() + k);
        history.levels.erase(history.levels.begin(), history.levels.begin() + k);
    }

    double thetaAt(double tSec) const
    {
        if (history.times.empty())
            return cfg.plant->restingAngle(history.initialLevel);
        cv::Mat out;
        cfg.plant->response(history, cv::Mat(1, 1, CV_64F, cv::Scalar(tSec - cfg.startLatency)), out);
        return out.at<double>(0);
    }

    int safeLevel() const { return asInt16(map->tab_registers[HR_SAFE_LEVEL]); }

    void enterFault(int code)
    {
        state = ACTUATOR_FAULT;
        fault = code;
        entryIndex = -1;
        applyLevel(safeLevel(), clockUs() * 1e-6);
    }

    void refreshInputs()
    {
        uint16_t* ir = map->tab_input_registers;
        ir[IR_MAGIC] = MAGIC;
        ir[IR_VERSION] = (PROTOCOL_MAJOR << 8) | PROTOCOL_MINOR;
        ir[IR_STATUS] = static_cast<uint16_t>(state);
        ir[IR_FAULT] = static_cast<uint16_t>(fault);
        ir[IR_MAX_LEVEL] = static_cast<uint16_t>(cfg.maxLevel);
        ir[IR_MIN_DWELL_US] = static_cast<uint16_t>(cfg.minDwellUs);
        ir[IR_CAPACITY] = static_cast<uint16_t>(cfg.capacity);
        ir[IR_CURRENT_LEVEL] = static_cast<uint16_t>(level & 0xFFFF);
        setU64(ir + IR_START_TIME_US, startUs);
        setU64(ir + IR_CLOCK_US, clockUs());
        ir[IR_LOADED_CHECKSUM] = static_cast<uint16_t>(state == ACTUATOR_LOADED ? loadedCrc : 0);
        ir[IR_ENTRY_INDEX] = static_cast<uint16_t>(entryIndex < 0 ? 0xFFFF : entryIndex);
    }

    void load()
    {
        const uint16_t* hr = map->tab_registers;
        const int n = hr[HR_LENGTH];
        if (n < 1 || n > cfg.capacity)
            return enterFault(FAULT_BAD_LENGTH);
        std::vector<int> regs = {n, hr[HR_INITIAL_LEVEL]};
        for (int i = 0; i < n * ENTRY_WORDS; ++i)
            regs.push_back(hr[HR_ENTRIES + i]);
        const int crc = busChecksum(regs);
        if (crc != hr[HR_CHECKSUM])
            return enterFault(FAULT_BAD_CHECKSUM);
        offsets.assign(n, 0);
        levels.assign(n, 0);
        loadedInitial = asInt16(hr[HR_INITIAL_LEVEL]);
        if (std::abs(asInt16(hr[HR_INITIAL_LEVEL])) > cfg.maxLevel)
            return enterFault(FAULT_LEVEL_RANGE);
        for (int i = 0; i < n; ++i)
        {
            const uint16_t* e = hr + HR_ENTRIES + ENTRY_WORDS * i;
            offsets[i] = (static_cast<uint32_t>(e[0]) << 16) | e[1];
            levels[i] = asInt16(e[2]);
            if (std::abs(levels[i]) > cfg.maxLevel)
                return enterFault(FAULT_LEVEL_RANGE);
            if ((i == 0 && offsets[0] != 0) ||
                (i > 0 && (offsets[i] <= offsets[i - 1] || offsets[i] - offsets[i - 1] < (uint32_t)cfg.minDwellUs)))
                return enterFault(FAULT_DWELL);
        }
        state = ACTUATOR_LOADED;
        fault = FAULT_NONE;
        loadedCrc = crc;
    }

    void command(int code)
    {
        switch (code)
        {
        case CMD_LOAD:
            if (state == ACTUATOR_RUNNING)
                return;  // ignored while running
            load();
            break;
        case CMD_START:
            if (state != ACTUATOR_LOADED)
                return enterFault(FAULT_NOT_LOADED);
            startUs = clockUs();
            logRow(startUs * 1e-6);  // the sample before the first switch
            state = ACTUATOR_RUNNING;
            entryIndex = 0;
            applyLevel(levels[0], startUs * 1e-6);
            logUntil = (startUs + offsets.back()) * 1e-6 + cfg.logTail;
            ++starts;
            {
                SimStartRecord rec;
                rec.initialLevel = loadedInitial;
                rec.offsetsUs = offsets;
                rec.levels = levels;
                rec.checksum = loadedCrc;
                startLog.push_back(std::move(rec));
                if (startLog.size() > 1000)
                    startLog.pop_front();
            }
            if (offsets.size() == 1)
                state = ACTUATOR_DONE;
            break;
        case CMD_STOP:
            applyLevel(safeLevel(), clockUs() * 1e-6);
            if (state == ACTUATOR_RUNNING)
                logUntil = clockUs() * 1e-6 + cfg.logTail;
            if (state != ACTUATOR_FAULT)
                state = ACTUATOR_IDLE;
            entryIndex = -1;
            break;
        case CMD_CLEAR_FAULT:
            if (state == ACTUATOR_FAULT)
            {
                state = ACTUATOR_IDLE;
                fault = FAULT_NONE;
            }
            break;
        default:
            enterFault(FAULT_BAD_COMMAND);
        }
    }

    // One tick of the real-time loop: switch due entries, log a sample.
    void tick()
    {
        std::lock_guard<std::mutex> lock(mtx);
        const uint64_t now = clockUs();
        if (state == ACTUATOR_RUNNING)
        {
            while (entryIndex + 1 < (int)offsets.size() && startUs + offsets[entryIndex + 1] <= now)
            {
                ++entryIndex;
                applyLevel(levels[entryIndex], (startUs + offsets[entryIndex]) * 1e-6);
            }
            if (entryIndex + 1 == (int)offsets.size())
                state = ACTUATOR_DONE;
        }
        if (now * 1e-6 <= logUntil)
            logRow(now * 1e-6);
    }

    void plantLoop()
    {
        const auto period = std::chrono::duration<double>(1.0 / cfg.logRateHz);
        auto next = std::chrono::steady_clock::now();
        while (running)
        {
            tick();
            next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
            const auto now = std::chrono::steady_clock::now();
            if (next < now)
                next = now;  // fell behind: skip, do not burst
            std::this_thread::sleep_until(next);
        }
        std::lock_guard<std::mutex> lock(mtx);
        if (csv.is_open())
            csv.flush();
    }

    // A write's effect on the controller once its values are in the map: a changed schedule must
    // be loaded (checked) again, and a command is executed.
    void afterWrite(int address, int count)
    {
        const int end = address + count;
        const bool touchesSchedule = (address <= HR_CHECKSUM && end > HR_LENGTH) || end > HR_ENTRIES;
        if (touchesSchedule && state == ACTUATOR_LOADED)
            state = ACTUATOR_IDLE;
        if (address <= HR_COMMAND && end > HR_COMMAND)
        {
            const int code = map->tab_registers[HR_COMMAND];
            map->tab_registers[HR_COMMAND] = 0;
            if (code != CMD_NONE)
                command(code);
        }
    }

    // Executes a write request without answering it (modbus_reply both executes and answers).
    void executeWrite(const uint8_t* query, int length, int hl, int fc, int address, int count)
    {
        if (address + count > map->nb_registers)
            return;  // out of the map: it would get an exception reply, nothing is written
        if (fc == 6)
            map->tab_registers[address] = static_cast<uint16_t>((query[hl + 3] << 8) | query[hl + 4]);
        else
        {
            if (query[hl + 5] != 2 * count || length < hl + 6 + 2 * count)
                return;
            for (int i = 0; i < count; ++i)
                map->tab_registers[address + i] = static_cast<uint16_t>((query[hl + 6 + 2 * i] << 8) | query[hl + 7 + 2 * i]);
        }
        afterWrite(address, count);
    }

    // The fault of this request, if any (under mtx): one-shot faults first, then a random draw.
    int chooseFault(int n, int fc, int address, int count, bool& executed, int& delayMs, int& exceptionCode)
    {
        SimFaults& f = faults;
        executed = false;
        delayMs = f.delayMs;
        exceptionCode = f.exceptionCode;
        int kind = -1;
        if (f.dropAfter > 0 && n == f.dropAfter)
        {
            f.dropAfter = -1;
            kind = SIM_FAULT_DROP_REQUEST;
        }
        else if (f.garbageAfter > 0 && n == f.garbageAfter)
        {
            f.garbageAfter = -1;
            kind = SIM_FAULT_GARBAGE;
        }
        else if (f.shortAfter > 0 && n == f.shortAfter)
        {
            f.shortAfter = -1;
            kind = SIM_FAULT_SHORT;
        }
        else if (fc == f.exceptionFunction &&
                 (f.exceptionRegister < 0 || (f.exceptionRegister >= address && f.exceptionRegister < address + count)))
            kind = SIM_FAULT_EXCEPTION;
        else if (f.randomRate > 0 && std::uniform_real_distribution<double>(0.0, 1.0)(faultRng) < f.randomRate)
        {
            std::vector<int> kinds;
            for (int k = 0; k < SIM_FAULT_KINDS; ++k)
                if (f.randomKinds & (1 << k))
                    kinds.push_back(k);
            if (!kinds.empty())
            {
                kind = kinds[std::uniform_int_distribution<int>(0, (int)kinds.size() - 1)(faultRng)];
                const bool coin = (faultRng() & 1) != 0;
                executed = kind == SIM_FAULT_DROP_REPLY || kind == SIM_FAULT_DELAY ||
                           ((kind == SIM_FAULT_GARBAGE || kind == SIM_FAULT_SHORT) && coin);
                if (kind == SIM_FAULT_DELAY)
                    delayMs = std::max(delayMs, f.randomDelayMs);
                exceptionCode = f.randomExceptionCode;
            }
        }
        if (kind < 0 && delayMs > 0)
            kind = SIM_FAULT_DELAY;  // every reply delayed
        if (kind >= 0)
        {
            ++counts.byKind[kind];
            ++counts.total;
            if ((fc == 3 || fc == 4) && kind != SIM_FAULT_EXCEPTION)
                ++counts.retriableOnReads;
        }
        return kind;
    }

    // Returns false when the connection must be closed (drop faults).
    bool handle(modbus_t* ctx, int fd, bool tcp, const uint8_t* query, int length)
    {
        const int hl = modbus_get_header_length(ctx);
        const int fc = query[hl];
        const int address = (query[hl + 1] << 8) | query[hl + 2];
        const int count = (fc == 3 || fc == 4 || fc == 16) ? ((query[hl + 3] << 8) | query[hl + 4]) : 1;
        const bool write = fc == 6 || fc == 16;
        bool executed = false;
        int delayMs = 0, exceptionCode = 4, kind = -1;
        {
            std::lock_guard<std::mutex> lock(mtx);
            kind = chooseFault(++requests - faultBase, fc, address, count, executed, delayMs, exceptionCode);
        }
        if (kind == SIM_FAULT_DROP_REQUEST)
            return false;
        if (delayMs > 0)
            std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
        auto rawSend = [&](const std::vector<uint8_t>& bytes) {
            if (tcp)
                (void)!::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
            else
                (void)!::write(fd, bytes.data(), bytes.size());
        };
        if (kind == SIM_FAULT_EXCEPTION)
        {
            modbus_reply_exception(ctx, query, static_cast<unsigned>(exceptionCode));
            return true;
        }
        if (kind == SIM_FAULT_DROP_REPLY || kind == SIM_FAULT_GARBAGE || kind == SIM_FAULT_SHORT)
        {
            std::lock_guard<std::mutex> lock(mtx);
            if (executed && write)
                executeWrite(query, length, hl, fc, address, count);
            if (kind == SIM_FAULT_DROP_REPLY)
                return false;
            if (kind == SIM_FAULT_GARBAGE)
            {
                std::vector<uint8_t> junk(11);
                for (auto& b : junk)
                    b = static_cast<uint8_t>(rng() & 0xFF);
                rawSend(junk);
                return true;
            }
            // The start of a plausible reply, cut off after two data bytes.
            std::vector<uint8_t> part(query, query + hl);
            if (tcp)
            {
                const int pdu = 2 + 2 * count;  // fc, byte count, data
                part[4] = static_cast<uint8_t>((pdu + 1) >> 8);
                part[5] = static_cast<uint8_t>((pdu + 1) & 0xFF);
            }
            part.push_back(static_cast<uint8_t>(fc));
            part.push_back(static_cast<uint8_t>(2 * count));
            part.push_back(0);
            part.push_back(0);
            rawSend(part);
            return true;
        }
        std::lock_guard<std::mutex> lock(mtx);
        refreshInputs();
        // modbus_reply executes the request, then answers; the answer may be lost (the peer gave up
        // waiting), the execution is not: the controller acts on what it received.
        modbus_reply(ctx, query, length, map);
        if (write && address + count <= map->nb_registers)
            afterWrite(address, count);
        return true;
    }

    void closeClient(size_t i)
    {
        modbus_free(clients[i].ctx);
        ::close(clients[i].fd);
        clients.erase(clients.begin() + i);
    }

    void serverLoop()
    {
        std::vector<uint8_t> query(MODBUS_TCP_MAX_ADU_LENGTH > MODBUS_RTU_MAX_ADU_LENGTH ? MODBUS_TCP_MAX_ADU_LENGTH
                                                                                        : MODBUS_RTU_MAX_ADU_LENGTH);
        while (running)
        {
            std::vector<pollfd> fds;
            if (listenFd >= 0)
                fds.push_back({listenFd, POLLIN, 0});
            if (ptyMaster >= 0)
                fds.push_back({ptyMaster, POLLIN, 0});
            for (const Client& c : clients)
                fds.push_back({c.fd, POLLIN, 0});
            if (::poll(fds.data(), fds.size(), 20) <= 0)
                continue;
            size_t k = 0;
            if (listenFd >= 0)
            {
                if (fds[k].revents & POLLIN)
                {
                    const int fd = ::accept(listenFd, nullptr, nullptr);
                    if (fd >= 0)
                    {
                        modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
                        modbus_set_socket(ctx, fd);
                        modbus_set_indication_timeout(ctx, 0, 200000);
                        modbus_set_byte_timeout(ctx, 0, 200000);
                        clients.push_back({fd, ctx});
                    }
                }
                ++k;
            }
            if (ptyMaster >= 0)
            {
                if (fds[k].revents & POLLIN)
                {
                    const int rc = modbus_receive(rtuCtx, query.data());
                    if (rc > 0)
                        handle(rtuCtx, ptyMaster, false, query.data(), rc);
                    else if (rc == -1)
                        modbus_flush(rtuCtx);
                }
                ++k;
            }
            // Requests are served in the order the connections were opened, which is the order a
            // host sends them in: a request left on a connection the host gave up on is executed
            // before the requests that followed it on a new connection, as by a device that reads
            // one queue. Clients accepted in this round have no entry in fds yet.
            const size_t polled = fds.size() - k;
            std::vector<size_t> finished;
            for (size_t i = 0; i < polled; ++i)
            {
                if (!(fds[k + i].revents & (POLLIN | POLLHUP | POLLERR)))
                    continue;
                const int rc = modbus_receive(clients[i].ctx, query.data());
                bool keep = rc >= 0;
                if (rc > 0)
                    keep = handle(clients[i].ctx, clients[i].fd, true, query.data(), rc);
                if (!keep)
                    finished.push_back(i);
            }
            for (size_t j = finished.size(); j-- > 0;)
                closeClient(finished[j]);
        }
    }
};

ActuatorSim::ActuatorSim(const SimConfig& config) : impl_(new Impl)
{
    Impl& s = *impl_;
    s.cfg = config;
    if (!s.cfg.plant)
        s.cfg.plant = Plant::create(14.4, 0.12, CV_PI / 180.0);
    CV_Assert(config.maxLevel >= 0 && config.maxLevel <= 32767);
    CV_Assert(config.minDwellUs >= 0 && config.minDwellUs <= 65535);
    CV_Assert(config.capacity >= 1 && config.capacity <= 5000);
    CV_Assert(config.logRateHz >= 1 && config.logRateHz <= 20000);
    CV_Assert(config.logTail >= 0);
    CV_Assert(config.tcpPort >= 0 && config.tcpPort <= 65535);
    s.map = modbus_mapping_new_start_address(0, 0, 0, 0, 0, HR_ENTRIES + ENTRY_WORDS * s.cfg.capacity, 0, IR_COUNT);
    if (!s.map)
        CV_Error(cv::Error::StsNoMem, "ActuatorSim: cannot allocate the register map");
    s.history.initialLevel = 0;
    const double sigma = 2 * CV_PI * s.cfg.plant->getNaturalFreqHz() * s.cfg.plant->getDampingRatio();
    if (sigma > 0 && std::isfinite(sigma))
        s.historyHorizon = 28.0 / sigma;  // e^-28 < 1e-12
}

ActuatorSim::~ActuatorSim()
{
    stop();
    modbus_mapping_free(impl_->map);
}

void ActuatorSim::start()
{
    Impl& s = *impl_;
    CV_Assert(!s.running);
    if (!s.cfg.csvPath.empty())
    {
        s.csv.open(s.cfg.csvPath);
        if (!s.csv)
            CV_Error(cv::Error::StsError, "ActuatorSim: cannot write the log '" + s.cfg.csvPath + "'");
        s.csv << "t,theta,level\n";
    }
    if (s.cfg.tcp)
    {
        s.listenFd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        const int one = 1;
        ::setsockopt(s.listenFd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = htons(static_cast<uint16_t>(s.cfg.tcpPort));
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // loopback only, never any other address
        if (::bind(s.listenFd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 || ::listen(s.listenFd, 8) != 0)
        {
            const std::string why = std::strerror(errno);
            ::close(s.listenFd);
            s.listenFd = -1;
            CV_Error(cv::Error::StsError, cv::format("ActuatorSim: cannot listen on 127.0.0.1:%d: %s", s.cfg.tcpPort, why.c_str()));
        }
        socklen_t len = sizeof(addr);
        ::getsockname(s.listenFd, reinterpret_cast<sockaddr*>(&addr), &len);
        s.port = ntohs(addr.sin_port);
    }
    if (s.cfg.rtu)
    {
        char name[256] = {0};
        if (::openpty(&s.ptyMaster, &s.ptySlave, name, nullptr, nullptr) != 0)
            CV_Error(cv::Error::StsError, std::string("ActuatorSim: openpty failed: ") + std::strerror(errno));
        termios tio{};
        ::tcgetattr(s.ptySlave, &tio);
        ::cfmakeraw(&tio);
        ::tcsetattr(s.ptySlave, TCSANOW, &tio);
        ::fcntl(s.ptyMaster, F_SETFD, FD_CLOEXEC);
        ::fcntl(s.ptySlave, F_SETFD, FD_CLOEXEC);
        s.ptyName = name;
        s.rtuCtx = modbus_new_rtu(name, 115200, 'N', 8, 1);
        modbus_set_slave(s.rtuCtx, s.cfg.rtuSlave);
        modbus_set_socket(s.rtuCtx, s.ptyMaster);
        modbus_set_indication_timeout(s.rtuCtx, 0, 200000);
        modbus_set_byte_timeout(s.rtuCtx, 0, 50000);
    }
    {
        std::lock_guard<std::mutex> lock(s.mtx);
        s.refreshInputs();
    }
    s.running = true;
    s.serverThread = std::thread([&s] { s.serverLoop(); });
    s.plantThread = std::thread([&s] { s.plantLoop(); });
}

void ActuatorSim::stop()
{
    Impl& s = *impl_;
    if (!s.running)
        return;
    s.running = false;
    s.serverThread.join();
    s.plantThread.join();
    while (!s.clients.empty())
        s.closeClient(s.clients.size() - 1);
    if (s.listenFd >= 0)
        ::close(s.listenFd);
    s.listenFd = -1;
    if (s.rtuCtx)
        modbus_free(s.rtuCtx);  // does not close the fd
    s.rtuCtx = nullptr;
    if (s.ptyMaster >= 0)
        ::close(s.ptyMaster);
    if (s.ptySlave >= 0)
        ::close(s.ptySlave);
    s.ptyMaster = s.ptySlave = -1;
    if (s.csv.is_open())
        s.csv.close();
}

int ActuatorSim::tcpPort() const { return impl_->port; }
std::string ActuatorSim::ptyPath() const { return impl_->ptyName; }

void ActuatorSim::setFaults(const SimFaults& faults)
{
    CV_Assert(faults.randomRate >= 0 && faults.randomRate <= 1);
    CV_Assert(faults.delayMs >= 0 && faults.randomDelayMs >= 0);
    std::lock_guard<std::mutex> lock(impl_->mtx);
    impl_->faults = faults;
    impl_->faultBase = impl_->requests;
    impl_->faultRng.seed(faults.randomSeed);
}

SimFaultCounts ActuatorSim::faultCounts() const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    return impl_->counts;
}

std::vector<SimStartRecord> ActuatorSim::takeStarts()
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    std::vector<SimStartRecord> out(impl_->startLog.begin(), impl_->startLog.end());
    impl_->startLog.clear();
    return out;
}

int ActuatorSim::state() const { std::lock_guard<std::mutex> l(impl_->mtx); return impl_->state; }
int ActuatorSim::fault() const { std::lock_guard<std::mutex> l(impl_->mtx); return impl_->fault; }
int ActuatorSim::currentLevel() const { std::lock_guard<std::mutex> l(impl_->mtx); return impl_->level; }
int ActuatorSim::startCount() const { std::lock_guard<std::mutex> l(impl_->mtx); return impl_->starts; }
int ActuatorSim::requestCount() const { std::lock_guard<std::mutex> l(impl_->mtx); return impl_->requests; }

double ActuatorSim::theta() const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    return impl_->thetaAt(impl_->clockUs() * 1e-6);
}

double ActuatorSim::lastStartHostTime() const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    const Impl& s = *impl_;
    return std::chrono::duration<double>(s.epoch.time_since_epoch()).count() + (double(s.startUs) - 1e6) * 1e-6;
}

std::string ActuatorSim::statusLine() const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    const Impl& s = *impl_;
    ActuatorStatus st;
    st.state = s.state;
    st.fault = s.fault;
    st.currentLevel = s.level;
    st.entryIndex = s.entryIndex;
    return cv::format("t=%.3f s  %s  theta=%.3f deg  requests=%d starts=%d", s.clockUs() * 1e-6, st.describe().c_str(),
                      s.thetaAt(s.clockUs() * 1e-6) * 180.0 / CV_PI, s.requests, s.starts);
}

}  // namespace dynblur_samples
