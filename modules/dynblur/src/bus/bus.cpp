// SPDX-License-Identifier: Apache-2.0
// ActuatorBus: a bounded-time Modbus TCP / RTU link through libmodbus.
#include "precomp.hpp"
#include "opencv2/dynblur/bus.hpp"

#include <modbus/modbus.h>

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <thread>

namespace cv {
namespace dynblur {

namespace {

double steadyNow()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Value of `key` in a "?a=1&b=2" query, or fallback.
std::string queryValue(const std::string& query, const std::string& key, const std::string& fallback)
{
    size_t pos = 0;
    while (pos < query.size())
    {
        size_t end = query.find('&', pos);
        if (end == std::string::npos)
            end = query.size();
        const std::string item = query.substr(pos, end - pos);
        const size_t eq = item.find('=');
        if (eq != std::string::npos && item.substr(0, eq) == key)
            return item.substr(eq + 1);
        pos = end + 1;
    }
    return fallback;
}

int parseInt(const std::string& text, const std::string& what, const std::string& uri)
{
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno != 0 || v < INT_MIN || v > INT_MAX)
        CV_Error(Error::StsBadArg, "ActuatorBus::create: bad " + what + " '" + text + "' in uri '" + uri + "'");
    return static_cast<int>(v);
}

class ActuatorBusImpl CV_FINAL : public ActuatorBus
{
public:
    ActuatorBusImpl(const String& uri, double timeout, int retries) : uri_(uri)
    {
        setResponseTimeout(timeout);
        setRetries(retries);
        std::string rest, query;
        const size_t q = uri.find('?');
        if (uri.compare(0, 6, "tcp://") == 0)
        {
            rest = uri.substr(6, q == std::string::npos ? std::string::npos : q - 6);
            query = q == std::string::npos ? "" : uri.substr(q + 1);
            const size_t colon = rest.rfind(':');
            if (colon == std::string::npos || colon == 0)
                CV_Error(Error::StsBadArg, "ActuatorBus::create: uri '" + uri + "' must be tcp://HOST:PORT");
            host_ = rest.substr(0, colon);
            port_ = parseInt(rest.substr(colon + 1), "port", uri);
            if (port_ < 1 || port_ > 65535)
                CV_Error(Error::StsOutOfRange, "ActuatorBus::create: port must be in [1, 65535] in '" + uri + "'");
            unit_ = parseInt(queryValue(query, "unit", "255"), "unit", uri);
            tcp_ = true;
        }
        else if (uri.compare(0, 4, "rtu:") == 0)
        {
            size_t start = 4;
            while (start < uri.size() && uri[start] == '/' && uri.compare(start, 2, "//") == 0)
                start += 2;  // accept rtu:///dev/ttyX too
            rest = uri.substr(start, q == std::string::npos ? std::string::npos : q - start);
            query = q == std::string::npos ? "" : uri.substr(q + 1);
            if (rest.empty())
                CV_Error(Error::StsBadArg, "ActuatorBus::create: uri '" + uri + "' must be rtu:DEVICE[?baud=..]");
            host_ = rest;
            baud_ = parseInt(queryValue(query, "baud", "115200"), "baud", uri);
            if (baud_ < 50 || baud_ > 4000000)
                CV_Error(Error::StsOutOfRange, "ActuatorBus::create: baud must be in [50, 4000000] in '" + uri + "'");
            const std::string parity = queryValue(query, "parity", "N");
            if (parity != "N" && parity != "E" && parity != "O")
                CV_Error(Error::StsBadArg, "ActuatorBus::create: parity must be N, E or O in '" + uri + "'");
            parity_ = parity[0];
            unit_ = parseInt(queryValue(query, "slave", "1"), "slave", uri);
            tcp_ = false;
        }
        else
            CV_Error(Error::StsBadArg, "ActuatorBus::create: uri '" + uri +
                                           "' must start with tcp:// or rtu: (e.g. tcp://127.0.0.1:1502, rtu:/dev/ttyUSB0?baud=115200)");
        if (unit_ < 0 || unit_ > 255)
            CV_Error(Error::StsOutOfRange, "ActuatorBus::create: unit/slave id must be in [0, 255] in '" + uri + "'");
    }

    ~ActuatorBusImpl() CV_OVERRIDE { close(); }

