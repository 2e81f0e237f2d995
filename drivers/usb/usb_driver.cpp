#include "usb/usb_driver.hpp"

#include "fovea/drivers/support.hpp"

#include <time.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <thread>

#include <libusb.h>
#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>

#include "serial/protocol.hpp"
#include "usb/frame_stream.hpp"
#include "usb/transfer_state.hpp"

namespace fovea::drivers::usb {
namespace {

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("usb");  // FOVEA_LOG_DRV_USB=debug
    return log;
}

TransferStatus to_status(libusb_transfer_status s) {
    switch (s) {
        case LIBUSB_TRANSFER_COMPLETED: return TransferStatus::kCompleted;
        case LIBUSB_TRANSFER_TIMED_OUT: return TransferStatus::kTimedOut;
        case LIBUSB_TRANSFER_CANCELLED: return TransferStatus::kCancelled;
        case LIBUSB_TRANSFER_STALL: return TransferStatus::kStall;
        case LIBUSB_TRANSFER_NO_DEVICE: return TransferStatus::kNoDevice;
        case LIBUSB_TRANSFER_OVERFLOW: return TransferStatus::kOverflow;
        default: return TransferStatus::kError;
    }
}

struct Config {
    uint16_t vid = 0, pid = 0;
    int interface = -1;
    int endpoint = 0;
    int transfers = 4;
    int transfer_size = 1024;
};

struct Shared {
    std::mutex mu;
    SampleSink sink;
    bool alive = true;
};

class UsbDriver;

struct SlotRef {
    UsbDriver* self;
    std::size_t slot;
};

class UsbDriver final : public Driver {
public:
    UsbDriver(Config cfg, uint32_t device_id) : cfg_(cfg), device_id_(device_id) {
        char addr[16];
        std::snprintf(addr, sizeof addr, "%04x:%04x", cfg.vid, cfg.pid);
        info_ = {"usb", "USB tracker (no hello yet)", addr, 0.0, {}, true, false};
    }
    ~UsbDriver() override { close(); }

    Result<void> open(boost::asio::io_context& io, SampleSink sink) override {
        if (const int rc = libusb_init(&ctx_); rc != 0) {
            ctx_ = nullptr;
            return make_error(std::string("libusb_init: ") + libusb_error_name(rc), rc);
        }
        io_ = &io;
        shared_ = std::make_shared<Shared>();
        shared_->sink = std::move(sink);
        if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) {
            const int rc = libusb_hotplug_register_callback(
                ctx_,
                static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                                  LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
                static_cast<libusb_hotplug_flag>(0), cfg_.vid, cfg_.pid, LIBUSB_HOTPLUG_MATCH_ANY,
                &UsbDriver::on_hotplug, this, &hotplug_);
            has_hotplug_ = rc == LIBUSB_SUCCESS;
        }
        stop_ = false;
        thread_ = std::thread([this] { run(); });
        return {};
    }

    void close() override {
        if (!thread_.joinable()) return;
        stop_ = true;
        thread_.join();
        if (has_hotplug_) libusb_hotplug_deregister_callback(ctx_, hotplug_);
        has_hotplug_ = false;
        libusb_exit(ctx_);
        ctx_ = nullptr;
        std::lock_guard lk(shared_->mu);
        shared_->alive = false;
    }

    DriverInfo describe() const override {
        std::lock_guard lk(stats_mu_);
        return info_;
    }
    DriverStats stats() const override {
        std::lock_guard lk(stats_mu_);
        return stats_;
    }

    void complete(std::size_t slot, libusb_transfer* t) {
        const TransferStatus st = to_status(t->status);
        if ((st == TransferStatus::kCompleted || st == TransferStatus::kTimedOut) &&
            t->actual_length > 0)
            stream_.feed({t->buffer, static_cast<std::size_t>(t->actual_length)}, monotonic_ns(),
                         device_id_, pending_);
        switch (set_->on_complete(slot, st, static_cast<std::size_t>(t->actual_length))) {
            case Action::kResubmit: submit(slot); break;
            case Action::kClearHaltAndResubmit: clear_halt_.push_back(slot); break;
            case Action::kRetire: break;
        }
    }

private:
    static void LIBUSB_CALL on_transfer(libusb_transfer* t) {
        auto* ref = static_cast<SlotRef*>(t->user_data);
        ref->self->complete(ref->slot, t);
    }

