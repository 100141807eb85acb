// Finding and loading plugin libraries: each is probed in a child process, its descriptors are
// checked defensively (docs/abi.md section 4), and the instance wrappers call through the C ABI.
// Over 700 lines because every check of what a plugin declares (descriptor, parameters, phases,
// translations) reads the same bounded-string rules, and the child-process probe runs those checks.
#include "hsr/plugin_registry.hpp"

#include "hsr/error.hpp"
#include "hsr/plugin_faults.hpp"
#include "hsr/spelling.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>

#ifndef _WIN32
#include <dlfcn.h>
#include <fcntl.h>
#include <link.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <new>
#include <optional>
#include <set>
#include <string_view>
#include <system_error>

namespace hsr {
namespace fs = std::filesystem;

namespace {

// The part of the descriptor every ABI version shares, and the part 1.0 requires.
constexpr size_t frozen_descriptor_size = offsetof(hsr_plugin_descriptor, kind) + sizeof(hsr_plugin_descriptor::kind);
constexpr size_t descriptor_size_1_0 = offsetof(hsr_plugin_descriptor, interface_table) + sizeof(void*);
constexpr size_t descriptor_size_1_5 = offsetof(hsr_plugin_descriptor, phase_count) + sizeof(uint32_t);
constexpr size_t phase_desc_size_1_5 = sizeof(hsr_phase_desc);
constexpr size_t descriptor_size_1_6 = offsetof(hsr_plugin_descriptor, translation_count) + sizeof(uint32_t);
constexpr size_t translation_size_1_6 = sizeof(hsr_translation);
constexpr size_t remover_size_1_0 = offsetof(IHiddenSurfaceRemover, extension);
constexpr size_t lighting_size_1_0 = offsetof(ILightingModel, extension);
constexpr size_t line_remover_size_1_2 = offsetof(IHiddenLineRemover, extension);
constexpr size_t param_desc_size_1_0 = sizeof(hsr_param_desc);

// Bounds on what a descriptor may declare: a plugin's strings and tables are read only within these,
// so that an unterminated string or a wild count is refused instead of read past its end.
constexpr size_t max_name_length = 256;    // api, name, version, parameter names
constexpr size_t max_text_length = 4096;   // descriptions, defaults, choices, help
constexpr uint32_t max_param_count = 256;
constexpr uint32_t max_phase_count = 256;
constexpr uint32_t max_translation_count = 8192;
constexpr size_t max_key_length = 2 * max_name_length + 16; // "choice:<param>:<choice>"
constexpr uint32_t max_struct_size = 4096; // a parameter description or an interface table

// The string, if s is not NULL and ends within max_length bytes (never reading further).
std::optional<std::string_view> bounded_string(const char* s, size_t max_length) {
    if (s == nullptr) return std::nullopt;
    const size_t length = strnlen(s, max_length);
    if (length == max_length) return std::nullopt;
    return std::string_view(s, length);
}

// Copies the first struct_size bytes of a plugin's struct into a zeroed host struct, so fields the
// plugin's (older) layout does not have read as NULL / 0.
template <class T>
T copy_prefix(const T& from, uint32_t struct_size) {
    T to{};
    std::memcpy(&to, &from, std::min<size_t>(struct_size, sizeof(T)));
    return to;
}

std::string plugin_label(const Plugin& p) {
    return std::string(kind_name(p.descriptor.kind)) + " plugin '" + p.descriptor.name + "'";
}

[[noreturn]] void throw_status(const Plugin& plugin, const char* what, hsr_status status,
                               const hsr_error& error) {
    // The plugin may have left the buffer unterminated: its last byte counts as the terminator.
    const std::string_view message(error.message, strnlen(error.message, sizeof error.message - 1));
    throw PluginError(status, fmt::format("{} failed in {} (status {}): {}", plugin_label(plugin), what,
                                          static_cast<int>(status), message.empty() ? "(no message)" : message));
}

std::vector<std::string> split_path_list(const char* list) {
    std::vector<std::string> out;
    if (list == nullptr) return out;
    std::string_view rest(list);
    while (!rest.empty()) {
        size_t colon = rest.find(':');
        if (colon != 0) out.emplace_back(rest.substr(0, colon));
        if (colon == std::string_view::npos) break;
        rest.remove_prefix(colon + 1);
    }
    return out;
}

// Boost.DLL reports a failed dlopen() with a generic error code; ask the dynamic loader again for
// its own words (missing file, wrong ELF class, unresolved symbol, ...).
std::string loader_message(const fs::path& path, const boost::system::error_code& ec) {
#ifndef _WIN32
    if (void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) {
        ::dlclose(handle);
    } else if (const char* why = ::dlerror()) {
        return why;
    }
#endif
    return ec.message();
}

template <class Table>
void require_functions(const Plugin& plugin, const Table& table) {
    if (table.create == nullptr || table.destroy == nullptr)
        throw Error("{} has a NULL create or destroy function", plugin_label(plugin));
}

// Calls into a plugin, marked for the fault line (plugin_faults.hpp); `what` is a string literal. A
// C++ exception must not cross the C ABI (the SDK's boundary catches them all), but a plugin written
// without the SDK may throw anyway: that becomes an hsr::Error rather than std::terminate.
// hsr::Error and std::bad_alloc pass unchanged: the host's own callbacks (counter sinks) may raise
// them from inside the call.
template <class F>
auto call_plugin(const Plugin& plugin, const char* what, F&& f) {
    const PluginCallScope scope(plugin.descriptor.name, what);
    try {
        return f();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw;
    } catch (...) {
        throw Error("{} let an exception escape from {} across the C ABI", plugin_label(plugin), what);
    }
}

// Whether the entry symbol is code: a data symbol of that name would be "called" and crash.
bool entry_is_function(void* address) {
#ifndef _WIN32
    Dl_info info{};
    void* symbol_entry = nullptr;
    if (::dladdr1(address, &info, &symbol_entry, RTLD_DL_SYMENT) == 0 || symbol_entry == nullptr)
        return true;  // the loader cannot tell; the probe process still guards the host
    const unsigned type = ELF64_ST_TYPE(static_cast<const ElfW(Sym)*>(symbol_entry)->st_info);
    return type == STT_FUNC || type == STT_GNU_IFUNC;
#else
    (void)address;
    return true;
#endif
}

}  // namespace

const std::string* Plugin::translated(std::string_view language, std::string_view key) const {
    for (const PluginTranslation& t : translations)
        if (t.language == language && t.key == key) return &t.text;
    return nullptr;
}

const char* kind_name(uint32_t kind) {
    switch (kind) {
    case HSR_KIND_HIDDEN_SURFACE_REMOVER: return "hidden-surface";
    case HSR_KIND_LIGHTING_MODEL: return "lighting";
    case HSR_KIND_HIDDEN_LINE_REMOVER: return "hidden-line";
    }
    return "unknown-kind";
}

namespace {

bool is_language_code(std::string_view code) {
    return (code.size() == 2 || code.size() == 3) &&
           std::all_of(code.begin(), code.end(), [](char c) { return c >= 'a' && c <= 'z'; });
}

bool has_param(const hsr_plugin_descriptor& d, std::string_view name) {
    for (uint32_t i = 0; i < d.param_count; ++i)
        if (name == param_desc(d, i).name) return true;
    return false;
}

bool has_choice(const hsr_plugin_descriptor& d, std::string_view param, std::string_view choice) {
    for (uint32_t i = 0; i < d.param_count; ++i) {
        const hsr_param_desc& p = param_desc(d, i);
        if (param != p.name || p.type != HSR_PARAM_ENUM) continue;
        std::string_view choices = p.choices;
        while (!choices.empty()) {
            const size_t bar = choices.find('|');
            if (choices.substr(0, bar) == choice) return true;
            if (bar == std::string_view::npos) break;
            choices.remove_prefix(bar + 1);
        }
    }
    return false;
}

bool has_phase(const hsr_plugin_descriptor& d, std::string_view name) {
    if (d.abi_minor < 5 || d.struct_size < descriptor_size_1_5) return false;
    for (uint32_t i = 0; i < d.phase_count; ++i)
        if (name == HSR_ELEMENT(hsr_phase_desc, d.phases, i)->name) return true;
    return false;
}

// Why the key cannot be one of this plugin's texts, or empty when it can.
std::string check_translation_key(const hsr_plugin_descriptor& d, std::string_view key) {
    if (key == "description") return {};
    const size_t colon = key.find(':');
    if (colon == std::string_view::npos || colon + 1 == key.size()) return "is not one the ABI lists";
    const std::string_view kind = key.substr(0, colon), name = key.substr(colon + 1);
    if (kind == "param" || kind == "help") return has_param(d, name) ? "" : "names no parameter of the plugin";
    if (kind == "phase") return has_phase(d, name) ? "" : "names no phase of the plugin";
    if (kind == "choice") {
        const size_t second = name.find(':');
        if (second == std::string_view::npos) return "needs choice:<parameter>:<choice>";
        return has_choice(d, name.substr(0, second), name.substr(second + 1)) ? "" : "names no choice of the plugin";
    }
    if (kind == "counter" || kind == "buffer" || kind == "step") return {};
    return "is not one the ABI lists";
}

}  // namespace

std::string check_translations(const hsr_plugin_descriptor& d) {
    if (d.translation_count > max_translation_count)
        return fmt::format("it declares {} translations, more than the {} allowed", d.translation_count,
                           max_translation_count);
    if (d.translations == nullptr) return "its translation table is missing";
    const uint32_t element_size = d.translations[0].struct_size;
    if (element_size < translation_size_1_6 || element_size > max_struct_size)
        return fmt::format("its translation table has elements of {} bytes", element_size);
    std::set<std::pair<std::string_view, std::string_view>> seen;
    for (uint32_t i = 0; i < d.translation_count; ++i) {
        const hsr_translation& t = *HSR_ELEMENT(hsr_translation, d.translations, i);
        const auto language = bounded_string(t.language, max_name_length);
        const auto key = bounded_string(t.key, max_key_length);
        const auto text = bounded_string(t.text, max_text_length);
        if (t.struct_size != element_size || !language || !key || !text)
            return fmt::format("its translation #{} is malformed", i);
        if (!is_language_code(*language))
            return fmt::format("its translation #{} has the language '{}', not a two- or three-letter code", i,
                               printable(*language, 16));
        if (text->empty()) return fmt::format("its translation '{}' ({}) is empty", printable(*key, 80), *language);
        const std::string key_problem = check_translation_key(d, *key);
        if (!key_problem.empty())
            return fmt::format("its translation key '{}' {}", printable(*key, 80), key_problem);
        if (!seen.emplace(*language, *key).second)
            return fmt::format("its translation '{}' ({}) is given twice", printable(*key, 80), *language);
    }
    return {};
}

std::string check_descriptor(const hsr_plugin_descriptor& d, uint32_t host_major, uint32_t host_minor) {
    if (d.struct_size < frozen_descriptor_size) return "its descriptor is too small to be an hsr descriptor";
    const auto api = bounded_string(d.api, max_name_length);
    if (!api || *api != HSR_API_NAME) return "it is not an hsr plugin (api name differs)";
    if (d.abi_major != host_major)
        return fmt::format("it was built for ABI {}.{}, this host speaks ABI {}.{} (major versions must match)",
                           d.abi_major, d.abi_minor, host_major, host_minor);
    if (d.abi_minor > host_minor)
        return fmt::format("it needs ABI {}.{}, newer than this host's {}.{}; update hsr", d.abi_major,
                           d.abi_minor, host_major, host_minor);
    if (d.struct_size < descriptor_size_1_0)
        return fmt::format("its descriptor has struct_size {}, ABI 1.0 needs at least {}", d.struct_size,
                           descriptor_size_1_0);
    if (d.kind != HSR_KIND_HIDDEN_SURFACE_REMOVER && d.kind != HSR_KIND_LIGHTING_MODEL &&
        d.kind != HSR_KIND_HIDDEN_LINE_REMOVER)
        return fmt::format("unknown plugin kind {}", static_cast<int>(d.kind));
    if (d.kind == HSR_KIND_HIDDEN_LINE_REMOVER && d.abi_minor < 2)
        return fmt::format("it claims ABI {}.{}, but hidden-line plugins came with ABI 1.2", d.abi_major, d.abi_minor);
    if (d.name == nullptr || d.name[0] == '\0') return "it has no name";
    if (!bounded_string(d.name, max_name_length))
        return fmt::format("its name does not end within {} bytes", max_name_length);
    if (d.version != nullptr && !bounded_string(d.version, max_name_length))
        return fmt::format("its version does not end within {} bytes", max_name_length);
    if (d.description != nullptr && !bounded_string(d.description, max_text_length))
        return fmt::format("its description does not end within {} bytes", max_text_length);
    if (d.interface_table == nullptr) return "it has no interface table";
    if (d.param_count > max_param_count)
        return fmt::format("it declares {} parameters, more than the {} allowed", d.param_count, max_param_count);
    if (d.param_count > 0 && d.params == nullptr) return "its parameter table is missing";
    if (d.param_count > 0 && d.params[0].struct_size < param_desc_size_1_0)
        return "its parameter table has elements smaller than ABI 1.0's";
    if (d.param_count > 0 && d.params[0].struct_size > max_struct_size)
        return fmt::format("its parameter table has elements of {} bytes, more than the {} allowed",
                           d.params[0].struct_size, max_struct_size);
    for (uint32_t i = 0; i < d.param_count; ++i) {
        const hsr_param_desc& p = param_desc(d, i);
        if (p.struct_size != d.params[0].struct_size || p.name == nullptr || p.name[0] == '\0' ||
            !bounded_string(p.name, max_name_length))
            return fmt::format("its parameter #{} is malformed", i);
        for (const char* text : {p.default_value, p.choices, p.help})
            if (text != nullptr && !bounded_string(text, max_text_length))
                return fmt::format("its parameter '{}' has a text that does not end within {} bytes", p.name,
                                   max_text_length);
        if (p.type < HSR_PARAM_BOOL || p.type > HSR_PARAM_COLOR)
            return fmt::format("its parameter '{}' has an unknown type", p.name);
        if (p.type == HSR_PARAM_ENUM && p.choices == nullptr)
            return fmt::format("its parameter '{}' is a choice without choices", p.name);
        try {
            parse_param_value(p, p.default_value ? p.default_value : "");
        } catch (const Error& e) {
            return fmt::format("its parameter '{}' has a bad default: {}", p.name, e.what());
        }
    }
    if (d.abi_minor >= 5 && d.struct_size >= descriptor_size_1_5 && d.phase_count > 0) {
        if (d.phase_count > max_phase_count)
            return fmt::format("it declares {} phases, more than the {} allowed", d.phase_count, max_phase_count);
        if (d.phases == nullptr) return "its phase table is missing";
        if (d.phases[0].struct_size < phase_desc_size_1_5 || d.phases[0].struct_size > max_struct_size)
            return fmt::format("its phase table has elements of {} bytes", d.phases[0].struct_size);
        for (uint32_t i = 0; i < d.phase_count; ++i) {
            const hsr_phase_desc& phase = *HSR_ELEMENT(hsr_phase_desc, d.phases, i);
            if (phase.struct_size != d.phases[0].struct_size || phase.name == nullptr || phase.name[0] == '\0' ||
                !bounded_string(phase.name, max_name_length) ||
                (phase.title != nullptr && !bounded_string(phase.title, max_text_length)))
                return fmt::format("its phase #{} is malformed", i);
        }
    }
    if (d.abi_minor >= 6 && d.struct_size >= descriptor_size_1_6 && d.translation_count > 0) {
        std::string reason = check_translations(d);
        if (!reason.empty()) return reason;
    }
    const uint32_t table_size = *static_cast<const uint32_t*>(d.interface_table);
    const size_t needed = d.kind == HSR_KIND_HIDDEN_SURFACE_REMOVER ? remover_size_1_0
                           : d.kind == HSR_KIND_LIGHTING_MODEL    ? lighting_size_1_0
                                                                  : line_remover_size_1_2;
    if (table_size < needed)
        return fmt::format("its interface table has struct_size {}, ABI {} needs at least {}", table_size,
                           d.kind == HSR_KIND_HIDDEN_LINE_REMOVER ? "1.2" : "1.0", needed);
    if (table_size > max_struct_size)
        return fmt::format("its interface table has struct_size {}, more than the {} allowed", table_size,
                           max_struct_size);
    return {};
}

std::vector<Plugin> load_plugin_library(const fs::path& path) {
    auto library = std::make_shared<boost::dll::shared_library>();
    boost::system::error_code ec;
    library->load(boost::dll::fs::path(path.string()), boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local, ec);
    if (ec) throw Error("{}: cannot load library: {}", path.string(), loader_message(path, ec));
    if (!library->has(HSR_ENTRY_SYMBOL))
        throw Error("{}: not an hsr plugin (no '{}' symbol)", path.string(), HSR_ENTRY_SYMBOL);
    auto& entry = library->get<const hsr_plugin_descriptor*(uint32_t)>(HSR_ENTRY_SYMBOL);
    if (!entry_is_function(reinterpret_cast<void*>(&entry)))
        throw Error("{}: not an hsr plugin ('{}' is not a function)", path.string(), HSR_ENTRY_SYMBOL);

    const std::string path_text = path.string();
    std::vector<Plugin> plugins;
    constexpr uint32_t max_plugins_per_library = 1024;
    for (uint32_t index = 0; index < max_plugins_per_library; ++index) {
        const hsr_plugin_descriptor* d = nullptr;
        // The descriptor's check reads what the plugin points to: a fault there is the plugin's too.
        const PluginCallScope scope(path_text.c_str(), HSR_ENTRY_SYMBOL);
        try {
            d = entry(index);
        } catch (...) {
            throw Error("{}: its '{}' let an exception escape across the C ABI", path.string(), HSR_ENTRY_SYMBOL);
        }
        if (d == nullptr) break;
        std::string reason = check_descriptor(*d);
        if (!reason.empty()) {
            const auto name = d->struct_size >= descriptor_size_1_0 ? bounded_string(d->name, max_name_length)
                                                                    : std::nullopt;
            throw Error("{}: plugin '{}' refused: {}", path.string(), name.value_or("?"), reason);
        }
        Plugin p;
        p.library = library;
        p.path = path;
        p.descriptor = copy_prefix(*d, d->struct_size);
        if (d->abi_minor < 5) {
            p.descriptor.phases = nullptr;
            p.descriptor.phase_count = 0;
        }
        if (d->abi_minor < 6) {
            p.descriptor.translations = nullptr;
            p.descriptor.translation_count = 0;
        }
        for (uint32_t i = 0; i < p.descriptor.translation_count; ++i) {
            const hsr_translation& t = *HSR_ELEMENT(hsr_translation, p.descriptor.translations, i);
            p.translations.push_back({t.language, t.key, t.text});
        }
        for (uint32_t i = 0; i < p.descriptor.phase_count; ++i) {
            const hsr_phase_desc& phase = *HSR_ELEMENT(hsr_phase_desc, p.descriptor.phases, i);
            p.phases.push_back({std::string(phase.name), phase.title != nullptr ? std::string(phase.title) : std::string()});
        }
        plugins.push_back(std::move(p));
    }
    if (plugins.empty()) throw Error("{}: the library describes no plugin", path.string());
    return plugins;
}

#ifndef _WIN32
namespace {

void write_all(int fd, std::string_view text) {
    while (!text.empty()) {
        const ssize_t n = ::write(fd, text.data(), text.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;
        text.remove_prefix(static_cast<size_t>(n));
    }
}

// The child's side of probe_plugin_libraries: load and validate each library in turn, report one
// line per library ("ok" or "refused REASON"), and leave without running any exit handler (the
// parent's and the plugins' belong to the parent).
[[noreturn]] void run_probe_child(const std::vector<fs::path>& paths, size_t first, int report_fd) {
    stop_reporting_plugin_faults();  // the parent reports how the child ended
    for (int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGPIPE}) ::signal(sig, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const rlimit no_core{0, 0};
    ::setrlimit(RLIMIT_CORE, &no_core);
    if (int null = ::open("/dev/null", O_RDWR); null >= 0) {
        ::dup2(null, STDOUT_FILENO);
        ::dup2(null, STDERR_FILENO);
    }
    std::vector<std::vector<Plugin>> keep_loaded;  // as in the parent, every library stays loaded
    for (size_t i = first; i < paths.size(); ++i) {
        std::string report;
        try {
            keep_loaded.push_back(load_plugin_library(paths[i]));
            report = "ok";
        } catch (const std::exception& e) {
            report = std::string("refused ") + e.what();
        } catch (...) {
            report = "refused " + paths[i].string() + ": an exception escaped while loading it";
        }
        std::replace(report.begin(), report.end(), '\n', ' ');
        write_all(report_fd, report + "\n");
    }
    ::_exit(0);
}

// Runs one child over paths[first..]; fills refusals from first on, up to and including the library
// the child died on (if it did). Returns the index after the last library with a verdict.
size_t probe_from(const std::vector<fs::path>& paths, size_t first, std::chrono::milliseconds timeout_each,
                  std::vector<std::string>& refusals) {
    const auto could_not_start = [&](int error) {
        refusals[first] = fmt::format("{}: refused: cannot start a process to check it ({})", paths[first].string(),
                                      std::strerror(error));
        return first + 1;
    };
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return could_not_start(errno);
    // Buffered output would otherwise be written twice if a library's constructor calls exit().
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int fork_error = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        return could_not_start(fork_error);
    }
    if (pid == 0) {
        ::close(fds[0]);
        run_probe_child(paths, first, fds[1]);
    }
    ::close(fds[1]);

    // Each library gets its own time limit, counted from the previous one's verdict.
    size_t next = first;
    std::string pending;
    bool timed_out = false;
    auto deadline = std::chrono::steady_clock::now() + timeout_each;
    while (next < paths.size()) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        pollfd wait_for{fds[0], POLLIN, 0};
        const int ready = left.count() > 0 ? ::poll(&wait_for, 1, static_cast<int>(left.count())) : 0;
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) {
            timed_out = ready == 0;
            break;
        }
        char buffer[4096];
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;  // end of file: the child is done (or gone)
        pending.append(buffer, static_cast<size_t>(n));
        for (size_t end; (end = pending.find('\n')) != std::string::npos; pending.erase(0, end + 1)) {
            const std::string_view line(pending.data(), end);
            constexpr std::string_view refused = "refused ";
            if (line.rfind(refused, 0) == 0) refusals[next] = std::string(line.substr(refused.size()));
            ++next;
            deadline = std::chrono::steady_clock::now() + timeout_each;
        }
    }
    ::close(fds[0]);
    if (timed_out) ::kill(pid, SIGKILL);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (next == paths.size()) return next;