    void connect() CV_OVERRIDE
    {
        close();
        modbus_t* ctx = tcp_ ? modbus_new_tcp(host_.c_str(), port_)
                             : modbus_new_rtu(host_.c_str(), baud_, parity_, 8, 1);
        if (!ctx)
            CV_Error(Error::StsError, "ActuatorBus: cannot create a Modbus context for '" + uri_ + "': " +
                                          modbus_strerror(errno));
        applyTimeouts(ctx);
        modbus_set_slave(ctx, unit_);
        modbus_set_error_recovery(ctx, MODBUS_ERROR_RECOVERY_NONE);
        if (modbus_connect(ctx) == -1)
        {
            const std::string why = modbus_strerror(errno);
            modbus_free(ctx);
            CV_Error(Error::StsError, "ActuatorBus: cannot connect to '" + uri_ + "': " + why);
        }
        ctx_ = ctx;
    }

    void close() CV_OVERRIDE
    {
        if (ctx_)
        {
            modbus_close(ctx_);
            modbus_free(ctx_);
            ctx_ = nullptr;
        }
    }

    bool isConnected() const CV_OVERRIDE { return ctx_ != nullptr; }

    std::vector<int> readInputRegisters(int address, int count) CV_OVERRIDE
    {
        return readRegisters(address, count, true);
    }
    std::vector<int> readHoldingRegisters(int address, int count) CV_OVERRIDE
    {
        return readRegisters(address, count, false);
    }

    void writeRegisters(int address, const std::vector<int>& values) CV_OVERRIDE
    {
        checkAddress(address, (int)values.size(), 123, "writeRegisters");
        std::vector<uint16_t> words(values.size());
        for (size_t i = 0; i < values.size(); ++i)
        {
            if (values[i] < -32768 || values[i] > 65535)
                CV_Error(Error::StsOutOfRange, cv::format("ActuatorBus::writeRegisters: values[%d] = %d must be in [-32768, 65535]",
                                                          (int)i, values[i]));
            words[i] = static_cast<uint16_t>(values[i] & 0xFFFF);
        }
        ensureConnected();
        const double t0 = steadyNow();
        const int rc = modbus_write_registers(ctx_, address, (int)words.size(), words.data());
        if (rc != (int)words.size())
            fail("write", address, (int)words.size(), rc == -1 ? errno : EMBBADDATA);
        record(t0);
    }

    void writeRegister(int address, int value) CV_OVERRIDE
    {
        checkAddress(address, 1, 1, "writeRegister");
        if (value < -32768 || value > 65535)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorBus::writeRegister: value = %d must be in [-32768, 65535]", value));
        ensureConnected();
        const double t0 = steadyNow();
        if (modbus_write_register(ctx_, address, static_cast<uint16_t>(value & 0xFFFF)) != 1)
            fail("write", address, 1, errno);
        record(t0);
    }

    String getUri() const CV_OVERRIDE { return uri_; }
    double getResponseTimeout() const CV_OVERRIDE { return timeout_; }
    void setResponseTimeout(double seconds) CV_OVERRIDE
    {
        if (!(seconds > 0 && seconds <= 60))
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorBus: responseTimeout = %g s must be in (0, 60]", seconds));
        timeout_ = seconds;
        if (ctx_)
            applyTimeouts(ctx_);
    }
    int getRetries() const CV_OVERRIDE { return retries_; }
    void setRetries(int retries) CV_OVERRIDE
    {
        if (retries < 0 || retries > 10)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorBus: retries = %d must be in [0, 10]", retries));
        retries_ = retries;
    }
    double getLastRoundTrip() const CV_OVERRIDE { return lastRoundTrip_; }
    double getLastSendTime() const CV_OVERRIDE { return lastSend_; }

private:
    void applyTimeouts(modbus_t* ctx) const
    {
        const uint32_t sec = static_cast<uint32_t>(timeout_);
        const uint32_t usec = static_cast<uint32_t>((timeout_ - sec) * 1e6);
        modbus_set_response_timeout(ctx, sec, usec);
        // Between two bytes of one reply: a short reply is reported within this time.
        const double byteTimeout = std::min(timeout_, 0.1);
        modbus_set_byte_timeout(ctx, 0, static_cast<uint32_t>(byteTimeout * 1e6));
    }

    void checkAddress(int address, int count, int maxCount, const char* fn) const
    {
        if (address < 0 || address > 65535)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorBus::%s: address = %d must be in [0, 65535]", fn, address));
        if (count < 1 || count > maxCount || address + count > 65536)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorBus::%s: count = %d must be in [1, %d] and end below 65536",
                                                      fn, count, maxCount));
    }

