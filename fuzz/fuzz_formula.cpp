// Fuzz target: a surface z = f(x, y) as `hsr render --surface FORMULA --range RANGE` makes it. The
// input's first line is the range text (hsr::parse_surface_range), the rest the formula; an input
// without a line break is a formula on the default range. The formula is sampled on at most 8 x 8
// points, so that the time goes into parsing, not into a large grid.
#include "fuzz_support.hpp"

#include "hsr/surface.hpp"

#include <algorithm>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return hsr::fuzz::run_one([&] {
        const std::string_view input = hsr::fuzz::as_text(data, size);
        const std::size_t line_end = input.find('\n');
        hsr::SurfaceRange range;
        std::string_view formula = input;
        if (line_end != std::string_view::npos) {
            range = hsr::parse_surface_range(input.substr(0, line_end));
            formula = input.substr(line_end + 1);
        }
        range.columns = std::min(range.columns, 8u);
        range.rows = std::min(range.rows, 8u);
        hsr::make_formula_surface(std::string(formula), range);
    });
}