    const std::string path = paths[next].string();
    if (timed_out)
        refusals[next] = fmt::format("{}: refused: timed out while loading (over {} ms)", path, timeout_each.count());
    else if (WIFSIGNALED(status))
        refusals[next] = fmt::format("{}: refused: crashed while loading (signal {}, {})", path, WTERMSIG(status),
                                     ::strsignal(WTERMSIG(status)));
    else
        refusals[next] = fmt::format("{}: refused: exited while loading (status {})", path,
                                     WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return next + 1;
}

}  // namespace

std::vector<std::string> probe_plugin_libraries(const std::vector<fs::path>& paths,
                                                std::chrono::milliseconds timeout_each) {
    std::vector<std::string> refusals(paths.size());
    // One child for the lot; when one library kills it, the next child starts after that library.
    for (size_t first = 0; first < paths.size();) first = probe_from(paths, first, timeout_each, refusals);
    return refusals;
}
#else
std::vector<std::string> probe_plugin_libraries(const std::vector<fs::path>& paths, std::chrono::milliseconds) {
    return std::vector<std::string>(paths.size());
}
#endif

std::string probe_plugin_library(const fs::path& path, std::chrono::milliseconds timeout) {
    return probe_plugin_libraries({path}, timeout).front();
}

void PluginRegistry::add_library(const fs::path& file) {
    add_probed_library(file, probe_plugin_library(file));
}

