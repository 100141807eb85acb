// hsr bench's text reports of its results (measure.hpp): the table printed at the end and the CSV
// file. The plot is in bench_plot.hpp.
#pragma once

#include "bench/measure.hpp"

#include <algorithm>
#include <iosfwd>
#include <string>
#include <vector>

namespace hsr::bench {

// One row per result: identification, sizes, depth complexity (empty when unknown), the status
// ("measured", "n/a" for a refusal, or the fault: "crashed (SIGSEGV)", "timed out") and its reason,
// median, min, q1, q3 and max of render (visibility minus build), shading and total, the build time,
// then one column per counter that any result reported (empty where a result does not have it, and
// every time column where nothing was timed).
void write_csv(std::ostream& out, const std::vector<Result>& results);
std::string csv_field(const std::string& text);  // quoted when it holds a comma, quote or newline

// The classic study's table, one block per resolution: algorithms down, models across, each cell
// "median [min-max]" in ms of visibility time (build excluded); then build times when any plugin
// reported one, and the shading and total medians. A cell without a time reads "n/a" (the plugin
// refused the scene) or its fault ("crashed (SIGSEGV)"), with its reason on a line below the block.
std::string format_table(const std::vector<Result>& results);

// The position of value in list, appended first if missing: the reports list sizes, models and
// algorithms in the order the results first name them.
template <class T>
std::size_t index_of(std::vector<T>& list, const T& value) {
    auto it = std::find(list.begin(), list.end(), value);
    if (it != list.end()) return std::size_t(it - list.begin());
    list.push_back(value);
    return list.size() - 1;
}

}  // namespace hsr::bench
