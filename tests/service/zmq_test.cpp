// The ZeroMQ fan-out: the Pupil-style codec, the [zmq] configuration, and a live round trip
// (fovead -> PUB on loopback -> SUB) that must carry every sample the ring carried.
#include <zmq.h>

#include <cmath>
#include <map>

#include "config.hpp"
#include "fovea/client.hpp"
#include "fovea/import/pupil_datum.hpp"
#include "service_fixture.hpp"
#include "zmq_publisher.hpp"

namespace fovea::service_test {
namespace {

using daemon::decode_pupil_gaze;
using daemon::encode_pupil_gaze;

fovea_eye eye(float x, float y, bool valid) {
    fovea_eye e{};
    e.norm_x = x;
    e.norm_y = y;
    e.deg_x = (x - 0.5f) * 40;
    e.deg_y = (y - 0.5f) * 30;
    e.pupil_mm = 3.25f;
    e.valid = valid ? FOVEA_VALID : 0;
    return e;
}

fovea_gaze_record sample_record() {
    fovea_gaze_record r{};
    r.index = 123456789012ull;
    r.t_capture_ns = 987654321012345678;
    r.t_receive_ns = r.t_capture_ns + 1111;
    r.t_processed_ns = r.t_capture_ns + 2222;
    r.t_publish_ns = r.t_capture_ns + 3333;
    r.left = eye(0.25f, 0.75f, true);
    r.right = eye(0.3f, 0.7f, true);
    r.combined = eye(0.275f, 0.725f, true);
    r.event = FOVEA_EVENT_SACCADE;
    r.flags = FOVEA_VALID | FOVEA_FLAG_LANDING_VALID | FOVEA_FLAG_SIMULATED;
    r.device_id = 2;
    r.clock_uncertainty_us = 12.5f;
    r.saccade_onset_ns = r.t_capture_ns - 20'000'000;
    r.saccade_amplitude_deg = 8.5f;
    r.saccade_peak_velocity_dps = 310.f;
    r.saccade_direction_deg = -45.f;
    r.landing_norm_x = 0.6f;
    r.landing_norm_y = 0.1f;
    r.landing_deg_x = 4.f;
    r.landing_deg_y = -12.f;
    r.landing_uncertainty_deg = 1.5f;
    return r;
}

void expect_eye_eq(const fovea_eye& a, const fovea_eye& b) {
    EXPECT_FLOAT_EQ(a.norm_x, b.norm_x);
    EXPECT_FLOAT_EQ(a.norm_y, b.norm_y);
    EXPECT_FLOAT_EQ(a.deg_x, b.deg_x);
    EXPECT_FLOAT_EQ(a.deg_y, b.deg_y);
    EXPECT_FLOAT_EQ(a.pupil_mm, b.pupil_mm);
    EXPECT_EQ(a.valid, b.valid);
}

TEST(ZmqCodec, RoundTripKeepsEveryFoveaField) {
    const fovea_gaze_record r = sample_record();
    const auto m = encode_pupil_gaze(r);
    auto g = decode_pupil_gaze(m.topic, m.payload);
    ASSERT_TRUE(g.ok()) << g.error().message;
    ASSERT_TRUE(g->fovea_fields);
    const fovea_gaze_record& d = g->record;
    EXPECT_EQ(d.index, r.index);
    EXPECT_EQ(d.t_capture_ns, r.t_capture_ns);
    EXPECT_EQ(d.t_receive_ns, r.t_receive_ns);
    EXPECT_EQ(d.t_processed_ns, r.t_processed_ns);
    EXPECT_EQ(d.t_publish_ns, r.t_publish_ns);
    EXPECT_EQ(d.event, r.event);
    EXPECT_EQ(d.flags, r.flags);
    EXPECT_EQ(d.device_id, r.device_id);
    EXPECT_FLOAT_EQ(d.clock_uncertainty_us, r.clock_uncertainty_us);
    expect_eye_eq(d.left, r.left);
    expect_eye_eq(d.right, r.right);
    expect_eye_eq(d.combined, r.combined);
    EXPECT_EQ(d.saccade_onset_ns, r.saccade_onset_ns);
    EXPECT_FLOAT_EQ(d.saccade_amplitude_deg, r.saccade_amplitude_deg);
    EXPECT_FLOAT_EQ(d.saccade_peak_velocity_dps, r.saccade_peak_velocity_dps);
    EXPECT_FLOAT_EQ(d.saccade_direction_deg, r.saccade_direction_deg);
    EXPECT_FLOAT_EQ(d.landing_norm_x, r.landing_norm_x);
    EXPECT_FLOAT_EQ(d.landing_norm_y, r.landing_norm_y);
    EXPECT_FLOAT_EQ(d.landing_deg_x, r.landing_deg_x);
    EXPECT_FLOAT_EQ(d.landing_deg_y, r.landing_deg_y);
    EXPECT_FLOAT_EQ(d.landing_uncertainty_deg, r.landing_uncertainty_deg);
}

TEST(ZmqCodec, PupilKeysUseBottomLeftOriginAndSeconds) {
    const fovea_gaze_record r = sample_record();
    const auto m = encode_pupil_gaze(r);
    auto g = decode_pupil_gaze(m.topic, m.payload);
    ASSERT_TRUE(g.ok());
    EXPECT_EQ(g->topic, "gaze.2d.01.");
    EXPECT_DOUBLE_EQ(g->norm_pos[0], r.combined.norm_x);
    EXPECT_NEAR(g->norm_pos[1], 1.0 - r.combined.norm_y, 1e-7);
    EXPECT_DOUBLE_EQ(g->confidence, 1.0);
    EXPECT_NEAR(g->timestamp, static_cast<double>(r.t_capture_ns) / 1e9, 1e-6);
}

TEST(ZmqCodec, PublishedDatumReadsAsAPupilGazeDatumInPupilsOwnDecoder) {
    // The decoder the pupil driver and the Pupil importer use on what Pupil Capture wrote.
    const fovea_gaze_record r = sample_record();
    const auto m = encode_pupil_gaze(r);
    auto d = import::decode_pupil_datum(m.payload);
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_TRUE(d->is_gaze());
    EXPECT_EQ(d->topic, m.topic);
    EXPECT_TRUE(d->from_eye(0) && d->from_eye(1));
    EXPECT_DOUBLE_EQ(d->confidence, 1.0);
    EXPECT_NEAR(d->norm_y, 1.0 - r.combined.norm_y, 1e-7);
    EXPECT_NEAR(d->timestamp, static_cast<double>(r.t_capture_ns) / 1e9, 1e-6);
}

TEST(ZmqCodec, TopicFollowsWhichEyesAreTracked) {
    fovea_gaze_record r = sample_record();
    struct Case {
        bool left, right;
        const char* topic;
        float x;
        double confidence;
    };
    for (const Case c : {Case{true, true, "gaze.2d.01.", 0.275f, 1.0},
                         Case{false, true, "gaze.2d.0.", 0.3f, 1.0},  // Pupil eye0 = right
                         Case{true, false, "gaze.2d.1.", 0.25f, 1.0},
                         Case{false, false, "gaze.2d.01.", 0.275f, 1.0}}) {
        r.left.valid = c.left ? FOVEA_VALID : 0;
        r.right.valid = c.right ? FOVEA_VALID : 0;
        const auto m = encode_pupil_gaze(r);
        EXPECT_EQ(m.topic, c.topic);
        auto g = decode_pupil_gaze(m.topic, m.payload);
        ASSERT_TRUE(g.ok());
        EXPECT_FLOAT_EQ(static_cast<float>(g->norm_pos[0]), c.x) << c.topic;
        EXPECT_DOUBLE_EQ(g->confidence, c.confidence);
    }
    r.left.valid = r.right.valid = r.combined.valid = 0;  // lost track: confidence 0
    const auto m = encode_pupil_gaze(r);
    EXPECT_EQ(m.topic, "gaze.2d.01.");
    EXPECT_DOUBLE_EQ(decode_pupil_gaze(m.topic, m.payload)->confidence, 0.0);
}

TEST(ZmqCodec, MalformedPayloadsAreRejected) {
    const auto m = encode_pupil_gaze(sample_record());
    EXPECT_FALSE(decode_pupil_gaze(m.topic, "").ok());
    EXPECT_FALSE(decode_pupil_gaze(m.topic, "\xc1\xc1\xc1").ok());
    EXPECT_FALSE(decode_pupil_gaze("gaze.2d.0.", m.payload).ok());   // topic frame disagrees
    EXPECT_FALSE(decode_pupil_gaze(m.topic, m.payload + "x").ok());  // trailing bytes
    for (std::size_t cut = 1; cut < m.payload.size(); cut += 7)
        EXPECT_FALSE(decode_pupil_gaze(m.topic, m.payload.substr(0, cut)).ok()) << cut;
    EXPECT_FALSE(decode_pupil_gaze(m.topic, std::string("\x92\x01\x02", 3)).ok());  // an array
}

TEST(ZmqConfig, ParsesPublishAndHighWaterMarkAndNamesBadKeys) {
    auto ok = daemon::parse_config("[zmq]\npublish = \"tcp://127.0.0.1:50020\"\nsend_hwm = 5000\n",
                                   "t.toml");
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_EQ(ok->zmq.publish, "tcp://127.0.0.1:50020");
    EXPECT_EQ(ok->zmq.send_hwm, 5000);
    EXPECT_TRUE(daemon::parse_config("", "t.toml")->zmq.publish.empty());  // off by default
    for (auto [text, key] : {std::pair{"[zmq]\nbogus = 1\n", "zmq.bogus"},
                             {"[zmq]\npublish = 5\n", "zmq.publish"},
                             {"[zmq]\npublish = \"localhost\"\n", "zmq.publish"},
                             {"[zmq]\nsend_hwm = 0\n", "zmq.send_hwm"},
                             {"[zmq]\nremote = \"tcp://127.0.0.1:1\"\n", "zmq.remote"},
                             {"zmq = \"x\"\n", "zmq"}}) {
        auto bad = daemon::parse_config(text, "t.toml");
        ASSERT_FALSE(bad.ok()) << text;
        EXPECT_NE(bad.error().message.find(std::string("t.toml: ") + key + ":"), std::string::npos)
            << bad.error().message;
    }
}

struct ZmqFanOut : ServiceTest {
    std::string endpoint;
    std::string remote;

