// The median of a few values (the upper one of an even count), shared by the gaze chain's
// robust summaries (calibration targets, target dwells).
#pragma once

#include <algorithm>
#include <vector>

namespace fovea::gaze::detail {

// `v` must not be empty; taken by value because it is partly sorted.
inline double median(std::vector<double> v) {
    const auto mid = v.begin() + static_cast<long>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

}  // namespace fovea::gaze::detail
