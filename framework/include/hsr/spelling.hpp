// The known word a mistyped one was probably meant to be: an option, a command or a plugin's name,
// for the "(did you mean ...?)" of a message.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hsr {

// The edit distance between a and b, counting an insertion, a deletion, a substitution or a swap
// of two neighbouring characters as one edit (optimal string alignment), letters compared without
// case.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The known word nearest to `typed`, when one is near enough to be a slip: at most one edit for a word
// of up to 5 characters, two up to 8, three beyond. The first of equally near words; none for a
// word that is known or for an empty one.
std::optional<std::string> closest_spelling(std::string_view typed, const std::vector<std::string>& known);

// " (did you mean WORD?)" for the closest spelling, else "": to append to a message.
std::string did_you_mean(std::string_view typed, const std::vector<std::string>& known);

}  // namespace hsr
