#include "hsr/params.hpp"

#include "hsr/error.hpp"
#include "hsr/spelling.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>

namespace hsr {
namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

bool parse_double(std::string_view text, double& out) {
    text = trim(text);
    if (text.size() > 1 && text.front() == '+' && text[1] != '-') text.remove_prefix(1);  // from_chars takes no '+'
    if (text.empty()) return false;
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, out);
    return ec == std::errc() && ptr == end && std::isfinite(out);
}

std::string lower(std::string_view s) {
    std::string r(s);
    std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return std::tolower(c); });
    return r;
}

bool parse_color(std::string_view text, float (&rgb)[3]) {
    text = trim(text);
    if (text.size() == 7 && text[0] == '#') {
        for (int i = 0; i < 3; ++i) {
            unsigned value = 0;
            auto [ptr, ec] = std::from_chars(text.data() + 1 + 2 * i, text.data() + 3 + 2 * i, value, 16);
            if (ec != std::errc() || ptr != text.data() + 3 + 2 * i) return false;
            rgb[i] = static_cast<float>(value) / 255.0f;
        }
        return true;
    }
    double channels[3];
    size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        size_t slash = text.find('/', start);
        if ((i < 2) != (slash != std::string_view::npos)) return false;
        std::string_view part = text.substr(start, i < 2 ? slash - start : std::string_view::npos);
        if (!parse_double(part, channels[i]) || channels[i] < 0.0 || channels[i] > 1.0) return false;
        start = slash + 1;
    }
    for (int i = 0; i < 3; ++i) rgb[i] = static_cast<float>(channels[i]);
    return true;
}

// A bound or value as the parameter's type reads: integers whole at any size (not 1e+08).
std::string format_number(const hsr_param_desc& desc, double v) {
    if (desc.type == HSR_PARAM_INT && std::abs(v) < 9.2e18) return fmt::format("{}", static_cast<int64_t>(v));
    return fmt::format("{:g}", v);
}

}  // namespace

const hsr_param_desc& param_desc(const hsr_plugin_descriptor& plugin, uint32_t i) {
    return *HSR_ELEMENT(hsr_param_desc, plugin.params, i);
}

std::vector<std::string> split_choices(const char* choices) {
    std::vector<std::string> out;
    if (choices == nullptr) return out;
    std::string_view rest(choices);
    while (true) {
        size_t bar = rest.find('|');
        out.emplace_back(rest.substr(0, bar));
        if (bar == std::string_view::npos) break;
        rest.remove_prefix(bar + 1);
    }
    return out;
}

PluginSpec parse_plugin_spec(std::string_view text) {
    PluginSpec spec;
    size_t colon = text.find(':');
    spec.name = std::string(trim(text.substr(0, colon)));
    if (spec.name.empty()) throw Error("plugin name missing in '{}'", printable(text));
    if (colon == std::string_view::npos) return spec;
    std::string_view rest = text.substr(colon + 1);
    while (!rest.empty()) {
        size_t comma = rest.find(',');
        std::string_view item = trim(rest.substr(0, comma));
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
        if (item.empty()) continue;
        size_t eq = item.find('=');
        if (eq == std::string_view::npos) {
            // A bare number is most likely the middle of a colour written with commas.
            const bool number_like = std::isdigit(static_cast<unsigned char>(item.front())) || item.front() == '.';
            throw Error("'{}' in '{}' is not key=value{}", printable(item), printable(text),
                        number_like ? " (a colour is written r/g/b)" : "");
        }
        std::string key(trim(item.substr(0, eq)));
        if (key.empty()) throw Error("empty key in '{}'", printable(text));
        spec.settings.emplace_back(key, std::string(trim(item.substr(eq + 1))));
    }
    return spec;
}

