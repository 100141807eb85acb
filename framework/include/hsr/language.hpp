// The language of messages a person reads: English (the default, and the command line's) or
// Russian (hsr view's page in Russian). say() writes one message in either, both format strings
// checked at compile time against the same arguments; Russian may reorder them with {0}, {1}.
#pragma once

#include <fmt/format.h>

#include <string>
#include <string_view>
#include <utility>

namespace hsr {

enum class Language { english, russian };

// "ru" is Russian; anything else English.
inline Language language_from_code(std::string_view code) { return code == "ru" ? Language::russian : Language::english; }

template <class... Args>
std::string say(Language language, fmt::format_string<Args...> english, fmt::format_string<Args...> russian, Args&&... args) {
    return fmt::format(language == Language::russian ? russian : english, std::forward<Args>(args)...);
}

}  // namespace hsr
