#include "fovea/gaze/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <utility>

#include "fovea/json_integer.hpp"
#include "gauss_jordan.hpp"
#include "median.hpp"

namespace fovea::gaze {

namespace {

constexpr int kN = Calibration::kTerms;

// Samples whose target lies within this of a target's first sample are that target. Calibration
// layouts space targets 8 deg and more apart; a head-mounted scene camera sees one marker wander
// up to ~1.2 deg as the head moves (a Pupil Capture calibration, tests/gaze).
constexpr double kSameTargetDeg = 3.0;
// A target is left out of an eye's fit when the fit through the others misses it by more than
// kInconsistentDeg and by more than kInconsistentRatio times what their own residuals expect
// there. On a real head-mounted tracker (same recording) healthy targets miss by 0.6-2.2 times
// the expected, a misread pupil by 86 deg, 12 times; a clean synthetic 9-point fit (its noise
// 0.01 deg) by up to 4.2 times, where the 3 deg floor is what keeps every target in.
constexpr double kInconsistentDeg = 3.0;
constexpr double kInconsistentRatio = 6.0;

void terms(double x, double y, double out[kN]) {
    out[0] = 1.0;
    out[1] = x;
    out[2] = y;
    out[3] = x * y;
    out[4] = x * x;
    out[5] = y * y;
}

double eval(const Calibration::Coefficients& c, const double norm[3], double x, double y) {
    double t[kN];
    terms((x - norm[0]) * norm[2], (y - norm[1]) * norm[2], t);
    double s = 0.0;
    for (int i = 0; i < kN; ++i) s += c[static_cast<size_t>(i)] * t[i];
    return s;
}

// Adds one sample's terms `v` and its target to the normal equations of both coordinates,
// [A | b_x | b_y | ...], the columns past kN + 2 left alone.
template <int Columns>
void add_to_normal_equations(double (&m)[kN][Columns], const double v[kN], double tx, double ty) {
    static_assert(Columns >= kN + 2);
    for (int r = 0; r < kN; ++r) {
        for (int c = 0; c < kN; ++c) m[r][c] += v[r] * v[c];
        m[r][kN] += v[r] * tx;
        m[r][kN + 1] += v[r] * ty;
    }
}

// One target's samples for one eye, summarized by medians (a glance does not move them).
struct TargetMedian {
    double rx, ry;  // raw, centred and scaled as the fit sees it
    double tx, ty;  // normalized display
    size_t target;
    int samples;
};

// Target `at` against the polynomial fitted through all the other targets: how far that fit puts
// it (deg), and how far it would put a target there that fits as well as the others do (deg):
// their residual spread, widened by the target's leverage, as for a studentized deleted
// residual. False when the others cannot be fitted or leave no residual degrees of freedom.
struct Deleted {
    double residual_deg, expected_deg;
};
bool deleted_residual(const std::vector<TargetMedian>& t, size_t at, const DisplayGeometry& display,
                      Deleted& out) {
    const int dof = 2 * (static_cast<int>(t.size()) - 1 - kN);  // both coordinates
    if (dof <= 0) return false;
    double m[kN][kN + 3] = {};
    double v[kN];
    for (size_t i = 0; i < t.size(); ++i) {
        if (i == at) continue;
        terms(t[i].rx, t[i].ry, v);
        add_to_normal_equations(m, v, t[i].tx, t[i].ty);
    }
    double at_terms[kN];
    terms(t[at].rx, t[at].ry, at_terms);
    for (int r = 0; r < kN; ++r) m[r][kN + 2] = at_terms[r];
    if (!detail::gauss_jordan<kN, 3>(m)) return false;
    auto miss_deg = [&](size_t i) {
        terms(t[i].rx, t[i].ry, v);
        double x = 0, y = 0;
        for (int r = 0; r < kN; ++r) {
            x += m[r][kN] * v[r];
            y += m[r][kN + 1] * v[r];
        }
        double px, py, qx, qy;
        display.to_degrees(x, y, px, py);
        display.to_degrees(t[i].tx, t[i].ty, qx, qy);
        return std::hypot(px - qx, py - qy);
    };
    double rss = 0.0, leverage = 0.0;
    for (size_t i = 0; i < t.size(); ++i) {
        if (i != at) rss += std::pow(miss_deg(i), 2);
    }
    for (int r = 0; r < kN; ++r) leverage += at_terms[r] * m[r][kN + 2];
    out.residual_deg = miss_deg(at);
    out.expected_deg = std::sqrt(rss / dof * (1.0 + std::max(0.0, leverage)));
    return std::isfinite(out.residual_deg) && std::isfinite(out.expected_deg);
}

// Leaves out, one at a time, the target that the fit through the others explains least, while
// it misses by more than kInconsistentDeg and kInconsistentRatio times what the others' spread
// expects there; returns those and then the check of each target still in.
std::vector<TargetCheck> check_targets(std::vector<TargetMedian>& t,
                                       const DisplayGeometry& display) {
    std::vector<TargetCheck> checks;
    for (;;) {
        size_t worst = t.size();
        Deleted worst_fit{0.0, 0.0};
        double worst_ratio = 0.0;
        for (size_t k = 0; k < t.size(); ++k) {
            Deleted d;
            if (!deleted_residual(t, k, display, d)) continue;
            const double ratio = d.residual_deg / std::max(d.expected_deg, 1e-9);
            if (ratio > worst_ratio) {
                worst = k;
                worst_fit = d;
                worst_ratio = ratio;
            }
        }
        if (worst == t.size() || worst_fit.residual_deg <= kInconsistentDeg ||
            worst_ratio <= kInconsistentRatio) {
            break;
        }
        checks.push_back({t[worst].tx, t[worst].ty, worst_fit.residual_deg, worst_fit.expected_deg,
                          t[worst].samples, true});
        t.erase(t.begin() + static_cast<long>(worst));
    }
    for (size_t k = 0; k < t.size(); ++k) {
        Deleted d;
        if (deleted_residual(t, k, display, d))
            checks.push_back({t[k].tx, t[k].ty, d.residual_deg, d.expected_deg, t[k].samples});
    }
    return checks;
}

bool usable(const EyeSample& e) {
    return e.valid && std::isfinite(e.x) && std::isfinite(e.y) && std::fabs(e.x) < 1e6 &&
           std::fabs(e.y) < 1e6;
}

}  // namespace

Calibration::Calibration(const DisplayGeometry& display) : display_(display) {}

void Calibration::begin() {
    points_.clear();
    targets_.clear();
    skipped_ = 0;
}

size_t Calibration::target_of(double tx, double ty) {
    double dx, dy;
    display_.to_degrees(tx, ty, dx, dy);
    auto near = [&](size_t k) {
        return std::hypot(dx - targets_[k].first, dy - targets_[k].second) <= kSameTargetDeg;
    };
    if (!points_.empty() && near(points_.back().target)) return points_.back().target;
    for (size_t k = 0; k < targets_.size(); ++k) {
        if (near(k)) return k;
    }
    targets_.emplace_back(dx, dy);
    return targets_.size() - 1;
}

void Calibration::add_sample(double tx, double ty, const EyeSample& left, const EyeSample& right) {
    if (!std::isfinite(tx) || !std::isfinite(ty) || (!usable(left) && !usable(right))) {
        ++skipped_;
        return;
    }
    const size_t target = target_of(tx, ty);
    points_.push_back({tx, ty, left, right, target});
}

Calibration::EyeFit Calibration::fit_eye(EyeSide side, EyeQuality& q) const {
    EyeFit fit;
    std::vector<size_t> idx;  // raw is centred and scaled: well-conditioned normal equations
    for (size_t i = 0; i < points_.size(); ++i) {
        if (usable(side == EyeSide::kLeft ? points_[i].left : points_[i].right)) idx.push_back(i);
    }
    auto raw = [&](size_t i) -> const EyeSample& {
        return side == EyeSide::kLeft ? points_[i].left : points_[i].right;
    };
    double mx = 0, my = 0;
    for (size_t i : idx) {
        mx += raw(i).x;
        my += raw(i).y;
    }
    mx /= std::max<double>(1.0, static_cast<double>(idx.size()));
    my /= std::max<double>(1.0, static_cast<double>(idx.size()));
    double spread = 0;
    for (size_t i : idx)
        spread = std::max({spread, std::fabs(raw(i).x - mx), std::fabs(raw(i).y - my)});
    fit.norm[0] = mx;
    fit.norm[1] = my;
    fit.norm[2] = spread > 0 ? 1.0 / spread : 1.0;
    {  // Targets the fit through the others cannot explain leave this eye's fit.
        std::map<size_t, std::vector<size_t>> by_target;
        for (size_t i : idx) by_target[points_[i].target].push_back(i);
        std::vector<TargetMedian> medians;
        for (const auto& [target, members] : by_target) {
            std::vector<double> rx, ry, tx, ty;
            for (size_t i : members) {
                rx.push_back((raw(i).x - mx) * fit.norm[2]);
                ry.push_back((raw(i).y - my) * fit.norm[2]);
                tx.push_back(points_[i].tx);
                ty.push_back(points_[i].ty);
            }
            medians.push_back({detail::median(rx), detail::median(ry), detail::median(tx),
                               detail::median(ty), target, static_cast<int>(members.size())});
        }
        q.target_checks = check_targets(medians, display_);
        if (medians.size() != by_target.size()) {
            std::vector<bool> kept_target(targets_.size(), false);
            for (const TargetMedian& t : medians) kept_target[t.target] = true;
            std::erase_if(idx, [&](size_t i) { return !kept_target[points_[i].target]; });
        }
    }
    auto fit_on = [&](const std::vector<size_t>& use, EyeFit& f) {
        f.norm[0] = fit.norm[0];
        f.norm[1] = fit.norm[1];
        f.norm[2] = fit.norm[2];
        double m[kN][kN + 2] = {};
        for (size_t i : use) {
            double t[kN];
            terms((raw(i).x - f.norm[0]) * f.norm[2], (raw(i).y - f.norm[1]) * f.norm[2], t);
            add_to_normal_equations(m, t, points_[i].tx, points_[i].ty);
        }
        f.ok = use.size() >= static_cast<size_t>(kN) && detail::gauss_jordan<kN, 2>(m);
        for (int r = 0; f.ok && r < kN; ++r) {
            f.cx[static_cast<size_t>(r)] = m[r][kN];
            f.cy[static_cast<size_t>(r)] = m[r][kN + 1];
        }
    };
    auto error_deg = [&](size_t i, const EyeFit& f) {
        double ax, ay, bx, by;
        display_.to_degrees(eval(f.cx, f.norm, raw(i).x, raw(i).y),
                            eval(f.cy, f.norm, raw(i).x, raw(i).y), ax, ay);
        display_.to_degrees(points_[i].tx, points_[i].ty, bx, by);
        return std::hypot(ax - bx, ay - by);
    };
    fit_on(idx, fit);
    if (!fit.ok) return fit;
    // One outlier pass: drop samples beyond 3x the median error (and > 0.5 deg), refit.
    std::vector<double> err;
    for (size_t i : idx) err.push_back(error_deg(i, fit));
    std::vector<double> sorted = err;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                     sorted.end());
    const double limit = std::max(0.5, 3.0 * sorted[sorted.size() / 2]);
    std::vector<size_t> kept;
    for (size_t k = 0; k < idx.size(); ++k) {
        if (err[k] <= limit) kept.push_back(idx[k]);
    }
    if (kept.size() != idx.size() && kept.size() >= static_cast<size_t>(kN)) {
        EyeFit refit;
        fit_on(kept, refit);
        if (refit.ok) fit = refit;
    } else {
        kept = idx;
    }
    q.fitted = true;
    q.samples_used = static_cast<int>(kept.size());
    q.samples_rejected = static_cast<int>(idx.size() - kept.size());
    measure(
        side, kept,
        [&](const EyeSample& e, double& x, double& y) {
            x = eval(fit.cx, fit.norm, e.x, e.y);
            y = eval(fit.cy, fit.norm, e.x, e.y);
        },
        q);
    return fit;
}

