#include "gazepoint/opengaze.hpp"

#include <charconv>
#include <cmath>

namespace fovea::drivers::gazepoint {
namespace {

bool is_name_char(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
}
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

std::optional<double> get_double(const Element& e, std::string_view name) {
    const std::string* v = e.get(name);
    if (!v) return std::nullopt;
    double d = 0;
    const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), d);
    if (ec != std::errc() || end != v->data() + v->size()) return NAN;  // present but unreadable
    return d;
}

std::optional<uint64_t> get_u64(const Element& e, std::string_view name, bool* bad) {
    const std::string* v = e.get(name);
    if (!v) return std::nullopt;
    uint64_t x = 0;
    const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), x);
    if (ec != std::errc() || end != v->data() + v->size()) {
        *bad = true;
        return std::nullopt;
    }
    return x;
}

bool plausible_xy(double x, double y) {
    return std::isfinite(x) && std::isfinite(y) && x > -1.0 && x < 2.0 && y > -1.0 && y < 2.0;
}

}  // namespace

const std::string* Element::get(std::string_view name) const {
    for (const auto& [k, v] : attributes)
        if (k == name) return &v;
    return nullptr;
}

std::optional<Element> parse_element(std::string_view t) {
    if (t.size() < 3 || t.front() != '<' || t.back() != '>') return std::nullopt;
    std::size_t i = 1;
    const std::size_t end = t.size() - 1;  // index of '>'
    Element e;
    while (i < end && is_name_char(t[i])) e.tag.push_back(t[i++]);
    if (e.tag.empty()) return std::nullopt;
    while (true) {
        const std::size_t before = i;
        while (i < end && is_space(t[i])) ++i;
        if (i == end) return e;
        if (t[i] == '/') return i + 1 == end ? std::optional<Element>(std::move(e)) : std::nullopt;
        if (i == before) return std::nullopt;  // attributes are separated by whitespace
        std::string name;
        while (i < end && is_name_char(t[i])) name.push_back(t[i++]);
        if (name.empty() || i + 1 >= end || t[i] != '=' || t[i + 1] != '"') return std::nullopt;
        i += 2;
        const std::size_t close = t.find('"', i);
        if (close == std::string_view::npos || close >= end) return std::nullopt;
        e.attributes.emplace_back(std::move(name), std::string(t.substr(i, close - i)));
        i = close + 1;
    }
}

std::string format_element(const Element& e) {
    std::string s = "<" + e.tag;
    for (const auto& [k, v] : e.attributes) s += " " + k + "=\"" + v + "\"";
    s += " />\r\n";
    return s;
}

void ElementStream::reset() {
    if (in_element_) reject(buf_.size());
    buf_.clear();
    in_element_ = false;
    in_sync_ = true;
}

void ElementStream::reject(std::size_t bytes) {
    ++stats_.dropped;
    stats_.garbage_bytes += bytes;
    if (in_sync_) ++stats_.resyncs;
    in_sync_ = false;
}

std::optional<Element> ElementStream::push(char c) {
    if (c == '<') {
        // Attribute values never contain '<': a new element starts here, whatever came before.
        if (in_element_) reject(buf_.size());
        buf_.assign(1, c);
        in_element_ = true;
        return std::nullopt;
    }
    if (!in_element_) {
        if (!is_space(c)) {
            ++stats_.garbage_bytes;
            if (in_sync_) ++stats_.resyncs;
            in_sync_ = false;
        }
        return std::nullopt;
    }
    buf_.push_back(c);
    if (c != '>') {
        if (buf_.size() > kMaxElementSize) {
            reject(buf_.size());
            buf_.clear();
            in_element_ = false;
        }
        return std::nullopt;
    }
    in_element_ = false;
    auto e = parse_element(buf_);
    if (!e) {
        reject(buf_.size());
        return std::nullopt;
    }
    ++stats_.elements;
    in_sync_ = true;
    return e;
}

