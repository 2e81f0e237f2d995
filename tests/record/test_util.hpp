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

// A fresh directory under the temp dir for one test, removed with its contents when the test
// ends; kept (and named on stderr) when the test has failed, to look at what it wrote.
class ScratchDir {
public:
    explicit ScratchDir(const std::string& name)
        : path_(std::filesystem::temp_directory_path() /
                ("fovea_record_" + name + "_" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        if (::testing::Test::HasFailure()) {
            std::fprintf(stderr, "kept %s\n", path_.c_str());
            return;
        }
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    friend std::filesystem::path operator/(const ScratchDir& d, const std::filesystem::path& p) {
        return d.path_ / p;
    }

private:
    std::filesystem::path path_;
};

}  // namespace fovea::record::test