hsr_param_value parse_param_value(const hsr_param_desc& desc, std::string_view text) {
    hsr_param_value v{};
    v.struct_size = sizeof v;
    v.name = desc.name;
    v.type = desc.type;
    switch (desc.type) {
    case HSR_PARAM_BOOL: {
        std::string t = lower(trim(text));
        if (t == "true" || t == "1" || t == "yes" || t == "on")
            v.number = 1;
        else if (t == "false" || t == "0" || t == "no" || t == "off")
            v.number = 0;
        else
            throw Error("'{}' is not a boolean (true or false; also yes/no, on/off, 1/0)", printable(text));
        break;
    }
    case HSR_PARAM_INT:
    case HSR_PARAM_FLOAT: {
        double number = 0;
        if (!parse_double(text, number))
            throw Error("'{}' is not a number", printable(text));
        if (desc.type == HSR_PARAM_INT && number != std::floor(number))
            throw Error("'{}' is not a whole number", printable(text));
        if (number < desc.min || number > desc.max)
            throw Error("{} is out of range [{}, {}]", printable(trim(text)), format_number(desc, desc.min),
                        format_number(desc, desc.max));
        v.number = number;
        break;
    }
    case HSR_PARAM_ENUM: {
        std::vector<std::string> choices = split_choices(desc.choices);
        std::string t(trim(text));
        auto it = std::find(choices.begin(), choices.end(), t);
        if (it == choices.end())
            throw Error("'{}' is not one of {}", printable(text), desc.choices ? desc.choices : "(no choices)");
        v.number = static_cast<double>(it - choices.begin());
        break;
    }
    case HSR_PARAM_COLOR:
        if (!parse_color(text, v.color))
            throw Error("'{}' is not a colour (r/g/b with channels in [0, 1], or #rrggbb)", printable(text));
        break;
    default:
        throw Error("unknown parameter type {}", static_cast<int>(desc.type));
    }
    return v;
}

ParamValues resolve_params(const hsr_plugin_descriptor& plugin, const std::vector<Setting>& settings) {
    const char* plugin_name = plugin.name ? plugin.name : "?";
    std::vector<std::string> known;
    for (uint32_t i = 0; i < plugin.param_count; ++i) known.emplace_back(param_desc(plugin, i).name);

    for (size_t i = 0; i < settings.size(); ++i) {
        const std::string& key = settings[i].first;
        if (std::find(known.begin(), known.end(), key) == known.end()) {
            std::string list;
            for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
            throw Error("plugin '{}' has no parameter '{}'{} (it has: {})", plugin_name, printable(key),
                        did_you_mean(key, known), list.empty() ? "none" : list);
        }
        for (size_t j = 0; j < i; ++j)
            if (settings[j].first == key)
                throw Error("parameter '{}' of plugin '{}' is given twice", printable(key), plugin_name);
    }

    ParamValues out;
    for (uint32_t i = 0; i < plugin.param_count; ++i) {
        const hsr_param_desc& desc = param_desc(plugin, i);
        std::string_view text = desc.default_value ? desc.default_value : "";
        bool from_user = false;
        for (const Setting& s : settings) {
            if (s.first == desc.name) {
                text = s.second;
                from_user = true;
            }
        }
        try {
            out.values_.push_back(parse_param_value(desc, text));
        } catch (const Error& e) {
            if (from_user)
                throw Error("parameter '{}' of plugin '{}': {}", desc.name, plugin_name, e.what());
            throw Error("plugin '{}' declares a bad default for '{}': {}", plugin_name, desc.name, e.what());
        }
    }
    return out;
}

std::string describe_param(const hsr_param_desc& desc) {
    std::string range;
    switch (desc.type) {
    case HSR_PARAM_BOOL: range = "true|false"; break;
    case HSR_PARAM_INT:
        range = fmt::format("integer {}..{}", format_number(desc, desc.min), format_number(desc, desc.max));
        break;
    case HSR_PARAM_FLOAT: range = fmt::format("{}..{}", format_number(desc, desc.min), format_number(desc, desc.max)); break;
    case HSR_PARAM_ENUM: range = desc.choices ? desc.choices : ""; break;
    case HSR_PARAM_COLOR: range = "colour r/g/b or #rrggbb"; break;
    }
    return fmt::format("{}={} ({}): {}", desc.name, desc.default_value ? desc.default_value : "", range,
                       desc.help ? desc.help : "");
}

std::string settings_key(const std::string& name, std::vector<Setting> settings) {
    std::sort(settings.begin(), settings.end());
    std::string key = name;
    for (const auto& [k, v] : settings) key += fmt::format("|{}={}", k, v);
    return key;
}

}  // namespace hsr
