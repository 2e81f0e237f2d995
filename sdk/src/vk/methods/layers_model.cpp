#include "layers_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace fovea::vk::methods {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;

// Eq. 2 for the layer after one of radius e; a layer cannot be finer than the display (s >= 1).
double sampling_after(double e_deg, const LayerOptions& o, double omega_star) {
    return std::max(1.0, (o.slope * e_deg + o.omega0_deg) / omega_star);
}

// Eqs. 3–4 for an inner (square) layer of radius e and sampling factor s.
double inner_diameter(const LayerDisplay& d, double e_deg, double s) {
    return 2.0 * d.resolution_px / s * std::tan(e_deg * kDegToRad) * d.distance_cm / d.width_cm;
}

double weight_of(int index, const LayerOptions& o) {
    return (o.half_rate_outer && index > 0) ? 0.5 : 1.0;
}

struct Search {
    const LayerDisplay& d;
    const LayerOptions& o;
    double omega_star;
    double e_star;
    std::vector<double> grid;  // candidate radii, ascending, all in (0, e*)
    std::vector<double> current;
    std::vector<double> best;
    double best_work = std::numeric_limits<double>::infinity();
    // Every layer after the inner one coarser than the display (s > 1). With half-rate weights
    // the unconstrained minimum can be a sliver of an inner layer followed by a second s = 1
    // layer: the fovea itself at half rate.
    bool coarser_outside = false;

    // Chooses radius number `k` (0-based) after a previous radius at grid index `from`, with
    // `work` already accumulated for layers 0..k-1 and `s` the sampling factor of layer k.
    void recurse(int k, std::size_t from, double s, double work) {
        const int n = o.layer_count;
        if (k == n - 1) {  // the outer layer covers the whole display at factor s
            const double dn = d.resolution_px / s;
            const double total = work + weight_of(k, o) * d.aspect * dn * dn;
            if (total < best_work) {
                best_work = total;
                best = current;
            }
            return;
        }
        for (std::size_t i = from; i < grid.size(); ++i) {
            const double e = grid[i];
            if (coarser_outside && sampling_after(e, o, omega_star) <= 1.0) continue;
            const double di = inner_diameter(d, e, s);
            const double w = work + weight_of(k, o) * di * di;
            if (w >= best_work) break;  // P_k grows with e: later radii cannot do better here
            current[static_cast<std::size_t>(k)] = e;
            recurse(k + 1, i + 1, sampling_after(e, o, omega_star), w);
        }
    }
};

}  // namespace

double display_radius_deg(const LayerDisplay& d) {
    return std::atan(d.width_cm / (2.0 * d.distance_cm)) * kRadToDeg;
}

double sharpness_deg(const LayerDisplay& d) {
    return std::atan(2.0 * d.width_cm / (d.distance_cm * d.resolution_px)) * kRadToDeg;
}

double resolution_for_fov(double fov_deg, double omega0_deg) {
    return 4.0 * std::tan(fov_deg * 0.5 * kDegToRad) / std::tan(omega0_deg * kDegToRad);
}

LayerDisplay acuity_matched_display(double fov_deg, double aspect, double omega0_deg) {
    LayerDisplay d;
    d.distance_cm = 1.0;  // only the ratio W*/V* matters
    d.width_cm = 2.0 * std::tan(fov_deg * 0.5 * kDegToRad);
    d.aspect = aspect;
    // Eq. 9 is not an integer; rounding D* moves ω* by < 0.05 % for the sizes of Fig. 12.
    d.resolution_px = static_cast<int>(std::lround(resolution_for_fov(fov_deg, omega0_deg)));
    return d;
}

LayerDisplay layer_display_for(int width_px, int height_px, double fov_h_deg, double fov_v_deg) {
    const bool portrait = height_px > width_px;
    LayerDisplay d;
    d.resolution_px = portrait ? height_px : width_px;
    d.distance_cm = 1.0;  // only W*/V* matters
    d.width_cm = 2.0 * std::tan((portrait ? fov_v_deg : fov_h_deg) * 0.5 * kDegToRad);
    d.aspect = portrait ? double(width_px) / height_px : double(height_px) / width_px;
    return d;
}

