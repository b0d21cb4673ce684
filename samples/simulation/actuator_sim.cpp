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
    std::vector<SimAxis> axes;
    SimAxisLimits limits;
    double logUntil = -1, lastLogT = -1;
    std::ofstream csv;
    int starts = 0, requests = 0;
    SimFaults faults;
    int faultBase = 0;              // requests counted before setFaults()
    std::mt19937 rng{12345};        // garbage bytes
    std::mt19937 faultRng{1};       // random fault decisions (seeded by setFaults)
    SimFaultCounts counts;
    std::deque<SimStartRecord> startLog;

    uint64_t clockUs() const
    {
        return static_cast<uint64_t>(
                   std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - epoch).count()) +
               1000000;  // the controller's clock does not start at 0
    }

    // Host steady_clock seconds of a controller clock value.
    double hostTime(uint64_t us) const
    {
        return std::chrono::duration<double>(epoch.time_since_epoch()).count() + (double(us) - 1e6) * 1e-6;
    }

    void logRow(double t)
    {
        if (!csv.is_open() || t <= lastLogT)
            return;
        csv << cv::format("%.6f", t);
        for (const SimAxis& axis : axes)
            csv << cv::format(",%.9f,%d", axis.thetaAt(t), axis.level());
        csv << "\n";
        lastLogT = t;
    }

    uint16_t* holding(int k) const { return map->tab_registers + axisHoldingBase(k); }
    int safeLevel(int k) const { return asInt16(holding(k)[HR_SAFE_LEVEL - HR_COMMAND]); }

    void refreshInputs()
    {
        uint16_t* ir = map->tab_input_registers;
        ir[IR_MAGIC] = MAGIC;
        ir[IR_VERSION] = (PROTOCOL_MAJOR << 8) | (cfg.oneAxisMap ? 0 : PROTOCOL_MINOR);
        ir[IR_MAX_LEVEL] = static_cast<uint16_t>(limits.maxLevel);
        ir[IR_MIN_DWELL_US] = static_cast<uint16_t>(limits.minDwellUs);
        ir[IR_CAPACITY] = static_cast<uint16_t>(limits.capacity);
        if (!cfg.oneAxisMap)
            ir[IR_AXIS_COUNT] = static_cast<uint16_t>(axes.size());
        const uint64_t now = clockUs();
        for (size_t k = 0; k < axes.size(); ++k)
            axes[k].fillInputs(ir + axisInputBase((int)k), now);
    }

    // One START for every axis: each LOADED axis starts at the same instant of the clock. A START
    // while an axis runs or is in FAULT, or with nothing loaded, puts every axis in FAULT.
    void startAll()
    {
        const uint64_t now = clockUs();
        bool anyLoaded = false, blocked = false;
        for (const SimAxis& axis : axes)
        {
            anyLoaded = anyLoaded || axis.state() == ACTUATOR_LOADED;
            blocked = blocked || axis.state() == ACTUATOR_RUNNING || axis.state() == ACTUATOR_FAULT;
        }
        if (blocked || !anyLoaded)
        {
            for (size_t k = 0; k < axes.size(); ++k)
                if (axes[k].state() != ACTUATOR_FAULT)
                    axes[k].enterFault(FAULT_NOT_LOADED, safeLevel((int)k), now);
            return;
        }
        logRow(now * 1e-6);  // the sample before the first switch
        for (size_t k = 0; k < axes.size(); ++k)
        {
            SimAxis& axis = axes[k];
            if (axis.state() != ACTUATOR_LOADED)
                continue;
            axis.start(now);
            logUntil = std::max(logUntil, axis.lastSwitch() + cfg.logTail);
            SimStartRecord rec;
            rec.axis = (int)k;
            rec.initialLevel = axis.initialLevel();
            rec.offsetsUs = axis.offsetsUs();
            rec.levels = axis.levels();
            rec.checksum = axis.checksum();
            startLog.push_back(std::move(rec));
            if (startLog.size() > 1000)
                startLog.pop_front();
        }
        ++starts;
    }

    // A command written to HR_COMMAND: LOAD concerns axis 0, the others every axis.
    void command(int code)
    {
        const uint64_t now = clockUs();
        switch (code)
        {
        case CMD_LOAD:
            axes[0].load(holding(0), limits, now);
            break;
        case CMD_START:
            startAll();
            break;
        case CMD_STOP:
            for (size_t k = 0; k < axes.size(); ++k)
            {
                if (axes[k].state() == ACTUATOR_RUNNING)
                    logUntil = now * 1e-6 + cfg.logTail;
                axes[k].stop(safeLevel((int)k), now);
            }
            break;
        case CMD_CLEAR_FAULT:
            for (SimAxis& axis : axes)
                axis.clearFault();
            break;
        default:
            for (size_t k = 0; k < axes.size(); ++k)
                axes[k].enterFault(FAULT_BAD_COMMAND, safeLevel((int)k), now);
        }
    }

    // A command written to a further axis's command register: LOAD only.
    void axisCommand(int k, int code)
    {
        if (code == CMD_LOAD)
            axes[k].load(holding(k), limits, clockUs());
        else
            axes[k].enterFault(FAULT_BAD_COMMAND, safeLevel(k), clockUs());
    }

    // One tick of the real-time loop: switch due entries, log a sample.
    void tick()
    {
        std::lock_guard<std::mutex> lock(mtx);
        const uint64_t now = clockUs();
        for (SimAxis& axis : axes)
            axis.tick(now);
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
    // First register after axis k's holding block.
    static int blockEnd(int k) { return k + 1 < MAX_AXES ? axisHoldingBase(k + 1) : 65536; }

    void afterWrite(int address, int count)
    {
        const int end = address + count;
        const int corrupt = faults.corruptRegister;
        if (corrupt >= address && corrupt < end)
            map->tab_registers[corrupt] ^= 1;
        for (int k = 0; k < (int)axes.size(); ++k)
        {
            const int base = axisHoldingBase(k);
            const bool touchesSchedule = (address <= base + HR_CHECKSUM - HR_COMMAND && end > base + HR_LENGTH - HR_COMMAND) ||
                                         (end > base + HR_ENTRIES - HR_COMMAND && address < blockEnd(k));
            if (touchesSchedule)
                axes[k].unload();
            if (address <= base && end > base)
            {
                const int code = map->tab_registers[base];
                map->tab_registers[base] = 0;
                if (code != CMD_NONE)
                    k == 0 ? command(code) : axisCommand(k, code);
            }
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
    CV_Assert(config.axes >= 1 && config.axes <= MAX_AXES);
    CV_Assert(config.axes == 1 || (config.capacity <= MAX_AXIS_CAPACITY && !config.oneAxisMap));
    CV_Assert((int)config.axisPlants.size() <= config.axes);
    for (int k = 0; k < config.axes; ++k)
    {
        const bool own = k < (int)config.axisPlants.size() && config.axisPlants[k];
        s.axes.emplace_back(own ? config.axisPlants[k] : s.cfg.plant, config.startLatency);
    }
    s.limits.maxLevel = config.maxLevel;
    s.limits.minDwellUs = config.minDwellUs;
    s.limits.capacity = config.capacity;
    const int lastAxis = config.axes - 1;
    const int holdingCount = axisHoldingBase(lastAxis) + (HR_ENTRIES - HR_COMMAND) + ENTRY_WORDS * config.capacity;
    const int inputCount = config.axes > 1 ? axisInputBase(lastAxis) + IR_AXIS_STRIDE
                                           : (config.oneAxisMap ? IR_COUNT : IR_AXIS_COUNT + 1);
    s.map = modbus_mapping_new_start_address(0, 0, 0, 0, 0, holdingCount, 0, inputCount);
    if (!s.map)
        CV_Error(cv::Error::StsNoMem, "ActuatorSim: cannot allocate the register map");
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
        s.csv << "t";
        for (size_t k = 0; k < s.axes.size(); ++k)
            s.csv << (s.axes.size() == 1 ? std::string(",theta,level") : cv::format(",theta%d,level%d", (int)k, (int)k));
        s.csv << "\n";
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

int ActuatorSim::axisCount() const { return (int)impl_->axes.size(); }

// The axis `axis`, checked (under the caller's lock).
static const SimAxis& axisAt(const std::vector<SimAxis>& axes, int axis)
{
    CV_Assert(axis >= 0 && axis < (int)axes.size());
    return axes[axis];
}

int ActuatorSim::state(int axis) const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    return axisAt(impl_->axes, axis).state();
}

int ActuatorSim::fault(int axis) const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    return axisAt(impl_->axes, axis).fault();
}

int ActuatorSim::currentLevel(int axis) const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    return axisAt(impl_->axes, axis).level();
}

