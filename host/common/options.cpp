// The options' shared parsing (options.hpp).
#include "common/options.hpp"

#include "hsr/params.hpp"

#include <charconv>
#include <cmath>
#include <string_view>

using hsr::host::UsageError;

uint64_t hsr::host::parse_seed(const std::string& text) {
    uint64_t seed = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), seed);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size())
        throw UsageError("--seed '{}': expected a whole number from 0 to 18446744073709551615", hsr::printable(text));
    return seed;
}

glm::vec3 hsr::host::parse_color_option(const std::string& text, const char* option) {
    hsr_param_desc desc{sizeof(hsr_param_desc), option, HSR_PARAM_COLOR, "", 0, 1, nullptr, ""};
    try {
        hsr_param_value v = hsr::parse_param_value(desc, text);
        return {v.color[0], v.color[1], v.color[2]};
    } catch (const hsr::Error& e) {
        throw UsageError("--{}: {}", option, e.what());
    }
}

namespace {

// "n0,n1,...": `count` finite numbers separated by commas, else a UsageError naming the option.
template <int kCount>
glm::vec<kCount, float> parse_number_list(const std::string& text, const char* option, const char* expected) {
    glm::vec<kCount, float> v{};
    std::size_t start = 0;
    for (int k = 0; k < kCount; ++k) {
        const std::size_t comma = k + 1 < kCount ? text.find(',', start) : text.size();
        const std::string_view part = std::string_view(text).substr(start, comma == std::string::npos ? 0 : comma - start);
        const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), v[k]);
        if (comma == std::string::npos || part.empty() || ec != std::errc() || end != part.data() + part.size() ||
            !std::isfinite(v[k]))
            throw UsageError("--{} '{}': expected {}", option, hsr::printable(text), expected);
        start = comma + 1;
    }
    return v;
}

}  // namespace

glm::vec3 hsr::host::parse_vector_option(const std::string& text, const char* option) {
    return parse_number_list<3>(text, option, "x,y,z (three finite numbers)");
}

glm::vec4 hsr::host::parse_plane_option(const std::string& text, const char* option) {
    const glm::vec4 plane = parse_number_list<4>(text, option, "a,b,c,d (four finite numbers)");
    if (plane.x == 0.0f && plane.y == 0.0f && plane.z == 0.0f)
        throw UsageError("--{} '{}': the plane's normal a,b,c is zero", option, hsr::printable(text));
    return plane;
}

