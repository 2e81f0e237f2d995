// fovead's service: one io_context thread owns the devices, the gaze chain, the ring and the
// control socket (DESIGN.md §4). Drivers post samples into the loop; nothing here blocks.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include "config.hpp"
#include "control.hpp"
#include "fovea/drivers/driver.hpp"
#include "fovea/gaze/pipeline.hpp"
#include "ring_writer.hpp"

namespace fovea::daemon {

class Daemon {
public:
    Daemon(DaemonConfig config, std::string config_path);
    ~Daemon();

    // Take the instance lock, create the rings, open the control socket and the devices.
    // An error is one clear line; nothing is left behind.
    Result<void> start();
    // Run the loop until SIGINT/SIGTERM or the `shutdown` command. Returns the exit code.
    int run();
    // Ask the loop to stop (any thread).
    void request_stop();

    nlohmann::json status() const;

    // Extension points for other subsystems (recording, calibration). Loop thread only.
    boost::asio::io_context& io() { return io_; }
    ControlServer& control() { return control_; }
    using RawObserver = std::function<void(const gaze::RawSample&)>;
    using PublishedObserver =
        std::function<void(const gaze::GazeSample&, const fovea_gaze_record&)>;
    void add_raw_observer(RawObserver o) { raw_observers_.push_back(std::move(o)); }
    void add_published_observer(PublishedObserver o) {
        published_observers_.push_back(std::move(o));
    }
    // Status sections contributed by other subsystems.
    void add_status_section(const std::string& key, std::function<nlohmann::json()> fn) {
        status_sections_.emplace_back(key, std::move(fn));
    }
    const DaemonConfig& config() const { return config_; }
    // Calibration (calibration_commands.cpp). Loop thread.
    std::size_t device_count() const { return devices_.size(); }
    // Apply `calibration` to device `device`'s chain from its next sample; nullptr removes it.
    // False when there is no such device.
    bool set_calibration(uint32_t device, const gaze::Calibration* calibration);
    // Tell every device where a calibration target is shown (or that none is); returns how
    // many follow it with their gaze (simulated trackers).
    int show_target(bool shown, double x, double y);
    // Whether the gaze chain predicts landings right now (recording logs it so replay matches).
    bool landing_prediction() const { return readers_attached_; }

private:
    struct Device;

    Result<void> take_instance_lock();
    void open_device(Device& d);
    void on_raw(Device& d, const gaze::RawSample& raw);
    void publish(Device& d, gaze::GazeSample& s);
    // publish = "live": the newest sample goes to the ring at once (provisional labels); the
    // finished one, labelled after the look-ahead, only to the observers (emit_final).
    void publish_live(Device& d, gaze::GazeSample& s);
    void emit_final(Device& d, gaze::GazeSample& s);
    // The device went quiet: its held samples, finished now, to the observers.
    void settle(Device& d);
    // Takes the driver's description (rate, clock) as it stands; rebuilds the gaze chain when
    // the rate or clock changed.
    void adopt_description(Device& d);
    void publish_head(Device& d, const drivers::HeadPose& pose);
    double lookahead_ms(const Device& d) const;
    // The gaze chain's configuration for a device as it describes itself.
    gaze::PipelineConfig pipeline_config(const drivers::DriverInfo& info,
                                         bool predict_landing) const;
    void register_commands();
    void on_signal(int signo);
    void reload();
    void tick();  // 4 Hz housekeeping: reader presence, rates, watchdog
    void shutdown();

    DaemonConfig config_;
    std::string config_path_;
    boost::asio::io_context io_;
    boost::asio::signal_set signals_;
    boost::asio::steady_timer tick_timer_;
    ControlServer control_;
    ring::RingWriter gaze_ring_;
    ring::RingWriter head_ring_;  // head pose from head trackers (HID usage 0x02)
    uint64_t head_poses_ = 0;
    std::vector<std::unique_ptr<Device>> devices_;
    std::vector<RawObserver> raw_observers_;
    std::vector<PublishedObserver> published_observers_;
    std::vector<std::pair<std::string, std::function<nlohmann::json()>>> status_sections_;
    std::vector<gaze::GazeSample> scratch_;
    gaze::GazeSample live_scratch_;
    int lock_fd_ = -1;
    bool readers_attached_ = false;
    bool stopping_ = false;
    int64_t started_ns_ = 0;
    std::chrono::steady_clock::time_point last_watchdog_{};
    uint64_t watchdog_usec_ = 0;
};

}  // namespace fovea::daemon
