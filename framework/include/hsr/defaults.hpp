// The light and background of a scene that names none, as text in the syntax of --light and
// --background: the renderer's defaults and the options' alike.
#pragma once

namespace hsr {

constexpr const char* default_light = "dir:-0.5,0.6,1";
constexpr const char* default_background = "0.15/0.15/0.17";

}  // namespace hsr
