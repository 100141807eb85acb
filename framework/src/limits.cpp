// The limits on work (limits.hpp): the process's settings, the --limit NAME=N syntax and the check.
#include "hsr/limits.hpp"

#include "hsr/error.hpp"

#include <array>
#include <charconv>
#include <string>

namespace hsr {
namespace {

constexpr std::array<LimitInfo, 11> table{{
    {"triangles", &Limits::triangles, "triangles to draw",
     "triangles drawn, every instance's counted (--repeat, a .scene file's repeat)"},
    {"stored-triangles", &Limits::stored_triangles, "stored triangles",
     "triangles stored one by one: a model file's faces (counted before it is read), a .scene file's "
     "meshes and polygons together, a Loop-subdivided bench model, or an instanced scene copied out for "
     "a hidden-line plugin or a plugin built against ABI 1.0"},
    {"model-bytes", &Limits::model_bytes, "bytes", "size of one model or .scene file, checked before it is read"},
    {"instances", &Limits::instances, "instances", "copies placed by --repeat or a .scene file's repeat"},
    {"lights", &Limits::lights, "lights", "lights of one picture (--light, a .scene file's light lines)"},
    {"surface-samples", &Limits::surface_samples, "grid samples", "grid samples of --surface and --heightmap"},
    {"heightmap-pixels", &Limits::heightmap_pixels, "pixels", "pixels of a --heightmap PNG, read before any step"},
    {"image-pixels", &Limits::image_pixels, "pixels", "width x height of the picture, times its samples per pixel (--samples)"},
    {"upload-bytes", &Limits::upload_bytes, "bytes", "size of one request body to hsr view: an uploaded model"},
    {"fragments", &Limits::fragments, "fragments", "surface fragments of one frame that a plugin hands back in lists (a-buffer)"},
    {"frames", &Limits::frames, "frames", "frames of one hsr render: --views, --yaw and --pitch ranges, all the lines of a --jobs file"},
}};

Limits& current() {
    static Limits limits;
    return limits;
}

const LimitInfo& info(uint64_t Limits::*limit) {
    for (const LimitInfo& entry : table)
        if (entry.value == limit) return entry;
    throw Error("internal error: a limit without a name");
}

}  // namespace

std::span<const LimitInfo> limit_table() { return table; }

const Limits& limits() { return current(); }

void set_limits(const Limits& limits) { current() = limits; }

void apply_limit_setting(Limits& limits, std::string_view setting) {
    const std::size_t equals = setting.find('=');
    const std::string_view name = setting.substr(0, equals);
    const LimitInfo* found = nullptr;
    std::string names;
    for (const LimitInfo& entry : table) {
        if (name == entry.name) found = &entry;
        names += names.empty() ? entry.name : fmt::format(", {}", entry.name);
    }
    if (equals == std::string_view::npos)
        throw Error("--limit '{}': expected NAME=N, e.g. triangles=500000000 (limits: {})", printable(setting), names);
    if (found == nullptr) throw Error("--limit: unknown limit '{}' (limits: {})", printable(name), names);
    const std::string_view text = setting.substr(equals + 1);
    uint64_t value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || value == 0)
        throw Error("--limit {}: '{}' is not a whole number of at least 1", found->name, printable(text));
    limits.*(found->value) = value;
}

Limits limits_from_settings(const std::vector<std::string>& settings) {
    Limits limits;
    for (const std::string& setting : settings) apply_limit_setting(limits, setting);
    return limits;
}

std::string describe_limit_option() {
    std::string text = "NAME=N, repeatable: raise (or lower) a limit on the work a command may ask for "
                       "(docs/robustness.md). NAME (default): what it bounds:";
    const Limits defaults;
    for (const LimitInfo& limit : table) text += fmt::format(" {} ({}): {};", limit.name, defaults.*(limit.value), limit.bounds);
    text.back() = '.';
    return text;
}

void check_limit(uint64_t Limits::*limit, uint64_t amount, std::string_view what, Language language) {
    const uint64_t allowed = limits().*limit;
    if (amount <= allowed) return;
    const LimitInfo& entry = info(limit);
    if (language == Language::russian)
        throw LimitError("{}{}{} — больше допустимого предела {} (его поднимает флаг --limit {}=N)", what,
                         what.empty() ? "" : ": ", amount, allowed, entry.name);
    throw LimitError("{}{}{} {}, over the limit of {} (raise it with --limit {}=N)", what, what.empty() ? "" : ": ", amount,
                entry.unit, allowed, entry.name);
}

}  // namespace hsr