std::optional<gaze::RawSample> decode_record(const Element& rec, const ServerClock& clock,
                                             GazeSource source, std::optional<uint64_t>* cnt,
                                             std::string* why) {
    const auto fail = [&](const char* reason) {
        if (why) *why = reason;
        return std::optional<gaze::RawSample>();
    };
    bool bad = false;
    if (cnt) *cnt = get_u64(rec, "CNT", &bad);
    gaze::RawSample s;
    if (auto tick = get_u64(rec, "TIME_TICK", &bad)) {
        if (clock.tick_hz <= 0)
            return fail("TIME_TICK before TIME_TICK_FREQUENCY was acknowledged");
        s.device_ticks = *tick;
    } else if (auto t = get_double(rec, "TIME")) {
        if (!std::isfinite(*t) || *t < 0 || *t > 1e9) return fail("absurd TIME");
        s.device_ticks = static_cast<uint64_t>(std::llround(*t * 1e6));
    } else {
        return fail("record has neither TIME_TICK nor TIME");
    }
    if (bad) return fail("unreadable CNT or TIME_TICK");

    const auto best_x = get_double(rec, "BPOGX"), best_y = get_double(rec, "BPOGY");
    const auto best_v = get_double(rec, "BPOGV");
    struct EyeKeys {
        const char *x, *y, *v, *pupil_m, *pupil_v;
    };
    const EyeKeys keys[2] = {{"LPOGX", "LPOGY", "LPOGV", "LPUPILD", "LPUPILV"},
                             {"RPOGX", "RPOGY", "RPOGV", "RPUPILD", "RPUPILV"}};
    gaze::EyeSample* eyes[2] = {&s.left, &s.right};
    bool any_gaze = false;
    for (int i = 0; i < 2; ++i) {
        auto x = get_double(rec, keys[i].x), y = get_double(rec, keys[i].y);
        auto v = get_double(rec, keys[i].v);
        if (source == GazeSource::kBest || !x || !y || !v) {
            x = best_x;
            y = best_y;
            v = best_v;
        }
        if (!x || !y || !v) continue;
        any_gaze = true;
        if (*v != 1.0) continue;  // the tracker says this eye is not valid: values are meaningless
        if (!plausible_xy(*x, *y)) return fail("absurd point of gaze");
        gaze::EyeSample& eye = *eyes[i];
        eye.x = *x;
        eye.y = *y;
        eye.valid = true;
        const auto pm = get_double(rec, keys[i].pupil_m), pv = get_double(rec, keys[i].pupil_v);
        if (pm && (!pv || *pv == 1.0) && *pm != 0.0) {
            const double mm = *pm * 1000.0;
            if (!(mm >= 0.5 && mm <= 12.0)) return fail("absurd pupil diameter");
            eye.pupil_mm = mm;
        }
    }
    if (!any_gaze) return fail("record has no point of gaze");
    return s;
}

std::vector<Element> startup_commands() {
    std::vector<Element> cmds;
    for (const char* id : {"ENABLE_SEND_COUNTER", "ENABLE_SEND_TIME", "ENABLE_SEND_TIME_TICK",
                           "ENABLE_SEND_POG_BEST", "ENABLE_SEND_POG_LEFT", "ENABLE_SEND_POG_RIGHT",
                           "ENABLE_SEND_PUPIL_LEFT", "ENABLE_SEND_PUPIL_RIGHT",
                           "ENABLE_SEND_EYE_LEFT", "ENABLE_SEND_EYE_RIGHT"}) {
        cmds.push_back({"SET", {{"ID", id}, {"STATE", "1"}}});
    }
    cmds.push_back({"GET", {{"ID", "TIME_TICK_FREQUENCY"}}});
    // Data last: every field above is on before the first record.
    cmds.push_back({"SET", {{"ID", "ENABLE_SEND_DATA"}, {"STATE", "1"}}});
    return cmds;
}

}  // namespace fovea::drivers::gazepoint
