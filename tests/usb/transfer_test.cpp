// The USB transfer state machine and the frame stream on generated transfer sequences: the serial
// protocol's frames chopped into transfers of random sizes, with timeouts, overflows, stalls,
// errors and unplugging.
#include <gtest/gtest.h>

#include <random>

#include "serial/protocol.hpp"
#include "usb/frame_stream.hpp"
#include "usb/transfer_state.hpp"

using namespace fovea::drivers::usb;
namespace serial = fovea::drivers::serial;

namespace {

fovea::gaze::RawSample make_sample(uint32_t i) {
    fovea::gaze::RawSample s;
    s.device_ticks = 1000u * i;
    s.left = {0.25 + 1e-4 * i, 0.5, 3.5, true};
    s.right = {0.26 + 1e-4 * i, 0.5, 3.4, true};
    return s;
}

std::vector<uint8_t> hello_bytes() {
    serial::Hello h;
    h.name = "usb test tracker";
    h.counter_bits = 32;
    std::vector<uint8_t> out;
    serial::encode_hello(h, 0, out);
    return out;
}

TEST(UsbTransferSet, CompletedTransfersAreResubmittedAndCounted) {
    TransferSet set(4);
    for (std::size_t i = 0; i < 4; ++i) set.on_submitted(i);
    EXPECT_EQ(set.in_flight_count(), 4u);
    EXPECT_EQ(set.on_complete(2, TransferStatus::kCompleted, 64), Action::kResubmit);
    EXPECT_FALSE(set.in_flight(2));
    set.on_submitted(2);
    EXPECT_EQ(set.on_complete(0, TransferStatus::kTimedOut, 3), Action::kResubmit);
    EXPECT_EQ(set.on_complete(1, TransferStatus::kOverflow, 0), Action::kResubmit);
    EXPECT_EQ(set.counters().completed, 1u);
    EXPECT_EQ(set.counters().bytes, 67u);
    EXPECT_EQ(set.counters().timeouts, 1u);
    EXPECT_EQ(set.counters().overflows, 1u);
    EXPECT_FALSE(set.gone());
}

TEST(UsbTransferSet, StallAsksForClearHaltAndPersistentErrorsMeanGone) {
    TransferSet set(1, 3);
    set.on_submitted(0);
    EXPECT_EQ(set.on_complete(0, TransferStatus::kStall, 0), Action::kClearHaltAndResubmit);
    for (int i = 0; i < 3; ++i) {
        set.on_submitted(0);
        const auto a = set.on_complete(0, TransferStatus::kError, 0);
        EXPECT_EQ(a, i < 2 ? Action::kResubmit : Action::kRetire) << i;
    }
    EXPECT_TRUE(set.gone());
    TransferSet recovers(1, 3);
    for (int i = 0; i < 20; ++i) {  // errors separated by good transfers never add up
        recovers.on_submitted(0);
        recovers.on_complete(0, i % 2 ? TransferStatus::kCompleted : TransferStatus::kError, 1);
    }
    EXPECT_FALSE(recovers.gone());
}

TEST(UsbTransferSet, NoDeviceRetiresEveryTransfer) {
    TransferSet set(3);
    for (std::size_t i = 0; i < 3; ++i) set.on_submitted(i);
    EXPECT_EQ(set.on_complete(1, TransferStatus::kNoDevice, 0), Action::kRetire);
    EXPECT_TRUE(set.gone());
    EXPECT_EQ(set.on_complete(0, TransferStatus::kCompleted, 10), Action::kRetire);
    EXPECT_EQ(set.on_complete(2, TransferStatus::kError, 0), Action::kRetire);
    EXPECT_TRUE(set.all_idle());
}

TEST(UsbTransferSet, StoppingRetiresCancelledTransfersUntilAllIdle) {
    TransferSet set(4);
    for (std::size_t i = 0; i < 4; ++i) set.on_submitted(i);
    set.begin_stop();
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_FALSE(set.all_idle());
        EXPECT_EQ(
            set.on_complete(i, i == 3 ? TransferStatus::kCompleted : TransferStatus::kCancelled, 0),
            Action::kRetire);
    }
    EXPECT_TRUE(set.all_idle());
    EXPECT_FALSE(set.gone());
    EXPECT_EQ(set.counters().cancelled, 3u);
}

TEST(UsbTransferSet, UnexpectedCancelEndsTheSessionAndSubmitFailureFreesTheSlot) {
    TransferSet set(2);
    set.on_submitted(0);
    EXPECT_EQ(set.on_complete(0, TransferStatus::kCancelled, 0), Action::kRetire);
    EXPECT_TRUE(set.gone());
    TransferSet s2(2);
    s2.on_submit_failed(0, false);
    EXPECT_FALSE(s2.gone());
    s2.on_submit_failed(1, true);
    EXPECT_TRUE(s2.gone());
    EXPECT_EQ(s2.counters().submit_failures, 2u);
}

