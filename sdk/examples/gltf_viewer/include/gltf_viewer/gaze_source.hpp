// Where the viewer's gaze comes from: a fixed point, a recorded trace (CSV t_s,x,y[,event,
// landing_x,landing_y,landing_uncertainty_deg,uncertainty_deg], the demo's format; event 2 =
// saccade), or live from a running fovead through its shared-memory ring (libfovea).
#pragma once

#include <memory>
#include <string>

#include "fovea/vk/acuity.hpp"

namespace gltfv {

class GazeSource {
public:
    virtual ~GazeSource() = default;
    // The gaze for a frame rendered at scene time t_s (live: the newest sample, aged to now).
    virtual fovea::vk::GazeState at(double t_s) = 0;
    virtual std::string describe() const = 0;
};

// spec: "centre" | "X,Y" (normalized) | "fovead" | "fovead:INSTANCE" | a trace file path.
// Null with `error` set on bad input (one line naming the problem).
std::unique_ptr<GazeSource> make_gaze_source(const std::string& spec, std::string& error);

}  // namespace gltfv