void PluginRegistry::add_probed_library(const fs::path& file, std::string refusal) {
    if (!refusal.empty()) {
        rejected_.push_back({file, std::move(refusal)});
        return;
    }
    try {
        for (Plugin& p : load_plugin_library(file)) {
            auto same = std::find_if(plugins_.begin(), plugins_.end(), [&](const Plugin& q) {
                return q.descriptor.kind == p.descriptor.kind && std::strcmp(q.descriptor.name, p.descriptor.name) == 0;
            });
            if (same != plugins_.end()) {
                rejected_.push_back({file, fmt::format("{} plugin '{}' is shadowed by {}", kind_name(p.descriptor.kind),
                                                       p.descriptor.name, same->path.string())});
                continue;
            }
            plugins_.push_back(std::move(p));
        }
    } catch (const Error& e) {
        rejected_.push_back({file, e.what()});
    }
}

void PluginRegistry::scan_directory(const fs::path& dir) {
    searched_.push_back(dir);
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    std::vector<fs::path> files;
    const std::string suffix = boost::dll::shared_library::suffix().string();
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
        if (e.is_regular_file(ec) && e.path().extension() == suffix) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    std::vector<std::string> refusals = probe_plugin_libraries(files);
    for (size_t i = 0; i < files.size(); ++i) add_probed_library(files[i], std::move(refusals[i]));
}