void Calibration::measure(EyeSide side, const std::vector<size_t>& use, const MapFn& map,
                          EyeQuality& q) const {
    // Accuracy: mean angular offset of every mapped sample from its target.
    // Precision per target, on the mapped samples in their arrival order.
    std::map<size_t, std::vector<std::pair<double, double>>> per_target;
    double acc = 0.0;
    for (size_t i : use) {
        const EyeSample& e = side == EyeSide::kLeft ? points_[i].left : points_[i].right;
        double mx = 0, my = 0, dx, dy, tx, ty;
        map(e, mx, my);
        display_.to_degrees(mx, my, dx, dy);
        display_.to_degrees(points_[i].tx, points_[i].ty, tx, ty);
        acc += std::hypot(dx - tx, dy - ty);
        per_target[points_[i].target].emplace_back(dx, dy);
    }
    q.accuracy_deg = use.empty() ? kNaN : acc / static_cast<double>(use.size());
    double s2s = 0.0, dev = 0.0;
    size_t n2s = 0, ndev = 0;
    for (const auto& [target, v] : per_target) {
        double cx = 0, cy = 0;
        for (const auto& p : v) {
            cx += p.first;
            cy += p.second;
        }
        cx /= static_cast<double>(v.size());
        cy /= static_cast<double>(v.size());
        for (size_t k = 0; k < v.size(); ++k) {
            dev += (v[k].first - cx) * (v[k].first - cx) + (v[k].second - cy) * (v[k].second - cy);
            ++ndev;
            if (k > 0) {
                const double ddx = v[k].first - v[k - 1].first, ddy = v[k].second - v[k - 1].second;
                s2s += ddx * ddx + ddy * ddy;
                ++n2s;
            }
        }
    }
    q.precision_rms_deg = n2s ? std::sqrt(s2s / static_cast<double>(n2s)) : 0.0;
    q.precision_sd_deg = ndev ? std::sqrt(dev / static_cast<double>(ndev)) : 0.0;
}

