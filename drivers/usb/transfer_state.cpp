#include "usb/transfer_state.hpp"

#include <cassert>

namespace fovea::drivers::usb {

TransferSet::TransferSet(std::size_t count, int max_consecutive_errors)
    : slots_(count, false), max_errors_(max_consecutive_errors) {}

void TransferSet::on_submitted(std::size_t slot) {
    assert(!slots_[slot] && "transfer submitted twice");
    slots_[slot] = true;
}

void TransferSet::on_submit_failed(std::size_t slot, bool no_device) {
    slots_[slot] = false;
    ++counters_.submit_failures;
    if (no_device) gone_ = true;
}

std::size_t TransferSet::in_flight_count() const {
    std::size_t n = 0;
    for (bool b : slots_) n += b;
    return n;
}

Action TransferSet::on_complete(std::size_t slot, TransferStatus status, std::size_t bytes) {
    assert(slots_[slot] && "completion for a transfer not in flight");
    slots_[slot] = false;
    switch (status) {
        case TransferStatus::kCompleted:
            ++counters_.completed;
            counters_.bytes += bytes;
            consecutive_errors_ = 0;
            break;
        case TransferStatus::kTimedOut:
            ++counters_.timeouts;
            counters_.bytes += bytes;  // a timed-out transfer may still carry data
            break;
        case TransferStatus::kOverflow:
            ++counters_.overflows;  // the device sent more than the buffer: data lost, resubmit
            break;
        case TransferStatus::kStall:
            ++counters_.stalls;
            if (++consecutive_errors_ > max_errors_) gone_ = true;
            if (!stopping_ && !gone_) return Action::kClearHaltAndResubmit;
            break;
        case TransferStatus::kError:
            ++counters_.errors;
            if (++consecutive_errors_ > max_errors_) gone_ = true;
            break;
        case TransferStatus::kNoDevice: gone_ = true; break;
        case TransferStatus::kCancelled:
            ++counters_.cancelled;
            if (!stopping_) gone_ = true;  // cancelled behind our back: the session is over
            break;
    }
    if (stopping_ || gone_) return Action::kRetire;
    return Action::kResubmit;
}

}  // namespace fovea::drivers::usb