    std::unique_ptr<Proc> start_publishing() {
        const auto cfg = write_file("z.toml",
                                    "[zmq]\npublish = \"tcp://127.0.0.1:*\"\n"
                                    "remote = \"tcp://127.0.0.1:*\"\n");
        auto d = start_daemon({"--config", cfg});
        auto st = query("status");
        if (st.ok() && st->contains("zmq")) {
            endpoint = (*st)["zmq"]["endpoint"].get<std::string>();
            remote = (*st)["zmq"].value("remote", "");
        }
        return d;
    }
};

TEST_F(ZmqFanOut, RoundTripCarriesEverySampleTheRingCarried) {
    auto d = start_publishing();
    ASSERT_FALSE(endpoint.empty()) << d->err();
    ASSERT_EQ(endpoint.rfind("tcp://127.0.0.1:", 0), 0u) << endpoint;

    fovea::Client ring(instance);
    auto sub = daemon::ZmqGazeSubscriber::connect(endpoint);
    ASSERT_TRUE(sub.ok()) << sub.error().message;
    // Slow joiner: what was published before the subscription reached the publisher is lost by
    // design; from the first message received on, nothing may be.
    auto first = (*sub)->receive(5000);
    ASSERT_TRUE(first.ok() && first->has_value()) << "no first message";
    constexpr int kSamples = 1500;  // 1.5 s of the simulated 1 kHz tracker
    std::vector<daemon::ZmqGaze> got{std::move(**first)};
    while (got.size() < kSamples) {
        auto g = (*sub)->receive(2000);
        ASSERT_TRUE(g.ok()) << g.error().message;
        ASSERT_TRUE(g->has_value()) << "stalled after " << got.size() << " messages";
        got.push_back(std::move(**g));
    }
    EXPECT_EQ((*sub)->malformed(), 0u);

    // Every index in order, each identical to the ring's record with that index.
    uint64_t cursor = got.front().record.index;
    std::vector<fovea_gaze_record> from_ring;
    while (from_ring.size() < got.size()) {
        auto b = ring.read(cursor, 512);
        ASSERT_EQ(b.dropped, 0u) << "ring overran before the comparison (4096 slots)";
        ASSERT_FALSE(b.writer_restarted);
        if (b.records.empty()) { ASSERT_TRUE(ring.wait(cursor, 2000)); }
        from_ring.insert(from_ring.end(), b.records.begin(), b.records.end());
    }
    for (std::size_t i = 0; i < got.size(); ++i) {
        const auto& z = got[i];
        const auto& r = from_ring[i];
        ASSERT_TRUE(z.fovea_fields);
        ASSERT_EQ(z.record.index, got.front().record.index + i) << "gap or reorder at " << i;
        ASSERT_EQ(z.record.index, r.index);
        ASSERT_EQ(z.record.t_capture_ns, r.t_capture_ns) << i;
        ASSERT_EQ(z.record.t_publish_ns, r.t_publish_ns) << i;
        ASSERT_FLOAT_EQ(z.record.combined.norm_x, r.combined.norm_x) << i;
        ASSERT_FLOAT_EQ(z.record.combined.norm_y, r.combined.norm_y) << i;
        if (r.flags & FOVEA_FLAG_PROVISIONAL) {
            // publish = "live" (the default): the ring got this sample before the detector's
            // look-ahead, with a causal label; the fan-out carries the final label.
            ASSERT_TRUE(r.event == FOVEA_EVENT_UNKNOWN || r.event == FOVEA_EVENT_SACCADE ||
                        r.event == FOVEA_EVENT_BLINK)
                << i;
            ASSERT_FALSE(z.record.flags & FOVEA_FLAG_PROVISIONAL) << i;
        } else {
            ASSERT_EQ(z.record.event, r.event) << i;
        }
        ASSERT_NEAR(z.timestamp, static_cast<double>(r.t_capture_ns) / 1e9, 1e-6);
        ASSERT_EQ(z.topic.rfind("gaze.2d.", 0), 0u);
    }
    auto st = query("status");
    ASSERT_TRUE(st.ok());
    EXPECT_EQ((*st)["zmq"]["failed"].get<uint64_t>(), 0u);
    EXPECT_GE((*st)["zmq"]["sent"].get<uint64_t>(), got.front().record.index + kSamples);
    ASSERT_TRUE(query("shutdown").ok());
    EXPECT_EQ(d->wait(5s), 0) << d->err();
}

// Samples of several devices reach the fan-out out of index order (each device's look-ahead
// is its own): a late sample is not missed, a gap is, and a publisher whose index starts again
// starts a new count.
TEST_F(ServiceTest, ZmqSubscriberCountsGapsNotReorderedSamples) {
    void* ctx = zmq_ctx_new();
    void* pub = zmq_socket(ctx, ZMQ_PUB);
    const std::string endpoint = "ipc://" + dir + "/reorder.zmq";
    ASSERT_EQ(zmq_bind(pub, endpoint.c_str()), 0);
    auto sub = daemon::ZmqGazeSubscriber::connect(endpoint);
    ASSERT_TRUE(sub.ok()) << sub.error().message;
    uint64_t sent = 100000;  // more than kReorderSpan: a fall back to 0 is a restart
    auto send = [&](uint64_t index) {
        fovea_gaze_record r{};
        r.index = index;
        r.t_capture_ns = 1;
        const auto m = daemon::encode_pupil_gaze(r);
        zmq_send(pub, m.topic.data(), m.topic.size(), ZMQ_SNDMORE);
        zmq_send(pub, m.payload.data(), m.payload.size(), 0);
    };
    auto receive = [&](int n) {
        for (int i = 0; i < n; ++i) {
            auto g = (*sub)->receive(2000);
            ASSERT_TRUE(g.ok() && g->has_value()) << "message " << i;
        }
    };
    // Until the subscription has reached the publisher (ZeroMQ's slow joiner).
    for (bool joined = false; !joined; ++sent) {
        send(sent);
        auto g = (*sub)->receive(20);
        ASSERT_TRUE(g.ok());
        joined = g->has_value();
    }
    EXPECT_EQ((*sub)->missed(), 0u);
    for (uint64_t i : {sent + 1, sent, sent + 3, sent + 2, sent + 6}) send(i);
    receive(5);
    EXPECT_EQ((*sub)->missed(), 2u);  // sent + 4 and sent + 5
    send(sent + 5);                   // later than its neighbours: the count goes down again
    receive(1);
    EXPECT_EQ((*sub)->missed(), 1u);
    // A restarted publisher: its index starts from 0 again; what was missed before stays.
    for (uint64_t i : {uint64_t{0}, uint64_t{1}, uint64_t{3}}) send(i);
    receive(3);
    EXPECT_EQ((*sub)->missed(), 2u);  // sent + 4, and 2 of the new run
    zmq_close(pub);
    zmq_ctx_term(ctx);
}

// A PUB socket drops what a lagging subscriber's queues cannot hold and never tells the sender:
// the subscriber counts every sample that did not arrive from the gaps in the ring index, and
// what arrived plus what it counted is every sample published meanwhile.
TEST_F(ZmqFanOut, ALaggingSubscriberCountsEverySampleItMissed) {
    // A Unix socket buffers a few hundred messages, loopback TCP tens of thousands.
    const auto cfg =
        write_file("hwm.toml", "[zmq]\npublish = \"ipc://" + dir + "/gaze.zmq\"\nsend_hwm = 10\n");
    auto d = start_daemon({"--config", cfg});
    auto st = query("status");
    ASSERT_TRUE(st.ok() && st->contains("zmq")) << d->err();
    auto sub = daemon::ZmqGazeSubscriber::connect((*st)["zmq"]["endpoint"].get<std::string>(),
                                                  "gaze.", 10);
    ASSERT_TRUE(sub.ok()) << sub.error().message;
    auto first = (*sub)->receive(5000);
    ASSERT_TRUE(first.ok() && first->has_value()) << "no first message";

    std::this_thread::sleep_for(2s);  // 2000 samples of the 1 kHz simulated tracker, unread
    fovea::Client ring(instance);
    const uint64_t published = ring.head();  // every one of these reaches the fan-out
    uint64_t received = 1, last = (*first)->record.index;
    while (last + 1 < published) {
        auto g = (*sub)->receive(2000);
        ASSERT_TRUE(g.ok()) << g.error().message;
        ASSERT_TRUE(g->has_value()) << "stalled at index " << last;
        last = (**g).record.index;
        ++received;
    }
    EXPECT_GT((*sub)->missed(), 500u) << received << " received";
    EXPECT_EQ(received + (*sub)->missed(), last - (*first)->record.index + 1);
    EXPECT_EQ((*sub)->malformed(), 0u);
}

// A tracker that goes quiet (its server stopped, a cable pulled) must not keep its last samples
// in the detector's look-ahead until it comes back: within a second of the silence the fan-out
// has carried the final version of every sample the ring carried.
TEST_F(ZmqFanOut, ATrackerThatGoesQuietHasEverySampleCarried) {
    auto sim = spawn(kFovea, {"simulate", "gazepoint", "--port", "0", "--rate", "150"});
    const std::string address = sim->first_line();
    ASSERT_FALSE(address.empty()) << sim->err();
    const auto cfg = write_file("quiet.toml",
                                "[zmq]\npublish = \"tcp://127.0.0.1:*\"\n"
                                "[[device]]\ndriver = \"gazepoint\"\naddress = \"" +
                                    address + "\"\n");
    auto d = start_daemon({"--config", cfg});
    auto st = query("status");
    ASSERT_TRUE(st.ok() && st->contains("zmq")) << d->err();
    auto sub = daemon::ZmqGazeSubscriber::connect((*st)["zmq"]["endpoint"].get<std::string>());
    ASSERT_TRUE(sub.ok()) << sub.error().message;
    auto first = (*sub)->receive(5000);
    ASSERT_TRUE(first.ok() && first->has_value()) << "no first message";

    std::this_thread::sleep_for(500ms);
    ASSERT_EQ(kill(sim->pid, SIGSTOP), 0);  // the connection stays open; nothing more comes
    std::this_thread::sleep_for(300ms);     // what was in flight reaches the ring
    fovea::Client ring(instance);
    uint64_t newest = 0;
    for (uint64_t cursor = 0;;) {
        auto b = ring.read(cursor, 512);
        if (b.records.empty()) break;
        newest = b.records.back().index;
    }
    uint64_t last = (*first)->record.index;
    for (;;) {
        auto g = (*sub)->receive(1500);
        ASSERT_TRUE(g.ok()) << g.error().message;
        if (!g->has_value()) break;
        last = (**g).record.index;
    }
    kill(sim->pid, SIGCONT);
    EXPECT_EQ(last, newest) << "samples held back while the tracker was quiet";
}

TEST_F(ZmqFanOut, WatchSubscribesAndPrintsConsecutiveSamples) {
    auto d = start_publishing();
    ASSERT_FALSE(endpoint.empty()) << d->err();
    auto w = spawn(kFovea, {"watch", "--zmq", endpoint, "--count", "200", "--wait", "5"});
    ASSERT_EQ(w->wait(10s), 0) << w->err();
    std::istringstream lines(w->out());
    std::string line;
    int n = 0;
    long long prev = -1;
    while (std::getline(lines, line)) {
        ASSERT_EQ(line.rfind("gaze.2d.", 0), 0u) << line;
        const auto hash = line.find('#');
        ASSERT_NE(hash, std::string::npos) << line;
        const long long idx = std::stoll(line.substr(hash + 1));
        if (prev >= 0) { EXPECT_EQ(idx, prev + 1) << line; }
        prev = idx;
        ++n;
    }
    EXPECT_EQ(n, 200);
}

// What Pupil tools do: ask Pupil Remote for the SUB_PORT, then subscribe to gaze there.
TEST_F(ZmqFanOut, PupilRemoteHandsOutTheSubPort) {
    auto d = start_publishing();
    ASSERT_FALSE(remote.empty()) << d->err();
    void* ctx = zmq_ctx_new();
    void* req = zmq_socket(ctx, ZMQ_REQ);
    const int timeout = 3000, linger = 0;
    zmq_setsockopt(req, ZMQ_RCVTIMEO, &timeout, sizeof timeout);
    zmq_setsockopt(req, ZMQ_LINGER, &linger, sizeof linger);
    ASSERT_EQ(zmq_connect(req, remote.c_str()), 0);
    auto ask = [&](const std::string& cmd) {
        EXPECT_EQ(zmq_send(req, cmd.data(), cmd.size(), 0), static_cast<int>(cmd.size()));
        char buf[128];
        const int n = zmq_recv(req, buf, sizeof buf, 0);
        return n < 0 ? std::string("<timeout>") : std::string(buf, static_cast<std::size_t>(n));
    };
    const std::string port = ask("SUB_PORT");
    EXPECT_EQ("tcp://127.0.0.1:" + port, endpoint);
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    const double t = std::stod(ask("t"));  // Pupil time = the clock of `timestamp`
    EXPECT_NEAR(t, static_cast<double>(ts.tv_sec) + ts.tv_nsec / 1e9, 1.0);
    EXPECT_EQ(ask("R"), "Unknown command.");
    zmq_close(req);
    zmq_ctx_term(ctx);

    auto sub = daemon::ZmqGazeSubscriber::connect("tcp://127.0.0.1:" + port, "gaze.2d.");
    ASSERT_TRUE(sub.ok());
    auto g = (*sub)->receive(5000);
    ASSERT_TRUE(g.ok() && g->has_value());
    EXPECT_NEAR((*g)->timestamp, t, 5.0);
    auto st = query("status");
    ASSERT_TRUE(st.ok());
    EXPECT_EQ((*st)["zmq"]["remote_requests"].get<uint64_t>(), 3u);
}

TEST_F(ZmqFanOut, EndpointInUseFailsTheStartWithAClearError) {
    auto d = start_publishing();
    ASSERT_FALSE(endpoint.empty()) << d->err();
    const auto cfg = write_file("busy.toml", "[zmq]\npublish = \"" + endpoint + "\"\n");
    auto second = spawn(kFovead, {"--instance", instance + "b", "--config", cfg});
    EXPECT_EQ(second->wait(5s), 2);
    EXPECT_NE(second->err().find("zmq.publish: cannot bind " + endpoint), std::string::npos)
        << second->err();
    EXPECT_TRUE(query("status").ok());  // the first daemon is unaffected
}

TEST_F(ZmqFanOut, WatchWithoutAPublisherTimesOutWithAClearError) {
    auto w =
        spawn(kFovea, {"watch", "--zmq", "tcp://127.0.0.1:9", "--count", "1", "--wait", "0.3"});
    EXPECT_NE(w->wait(5s), 0);
    EXPECT_NE(w->err().find("no gaze from tcp://127.0.0.1:9"), std::string::npos) << w->err();
}

}  // namespace
}  // namespace fovea::service_test