CalibrationQuality Calibration::evaluate_unmapped() const {
    CalibrationQuality q;
    q.targets = static_cast<int>(targets_.size());
    for (EyeSide side : {EyeSide::kLeft, EyeSide::kRight}) {
        EyeQuality& e = side == EyeSide::kLeft ? q.left : q.right;
        std::vector<size_t> idx;
        for (size_t i = 0; i < points_.size(); ++i) {
            if (usable(side == EyeSide::kLeft ? points_[i].left : points_[i].right))
                idx.push_back(i);
        }
        if (idx.empty()) continue;
        e.samples_used = static_cast<int>(idx.size());
        measure(
            side, idx,
            [](const EyeSample& raw, double& x, double& y) {
                x = raw.x;
                y = raw.y;
            },
            e);
    }
    return q;
}

Result<CalibrationQuality> Calibration::fit() {
    if (targets_.size() < static_cast<size_t>(kN)) {
        return make_error("calibration needs at least 6 distinct targets, got " +
                          std::to_string(targets_.size()));
    }
    CalibrationQuality q;
    q.targets = static_cast<int>(targets_.size());
    EyeFit l = fit_eye(EyeSide::kLeft, q.left);
    EyeFit r = fit_eye(EyeSide::kRight, q.right);
    if (!l.ok && !r.ok) {
        return make_error(
            "calibration fit failed for both eyes (too few valid samples or "
            "targets not spread over the display)");
    }
    left_ = l;
    right_ = r;
    quality_ = q;
    return q;
}

