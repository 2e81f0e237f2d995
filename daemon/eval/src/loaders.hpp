// Helpers the dataset loaders share (private to fovea::eval).
#pragma once

#include <string>
#include <vector>

#include "fovea/gaze/sample.hpp"

namespace fovea::eval::detail {

// The display a loader uses for sources recorded in degrees: normalized coordinates that map
// back to the same degrees exactly.
gaze::DisplayGeometry degree_display();
// 1 / the median positive step of t_s, or fallback_hz with fewer than 10 steps.
double rate_from_steps(const std::vector<double>& t_s, double fallback_hz);
// device_ticks (µs) and receive time of a sample t_s seconds after the first.
void set_time(gaze::RawSample& s, double t_s);
// Content tests for the folder walk (fovea::import's format detection).
bool is_lund2013_csv(const std::string& path);
bool dir_has_format(const std::string& dir, const char* ext, const char* format_name);

}  // namespace fovea::eval::detail