double inner_radius_for_fovea(const LayerDisplay& d, double fovea_deg, double reach) {
    // In focal lengths on the image plane: the display spans ±hx by ±hy around the axis.
    const double hx = std::tan(display_radius_deg(d) * kDegToRad), hy = d.aspect * hx;
    const double cos_fovea = std::cos(fovea_deg * kDegToRad);
    auto cos_angle = [](double ax, double ay, double bx, double by) {
        return (ax * bx + ay * by + 1.0) /
               std::sqrt((ax * ax + ay * ay + 1.0) * (bx * bx + by * by + 1.0));
    };
    // The farthest, over every direction from the corner gaze, that a point `fovea_deg` away
    // lies (by symmetry one corner serves all four; the steepest direction is not the
    // diagonal, so search them).
    double span = 0.0;
    constexpr int kDirections = 1440;
    for (int k = 0; k < kDirections; ++k) {
        const double a = 2.0 * kPi * k / kDirections;
        const double ux = std::cos(a), uy = std::sin(a);
        double lo = 0.0, hi = 4.0 * std::hypot(hx, hy) + 4.0;  // the angle grows along the line
        if (cos_angle(hx, hy, hx + hi * ux, hy + hi * uy) > cos_fovea) continue;  // never reached
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            (cos_angle(hx, hy, hx + mid * ux, hy + mid * uy) > cos_fovea ? lo : hi) = mid;
        }
        span = std::max(span, hi);
    }
    return std::atan(span / reach) * kRadToDeg;
}

LayerPlan evaluate_layers(const LayerDisplay& d, const LayerOptions& o,
                          const std::vector<double>& radii_deg) {
    const double omega_star = sharpness_deg(d);
    LayerPlan plan;
    plan.display_pixels = d.aspect * double(d.resolution_px) * double(d.resolution_px);
    double s = 1.0;
    for (std::size_t i = 0; i <= radii_deg.size(); ++i) {
        Layer l;
        l.sampling_factor = s;
        l.weight = weight_of(static_cast<int>(i), o);
        if (i < radii_deg.size()) {
            l.radius_deg = radii_deg[i];
            l.diameter_px = inner_diameter(d, l.radius_deg, s);
            l.height_px = l.diameter_px;
            l.pixels = l.diameter_px * l.diameter_px;
            s = sampling_after(l.radius_deg, o, omega_star);
        } else {
            l.radius_deg = display_radius_deg(d);
            l.diameter_px = d.resolution_px / s;
            l.height_px = d.aspect * l.diameter_px;
            l.pixels = d.aspect * l.diameter_px * l.diameter_px;
        }
        plan.work += l.weight * l.pixels;
        plan.layers.push_back(l);
    }
    return plan;
}

Result<LayerPlan> optimise_layers(const LayerDisplay& d, const LayerOptions& o) {
    if (o.layer_count < 2 || o.layer_count > 4)
        return make_error("layer count must be 2..4, got " + std::to_string(o.layer_count));
    if (!(o.slope > 0.0) || !(o.omega0_deg > 0.0))
        return make_error("MAR slope and omega0 must be positive");
    if (d.resolution_px <= 0 || !(d.width_cm > 0.0) || !(d.distance_cm > 0.0) ||
        !(d.aspect > 0.0) || d.aspect > 1.0)
        return make_error(
            "display needs positive size, distance, resolution and aspect <= 1 (measure a "
            "portrait display along its longer axis: layer_display_for)");
    if (o.steps < o.layer_count) return make_error("too few discretisation steps");
    if (!(o.min_inner_deg >= 0.0)) return make_error("min_inner_deg must be >= 0");

    Search search{d, o, sharpness_deg(d), display_radius_deg(d), {}, {}, {}};
    for (int i = 1; i < o.steps; ++i) search.grid.push_back(search.e_star * i / o.steps);
    search.current.assign(static_cast<std::size_t>(o.layer_count - 1), 0.0);

    if (o.fixed_s2) {
        if (o.layer_count < 3) return make_error("a fixed s2 needs at least 3 layers");
        // Eq. 2 inverted: s_2 fixes e_1; the search runs over the remaining radii.
        const double e1 = (*o.fixed_s2 * search.omega_star - o.omega0_deg) / o.slope;
        if (!(e1 > 0.0) || e1 >= search.e_star)
            return make_error("fixed s2 puts e1 outside the display");
        const double d1 = inner_diameter(d, e1, 1.0);
        search.current[0] = e1;
        const auto from = static_cast<std::size_t>(
            std::upper_bound(search.grid.begin(), search.grid.end(), e1) - search.grid.begin());
        search.recurse(1, from, sampling_after(e1, o, search.omega_star),
                       weight_of(0, o) * d1 * d1);
    } else {
        // A lower bound on e_1 starts the first radius further out on the same grid.
        const auto from = static_cast<std::size_t>(
            std::lower_bound(search.grid.begin(), search.grid.end(), o.min_inner_deg) -
            search.grid.begin());
        search.coarser_outside = o.half_rate_outer;
        search.recurse(0, from, 1.0, 0.0);
        if (search.best.empty() && search.coarser_outside) {  // a display too coarse for it
            search.coarser_outside = false;
            search.recurse(0, from, 1.0, 0.0);
        }
    }
    if (search.best.empty()) return make_error("no admissible layer radii on this grid");
    return evaluate_layers(d, o, search.best);
}

}  // namespace fovea::vk::methods