bool PluginRegistry::contains(hsr_plugin_kind kind, const std::string& name) const {
    return std::any_of(plugins_.begin(), plugins_.end(),
                       [&](const Plugin& p) { return p.descriptor.kind == kind && name == p.descriptor.name; });
}

const Plugin& PluginRegistry::find(hsr_plugin_kind kind, const std::string& name) const {
    return find_any({kind}, name);
}

const Plugin& PluginRegistry::find_any(std::initializer_list<hsr_plugin_kind> kinds, const std::string& name) const {
    for (hsr_plugin_kind kind : kinds)
        for (const Plugin& p : plugins_)
            if (p.descriptor.kind == kind && name == p.descriptor.name) return p;
    std::string kinds_text, found;
    std::vector<std::string> known;
    for (hsr_plugin_kind kind : kinds) {
        kinds_text += (kinds_text.empty() ? "" : " or ") + std::string(kind_name(kind));
        std::string names;
        for (const Plugin& p : plugins_)
            if (p.descriptor.kind == kind) {
                names += (names.empty() ? "" : ", ") + std::string(p.descriptor.name);
                known.emplace_back(p.descriptor.name);
            }
        if (kinds.size() > 1) names = std::string(kind_name(kind)) + ": " + (names.empty() ? "none" : names);
        if (!names.empty()) found += (found.empty() ? "" : "; ") + names;
    }
    std::string where;
    for (const fs::path& d : searched_) where += (where.empty() ? "" : ", ") + printable(d.string(), kMaxQuotedPathChars);
    std::string refused;
    for (const RejectedLibrary& r : rejected_) {
        // A library refused before it named its plugins is matched by its file name (NAME.so, hsr-NAME.so).
        const std::string stem = r.path.stem().string();
        if (r.reason.find("'" + name + "'") != std::string::npos || stem == name || stem == "hsr-" + name)
            refused = "; refused: " + r.reason;
    }
    throw Error("no {} plugin named '{}'{} (searched: {}; found: {}){}", kinds_text, printable(name),
                did_you_mean(name, known), where.empty() ? "nowhere" : where, found.empty() ? "none" : found, refused);
}

