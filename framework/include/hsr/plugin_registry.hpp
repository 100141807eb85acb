// Finding, loading and instantiating plugins through the C ABI (Boost.DLL underneath). The host and
// the tests use this; plugins never do.
#pragma once

#include "hsr/abi.h"
#include "hsr/params.hpp"

#include <chrono>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

namespace boost::dll {
class shared_library;
}

namespace hsr {

// Semantic check of a descriptor against this host's ABI version. Returns an empty string when the
// plugin is acceptable, else the reason it is refused. host_major/minor are parameters so that the
// policy itself can be tested.
std::string check_descriptor(const hsr_plugin_descriptor& d, uint32_t host_major = HSR_ABI_MAJOR,
                             uint32_t host_minor = HSR_ABI_MINOR);

// The reason a descriptor's translation table (ABI 1.6) is refused, or empty; check_descriptor calls it.
std::string check_translations(const hsr_plugin_descriptor& d);

const char* kind_name(uint32_t kind);  // an hsr_plugin_kind: "hidden-surface" / "lighting" / "hidden-line"

// One plugin found in a library. Keeps the library loaded for as long as it (or any instance made
// from it) lives.
// One phase of an algorithm (ABI 1.5, hsr_phase_desc), copied from the plugin.
struct PluginPhase {
    std::string name, title;
};

// One of a plugin's texts in another language (ABI 1.6, hsr_translation), copied from the plugin.
struct PluginTranslation {
    std::string language, key, text;
};

struct Plugin {
    std::shared_ptr<boost::dll::shared_library> library;
    std::filesystem::path path;
    hsr_plugin_descriptor descriptor{};  // copy, zero-filled beyond the plugin's struct_size
    std::vector<PluginPhase> phases;     // the descriptor's, in its order; empty before ABI 1.5
    std::vector<PluginTranslation> translations;  // in the descriptor's order; empty before ABI 1.6

    // The text `key` (an hsr_translation key) in `language`, or nullptr when the plugin gives none.
    const std::string* translated(std::string_view language, std::string_view key) const;
};

struct RejectedLibrary {
    std::filesystem::path path;
    std::string reason;
};

// Loads one library into this process and returns its plugins; throws hsr::Error with the reason
// when the file is not a loadable hsr plugin library (no entry symbol, wrong ABI, ...). Loading runs
// the library's constructors, so a library not yet known to be harmless goes through
// probe_plugin_library first.
std::vector<Plugin> load_plugin_library(const std::filesystem::path& path);

// Loads and validates the library as load_plugin_library does, but in a child process, so that a
// constructor or descriptor that crashes, exits or hangs takes down only the child. Returns an empty
// string when the library loaded and every descriptor passed, else the refusal ("PATH: refused:
// crashed while loading (signal 11, ...)", "... timed out while loading", the validation's reason).
std::string probe_plugin_library(const std::filesystem::path& path,
                                 std::chrono::milliseconds timeout = std::chrono::seconds(5));
// The same for several libraries, loaded one after the other in one child (a new child after each
// library that kills one); one refusal (or empty string) per path, in order.
std::vector<std::string> probe_plugin_libraries(const std::vector<std::filesystem::path>& paths,
                                                std::chrono::milliseconds timeout_each = std::chrono::seconds(5));

class PluginRegistry {
public:
    // Scans each directory (non-recursively) for shared libraries; a directory that does not exist
    // is remembered as searched. Each library is probed (probe_plugin_library) before it is loaded
    // here; libraries that are not acceptable plugins are recorded as rejected.
    void scan_directory(const std::filesystem::path& dir);
    void add_library(const std::filesystem::path& file);

    // The plugin of that kind and name; throws hsr::Error listing where it looked and what it found.
    const Plugin& find(hsr_plugin_kind kind, const std::string& name) const;
    // The first plugin of that name among the kinds, tried in order; the error lists every kind's.
    const Plugin& find_any(std::initializer_list<hsr_plugin_kind> kinds, const std::string& name) const;
    // Whether a plugin of that kind and name was found.
    bool contains(hsr_plugin_kind kind, const std::string& name) const;

