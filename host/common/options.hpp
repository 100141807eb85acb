// What the commands' options share: their defaults, and the parsing of numbers, colours, points and
// planes, each mistake a UsageError that names the option.
#pragma once

#include "hsr/error.hpp"
#include "hsr/defaults.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>

namespace hsr::host {

using hsr::UsageError;

constexpr const char* default_algorithm = "zbuffer";
constexpr const char* default_lighting = "blinn-phong";
using hsr::default_background;
using hsr::default_light;
constexpr double max_line_width = 64.0;  // --line-width, pixels

// A colour option's value, "r/g/b" or "#rrggbb".
glm::vec3 parse_color_option(const std::string& text, const char* option);
// --seed's value: a whole number from 0 to 2^64 - 1.
uint64_t parse_seed(const std::string& text);
// A point or vector option's value, "x,y,z" of finite numbers.
glm::vec3 parse_vector_option(const std::string& text, const char* option);
// A --clip-plane value, "a,b,c,d" of finite numbers with (a, b, c) not zero.
glm::vec4 parse_plane_option(const std::string& text, const char* option);

}  // namespace hsr::host
