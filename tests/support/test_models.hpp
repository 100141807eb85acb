// The models the tests read. The small ones are committed in models/; bunny.obj and monkey.obj are
// fetched from Debian packages by models/fetch-models.sh and never committed. A test that needs a
// fetched model which is not there stops with the message `models not fetched: run
// models/fetch-models.sh`, which ctest reports as skipped rather than failed
// (SKIP_REGULAR_EXPRESSION in tests/CMakeLists.txt).
#pragma once

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace test_models {

inline const std::filesystem::path dir = HSR_MODELS_DIR;
inline constexpr const char* fetched[] = {"bunny.obj", "monkey.obj"};

// Stops the test, reported as skipped, unless every fetched model is there.
inline void require_fetched() {
    for (const char* file : fetched)
        if (!std::filesystem::exists(dir / file))
            FAIL("models not fetched: run models/fetch-models.sh (models/" << file << " is missing)");
}

// models/<file>. For a fetched model, or a .scene file that names one, require_fetched() first.
inline std::filesystem::path path(const std::string& file) {
    const std::filesystem::path result = dir / file;
    bool needs_fetched = false;
    for (const char* name : fetched) needs_fetched |= file == name;
    if (file.ends_with(".scene")) {
        std::ifstream in(result);
        const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        for (const char* name : fetched) needs_fetched |= text.find(name) != std::string::npos;
    }
    if (needs_fetched) require_fetched();
    return result;
}

}  // namespace test_models
