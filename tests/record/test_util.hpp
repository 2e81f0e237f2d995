// Helpers shared by the record tests: scratch directories.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

namespace fovea::record::test {

inline std::filesystem::path scratch_dir(const std::string& name) {
    auto d = std::filesystem::temp_directory_path() /
             ("fovea_record_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

}  // namespace fovea::record::test