// A simulated device session: frames chopped into transfers; the test drives completions the way
// libusb would and checks that every frame in a delivered transfer arrives.
TEST(UsbFrameStream, EveryFrameInADeliveredTransferArrivesWhateverTheChunking) {
    std::mt19937 rng(1234);
    for (int round = 0; round < 20; ++round) {
        std::vector<uint8_t> wire = hello_bytes();
        const uint32_t n = 500;
        for (uint32_t i = 0; i < n; ++i)
            serial::encode_sample(make_sample(i), static_cast<uint16_t>(i + 1), wire);
        TransferSet set(4);
        FrameStream stream;
        std::vector<fovea::gaze::RawSample> out;
        for (std::size_t i = 0; i < 4; ++i) set.on_submitted(i);
        std::size_t pos = 0, slot = 0;
        std::uniform_int_distribution<std::size_t> size(1, 512);
        std::uniform_int_distribution<int> kind(0, 99);
        uint64_t timeouts = 0;
        while (pos < wire.size()) {
            const std::size_t len = std::min(size(rng), wire.size() - pos);
            // 5 % of transfers time out carrying what had arrived: that data counts too.
            const bool timeout = kind(rng) < 5;
            timeouts += timeout;
            stream.feed({wire.data() + pos, len}, 1, 9, out);
            const auto a = set.on_complete(
                slot, timeout ? TransferStatus::kTimedOut : TransferStatus::kCompleted, len);
            ASSERT_EQ(a, Action::kResubmit);
            set.on_submitted(slot);
            slot = (slot + 1) % 4;
            pos += len;
        }
        ASSERT_EQ(out.size(), n) << "round " << round;
        for (uint32_t i = 0; i < n; ++i) {
            EXPECT_EQ(out[i].device_ticks, 1000u * i);
            EXPECT_NEAR(out[i].left.x, 0.25 + 1e-4 * i, 1e-6);
            EXPECT_EQ(out[i].device_id, 9u);
        }
        EXPECT_EQ(set.counters().bytes, wire.size());
        EXPECT_EQ(set.counters().timeouts, timeouts);
        EXPECT_EQ(stream.counters().lost, 0u);
        EXPECT_EQ(stream.counters().dropped, 0u);
        ASSERT_TRUE(stream.hello());
        EXPECT_EQ(stream.hello()->name, "usb test tracker");
    }
}

TEST(UsbFrameStream, LostTransfersCostOnlyTheirFramesAndAreCounted) {
    std::vector<std::vector<uint8_t>> transfers;
    transfers.push_back(hello_bytes());
    for (uint32_t i = 0; i < 301; ++i) {  // frame 301 (delivered) closes the last gap
        std::vector<uint8_t> frame;
        serial::encode_sample(make_sample(i), static_cast<uint16_t>(i + 1), frame);
        transfers.push_back(frame);  // one frame per interrupt transfer
    }
    FrameStream stream;
    std::vector<fovea::gaze::RawSample> out;
    uint32_t overflowed = 0;
    for (std::size_t t = 0; t < transfers.size(); ++t) {
        if (t > 1 && t % 10 == 0) {  // overflow: the transfer's data never reaches us
            ++overflowed;
            continue;
        }
        // Some transfers arrive torn in half with garbage glued in between.
        if (t % 7 == 3) {
            const auto& f = transfers[t];
            const std::size_t half = f.size() / 2;
            stream.feed({f.data(), half}, 0, 0, out);
            const uint8_t junk[] = {0x00, 0x13, 0x37, 0xFF, 0x00};
            stream.feed(junk, 0, 0, out);
            stream.feed({f.data() + half, f.size() - half}, 0, 0, out);
            continue;
        }
        stream.feed(transfers[t], 0, 0, out);
    }
    // A torn transfer loses its own frame (the junk's 0x00 ends it early) and nothing else.
    uint32_t torn = 0;
    for (std::size_t t = 1; t < transfers.size(); ++t)
        torn += (t % 7 == 3) && !(t > 1 && t % 10 == 0);
    EXPECT_EQ(out.size(), 301u - overflowed - torn);
    EXPECT_EQ(stream.counters().lost, overflowed + torn);  // every gap seen in the sequence
    EXPECT_EQ(stream.counters().dropped, 3u * torn);       // first half, junk, second half
}

TEST(UsbFrameStream, SamplesBeforeHelloAreDroppedAndResetForgetsTheSession) {
    std::vector<uint8_t> wire;
    serial::encode_sample(make_sample(1), 1, wire);
    FrameStream stream;
    std::vector<fovea::gaze::RawSample> out;
    stream.feed(wire, 0, 0, out);
    EXPECT_TRUE(out.empty());
    EXPECT_EQ(stream.counters().dropped, 1u);
    const auto hello = hello_bytes();
    stream.feed(hello, 0, 0, out);
    stream.feed(wire, 0, 0, out);
    EXPECT_EQ(out.size(), 1u);
    // Unplugged mid-frame: the partial frame is discarded with the session.
    stream.feed({wire.data(), wire.size() / 2}, 0, 0, out);
    stream.reset();
    EXPECT_FALSE(stream.hello());
    stream.feed(hello, 0, 0, out);
    stream.feed(wire, 0, 0, out);
    EXPECT_EQ(out.size(), 2u);
}

}  // namespace
