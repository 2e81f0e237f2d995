#include "gazepoint/server_sim.hpp"

#include <array>
#include <chrono>
#include <cstdio>
#include <deque>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>

#include "gazepoint/opengaze.hpp"

namespace fovea::drivers::gazepoint {

using boost::asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::size_t kMaxQueuedBytes = 4 << 20;  // a client this far behind is cut off
const std::set<std::string> kKnownIds = {
    "ENABLE_SEND_DATA",      "ENABLE_SEND_COUNTER",    "ENABLE_SEND_TIME",
    "ENABLE_SEND_TIME_TICK", "ENABLE_SEND_POG_BEST",   "ENABLE_SEND_POG_LEFT",
    "ENABLE_SEND_POG_RIGHT", "ENABLE_SEND_PUPIL_LEFT", "ENABLE_SEND_PUPIL_RIGHT",
    "ENABLE_SEND_EYE_LEFT",  "ENABLE_SEND_EYE_RIGHT",  "ENABLE_SEND_POG_FIX",
    "ENABLE_SEND_CURSOR"};

struct Client {
    explicit Client(tcp::socket s) : socket(std::move(s)) {}
    tcp::socket socket;
    ElementStream stream;
    std::set<std::string> enabled;
    bool streaming = false;
    bool writing = false;
    bool closed = false;
    std::deque<std::pair<std::string, bool>> queue;  // bytes, is a record
    std::size_t queued_bytes = 0;
    std::array<char, 4096> buf{};
};

}  // namespace

struct SimServer::Impl : std::enable_shared_from_this<Impl> {
    Impl(boost::asio::io_context& io_, const ServerOptions& o) : io(io_), opt(o), timer(io_) {
        opt.sim.counter_bits = 64;
        opt.sim.tick_hz = opt.tick_hz;
        if (opt.sim.counter_offset < 0) opt.sim.counter_offset = 123'456'789'000;
        tracker.emplace(opt.sim);
        rng = opt.sim.seed * 0x9E3779B97F4A7C15ULL + 7;
    }

    boost::asio::io_context& io;
    ServerOptions opt;
    std::optional<tcp::acceptor> acceptor;
    boost::asio::steady_timer timer;
    std::optional<sim::SimTracker> tracker;
    std::vector<std::shared_ptr<Client>> clients;
    Stats stats;
    uint64_t rng = 1;
    uint64_t index = 0;
    Clock::time_point start{};
    bool running = false;

    double uniform() {
        rng ^= rng >> 12;
        rng ^= rng << 25;
        rng ^= rng >> 27;
        return static_cast<double>((rng * 0x2545F4914F6CDD1DULL) >> 11) * 0x1.0p-53;
    }

    void accept() {
        acceptor->async_accept(
            [self = shared_from_this()](boost::system::error_code ec, tcp::socket s) {
                if (!self->running) return;
                if (!ec) {
                    s.set_option(tcp::no_delay(true));
                    auto c = std::make_shared<Client>(std::move(s));
                    self->clients.push_back(c);
                    ++self->stats.clients;
                    self->read(c);
                }
                self->accept();
            });
    }

    void read(const std::shared_ptr<Client>& c) {
        c->socket.async_read_some(
            boost::asio::buffer(c->buf),
            [self = shared_from_this(), c](boost::system::error_code ec, std::size_t n) {
                if (ec || c->closed) {
                    self->drop(c);
                    return;
                }
                c->stream.feed(std::string_view(c->buf.data(), n),
                               [&](const Element& e) { self->on_command(*c, e); });
                self->flush(c);
                self->read(c);
            });
    }

    void on_command(Client& c, const Element& e) {
        const std::string* id = e.get("ID");
        if (!id) return;
        if (e.tag == "SET" && kKnownIds.count(*id)) {
            const std::string* state = e.get("STATE");
            const bool on = state && *state == "1";
            if (*id == "ENABLE_SEND_DATA") {
                c.streaming = on;
            } else if (on) {
                c.enabled.insert(*id);
            } else {
                c.enabled.erase(*id);
            }
            enqueue(c, format_element({"ACK", {{"ID", *id}, {"STATE", on ? "1" : "0"}}}));
        } else if (e.tag == "GET" && *id == "TIME_TICK_FREQUENCY") {
            char freq[32];
            std::snprintf(freq, sizeof freq, "%.0f", opt.tick_hz);
            enqueue(c, format_element({"ACK", {{"ID", *id}, {"FREQ", freq}}}));
        } else {
            enqueue(c, format_element({"NACK", {{"ID", *id}}}));
        }
    }