std::vector<fs::path> default_plugin_dirs(const fs::path& executable_dir, const std::vector<std::string>& extra) {
    std::vector<fs::path> dirs;
    // <exe dir>/plugins in a build tree, <prefix>/lib/hsr/plugins when installed; the first is
    // named even when missing if the second is too, so that "searched:" says where to look.
    const fs::path beside = executable_dir / "plugins";
    const fs::path installed = executable_dir.parent_path() / HSR_INSTALL_PLUGIN_DIR;
    std::error_code ec;
    const bool is_installed = fs::is_directory(installed, ec);
    if (fs::is_directory(beside, ec) || !is_installed) dirs.push_back(beside);
    if (is_installed) dirs.push_back(installed);
    for (fs::path& d : plugin_path_dirs(extra)) dirs.push_back(std::move(d));
    return dirs;
}

std::vector<fs::path> plugin_path_dirs(const std::vector<std::string>& extra) {
    std::vector<fs::path> dirs;
    for (const std::string& d : split_path_list(std::getenv("HSR_PLUGIN_PATH"))) dirs.emplace_back(d);
    for (const std::string& d : extra) dirs.emplace_back(d);
    return dirs;
}

// ---------------------------------------------------------------------------------------------------

HiddenSurfaceRemover::HiddenSurfaceRemover(const Plugin& plugin, const std::vector<Setting>& settings)
    : plugin_(plugin), key_(settings_key(plugin.path.string() + "|" + plugin.descriptor.name, settings)) {
    if (plugin.descriptor.kind != HSR_KIND_HIDDEN_SURFACE_REMOVER)
        throw Error("'{}' is a {} plugin, not a hidden-surface remover", plugin.descriptor.name,
                    kind_name(plugin.descriptor.kind));
    const auto& table = *static_cast<const IHiddenSurfaceRemover*>(plugin.descriptor.interface_table);
    table_ = copy_prefix(table, table.struct_size);
    require_functions(plugin_, table_);
    if (table_.render == nullptr) throw Error("{} has a NULL render function", plugin_label(plugin_));
    ParamValues values = resolve_params(plugin.descriptor, settings);
    hsr_error error{};
    hsr_status status = call_plugin(plugin_, "create", [&] {
        return table_.create(values.data(), values.size(), &instance_, &error);
    });
    if (status != HSR_OK) throw_status(plugin_, "create", status, error);
}