    const std::vector<Plugin>& plugins() const { return plugins_; }
    const std::vector<RejectedLibrary>& rejected() const { return rejected_; }
    const std::vector<std::filesystem::path>& searched() const { return searched_; }

private:
    void add_probed_library(const std::filesystem::path& file, std::string refusal);

    std::vector<Plugin> plugins_;
    std::vector<RejectedLibrary> rejected_;
    std::vector<std::filesystem::path> searched_;
};

// The directories the host searches, in order: the build's (or install's) plugin folder next to the
// executable, then each entry of $HSR_PLUGIN_PATH (':'-separated), then the extra ones given.
std::vector<std::filesystem::path> default_plugin_dirs(const std::filesystem::path& executable_dir,
                                                       const std::vector<std::string>& extra);
// The folders searched after the host's own: each entry of $HSR_PLUGIN_PATH, then the extra ones.
std::vector<std::filesystem::path> plugin_path_dirs(const std::vector<std::string>& extra);

// Instances: RAII over the C create/destroy pair. Every call turns a non-OK status into
// hsr::PluginError carrying the status and the plugin's message, and is marked with a
// PluginCallScope, so that a crash in it names the plugin (plugin_faults.hpp). Each holds the plugin
// (and so its library) alive.
class HiddenSurfaceRemover {
public:
    HiddenSurfaceRemover(const Plugin& plugin, const std::vector<Setting>& settings);
    ~HiddenSurfaceRemover();
    HiddenSurfaceRemover(const HiddenSurfaceRemover&) = delete;
    HiddenSurfaceRemover& operator=(const HiddenSurfaceRemover&) = delete;

    void render(const hsr_scene& scene, const hsr_camera& camera, hsr_visibility_buffer& target,
                const hsr_counter_sink* counters);
    // Whether the plugin renders step by step (ABI 1.3 render_steps).
    bool has_steps() const;
    // render() reporting each step to steps, which may stop it; throws hsr::Error when !has_steps().
    void render_steps(const hsr_scene& scene, const hsr_camera& camera, hsr_visibility_buffer& target,
                      const hsr_counter_sink* counters, const hsr_step_sink& steps);
    // Whether the plugin returns fragment lists (ABI 1.4 render_fragments).
    bool has_fragments() const;
    // render() that also hands each pixel's fragment lists to `fragments`; throws hsr::Error when
    // !has_fragments().
    void render_fragments(const hsr_scene& scene, const hsr_camera& camera, hsr_visibility_buffer& target,
                          const hsr_counter_sink* counters, const hsr_fragment_sink& fragments);
    const Plugin& plugin() const { return plugin_; }
    // The plugin's file and name and the instance's settings (settings_key), for caches.
    const std::string& key() const { return key_; }

private:
    Plugin plugin_;
    std::string key_;
    IHiddenSurfaceRemover table_{};  // zero-filled beyond the plugin's struct_size
    void* instance_ = nullptr;
};

class LightingModel {
public:
    LightingModel(const Plugin& plugin, const std::vector<Setting>& settings);
    ~LightingModel();
    LightingModel(const LightingModel&) = delete;
    LightingModel& operator=(const LightingModel&) = delete;

    void prepare(const hsr_scene& scene, const hsr_shading_context& context);
    void shade(hsr_fragment_batch& batch) const;
    const Plugin& plugin() const { return plugin_; }

private:
    Plugin plugin_;
    ILightingModel table_{};
    void* instance_ = nullptr;
};

class HiddenLineRemover {
public:
    HiddenLineRemover(const Plugin& plugin, const std::vector<Setting>& settings);
    ~HiddenLineRemover();
    HiddenLineRemover(const HiddenLineRemover&) = delete;
    HiddenLineRemover& operator=(const HiddenLineRemover&) = delete;

    // trace and counters may be NULL. An error returned by segments.emit comes back as hsr::Error.
    void render_lines(const hsr_scene& scene, const hsr_camera& camera, const hsr_line_request& request,
                      const hsr_segment_sink& segments, const hsr_trace_sink* trace, const hsr_counter_sink* counters);
    const Plugin& plugin() const { return plugin_; }

private:
    Plugin plugin_;
    IHiddenLineRemover table_{};
    void* instance_ = nullptr;
};

}  // namespace hsr
