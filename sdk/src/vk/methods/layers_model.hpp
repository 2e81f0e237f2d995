// Guenter et al. 2012, §4.3: eccentricity-layer radii and sampling factors that keep the rendered
// resolution at or above a linear MAR line (Eq. 1) while minimising the pixels of all layers.
// Pure C++ (no Vulkan): used by the `layers` method for its constants and by the unit tests.
// All functions are pure and may be called from any thread.
#pragma once

#include <optional>
#include <vector>

#include "fovea/result.hpp"

namespace fovea::vk::methods {

// The display as Guenter parameterises it, measured along its longer axis (his footnote 8:
// for a portrait display width and resolution are those of the vertical axis), so that
// aspect = shorter / longer <= 1 for every display.
struct LayerDisplay {
    int resolution_px = 1920;    // D*: resolution along the longer axis
    double width_cm = 51.0;      // W*: size along the longer axis
    double distance_cm = 59.0;   // V*
    double aspect = 9.0 / 16.0;  // α*
};

// A display of `width_px` x `height_px` pixels spanning `fov_h_deg` x `fov_v_deg` (symmetric
// planar projection), oriented along its longer axis: landscape and portrait alike.
LayerDisplay layer_display_for(int width_px, int height_px, double fov_h_deg, double fov_v_deg);

double display_radius_deg(const LayerDisplay& d);  // e*, Eq. 6
double sharpness_deg(const LayerDisplay& d);       // ω*, Eq. 7 (degrees per cycle = 2 pixels)
// Eq. 9: horizontal resolution at which a display of field of view `fov_deg` has ω* = ω0.
double resolution_for_fov(double fov_deg, double omega0_deg);
// A display of field of view `fov_deg` and aspect `aspect` whose sharpness equals ω0 (Fig. 12).
LayerDisplay acuity_matched_display(double fov_deg, double aspect, double omega0_deg);

// The smallest inner radius e_1 (Eq. 3's measure: the angle at the display centre) whose layer
// covers, within the inner `reach` fraction of its radius (0.6: where its blend starts), every
// point within `fovea_deg` of the gaze wherever the gaze is. A degree spans the most pixels at
// the corners of a planar display, so the worst case is a gaze at a corner looking inwards.
double inner_radius_for_fovea(const LayerDisplay& d, double fovea_deg, double reach);

struct LayerOptions {
    int layer_count = 3;             // n, 2..4
    double slope = 0.022;            // m (quality B; quality A is 0.0275)
    double omega0_deg = 1.0 / 48.0;  // foveal MAR
    int steps = 240;                 // discretisation of (0, e*) for the brute-force search
    bool half_rate_outer = false;    // w_1 = 1, w_i = 1/2 for i > 1 (staggered updates)
    std::optional<double> fixed_s2;  // the "n = 3*" variant of Fig. 12: s_2 forced (e.g. 2)
    double min_inner_deg = 0.0;      // e_1 >= this (keep a full-rate fovea; 0 = pure §4.3)
};

struct Layer {
    double radius_deg = 0.0;       // e_i (the outer layer's is e*)
    double sampling_factor = 1.0;  // s_i >= 1, layer pixel size in display pixels (Eq. 2)
    double diameter_px = 0.0;      // D_i, in layer pixels (Eq. 3)
    double height_px = 0.0;        // vertical size in layer pixels (square except the outer)
    double pixels = 0.0;           // P_i (Eq. 4)
    double weight = 1.0;           // w_i (Eq. 5)
};

struct LayerPlan {
    std::vector<Layer> layers;  // inner first
    double work = 0.0;          // P = Σ w_i P_i (Eq. 5)
    double display_pixels = 0;  // P* (Eq. 8)
    double speedup() const { return display_pixels / work; }
    double shaded_fraction() const { return work / display_pixels; }
};

// Evaluates Eqs. 2–5 for given inner radii e_1 < ... < e_{n-1} (degrees, all < e*).
LayerPlan evaluate_layers(const LayerDisplay& d, const LayerOptions& o,
                          const std::vector<double>& radii_deg);

// Brute-force minimisation of Eq. 5 over the discretised radii (§4.3). Errors on bad input.
Result<LayerPlan> optimise_layers(const LayerDisplay& d, const LayerOptions& o);

}  // namespace fovea::vk::methods
