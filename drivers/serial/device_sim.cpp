#include "serial/device_sim.hpp"

#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace fovea::drivers::serial {

Result<std::unique_ptr<PtyPort>> PtyPort::open(const std::string& link) {
    std::unique_ptr<PtyPort> p(new PtyPort());
    p->master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (p->master_ < 0)
        return make_error(std::string("posix_openpt: ") + std::strerror(errno), errno);
    char name[128];
    if (::grantpt(p->master_) != 0 || ::unlockpt(p->master_) != 0 ||
        ::ptsname_r(p->master_, name, sizeof name) != 0)
        return make_error(std::string("pty setup: ") + std::strerror(errno), errno);
    p->slave_path_ = name;
    p->slave_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (p->slave_ < 0)
        return make_error(std::string("open ") + name + ": " + std::strerror(errno), errno);
    termios tio{};
    ::tcgetattr(p->slave_, &tio);
    ::cfmakeraw(&tio);
    ::tcsetattr(p->slave_, TCSANOW, &tio);
    if (!link.empty()) {
        // Atomic replace: a host polling the link never sees it missing during a reopen.
        const std::string tmp = link + ".tmp" + std::to_string(::getpid());
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        std::filesystem::create_symlink(name, tmp, ec);
        if (!ec) std::filesystem::rename(tmp, link, ec);
        if (ec) return make_error("symlink " + link + ": " + ec.message(), ec.value());
        p->link_ = link;
    }
    return p;
}

PtyPort::~PtyPort() {
    if (!link_.empty()) {
        std::error_code ec;
        if (std::filesystem::read_symlink(link_, ec) == slave_path_)
            std::filesystem::remove(link_, ec);
    }
    if (slave_ >= 0) ::close(slave_);
    if (master_ >= 0) ::close(master_);
}

Result<std::size_t> PtyPort::write(std::span<const uint8_t> bytes) {
    const ssize_t n = ::write(master_, bytes.data(), bytes.size());
    if (n >= 0) return static_cast<std::size_t>(n);
    if (errno == EAGAIN || errno == EINTR) return std::size_t{0};
    return make_error(std::string("pty write: ") + std::strerror(errno), errno);
}

Result<std::size_t> PtyPort::read(std::span<uint8_t> bytes) {
    const ssize_t n = ::read(master_, bytes.data(), bytes.size());
    if (n >= 0) return static_cast<std::size_t>(n);
    if (errno == EAGAIN || errno == EINTR || errno == EIO) return std::size_t{0};
    return make_error(std::string("pty read: ") + std::strerror(errno), errno);
}

DeviceEmulator::DeviceEmulator(const sim::SimConfig& sim, const FaultOptions& faults,
                               std::string name)
    : sim_config_(sim),
      faults_(faults),
      name_(std::move(name)),
      tracker_(std::make_unique<sim::SimTracker>(sim)),
      rng_(faults.seed * 0x9E3779B97F4A7C15ULL + 1) {}

double DeviceEmulator::uniform() {
    // xorshift64*: faults need no more than a cheap, seeded stream.
    rng_ ^= rng_ >> 12;
    rng_ ^= rng_ << 25;
    rng_ ^= rng_ >> 27;
    return static_cast<double>((rng_ * 0x2545F4914F6CDD1DULL) >> 11) * 0x1.0p-53;
}

void DeviceEmulator::hello(std::vector<uint8_t>& out) {
    Hello h;
    h.binocular = sim_config_.binocular;
    h.has_pupil = true;
    h.counter_bits = static_cast<uint8_t>(sim_config_.counter_bits);
    h.tick_hz = static_cast<uint32_t>(sim_config_.tick_hz);
    h.rate_mhz = static_cast<uint32_t>(std::lround(sim_config_.rate_hz * 1000.0));
    h.baud = baud_;
    h.name = name_;
    encode_hello(h, seq_++, out);
    ++stats_.frames;
    ++stats_.hellos;
}

void DeviceEmulator::next_sample(std::vector<uint8_t>& out, gaze::RawSample* sample) {
    const auto frame = tracker_->next();
    last_ticks_ = frame.raw.device_ticks;
    if (sample) *sample = frame.raw;
    const uint16_t seq = seq_++;
    if (faults_.drop > 0 && uniform() < faults_.drop) {
        ++stats_.dropped;
        return;
    }
    if (faults_.garbage > 0 && uniform() < faults_.garbage) {
        const int n = 1 + static_cast<int>(uniform() * 64);
        for (int i = 0; i < n; ++i) out.push_back(static_cast<uint8_t>(uniform() * 256));
        ++stats_.garbage_bursts;
    }
    const std::size_t start = out.size();
    encode_sample(frame.raw, seq, out);
    if (faults_.corrupt > 0 && uniform() < faults_.corrupt) {
        // Flip a byte inside the frame (not the delimiters around it).
        const std::size_t len = out.size() - start - 2;
        const std::size_t at = start + 1 + static_cast<std::size_t>(uniform() * len);
        out[at] ^= static_cast<uint8_t>(1 + uniform() * 255);
        ++stats_.corrupted;
        return;
    }
    ++stats_.frames;
}

void DeviceEmulator::on_host_bytes(std::span<const uint8_t> bytes, std::vector<uint8_t>& out) {
    host_decoder_.feed(
        bytes,
        [&](const Frame& f) {
            if (f.type == static_cast<uint8_t>(FrameType::kHelloRequest)) {
                ++stats_.host_frames;
                hello(out);
            } else if (f.type == static_cast<uint8_t>(FrameType::kConfigure)) {
                const auto c = decode_configure(f.payload);
                if (!c) return;
                ++stats_.host_frames;
                if (c->baud != 0) baud_ = c->baud;
                const double rate = c->rate_mhz / 1000.0;
                if (c->rate_mhz != 0 && rate >= 60.0 && rate <= 2000.0 &&
                    rate != sim_config_.rate_hz) {
                    // Keep the device counter running across the change; new seed, new movements.
                    const double ticks = sim_config_.tick_hz / rate;
                    const uint64_t mask = sim_config_.counter_bits == 64
                                              ? ~0ULL
                                              : (1ULL << sim_config_.counter_bits) - 1;
                    sim_config_.counter_offset = static_cast<int64_t>(
                        (last_ticks_ + static_cast<uint64_t>(ticks)) & mask & ~(1ULL << 63));
                    sim_config_.rate_hz = rate;
                    sim_config_.seed += 1;
                    tracker_ = std::make_unique<sim::SimTracker>(sim_config_);
                }
                hello(out);
            }
        },
        [](FrameDecoder::Reject) {});
}

}  // namespace fovea::drivers::serial
