// Meng et al. 2018, kernel log-polar mapping (Eqs. 9–13): screen pixel <-> reduced LP buffer,
// centred on the gaze. Pure C++ (no Vulkan): used by the `kfr` method for its constants and by
// tests; shaders/kfr_map.glsl implements the same formulas. Pure functions, any thread.
#pragma once

#include <vector>

#include "fovea/result.hpp"

namespace fovea::vk::methods {

// K(x) = Σ β_i x^i on [0, 1], monotonically increasing, K(0) = 0, K(1) = 1 (Eq. 9). The pure
// power kernel x^α (non-integer α allowed) is the special case the paper's study uses.
class KfrKernel {
public:
    static KfrKernel power(double alpha);                            // asserts alpha > 0
    static Result<KfrKernel> polynomial(std::vector<double> betas);  // β_0..β_k
    double eval(double x) const;                                     // K(x), x clamped to [0, 1]
    double inverse(double y) const;  // K^{-1}(y), y clamped to [0, 1]
    bool is_power() const { return betas_.empty(); }
    double alpha() const { return alpha_; }
    const std::vector<double>& betas() const { return betas_; }

private:
    double alpha_ = 1.0;
    std::vector<double> betas_;  // empty: power kernel
};

struct Vec2d {
    double x = 0.0;
    double y = 0.0;
};

// The kernel the paper's study calls "K(x) = x^α". Eq. 10 applied literally (u = K^{-1}(ℓ)·w with
// K = x^α) gives the fovea ever more LP columns as α grows (α = 4: 3/4 of the buffer within 10
// pixels of the gaze), the opposite of what Figs. 3–5 report (α moves samples to the periphery;
// from α ≈ 5 the fovea suffers). The reported behaviour is u = ℓ^α·w, i.e. K(x) = x^{1/α}; that is
// the default. `literal` selects K(x) = x^α for comparison.
KfrKernel kfr_study_kernel(double alpha, bool literal = false);

// The LP buffer is w × h = ceil(W/σ) × ceil(H/σ): σ² is the pixel-count reduction (§3).
int kfr_buffer_extent(int screen_extent, double sigma);

class KfrMap {
public:
    // Screen W × H pixels, LP buffer w × h, gaze in screen pixels (clamped to the screen).
    KfrMap(int screen_w, int screen_h, int buffer_w, int buffer_h, Vec2d gaze, KfrKernel kernel);

    // Eq. 10: screen point (pixel units, continuous) -> LP coordinates u ∈ [0, w], v ∈ [0, h).
    // Points within one pixel of the gaze map to u = 0 (log r clamped at 0: no -inf, no NaN).
    Vec2d forward(Vec2d screen) const;
    // Inverse of Eq. 10: LP coordinates -> screen point. v wraps modulo h.
    Vec2d inverse(Vec2d lp) const;
    // Screen pixels per LP texel along u at LP coordinate u (dr/du): the peripheral blur scale.
    double radial_scale(double u) const;

    double log_max_radius() const { return L_; }  // Eq. 12
    Vec2d gaze() const { return gaze_; }          // as clamped to the screen
    int buffer_width() const { return w_; }
    int buffer_height() const { return h_; }

private:
    int w_, h_;
    Vec2d gaze_;
    KfrKernel kernel_;
    double L_;
};

// Eq. 12–13: log of the largest distance from the gaze to a screen corner (at least log 2, so a
// gaze outside a degenerate 1-pixel screen never divides by zero).
double kfr_log_max_radius(int screen_w, int screen_h, Vec2d gaze);

}  // namespace fovea::vk::methods