int ActuatorSim::startCount() const { std::lock_guard<std::mutex> l(impl_->mtx); return impl_->starts; }
int ActuatorSim::requestCount() const { std::lock_guard<std::mutex> l(impl_->mtx); return impl_->requests; }

double ActuatorSim::theta(int axis) const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    return axisAt(impl_->axes, axis).thetaAt(impl_->clockUs() * 1e-6);
}

double ActuatorSim::lastStartHostTime(int axis) const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    return impl_->hostTime(axisAt(impl_->axes, axis).startUs());
}

double ActuatorSim::lastFirstSwitchHostTime(int axis) const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    const uint64_t us = axisAt(impl_->axes, axis).firstSwitchUs();
    return us ? impl_->hostTime(us) : 0.0;
}

std::string ActuatorSim::statusLine() const
{
    std::lock_guard<std::mutex> l(impl_->mtx);
    const Impl& s = *impl_;
    const double t = s.clockUs() * 1e-6;
    std::string line = cv::format("t=%.3f s", t);
    for (size_t k = 0; k < s.axes.size(); ++k)
    {
        const SimAxis& axis = s.axes[k];
        ActuatorStatus st;
        st.state = axis.state();
        st.fault = axis.fault();
        st.currentLevel = axis.level();
        st.entryIndex = axis.entryIndex();
        line += cv::format("  %s%s  theta=%.3f deg", s.axes.size() > 1 ? cv::format("axis %d: ", (int)k).c_str() : "",
                           st.describe().c_str(), axis.thetaAt(t) * 180.0 / CV_PI);
    }
    return line + cv::format("  requests=%d starts=%d", s.requests, s.starts);
}

}  // namespace dynblur_samples
