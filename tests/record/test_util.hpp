// Helpers shared by the record tests: scratch directories and the independent Python reader.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

namespace fovea::record::test {

inline std::filesystem::path scratch_dir(const std::string& name) {
    auto d = std::filesystem::temp_directory_path() /
             ("fovea_record_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

// Run tests/record/xdf_reader.py on `path`; returns its JSON summary, or null JSON and
// records a failure (with the script's stderr) when it rejects the file.
inline nlohmann::json python_read(const std::string& path, const std::string& flags = "") {
#ifdef FOVEA_XDF_PY_READER
    const std::string out = path + ".py.json";
    const std::string err = path + ".py.err";
    const std::string cmd = std::string(FOVEA_PYTHON3) + " " + FOVEA_XDF_PY_READER + " '" + path +
                            "' " + flags + " > '" + out + "' 2> '" + err + "'";
    const int rc = std::system(cmd.c_str());
    if (rc != 0) {
        std::string msg;
        if (FILE* f = std::fopen(err.c_str(), "r")) {
            char b[512];
            while (std::fgets(b, sizeof b, f)) msg += b;
            std::fclose(f);
        }
        ADD_FAILURE() << "independent reader rejected " << path << ": " << msg;
        return nullptr;
    }
    FILE* f = std::fopen(out.c_str(), "r");
    std::string text;
    char b[4096];
    std::size_t n;
    while ((n = std::fread(b, 1, sizeof b, f)) > 0) text.append(b, n);
    std::fclose(f);
    return nlohmann::json::parse(text);
#else
    (void)path;
    (void)flags;
    return nlohmann::json();
#endif
}

inline bool have_python() {
#ifdef FOVEA_XDF_PY_READER
    return true;
#else
    return false;
#endif
}

}  // namespace fovea::record::test
