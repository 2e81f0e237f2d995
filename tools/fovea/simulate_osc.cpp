// `fovea simulate osc --port P [--host H] [--preset vrchat|vrcft-v2] [--rate HZ] [--frames N]
// [--blink-every K] [--blink-frames B]`: an OSC sender on liblo (the library the osc driver
// receives with) playing a VR eye tracker: gaze circling 10 deg wide, and every K-th frame
// starting B frames with the eyes closed. Lids/closed amounts go before the gaze of the same
// frame, as EyeTrackVR sends them. Prints the frames sent and how many were closed.
#include "simulate_osc.hpp"

#include <lo/lo.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>

namespace fovea::cli {
namespace {

struct Options {
    std::string host = "127.0.0.1";
    int port = 9000;
    std::string preset = "vrchat";
    double rate_hz = 120;
    int frames = 600;
    int blink_every = 100;
    int blink_frames = 10;
};

void send(lo_address to, const char* path, std::initializer_list<float> values) {
    lo_message m = lo_message_new();
    for (float v : values) lo_message_add_float(m, v);
    if (lo_send_message(to, path, m) < 0)
        throw std::runtime_error(std::string("osc send ") + path + ": " + lo_address_errstr(to));
    lo_message_free(m);
}

void run(const Options& o) {
    if (o.preset != "vrchat" && o.preset != "vrcft-v2")
        throw std::runtime_error("--preset must be vrchat or vrcft-v2");
    lo_address to = lo_address_new(o.host.c_str(), std::to_string(o.port).c_str());
    if (!to) throw std::runtime_error("bad OSC destination " + o.host);
    constexpr double kDeg = 0.017453292519943295;
    const auto start = std::chrono::steady_clock::now();
    int closed_frames = 0;
    for (int i = 0; i < o.frames; ++i) {
        std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                  std::chrono::duration<double>(i / o.rate_hz)));
        const bool closed = o.blink_every > 0 && i % o.blink_every < o.blink_frames;
        closed_frames += closed;
        const double phase = 2 * M_PI * i / 120.0;
        const double yaw = 10 * std::cos(phase), pitch = 5 * std::sin(phase);  // degrees
        if (o.preset == "vrchat") {
            send(to, "/tracking/eye/EyesClosedAmount", {closed ? 1.0f : 0.0f});
            const float x = static_cast<float>(std::sin(yaw * kDeg) * std::cos(pitch * kDeg));
            const float y = static_cast<float>(std::sin(pitch * kDeg));
            const float z = static_cast<float>(std::cos(yaw * kDeg) * std::cos(pitch * kDeg));
            send(to, "/tracking/eye/LeftRightVec", {x, y, z, x, y, z});
        } else {
            const std::string p = "/avatar/parameters/v2/";
            const float lid = closed ? 0.0f : 0.8f;
            send(to, (p + "EyeLidLeft").c_str(), {lid});
            send(to, (p + "EyeLidRight").c_str(), {lid});
            send(to, (p + "PupilDilation").c_str(), {0.5f});
            const float x = static_cast<float>(yaw / 45.0), y = static_cast<float>(pitch / 45.0);
            for (const char* a : {"EyeLeftX", "EyeRightX"}) send(to, (p + a).c_str(), {x});
            for (const char* a : {"EyeLeftY", "EyeRightY"}) send(to, (p + a).c_str(), {y});
        }
    }
    lo_address_free(to);
    std::printf("sent %d frames (%d with the eyes closed) to %s:%d as %s\n", o.frames,
                closed_frames, o.host.c_str(), o.port, o.preset.c_str());
}

}  // namespace

void add_simulate_osc(CLI::App& simulate) {
    static Options o;
    CLI::App* c = simulate.add_subcommand("osc", "OSC sender playing a VR eye tracker (liblo)");
    c->add_option("--port", o.port, "UDP port to send to")->required()->check(CLI::Range(1, 65535));
    c->add_option("--host", o.host, "Host to send to");
    c->add_option("--preset", o.preset, "vrchat or vrcft-v2");
    c->add_option("--rate", o.rate_hz, "Frames per second")->check(CLI::Range(1.0, 2000.0));
    c->add_option("--frames", o.frames, "Frames to send")->check(CLI::Range(1, 10'000'000));
    c->add_option("--blink-every", o.blink_every, "A blink starts every K frames (0: none)");
    c->add_option("--blink-frames", o.blink_frames, "Frames each blink lasts");
    c->callback([] { run(o); });
}

}  // namespace fovea::cli
