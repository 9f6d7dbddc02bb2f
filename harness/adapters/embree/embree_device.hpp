#pragma once
// harness::embree_device — what every Embree adapter (rays on triangles, user geometry,
// rtcCollide) needs of Embree 3's device: one device per adapter, created with "threads=1"
// (the harness times single-threaded work; Embree's tasking system is process-wide), the bytes
// Embree holds counted by its memory monitor (for the memory_bytes figures), and a failed call
// turned into an exception naming the adapter, the call and Embree's error code.

#include <embree3/rtcore.h>

#include <atomic>
#include <stdexcept>
#include <string>

namespace harness {

class embree_device {
public:
    // `adapter` prefixes error messages ("embree", "embree_user", ...).
    explicit embree_device(std::string adapter) : adapter_(std::move(adapter)), device_(rtcNewDevice("threads=1")) {
        if (!device_) fail("rtcNewDevice");
        rtcSetDeviceMemoryMonitorFunction(device_, &count_bytes, &bytes_);
    }
    ~embree_device() { rtcReleaseDevice(device_); }
    embree_device(const embree_device&) = delete;
    embree_device& operator=(const embree_device&) = delete;

    RTCDevice get() const { return device_; }

    // Bytes Embree holds now.
    long long bytes() const { return bytes_.load(std::memory_order_relaxed); }

    // Throws std::runtime_error naming `call` and the device's error code.
    [[noreturn]] void fail(const std::string& call) const {
        const RTCError code = device_ ? rtcGetDeviceError(device_) : RTC_ERROR_UNKNOWN;
        throw std::runtime_error(adapter_ + ": " + call + " failed (RTCError " + std::to_string(static_cast<int>(code)) + ")");
    }

    // Throws if the last calls left an error on the device.
    void check(const std::string& call) const {
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) fail(call);
    }

private:
    // Embree's memory monitor: called before each allocation with bytes > 0 and after each
    // free with bytes < 0.
    static bool count_bytes(void* user, ssize_t bytes, bool /*post*/) {
        static_cast<std::atomic<long long>*>(user)->fetch_add(static_cast<long long>(bytes), std::memory_order_relaxed);
        return true;  // never refuse an allocation
    }

    std::string adapter_;
    RTCDevice device_;
    std::atomic<long long> bytes_{0};
};

}  // namespace harness