    void enqueue(Client& c, std::string s, bool record = false) {
        c.queued_bytes += s.size();
        c.queue.emplace_back(std::move(s), record);
    }

    void flush(const std::shared_ptr<Client>& c) {
        if (c->closed || c->writing || c->queue.empty()) return;
        if (c->queued_bytes > kMaxQueuedBytes) {
            drop(c);
            return;
        }
        c->writing = true;
        auto batch = std::make_shared<std::string>();
        // (end offset, records) per queued element: a write cut short by stop() still counts
        // the records that reached the kernel whole.
        auto ends = std::make_shared<std::vector<std::pair<std::size_t, uint64_t>>>();
        while (!c->queue.empty()) {
            *batch += c->queue.front().first;
            ends->emplace_back(batch->size(), c->queue.front().second);
            c->queue.pop_front();
        }
        c->queued_bytes = 0;
        boost::asio::async_write(c->socket, boost::asio::buffer(*batch),
                                 [self = shared_from_this(), c, batch, ends](
                                     boost::system::error_code ec, std::size_t written) {
                                     c->writing = false;
                                     for (const auto& [end, n] : *ends)
                                         if (end <= written)
                                             self->stats.records +=
                                                 n;  // handed to the kernel: sent
                                     if (ec) {
                                         self->drop(c);
                                         return;
                                     }
                                     self->flush(c);
                                 });
    }

    void drop(const std::shared_ptr<Client>& c) {
        if (c->closed) return;
        c->closed = true;
        boost::system::error_code ignored;
        c->socket.shutdown(tcp::socket::shutdown_both, ignored);
        c->socket.close(ignored);
        std::erase(clients, c);
    }

    std::chrono::nanoseconds due(uint64_t n) const {
        return std::chrono::nanoseconds(static_cast<int64_t>(n * 1e9 / opt.sim.rate_hz));
    }

    void tick() {
        timer.expires_at(start + due(index) + std::chrono::milliseconds(1));
        timer.async_wait([self = shared_from_this()](boost::system::error_code ec) {
            if (ec || !self->running) return;
            const auto now = Clock::now();
            while (self->start + self->due(self->index) <= now) self->emit();
            for (const auto& c : std::vector(self->clients)) self->flush(c);
            self->tick();
        });
    }

    void emit() {
        const auto f = tracker->next();
        const uint64_t cnt = index++;
        bool any = false;
        for (const auto& c : clients) any |= c->streaming;
        if (!any) return;
        if (opt.drop > 0 && uniform() < opt.drop) {
            ++stats.dropped;
            return;
        }
        std::string garbage;
        if (opt.garbage > 0 && uniform() < opt.garbage) {
            // Stray bytes, sometimes with a truncated element in them.
            const int n = 1 + static_cast<int>(uniform() * 40);
            for (int i = 0; i < n; ++i) garbage.push_back(static_cast<char>(33 + uniform() * 90));
            if (uniform() < 0.5) garbage += "<REC CNT=\"";
            ++stats.garbage;
        }
        for (const auto& c : clients) {
            if (!c->streaming) continue;
            if (!garbage.empty()) enqueue(*c, garbage);
            enqueue(*c, format_record(*c, f, cnt), true);
        }
    }

