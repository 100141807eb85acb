// hsr bench's table and CSV (bench_report.hpp).
#include "bench/bench_report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <ostream>

namespace hsr::bench {
namespace {

// ms with a precision that suits its size: 0.412, 4.12, 41.2, 412.
std::string format_ms(double ms) {
    const double a = std::fabs(ms);
    if (a < 1.0) return fmt::format("{:.3f}", ms);
    if (a < 10.0) return fmt::format("{:.2f}", ms);
    if (a < 100.0) return fmt::format("{:.1f}", ms);
    return fmt::format("{:.0f}", ms);
}

std::string thousands(uint64_t n) {
    std::string digits = std::to_string(n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

double megabytes(uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); }

}  // namespace

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

void write_csv(std::ostream& out, const std::vector<Result>& results) {
    std::vector<std::string> counters;  // every counter any result has, in the order first seen
    for (const Result& r : results)
        for (const auto& c : r.counters) index_of(counters, c.first);
    out << "algorithm,model,width,height,faces,stored_faces,instances,layers,zoom,depth_complexity,"
           "depth_complexity_max,warmup,repetitions,status,reason";
    for (const char* what : {"visibility", "shading", "total"})
        for (const char* stat : {"median", "min", "q1", "q3", "max"}) out << ',' << what << '_' << stat << "_ms";
    out << ",build_ms,build_calls,peak_memory_mb,memory_before_mb";
    for (const std::string& c : counters) out << ',' << csv_field(c);
    out << '\n';
    for (const Result& r : results) {
        out << csv_field(r.algorithm) << ',' << csv_field(r.model) << ',' << r.width << ',' << r.height << ','
            << r.faces << ',' << r.stored_faces << ',' << r.instances << ',' << r.layers << ','
            << fmt::format("{:.4g}", r.zoom) << ',';
        if (r.depth_complexity) out << fmt::format("{:.4f},{}", *r.depth_complexity, r.depth_complexity_max);
        else out << ',';
        out << ',' << r.warmup << ',' << r.repetitions << ',';
        if (r.measured()) {
            out << "measured,";
        } else {
            out << (r.fault.empty() ? "n/a" : csv_field(r.fault)) << ','
                << csv_field(r.fault.empty() ? r.refused : r.fault_detail);
            out << std::string(3 * 5 + 2 + 2, ',');  // no time, no build, no memory
        }
        if (r.measured()) {
            for (const Summary* s : {&r.visibility, &r.shading, &r.total})
                out << fmt::format(",{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}", s->median, s->min, s->q1, s->q3, s->max);
            out << fmt::format(",{:.4f},{}", r.build_ms, r.build_calls);
            if (r.memory.known()) out << fmt::format(",{:.1f},{:.1f}", megabytes(r.memory.peak), megabytes(r.memory.before));
            else out << ",,";
        }
        for (const std::string& name : counters) {
            out << ',';
            for (const auto& [n, v] : r.counters)
                if (n == name) {
                    out << v;
                    break;
                }
        }
        out << '\n';
    }
}

std::string format_table(const std::vector<Result>& results) {
    std::vector<std::pair<uint32_t, uint32_t>> sizes;
    std::vector<std::string> models, algorithms;
    for (const Result& r : results) {
        index_of(sizes, std::make_pair(r.width, r.height));
        index_of(models, r.model);
        index_of(algorithms, r.algorithm);
    }
    auto find = [&](const std::string& a, const std::string& m, std::pair<uint32_t, uint32_t> size) -> const Result* {
        for (const Result& r : results)
            if (r.algorithm == a && r.model == m && r.width == size.first && r.height == size.second) return &r;
        return nullptr;
    };

    std::string out;
    for (const auto& size : sizes) {
        // Rows of cells: a label column, then one per model.
        std::vector<std::vector<std::string>> rows;
        auto add_row = [&](const std::string& label, const std::function<std::string(const Result&)>& cell,
                           const std::vector<std::string>& which) {
            for (const std::string& a : which) {
                std::vector<std::string> row{a.empty() ? label : a};
                bool any = false;
                for (const std::string& m : models) {
                    const Result* r = nullptr;
                    if (a.empty()) {
                        for (const std::string& alg : algorithms)
                            if ((r = find(alg, m, size))) break;
                    } else {
                        r = find(a, m, size);
                    }
                    row.push_back(r ? cell(*r) : "");
                    any = any || (r && !row.back().empty());
                }
                if (any) rows.push_back(std::move(row));
            }
        };
        auto separator = [&] { rows.push_back({}); };
        auto heading = [&](const std::string& text) { rows.push_back({"#" + text}); };

        unsigned reps = 0, warmup = 0;
        bool any_build = false;
        for (const Result& r : results)
            if (r.width == size.first && r.height == size.second) {
                reps = std::max(reps, r.repetitions);
                warmup = std::max(warmup, r.warmup);
                any_build = any_build || r.build_ms > 0;
            }
        std::vector<std::string> header{""};
        header.insert(header.end(), models.begin(), models.end());
        rows.push_back(header);
        add_row("faces", [](const Result& r) { return thousands(r.faces); }, {""});
        add_row("depth complexity",
                [](const Result& r) { return r.depth_complexity ? fmt::format("{:.2f}", *r.depth_complexity) : "-"; },
                {""});
        separator();
        add_row("", [](const Result& r) {
            if (!r.refused.empty()) return std::string("n/a");
            if (!r.fault.empty()) return r.fault;
            return fmt::format("{} [{}-{}]", format_ms(r.visibility.median), format_ms(r.visibility.min),
                               format_ms(r.visibility.max));
        }, algorithms);
        if (any_build) {
            heading("build time, ms (once per scene, reported by the plugin; not in the times above)");
            std::vector<std::string> builders;  // only the algorithms that build something
            for (const Result& r : results)
                if (r.width == size.first && r.height == size.second && r.build_ms > 0) index_of(builders, r.algorithm);
            add_row("", [](const Result& r) { return r.build_ms > 0 ? format_ms(r.build_ms) : "-"; }, builders);
        }
        heading("shading, ms (median)");
        add_row("", [](const Result& r) { return r.measured() ? format_ms(r.shading.median) : "n/a"; },
                algorithms);
        heading("total = visibility + shading, ms (median)");
        add_row("", [](const Result& r) { return r.measured() ? format_ms(r.total.median) : "n/a"; }, algorithms);
        heading("peak memory, MB: the process that made the calls, during the measurement (+ what it added to what it held)");
        add_row("", [](const Result& r) {
            if (!r.memory.known()) return std::string(r.measured() ? "-" : "n/a");
            return fmt::format("{:.0f} (+{:.0f})", megabytes(r.memory.peak), megabytes(r.memory.added()));
        }, algorithms);

        std::vector<std::size_t> width(models.size() + 1, 0);
        for (const auto& row : rows)
            if (!row.empty() && row[0].rfind('#', 0) != 0)
                for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
        out += fmt::format("{}x{}: visibility time, ms (hidden-surface plugin, build excluded): median [min-max] of {} "
                           "run{} after {} warm-up\n",
                           size.first, size.second, reps, reps == 1 ? "" : "s", warmup);
        for (const auto& row : rows) {
            if (row.empty()) {
                std::size_t total = 0;
                for (std::size_t w : width) total += w + 2;
                out += std::string(total - 2, '-') + "\n";
                continue;
            }
            if (row[0].rfind('#', 0) == 0) {
                out += row[0].substr(1) + "\n";
                continue;
            }
            std::string line = fmt::format("{:<{}}", row[0], width[0]);
            for (std::size_t c = 1; c < row.size(); ++c) line += fmt::format("  {:>{}}", row[c], width[c]);
            while (!line.empty() && line.back() == ' ') line.pop_back();
            out += line + "\n";
        }
        for (const Result& r : results)
            if (!r.measured() && r.width == size.first && r.height == size.second)
                out += fmt::format("{}: {} on {}: {}\n", r.fault.empty() ? "n/a" : r.fault, r.algorithm, r.model,
                                   r.fault.empty() ? r.refused : r.fault_detail);
        out += "\n";
    }
    return out;
}

}  // namespace hsr::bench