HiddenSurfaceRemover::~HiddenSurfaceRemover() {
    if (instance_ == nullptr) return;
    try {
        const PluginCallScope scope(plugin_.descriptor.name, "destroy");
        table_.destroy(instance_);
    } catch (...) {
        std::cerr << "hsr: warning: " << plugin_label(plugin_) << " let an exception escape from destroy\n";
    }
}

void HiddenSurfaceRemover::render(const hsr_scene& scene, const hsr_camera& camera, hsr_visibility_buffer& target,
                                  const hsr_counter_sink* counters) {
    hsr_error error{};
    hsr_status status =
        call_plugin(plugin_, "render", [&] { return table_.render(instance_, &scene, &camera, &target, counters, &error); });
    if (status != HSR_OK) throw_status(plugin_, "render", status, error);
}

bool HiddenSurfaceRemover::has_steps() const {
    return plugin_.descriptor.abi_minor >= 3 && table_.render_steps != nullptr;
}

void HiddenSurfaceRemover::render_steps(const hsr_scene& scene, const hsr_camera& camera, hsr_visibility_buffer& target,
                                        const hsr_counter_sink* counters, const hsr_step_sink& steps) {
    if (!has_steps())
        throw Error("hidden-surface plugin '{}' cannot show its steps ({})", plugin_.descriptor.name,
                    plugin_.descriptor.abi_minor < 3 ? fmt::format("it is built against ABI 1.{}, steps came with 1.3",
                                                                   plugin_.descriptor.abi_minor)
                                                     : std::string("it has no render_steps"));
    hsr_error error{};
    hsr_status status = call_plugin(plugin_, "render_steps", [&] {
        return table_.render_steps(instance_, &scene, &camera, &target, counters, &steps, &error);
    });
    if (status != HSR_OK) throw_status(plugin_, "render_steps", status, error);
}

