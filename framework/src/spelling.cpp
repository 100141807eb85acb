// Suggestions for mistyped words (spelling.hpp).
#include "hsr/spelling.hpp"

#include "hsr/error.hpp"

#include <algorithm>
#include <cctype>

namespace hsr {

std::size_t edit_distance(std::string_view a, std::string_view b) {
    const auto same = [](char x, char y) {
        return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
    };
    const std::size_t columns = b.size() + 1;
    // Three rows of the table: the row two before (for swaps), the one before, this one.
    std::vector<std::size_t> before_last(columns), last(columns), row(columns);
    for (std::size_t j = 0; j < columns; ++j) last[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        row[0] = i;
        for (std::size_t j = 1; j < columns; ++j) {
            const std::size_t substitution = last[j - 1] + (same(a[i - 1], b[j - 1]) ? 0 : 1);
            row[j] = std::min({last[j] + 1, row[j - 1] + 1, substitution});
            if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1]))
                row[j] = std::min(row[j], before_last[j - 2] + 1);
        }
        std::swap(before_last, last);
        std::swap(last, row);
    }
    return last[b.size()];
}

std::optional<std::string> closest_spelling(std::string_view typed, const std::vector<std::string>& known) {
    if (typed.empty()) return std::nullopt;
    const std::size_t allowed = typed.size() <= 5 ? 1 : typed.size() <= 8 ? 2 : 3;
    std::optional<std::string> best;
    std::size_t best_distance = allowed + 1;
    for (const std::string& word : known) {
        if (word == typed) return std::nullopt;
        // Beyond `allowed` in length alone: no need for the table.
        const std::size_t length_gap = word.size() > typed.size() ? word.size() - typed.size() : typed.size() - word.size();
        if (length_gap >= best_distance) continue;
        const std::size_t distance = edit_distance(typed, word);
        if (distance < best_distance) {
            best_distance = distance;
            best = word;
        }
    }
    return best;
}

std::string did_you_mean(std::string_view typed, const std::vector<std::string>& known) {
    const std::optional<std::string> closest = closest_spelling(typed, known);
    return closest ? " (did you mean " + printable(*closest) + "?)" : "";
}

}  // namespace hsr
