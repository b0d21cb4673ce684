// SPDX-License-Identifier: Apache-2.0
// Fuzzes the actuator driver's handling of the controller's Modbus replies (src/bus/bus.cpp through
// libmodbus, src/bus/bus_driver.cpp): a fake controller on a real loopback TCP socket answers each request
// of the driver's connect/upload/start/status/wait/stop sequence as the input says: a well-formed
// reply with registers taken from the input, a Modbus exception, a fuzzed PDU behind a correct
// header, a fuzzed header, raw bytes, silence (the client times out), or a closed connection.
//
// Input, read from the front: byte 0 the client's retries (mod 3), byte 1 the schedule length
// (1 + byte mod 45), then the script: per request one kind byte (mod REPLY_KIND_COUNT) and what that
// kind needs (register values as big-endian words, an exception code, a length byte and bytes).
// Once the script is used up the controller closes every connection. fuzz/corpus/modbus_reply/
// is made by fuzz/make_modbus_seeds.py.
// Besides crashes, sanitizer reports and hangs, the harness checks the driver's safety rule: a START
// command is never written unless upload() verified the schedule first.
#include "fuzz_common.hpp"

#include <opencv2/dynblur.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

using namespace cv::dynblur;

namespace {

//! Reads the input from the front; zeros once it is used up.
class ByteReader
{
public:
    ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
    size_t remaining() const { return size_ - pos_; }
    uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
    uint16_t word()
    {
        const int hi = byte();
        return static_cast<uint16_t>((hi << 8) | byte());
    }
    std::vector<uint8_t> bytes(size_t n)
    {
        n = std::min(n, remaining());
        std::vector<uint8_t> out(data_ + pos_, data_ + pos_ + n);
        pos_ += n;
        return out;
    }

private:
    const uint8_t* data_;
    size_t size_;
    size_t pos_ = 0;
};

enum ReplyKind
{
    REPLY_OK = 0,            //!< well-formed; holding registers from the register bank, input registers from the input
    REPLY_OK_INPUT_VALUES,   //!< well-formed; every register value from the input
    REPLY_EXCEPTION,         //!< function | 0x80 and an exception code from the input
    REPLY_FUZZED_PDU,        //!< a correct MBAP header around a PDU of input bytes
    REPLY_FUZZED_HEADER,     //!< a well-formed PDU behind an MBAP header of input bytes
    REPLY_RAW,               //!< input bytes only
    REPLY_SILENT,            //!< no reply: the client's response timeout
    REPLY_CLOSE,             //!< the connection is closed
    REPLY_KIND_COUNT
};

//! One listening socket on 127.0.0.1 for the whole run; each input gets a serving thread.
class FakeController
{
public:
    FakeController()
    {
        listenFd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        addr.sin_port = 0;
        socklen_t len = sizeof(addr);
        if (listenFd_ < 0 || ::bind(listenFd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
            ::listen(listenFd_, 16) != 0 || ::getsockname(listenFd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
            std::abort();
        port_ = ntohs(addr.sin_port);
    }

    int port() const { return port_; }

    //! Serves `script` until stop() (call from the serving thread).
    void serve(const std::vector<uint8_t>& script)
    {
        ByteReader in(script.data(), script.size());
        std::fill(bank_.begin(), bank_.end(), 0);
        startWrites_ = 0;
        while (!stop_.load())
        {
            if (!readable(listenFd_))
                continue;
            const int conn = ::accept4(listenFd_, nullptr, nullptr, SOCK_CLOEXEC);
            if (conn < 0)
                continue;
            while (!stop_.load() && in.remaining() > 0)
            {
                std::vector<uint8_t> request;
                if (!readable(conn))
                    continue;
                if (!receive(conn, request))
                    break;  // the client closed or sent garbage
                if (!answer(conn, request, in))
                    break;
            }
            closeAbortively(conn);
        }
    }

    void stop() { stop_.store(true); }
    void reset() { stop_.store(false); }
    int startWrites() const { return startWrites_; }

private:
    bool readable(int fd) const
    {
        pollfd p{fd, POLLIN, 0};
        return ::poll(&p, 1, 2) > 0;
    }

    static bool receiveAll(int fd, uint8_t* out, size_t n)
    {
        while (n > 0)
        {
            const ssize_t got = ::recv(fd, out, n, 0);
            if (got <= 0)
                return false;
            out += got;
            n -= static_cast<size_t>(got);
        }
        return true;
    }

    //! One Modbus TCP request: the 7-byte MBAP header, then length - 1 PDU bytes.
    static bool receive(int fd, std::vector<uint8_t>& request)
    {
        request.assign(7, 0);
        if (!receiveAll(fd, request.data(), 7))
            return false;
        const int length = (request[4] << 8) | request[5];
        if (length < 2 || length > 254)
            return false;
        request.resize(6 + static_cast<size_t>(length));
        return receiveAll(fd, request.data() + 7, static_cast<size_t>(length) - 1);
    }

    static void sendAll(int fd, const std::vector<uint8_t>& bytes)
    {
        size_t off = 0;
        while (off < bytes.size())
        {
            const ssize_t sent = ::send(fd, bytes.data() + off, bytes.size() - off, MSG_NOSIGNAL);
            if (sent <= 0)
                return;
            off += static_cast<size_t>(sent);
        }
    }

    static void closeAbortively(int fd)
    {
        const linger l{1, 0};  // RST: no TIME_WAIT pile-up over millions of connections
        ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &l, sizeof(l));
        ::close(fd);
    }

    static int word(const std::vector<uint8_t>& b, size_t at) { return (b[at] << 8) | b[at + 1]; }
    static void putWord(std::vector<uint8_t>& b, int w)
    {
        b.push_back(static_cast<uint8_t>((w >> 8) & 0xFF));
        b.push_back(static_cast<uint8_t>(w & 0xFF));
    }

    //! The well-formed reply PDU; updates the register bank on writes.
    std::vector<uint8_t> wellFormedPdu(const std::vector<uint8_t>& req, ByteReader& in, bool inputValues)
    {
        const uint8_t fc = req[7];
        std::vector<uint8_t> pdu{fc};
        if ((fc == 3 || fc == 4) && req.size() >= 12)
        {
            const int address = word(req, 8), count = std::min(word(req, 10), 125);
            pdu.push_back(static_cast<uint8_t>(2 * count));
            for (int i = 0; i < count; ++i)
                putWord(pdu, fc == 4 || inputValues ? in.word() : bank_[(address + i) & 0xFFFF]);
        }
        else if (fc == 6 && req.size() >= 12)
        {
            const int address = word(req, 8), value = word(req, 10);
            bank_[address] = static_cast<uint16_t>(value);
            if (address == busmap::HR_COMMAND && value == CMD_START)
                ++startWrites_;
            pdu.insert(pdu.end(), req.begin() + 8, req.begin() + 12);
        }
        else if (fc == 16 && req.size() >= 13)
        {
            const int address = word(req, 8), count = word(req, 10);
            for (int i = 0; i < count && 13 + 2 * static_cast<size_t>(i) + 1 < req.size(); ++i)
            {
                const int a = (address + i) & 0xFFFF, value = word(req, 13 + 2 * static_cast<size_t>(i));
                bank_[a] = static_cast<uint16_t>(value);
                if (a == busmap::HR_COMMAND && value == CMD_START)
                    ++startWrites_;
            }
            pdu.insert(pdu.end(), req.begin() + 8, req.begin() + 12);
        }
        else
            pdu = {static_cast<uint8_t>(fc | 0x80), 1};  // illegal function
        return pdu;
    }

    static std::vector<uint8_t> frame(const std::vector<uint8_t>& req, const std::vector<uint8_t>& pdu)
    {
        std::vector<uint8_t> out(req.begin(), req.begin() + 4);  // transaction and protocol ids
        putWord(out, static_cast<int>(pdu.size()) + 1);
        out.push_back(req[6]);  // unit id
        out.insert(out.end(), pdu.begin(), pdu.end());
        return out;
    }

    //! Sends the reply the script asks for; false closes the connection.
    bool answer(int fd, const std::vector<uint8_t>& req, ByteReader& in)
    {
        switch (static_cast<ReplyKind>(in.byte() % REPLY_KIND_COUNT))
        {
        case REPLY_OK:
            sendAll(fd, frame(req, wellFormedPdu(req, in, false)));
            return true;
        case REPLY_OK_INPUT_VALUES:
            sendAll(fd, frame(req, wellFormedPdu(req, in, true)));
            return true;
        case REPLY_EXCEPTION:
            sendAll(fd, frame(req, {static_cast<uint8_t>(req[7] | 0x80), in.byte()}));
            return true;
        case REPLY_FUZZED_PDU:
            sendAll(fd, frame(req, in.bytes(in.byte())));
            return true;
        case REPLY_FUZZED_HEADER:
        {
            std::vector<uint8_t> reply = in.bytes(7);
            reply.resize(7, 0);
            const std::vector<uint8_t> pdu = wellFormedPdu(req, in, true);
            reply.insert(reply.end(), pdu.begin(), pdu.end());
            sendAll(fd, reply);
            return true;
        }
        case REPLY_RAW:
            sendAll(fd, in.bytes(in.word() % 301));
            return true;
        case REPLY_SILENT:
            return true;
        case REPLY_CLOSE:
        default:
            return false;
        }
    }

    int listenFd_ = -1;
    int port_ = 0;
    std::atomic<bool> stop_{false};
    std::vector<uint16_t> bank_ = std::vector<uint16_t>(65536, 0);  //!< holding registers
    int startWrites_ = 0;
};

//! A schedule the host limits accept: `n` switches 2 ms apart, levels within ±16.
SwitchSchedule makeSchedule(int n)
{
    SwitchSchedule s;
    s.initialLevel = 0;
    for (int i = 0; i < n; ++i)
    {
        s.times.push_back(0.002 * i);
        s.levels.push_back((i % 2 == 0 ? 1 : -1) * (1 + i % 16));
    }
    return s;
}

//! Runs one driver call; a cv::Exception is its way to report a fault. With DYNBLUR_FUZZ_VERBOSE set
//! (when replaying one input by hand), prints each call's outcome.
template <class F>
bool attempt(const char* what, F f)
{
    static const bool verbose = std::getenv("DYNBLUR_FUZZ_VERBOSE") != nullptr;
    try
    {
        f();
        if (verbose)
            std::fprintf(stderr, "%s: ok\n", what);
        return true;
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
        if (verbose)
            std::fprintf(stderr, "%s: %s\n", what, e.err.c_str());
        return false;
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static FakeController controller;
    ByteReader in(data, size);
    const int retries = in.byte() % 3;
    const int entries = 1 + in.byte() % 45;  // above 40: two upload requests
    const std::vector<uint8_t> script = in.bytes(in.remaining());

    controller.reset();
    std::thread server([&] { controller.serve(script); });
    bool uploaded = false;
    {
        const cv::Ptr<ActuatorBus> bus =
            ActuatorBus::create(cv::format("tcp://127.0.0.1:%d", controller.port()), 0.01, retries);  // 10 ms: loopback
        const cv::Ptr<ActuatorDriver> driver = ActuatorDriver::create(bus, ActuatorLimits());
        attempt("connect", [&] { driver->connect(); });
        uploaded = attempt("upload", [&] { driver->upload(makeSchedule(entries)); });
        attempt("start", [&] { driver->start(); });
        attempt("status", [&] { (void)driver->status().describe(); });
        attempt("waitUntilDone", [&] { driver->waitUntilDone(0.0); });
        attempt("stop", [&] { driver->stop(); });
    }
    controller.stop();
    server.join();
    // Safety: START goes out only after a verified upload, and only once.
    if (controller.startWrites() > (uploaded ? 1 : 0))
        std::abort();
    return 0;
}