bool HiddenSurfaceRemover::has_fragments() const {
    return plugin_.descriptor.abi_minor >= 4 && table_.render_fragments != nullptr;
}

void HiddenSurfaceRemover::render_fragments(const hsr_scene& scene, const hsr_camera& camera,
                                            hsr_visibility_buffer& target, const hsr_counter_sink* counters,
                                            const hsr_fragment_sink& fragments) {
    if (!has_fragments())
        throw Error("hidden-surface plugin '{}' returns one surface per pixel, not fragment lists",
                    plugin_.descriptor.name);
    hsr_error error{};
    hsr_status status = call_plugin(plugin_, "render_fragments", [&] {
        return table_.render_fragments(instance_, &scene, &camera, &target, counters, &fragments, &error);
    });
    if (status != HSR_OK) throw_status(plugin_, "render_fragments", status, error);
}

LightingModel::LightingModel(const Plugin& plugin, const std::vector<Setting>& settings) : plugin_(plugin) {
    if (plugin.descriptor.kind != HSR_KIND_LIGHTING_MODEL)
        throw Error("'{}' is a {} plugin, not a lighting model", plugin.descriptor.name,
                    kind_name(plugin.descriptor.kind));
    const auto& table = *static_cast<const ILightingModel*>(plugin.descriptor.interface_table);
    table_ = copy_prefix(table, table.struct_size);
    require_functions(plugin_, table_);
    if (table_.prepare == nullptr || table_.shade == nullptr)
        throw Error("{} has a NULL prepare or shade function", plugin_label(plugin_));
    ParamValues values = resolve_params(plugin.descriptor, settings);
    hsr_error error{};
    hsr_status status = call_plugin(plugin_, "create", [&] {
        return table_.create(values.data(), values.size(), &instance_, &error);
    });
    if (status != HSR_OK) throw_status(plugin_, "create", status, error);
}