EyeSample Calibration::apply(EyeSide side, const EyeSample& raw) const {
    const EyeFit& f = side == EyeSide::kLeft ? left_ : right_;
    if (!f.ok || !raw.valid) return raw;
    EyeSample out = raw;
    out.x = eval(f.cx, f.norm, raw.x, raw.y);
    out.y = eval(f.cy, f.norm, raw.x, raw.y);
    if (!std::isfinite(out.x) || !std::isfinite(out.y)) out.valid = false;
    return out;
}

std::string Calibration::to_json() const {
    nlohmann::json j;
    j["version"] = 1;
    j["model"] = "poly2_cross";
    auto eye = [](const EyeFit& f, const EyeQuality& q) {
        nlohmann::json e;
        e["fitted"] = f.ok;
        if (f.ok) {
            e["cx"] = f.cx;
            e["cy"] = f.cy;
            e["norm"] = {f.norm[0], f.norm[1], f.norm[2]};
            e["accuracy_deg"] = q.accuracy_deg;
            e["precision_rms_deg"] = q.precision_rms_deg;
            e["precision_sd_deg"] = q.precision_sd_deg;
        }
        return e;
    };
    j["left"] = eye(left_, quality_.left);
    j["right"] = eye(right_, quality_.right);
    j["targets"] = quality_.targets;
    return j.dump(2);
}