    void ensureConnected()
    {
        if (!ctx_)
            connect();
    }

    std::vector<int> readRegisters(int address, int count, bool input)
    {
        checkAddress(address, count, 125, input ? "readInputRegisters" : "readHoldingRegisters");
        std::vector<uint16_t> words(count);
        int lastErr = 0;
        std::string lastWhat;
        for (int attempt = 0; attempt <= retries_; ++attempt)
        {
            try
            {
                ensureConnected();
            }
            catch (const cv::Exception& e)
            {
                lastWhat = e.err;
                lastErr = -1;
                continue;
            }
            const double t0 = steadyNow();
            const int rc = input ? modbus_read_input_registers(ctx_, address, count, words.data())
                                 : modbus_read_registers(ctx_, address, count, words.data());
            if (rc == count)
            {
                record(t0);
                return std::vector<int>(words.begin(), words.end());
            }
            lastErr = rc == -1 ? errno : EMBBADDATA;
            lastWhat.clear();
            // An exception reply is an answer, not a transport fault: retrying will not help.
            if (lastErr > MODBUS_ENOBASE && lastErr < MODBUS_ENOBASE + 12)
                break;
            recover();
        }
        if (lastErr == -1)
            CV_Error(Error::StsError, cv::format("ActuatorBus: reading %s registers %d..%d on '%s' failed after %d attempts: %s",
                                                 input ? "input" : "holding", address, address + count - 1,
                                                 uri_.c_str(), retries_ + 1, lastWhat.c_str()));
        fail(input ? "read input" : "read holding", address, count, lastErr, retries_ + 1);
        return {};
    }

    // After a transport error the stream may hold stray bytes: resynchronise. A TCP stream out of
    // step cannot be trusted: reconnect on the next call (the transaction id then tells replies
    // apart). A serial line has no such id: a reply that comes after the timeout would be taken for
    // the answer to the next request (a stale acknowledgement or stale register values), so wait
    // until the line has been quiet for one response timeout, discarding what arrives (at most
    // four timeouts): a reply up to twice the timeout late is then never mistaken.
    void recover()
    {
        if (!ctx_)
            return;
        if (tcp_)
        {
            close();
            return;
        }
        const int fd = modbus_get_socket(ctx_);
        const int quietMs = std::max(1, (int)std::ceil(timeout_ * 1e3));
        const double deadline = steadyNow() + 4 * timeout_;
        modbus_flush(ctx_);
        while (steadyNow() < deadline)
        {
            pollfd p{fd, POLLIN, 0};
            if (::poll(&p, 1, quietMs) <= 0)
                break;  // quiet for a whole timeout
            std::this_thread::sleep_for(std::chrono::milliseconds(2));  // let the rest of the frame arrive
            modbus_flush(ctx_);
        }
    }

    [[noreturn]] void fail(const char* what, int address, int count, int err, int attempts = 1)
    {
        const std::string why = modbus_strerror(err);
        const bool exceptionReply = err > MODBUS_ENOBASE && err < MODBUS_ENOBASE + 12;
        if (!exceptionReply)
            recover();
        CV_Error(Error::StsError, cv::format("ActuatorBus: %s registers %d..%d on '%s' failed%s: %s%s", what, address,
                                             address + count - 1, uri_.c_str(),
                                             attempts > 1 ? cv::format(" after %d attempts", attempts).c_str() : "",
                                             exceptionReply ? "Modbus exception reply: " : "", why.c_str()));
    }

    void record(double t0)
    {
        lastSend_ = t0;
        lastRoundTrip_ = steadyNow() - t0;
    }

    String uri_;
    std::string host_;
    int port_ = 0, baud_ = 115200, unit_ = 1;
    char parity_ = 'N';
    bool tcp_ = true;
    double timeout_ = 0.5;
    int retries_ = 2;
    double lastRoundTrip_ = 0, lastSend_ = 0;
    modbus_t* ctx_ = nullptr;
};

}  // namespace

Ptr<ActuatorBus> ActuatorBus::create(const String& uri, double responseTimeout, int retries)
{
    return makePtr<ActuatorBusImpl>(uri, responseTimeout, retries);
}

}  // namespace dynblur
}  // namespace cv