    std::string format_record(const Client& c, const sim::SimTracker::Frame& f, uint64_t cnt) {
        const auto on = [&](const char* id) { return c.enabled.count(id) != 0; };
        std::string r = "<REC";
        char b[160];
        const auto add = [&](const char* fmt, auto... v) {
            std::snprintf(b, sizeof b, fmt, v...);
            r += b;
        };
        const auto& L = f.raw.left;
        const auto& R = f.raw.right;
        const auto xy = [](const gaze::EyeSample& e, bool x) {
            return e.valid ? (x ? e.x : e.y) : 0.0;
        };
        if (on("ENABLE_SEND_COUNTER")) add(" CNT=\"%llu\"", static_cast<unsigned long long>(cnt));
        if (on("ENABLE_SEND_TIME"))
            add(" TIME=\"%.5f\"", static_cast<double>(index) / opt.sim.rate_hz);
        if (on("ENABLE_SEND_TIME_TICK")) {
            add(" TIME_TICK=\"%llu\"", static_cast<unsigned long long>(f.raw.device_ticks));
        }
        if (on("ENABLE_SEND_POG_LEFT")) {
            add(" LPOGX=\"%.5f\" LPOGY=\"%.5f\" LPOGV=\"%d\"", xy(L, true), xy(L, false),
                L.valid ? 1 : 0);
        }
        if (on("ENABLE_SEND_POG_RIGHT")) {
            add(" RPOGX=\"%.5f\" RPOGY=\"%.5f\" RPOGV=\"%d\"", xy(R, true), xy(R, false),
                R.valid ? 1 : 0);
        }
        if (on("ENABLE_SEND_POG_BEST")) {
            const int n = (L.valid ? 1 : 0) + (R.valid ? 1 : 0);
            const double bx = n ? (xy(L, true) + xy(R, true)) / n : 0.0;
            const double by = n ? (xy(L, false) + xy(R, false)) / n : 0.0;
            add(" BPOGX=\"%.5f\" BPOGY=\"%.5f\" BPOGV=\"%d\"", bx, by, n ? 1 : 0);
        }
        if (on("ENABLE_SEND_PUPIL_LEFT")) {
            add(" LPCX=\"0.40000\" LPCY=\"0.50000\" LPD=\"%.3f\" LPS=\"1.000\" LPV=\"%d\"",
                L.valid ? L.pupil_mm * 6.5 : 0.0, L.valid ? 1 : 0);
        }
        if (on("ENABLE_SEND_PUPIL_RIGHT")) {
            add(" RPCX=\"0.60000\" RPCY=\"0.50000\" RPD=\"%.3f\" RPS=\"1.000\" RPV=\"%d\"",
                R.valid ? R.pupil_mm * 6.5 : 0.0, R.valid ? 1 : 0);
        }
        if (on("ENABLE_SEND_EYE_LEFT")) {
            add(" LEYEX=\"-0.03000\" LEYEY=\"0.00000\" LEYEZ=\"0.60000\" LPUPILD=\"%.6f\" "
                "LPUPILV=\"%d\"",
                L.valid ? L.pupil_mm / 1000.0 : 0.0, L.valid ? 1 : 0);
        }
        if (on("ENABLE_SEND_EYE_RIGHT")) {
            add(" REYEX=\"0.03000\" REYEY=\"0.00000\" REYEZ=\"0.60000\" RPUPILD=\"%.6f\" "
                "RPUPILV=\"%d\"",
                R.valid ? R.pupil_mm / 1000.0 : 0.0, R.valid ? 1 : 0);
        }
        r += " />\r\n";
        return r;
    }
};

SimServer::SimServer(boost::asio::io_context& io, const ServerOptions& options)
    : impl_(std::make_shared<Impl>(io, options)) {}

SimServer::~SimServer() { stop(); }

Result<void> SimServer::start() {
    auto& s = *impl_;
    boost::system::error_code ec;
    s.acceptor.emplace(s.io);
    const tcp::endpoint ep(boost::asio::ip::address_v4::loopback(), s.opt.port);
    s.acceptor->open(ep.protocol(), ec);
    if (!ec) s.acceptor->set_option(tcp::acceptor::reuse_address(true), ec);
    if (!ec) s.acceptor->bind(ep, ec);
    if (!ec) s.acceptor->listen(boost::asio::socket_base::max_listen_connections, ec);
    if (ec) {
        s.acceptor.reset();
        return make_error("gazepoint sim: cannot listen on 127.0.0.1:" +
                              std::to_string(s.opt.port) + ": " + ec.message(),
                          ec.value());
    }
    s.running = true;
    s.start = Clock::now();
    s.accept();
    s.tick();
    return {};
}

void SimServer::stop() {
    auto& s = *impl_;
    if (!s.running) return;
    s.running = false;
    boost::system::error_code ignored;
    if (s.acceptor) s.acceptor->close(ignored);
    s.timer.cancel();
    for (const auto& c : std::vector(s.clients)) s.drop(c);
}

uint16_t SimServer::port() const {
    boost::system::error_code ec;
    return impl_->acceptor ? impl_->acceptor->local_endpoint(ec).port() : 0;
}

SimServer::Stats SimServer::stats() const { return impl_->stats; }

}  // namespace fovea::drivers::gazepoint
