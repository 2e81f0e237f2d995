// What to do with each completed libusb transfer of one device session: resubmit, clear a stall,
// retire while stopping, or declare the device gone. Pure logic (no libusb) so it is tested on
// generated completion sequences. Owned by the USB event thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fovea::drivers::usb {

// Mirrors libusb_transfer_status.
enum class TransferStatus : uint8_t {
    kCompleted,
    kError,
    kTimedOut,
    kCancelled,
    kStall,
    kNoDevice,
    kOverflow
};

enum class Action : uint8_t {
    kResubmit,              // submit the same transfer again
    kClearHaltAndResubmit,  // libusb_clear_halt on the endpoint, then resubmit
    kRetire,                // leave it idle (stopping, or the device is gone)
};

class TransferSet {
public:
    struct Counters {
        uint64_t completed = 0, bytes = 0, errors = 0, timeouts = 0, stalls = 0, overflows = 0,
                 cancelled = 0, submit_failures = 0;
    };

    // `max_consecutive_errors`: errors/stalls in a row after which the device counts as gone.
    explicit TransferSet(std::size_t count, int max_consecutive_errors = 8);

    void on_submitted(std::size_t slot);
    // A submit that failed leaves the slot idle; LIBUSB_ERROR_NO_DEVICE marks the device gone.
    void on_submit_failed(std::size_t slot, bool no_device);
    Action on_complete(std::size_t slot, TransferStatus status, std::size_t bytes);
    // Closing: every later completion retires its slot. Cancel the in-flight ones yourself.
    void begin_stop() { stopping_ = true; }

    bool stopping() const { return stopping_; }
    bool gone() const { return gone_; }
    bool in_flight(std::size_t slot) const { return slots_[slot]; }
    std::size_t in_flight_count() const;
    // Safe to free transfers and release the interface.
    bool all_idle() const { return in_flight_count() == 0; }
    const Counters& counters() const { return counters_; }

private:
    std::vector<bool> slots_;  // true while in flight
    int max_errors_;
    int consecutive_errors_ = 0;
    bool stopping_ = false;
    bool gone_ = false;
    Counters counters_;
};

}  // namespace fovea::drivers::usb
