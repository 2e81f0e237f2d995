// The independent XDF oracle: Debian's libxdf (libxdf-dev, the reader SigViewer uses) must read
// every file we write as our own reader does. Tests only.
#pragma once

#include <string>

namespace fovea::record::test {

// Load `path` with libxdf and with xdf::read_file and expect them to agree: the same streams in
// the same order (name, type, channel count, format and labels, nominal rate), each with the same
// sample count and bit-identical time stamps, the same values at libxdf's float precision, and,
// unless the file may lack them, a footer whose sample_count is the number of samples read. libxdf
// 0.99.8 crashes on a stream without samples (reported as a failure here): skip those.
void expect_libxdf_agrees(const std::string& path, bool require_footers = true);

}  // namespace fovea::record::test