Result<Calibration> Calibration::from_json(const std::string& text, const DisplayGeometry& d) {
    Calibration c(d);
    try {
        const auto j = nlohmann::json::parse(text);
        auto count = [&j](const char* key, int64_t fallback) -> std::optional<int64_t> {
            const auto it = j.find(key);
            if (it == j.end()) return fallback;
            return json_integer(*it, 0, 1'000'000);
        };
        if (count("version", 0) != 1 || j.value("model", "") != "poly2_cross") {
            return make_error("calibration: unsupported version or model");
        }
        // Quality figures are NaN when unknown, which to_json() writes as null.
        auto figure = [](const nlohmann::json& e, const char* key) {
            const auto it = e.find(key);
            return it != e.end() && it->is_number() ? it->get<double>() : kNaN;
        };
        auto eye = [&figure](const nlohmann::json& e, EyeFit& f, EyeQuality& q) {
            f.ok = e.value("fitted", false);
            if (!f.ok) return true;
            f.cx = e.at("cx").get<Coefficients>();
            f.cy = e.at("cy").get<Coefficients>();
            const auto norm = e.at("norm").get<std::array<double, 3>>();
            for (int i = 0; i < 3; ++i) f.norm[i] = norm[static_cast<size_t>(i)];
            if (!std::isfinite(f.norm[0]) || !std::isfinite(f.norm[1]) || !(f.norm[2] > 0)) {
                return false;
            }
            for (int i = 0; i < kN; ++i) {
                if (!std::isfinite(f.cx[static_cast<size_t>(i)]) ||
                    !std::isfinite(f.cy[static_cast<size_t>(i)])) {
                    return false;
                }
            }
            q.fitted = true;
            q.accuracy_deg = figure(e, "accuracy_deg");
            q.precision_rms_deg = figure(e, "precision_rms_deg");
            q.precision_sd_deg = figure(e, "precision_sd_deg");
            return true;
        };
        if (!eye(j.at("left"), c.left_, c.quality_.left) ||
            !eye(j.at("right"), c.right_, c.quality_.right)) {
            return make_error("calibration: non-finite coefficient");
        }
        const auto targets = count("targets", 0);
        if (!targets) return make_error("calibration: \"targets\" must be a count");
        c.quality_.targets = static_cast<int>(*targets);
    } catch (const std::exception& e) {
        return make_error(std::string("calibration: bad JSON: ") + e.what());
    }
    return c;
}

Result<void> Calibration::save(const std::string& path) const {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::trunc);
        if (!f) return make_error("cannot write " + tmp);
        f << to_json() << '\n';
        if (!f.flush()) return make_error("write failed: " + tmp);
    }
    // Rename so a crash never leaves a half-written calibration.
    if (std::rename(tmp.c_str(), path.c_str()) != 0) return make_error("cannot rename to " + path);
    return {};
}

Result<Calibration> Calibration::load(const std::string& path, const DisplayGeometry& d) {
    std::ifstream f(path);
    if (!f) return make_error("cannot read calibration " + path);
    std::stringstream ss;
    ss << f.rdbuf();
    return from_json(ss.str(), d);
}

Result<std::string> Calibration::user_path(const std::string& dir, const std::string& user) {
    if (user.empty() || user.size() > 64 || user[0] == '.') {
        return make_error("bad user name '" + printable(user) + "'");
    }
    for (char ch : user) {
        const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                        (ch >= '0' && ch <= '9') || ch == '.' || ch == '_' || ch == '-';
        if (!ok) return make_error("bad user name '" + printable(user) + "': use [A-Za-z0-9._-]");
    }
    return dir + "/" + user + ".json";
}

}  // namespace fovea::gaze