LightingModel::~LightingModel() {
    if (instance_ == nullptr) return;
    try {
        const PluginCallScope scope(plugin_.descriptor.name, "destroy");
        table_.destroy(instance_);
    } catch (...) {
        std::cerr << "hsr: warning: " << plugin_label(plugin_) << " let an exception escape from destroy\n";
    }
}

void LightingModel::prepare(const hsr_scene& scene, const hsr_shading_context& context) {
    hsr_error error{};
    hsr_status status =
        call_plugin(plugin_, "prepare", [&] { return table_.prepare(instance_, &scene, &context, &error); });
    if (status != HSR_OK) throw_status(plugin_, "prepare", status, error);
}

void LightingModel::shade(hsr_fragment_batch& batch) const {
    hsr_error error{};
    hsr_status status = call_plugin(plugin_, "shade", [&] { return table_.shade(instance_, &batch, &error); });
    if (status != HSR_OK) throw_status(plugin_, "shade", status, error);
}

HiddenLineRemover::HiddenLineRemover(const Plugin& plugin, const std::vector<Setting>& settings) : plugin_(plugin) {
    if (plugin.descriptor.kind != HSR_KIND_HIDDEN_LINE_REMOVER)
        throw Error("'{}' is a {} plugin, not a hidden-line remover", plugin.descriptor.name,
                    kind_name(plugin.descriptor.kind));
    const auto& table = *static_cast<const IHiddenLineRemover*>(plugin.descriptor.interface_table);
    table_ = copy_prefix(table, table.struct_size);
    require_functions(plugin_, table_);
    if (table_.render_lines == nullptr) throw Error("{} has a NULL render_lines function", plugin_label(plugin_));
    ParamValues values = resolve_params(plugin.descriptor, settings);
    hsr_error error{};
    hsr_status status = call_plugin(plugin_, "create", [&] {
        return table_.create(values.data(), values.size(), &instance_, &error);
    });
    if (status != HSR_OK) throw_status(plugin_, "create", status, error);
}

HiddenLineRemover::~HiddenLineRemover() {
    if (instance_ == nullptr) return;
    try {
        const PluginCallScope scope(plugin_.descriptor.name, "destroy");
        table_.destroy(instance_);
    } catch (...) {
        std::cerr << "hsr: warning: " << plugin_label(plugin_) << " let an exception escape from destroy\n";
    }
}

void HiddenLineRemover::render_lines(const hsr_scene& scene, const hsr_camera& camera, const hsr_line_request& request,
                                     const hsr_segment_sink& segments, const hsr_trace_sink* trace,
                                     const hsr_counter_sink* counters) {
    hsr_error error{};
    hsr_status status = call_plugin(plugin_, "render_lines", [&] {
        return table_.render_lines(instance_, &scene, &camera, &request, &segments, trace, counters, &error);
    });
    if (status != HSR_OK) throw_status(plugin_, "render_lines", status, error);
}

}  // namespace hsr
