// The outline of a run step by step: its steps grouped into runs of consecutive steps with the same
// type, phase and level, and the first step of each phase and type with its text. A viewer moves
// through an algorithm by it (the next culled node, the next phase, the next level) without
// rendering the steps in between. Made by one whole run of a plugin's steps (pipeline.hpp,
// resolve_visibility_steps; lines.hpp, LineSettings::outline).
#pragma once

#include "hsr/abi.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hsr {

struct StepOutline {
    struct Run {
        uint64_t first = 0, count = 0;      // first step (1-based) and how many
        uint32_t type = 0, phase = 0;       // indices into types and phases
        uint32_t level = HSR_NO_LEVEL;
    };
    struct First {
        uint64_t step = 0;
        std::string text;
    };

    uint64_t total = 0;  // steps of the whole run, counted past max_runs too
    std::vector<Run> runs;
    bool truncated = false;  // more runs than max_runs: the runs stop there
    std::size_t max_runs = 200000;
    std::vector<std::string> types, phases;  // phase "" for steps that name none
    std::map<std::string, First> firsts;     // "phase:NAME" and "type:NAME"
    // A plugin names a handful of types and phases; past max_names of each the rest count as one,
    // "other", without firsts, so that a plugin naming a new one at every step stays linear.
    static constexpr std::size_t max_names = 256;

    // Step total + 1: its type, phase ("" for none), level, and text() giving its text, called only
    // for the first step of a phase or type.
    template <class Text>
    void add(std::string_view type, std::string_view phase, uint32_t level, Text&& text) {
        const uint64_t index = ++total;
        if (index > 1 && level == current_.level && types[current_.type] == type && phases[current_.phase] == phase) {
            if (!truncated) ++runs.back().count;
            return;
        }
        current_ = {index, 1, intern(types, type), intern(phases, phase), level};
        std::optional<std::string> text_once;  // the step's text, asked for at most once
        auto step_text = [&]() -> const std::string& {
            if (!text_once) text_once.emplace(text());
            return *text_once;
        };
        if (!phase.empty() && current_.phase < max_names) note_first("phase:", phase, index, step_text);
        if (current_.type < max_names) note_first("type:", type, index, step_text);
        if (truncated) return;
        if (runs.size() >= max_runs) {
            truncated = true;
            return;
        }
        runs.push_back(current_);
    }

private:
    Run current_;  // the run the last step belongs to, kept past max_runs too
    static uint32_t intern(std::vector<std::string>& names, std::string_view name) {
        for (std::size_t k = 0; k < names.size(); ++k)
            if (names[k] == name) return uint32_t(k);
        if (names.size() >= max_names) name = "other";
        for (std::size_t k = max_names; k < names.size(); ++k)
            if (names[k] == name) return uint32_t(k);
        names.emplace_back(name);
        return uint32_t(names.size() - 1);
    }
    template <class Text>
    void note_first(const char* prefix, std::string_view name, uint64_t index, Text& text) {
        std::string key = prefix;
        key += name;
        if (firsts.find(key) == firsts.end()) firsts.emplace(std::move(key), First{index, std::string(text())});
    }
};

}  // namespace hsr