    static int LIBUSB_CALL on_hotplug(libusb_context*, libusb_device* dev,
                                      libusb_hotplug_event event, void* user) {
        auto* self = static_cast<UsbDriver*>(user);
        if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED) self->rescan_ = true;
        if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT && self->handle_ &&
            libusb_get_device(self->handle_) == dev)
            self->left_ = true;
        return 0;  // stay registered
    }

    void run() {
        using Clock = std::chrono::steady_clock;
        auto next_scan = Clock::now();
        auto next_hello = Clock::now();
        auto backoff = std::chrono::milliseconds(250);
        while (!stop_) {
            const auto now = Clock::now();
            if (handle_ == nullptr && (rescan_.exchange(false) || now >= next_scan)) {
                if (connect()) {
                    backoff = std::chrono::milliseconds(250);
                    next_hello = now;
                } else {
                    // Hotplug wakes us early; the poll is the fallback where it is missing.
                    next_scan = now + backoff;
                    backoff = std::min(backoff * 2, std::chrono::milliseconds(5000));
                }
            }
            if (handle_ != nullptr && (set_->gone() || left_)) {
                set_error("device gone (unplugged?)");
                teardown();
            }
            if (handle_ != nullptr && !stream_.hello() && ep_out_ != 0 && now >= next_hello) {
                request_hello();
                next_hello = now + std::chrono::milliseconds(250);
            }
            timeval tv{0, 100'000};
            libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
            for (std::size_t slot : clear_halt_) {
                if (handle_ == nullptr || set_->stopping() || set_->gone()) break;
                libusb_clear_halt(handle_, ep_in_);
                submit(slot);
            }
            clear_halt_.clear();
            publish();
        }
        teardown();
    }

    bool connect() {
        libusb_device** list = nullptr;
        const ssize_t n = libusb_get_device_list(ctx_, &list);
        if (n < 0)
            return set_error(std::string("libusb_get_device_list: ") +
                             libusb_error_name(static_cast<int>(n)));
        libusb_device* found = nullptr;
        for (ssize_t i = 0; i < n; ++i) {
            libusb_device_descriptor d{};
            if (libusb_get_device_descriptor(list[i], &d) == 0 && d.idVendor == cfg_.vid &&
                d.idProduct == cfg_.pid) {
                found = list[i];
                break;
            }
        }
        bool ok = false;
        if (found == nullptr) {
            set_error("no USB device " + info_.address);
        } else if (const int rc = libusb_open(found, &handle_); rc != 0) {
            handle_ = nullptr;
            set_error("libusb_open " + info_.address + ": " + libusb_error_name(rc) +
                      (rc == LIBUSB_ERROR_ACCESS ? " (see udev/README.md)" : ""));
        } else {
            ok = claim(found);
            if (!ok) {
                libusb_close(handle_);
                handle_ = nullptr;
            }
        }
        libusb_free_device_list(list, 1);
        return ok;
    }

    // Finds the interface and endpoints, detaches a kernel driver, claims, starts the transfers.
    bool claim(libusb_device* dev) {
        libusb_config_descriptor* config = nullptr;
        if (libusb_get_active_config_descriptor(dev, &config) != 0)
            return set_error("cannot read the active configuration");
        iface_ = -1;
        ep_in_ = ep_out_ = 0;
        for (int i = 0; i < config->bNumInterfaces && iface_ < 0; ++i) {
            if (config->interface[i].num_altsetting < 1) continue;
            const libusb_interface_descriptor& alt = config->interface[i].altsetting[0];
            if (cfg_.interface >= 0 ? alt.bInterfaceNumber != cfg_.interface : alt.bInterfaceClass != LIBUSB_CLASS_VENDOR_SPEC)
                continue;
            for (int e = 0; e < alt.bNumEndpoints; ++e) {
                const libusb_endpoint_descriptor& ep = alt.endpoint[e];
                const int type = ep.bmAttributes & LIBUSB_TRANSFER_TYPE_MASK;
                if (type != LIBUSB_TRANSFER_TYPE_BULK && type != LIBUSB_TRANSFER_TYPE_INTERRUPT)
                    continue;
                if (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) {
                    if (ep_in_ == 0 &&
                        (cfg_.endpoint == 0 || ep.bEndpointAddress == cfg_.endpoint)) {
                        ep_in_ = ep.bEndpointAddress;
                        interrupt_ = type == LIBUSB_TRANSFER_TYPE_INTERRUPT;
                    }
                } else if (ep_out_ == 0) {
                    ep_out_ = ep.bEndpointAddress;
                    out_interrupt_ = type == LIBUSB_TRANSFER_TYPE_INTERRUPT;
                }
            }
            if (ep_in_ != 0) iface_ = alt.bInterfaceNumber;
        }
        libusb_free_config_descriptor(config);
        if (iface_ < 0)
            return set_error("no vendor-class interface with a bulk/interrupt IN endpoint");
        detached_ = false;
        if (libusb_kernel_driver_active(handle_, iface_) == 1) {
            if (const int rc = libusb_detach_kernel_driver(handle_, iface_); rc != 0)
                return set_error(std::string("detaching the kernel driver: ") +
                                 libusb_error_name(rc));
            detached_ = true;
        }
        if (const int rc = libusb_claim_interface(handle_, iface_); rc != 0) {
            reattach();
            return set_error(std::string("libusb_claim_interface: ") + libusb_error_name(rc));
        }
        const auto count = static_cast<std::size_t>(cfg_.transfers);
        set_.emplace(count);
        refs_.resize(count);
        buffers_.assign(count, std::vector<uint8_t>(static_cast<std::size_t>(cfg_.transfer_size)));
        transfers_.assign(count, nullptr);
        for (std::size_t i = 0; i < count; ++i) {
            refs_[i] = {this, i};
            transfers_[i] = libusb_alloc_transfer(0);
            if (interrupt_)
                libusb_fill_interrupt_transfer(transfers_[i], handle_, ep_in_, buffers_[i].data(),
                                               cfg_.transfer_size, &on_transfer, &refs_[i], 0);
            else
                libusb_fill_bulk_transfer(transfers_[i], handle_, ep_in_, buffers_[i].data(),
                                          cfg_.transfer_size, &on_transfer, &refs_[i], 0);
            submit(i);
        }
        stream_.reset();
        left_ = false;
        std::lock_guard lk(stats_mu_);
        if (ever_connected_) ++stats_.reconnects;
        ever_connected_ = true;
        stats_.connected = true;
        logger()->info("{}: connected (interface {}, endpoint 0x{:02x}, {})", info_.address, iface_,
                       ep_in_, interrupt_ ? "interrupt" : "bulk");
        return true;
    }

    void submit(std::size_t slot) {
        const int rc = libusb_submit_transfer(transfers_[slot]);
        if (rc == 0)
            set_->on_submitted(slot);
        else
            set_->on_submit_failed(slot, rc == LIBUSB_ERROR_NO_DEVICE);
    }

    void request_hello() {
        std::vector<uint8_t> bytes;
        serial::encode_hello_request(host_seq_++, bytes);
        int sent = 0;
        if (out_interrupt_)
            libusb_interrupt_transfer(handle_, ep_out_, bytes.data(),
                                      static_cast<int>(bytes.size()), &sent, 100);
        else
            libusb_bulk_transfer(handle_, ep_out_, bytes.data(), static_cast<int>(bytes.size()),
                                 &sent, 100);
    }

    // Cancels the transfers, waits for their callbacks, releases and reattaches, closes.
    void teardown() {
        if (handle_ == nullptr) return;
        set_->begin_stop();
        for (std::size_t i = 0; i < transfers_.size(); ++i)
            if (set_->in_flight(i)) libusb_cancel_transfer(transfers_[i]);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
        while (!set_->all_idle() && std::chrono::steady_clock::now() < deadline) {
            timeval tv{0, 50'000};
            libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
        }
        publish();
        if (set_->all_idle())  // otherwise leak them rather than free memory libusb still uses
            for (auto* t : transfers_) libusb_free_transfer(t);
        transfers_.clear();
        libusb_release_interface(handle_, iface_);
        reattach();
        libusb_close(handle_);
        handle_ = nullptr;
        bytes_base_ += set_->counters().bytes;  // keep totals across sessions
        overflow_base_ += set_->counters().overflows;
        set_.reset();
        update_stats();
        std::lock_guard lk(stats_mu_);
        stats_.connected = false;
    }

    void reattach() {
        if (detached_) libusb_attach_kernel_driver(handle_, iface_);
        detached_ = false;
    }

    void publish() {
        update_stats();
        if (pending_.empty()) return;
        boost::asio::post(*io_, [shared = shared_, samples = std::move(pending_)] {
            std::lock_guard lk(shared->mu);
            if (!shared->alive || !shared->sink) return;
            for (const auto& s : samples) shared->sink(s);
        });
        pending_.clear();
    }

    void update_stats() {
        const auto c = stream_.counters();
        std::lock_guard lk(stats_mu_);
        stats_.samples = c.samples;
        stats_.frames_dropped =
            c.dropped + overflow_base_ + (set_ ? set_->counters().overflows : 0);
        stats_.frames_lost = c.lost;
        stats_.resyncs = c.resyncs;
        stats_.bytes = bytes_base_ + (set_ ? set_->counters().bytes : 0);
        if (const auto& h = stream_.hello()) {
            info_.name = h->name;
            info_.nominal_rate_hz = h->rate_mhz / 1000.0;
            info_.clock = {h->counter_bits, static_cast<double>(h->tick_hz)};
            info_.binocular = h->binocular;
            info_.has_pupil = h->has_pupil;
        }
    }

    bool set_error(const std::string& why) {
        std::lock_guard lk(stats_mu_);
        if (why != stats_.last_error) logger()->info("{}", why);  // one line per new condition
        stats_.last_error = why;
        return false;
    }

    Config cfg_;
    uint32_t device_id_;
    boost::asio::io_context* io_ = nullptr;
    std::shared_ptr<Shared> shared_;
    libusb_context* ctx_ = nullptr;
    libusb_hotplug_callback_handle hotplug_ = 0;
    bool has_hotplug_ = false;
    std::thread thread_;
    std::atomic<bool> stop_{false};
    std::atomic<bool> rescan_{true};
    std::atomic<bool> left_{false};
    // Event thread only:
    libusb_device_handle* handle_ = nullptr;
    int iface_ = -1;
    uint8_t ep_in_ = 0, ep_out_ = 0;
    bool interrupt_ = false, out_interrupt_ = false, detached_ = false;
    std::optional<TransferSet> set_;
    std::vector<SlotRef> refs_;
    std::vector<std::vector<uint8_t>> buffers_;
    std::vector<libusb_transfer*> transfers_;
    std::vector<std::size_t> clear_halt_;
    std::vector<gaze::RawSample> pending_;
    FrameStream stream_;
    uint16_t host_seq_ = 0;
    uint64_t bytes_base_ = 0, overflow_base_ = 0;
    mutable std::mutex stats_mu_;
    DriverStats stats_;
    DriverInfo info_;
    bool ever_connected_ = false;
};

}  // namespace

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    Config cfg;
    const auto vid = parse_usb_id(config["vid"]);
    const auto pid = parse_usb_id(config["pid"]);
    if (!vid || !pid)
        return make_error("usb: 'vid' and 'pid' are required (0..0xFFFF, integer or hex string)");
    cfg.vid = *vid;
    cfg.pid = *pid;
    cfg.interface = static_cast<int>(config["interface"].value_or(int64_t{-1}));
    cfg.endpoint = static_cast<int>(config["endpoint"].value_or(int64_t{0}));
    cfg.transfers = static_cast<int>(config["transfers"].value_or(int64_t{4}));
    cfg.transfer_size = static_cast<int>(config["transfer_size"].value_or(int64_t{1024}));
    if (cfg.transfers < 1 || cfg.transfers > 32) return make_error("usb: transfers must be 1..32");
    if (cfg.transfer_size < 64 || cfg.transfer_size > 65536)
        return make_error("usb: transfer_size must be 64..65536");
    if (cfg.endpoint != 0 && !(cfg.endpoint & 0x80))
        return make_error("usb: endpoint must be an IN endpoint address (0x81..0x8F)");
    return std::unique_ptr<Driver>(std::make_unique<UsbDriver>(cfg, device_id));
}

Result<std::vector<UsbDeviceInfo>> list_usb_devices() {
    libusb_context* ctx = nullptr;
    if (const int rc = libusb_init(&ctx); rc != 0)
        return make_error(std::string("libusb_init: ") + libusb_error_name(rc), rc);
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx, &list);
    std::vector<UsbDeviceInfo> out;
    for (ssize_t i = 0; i < n; ++i) {
        libusb_device_descriptor d{};
        if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
        out.push_back({d.idVendor, d.idProduct, libusb_get_bus_number(list[i]),
                       libusb_get_device_address(list[i]), d.bDeviceClass});
    }
    if (n >= 0) libusb_free_device_list(list, 1);
    libusb_exit(ctx);
    if (n < 0)
        return make_error(
            std::string("libusb_get_device_list: ") + libusb_error_name(static_cast<int>(n)),
            static_cast<int>(n));
    return out;
}

}  // namespace fovea::drivers::usb
