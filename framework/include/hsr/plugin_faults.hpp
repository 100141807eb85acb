// Naming the plugin that ends the process. The instance wrappers (plugin_registry.hpp) mark each call
// into a plugin with a PluginCallScope; once report_plugin_faults() has run, a fatal signal or an
// exit() that arrives while such a call is in progress writes one line to stderr naming the plugin:
//
//   hsr: error: plugin 'NAME' crashed in CALL (SIGSEGV)      SIGSEGV, SIGBUS, SIGILL, SIGFPE
//   hsr: error: plugin 'NAME' aborted in CALL (SIGABRT)      SIGABRT (abort(), std::terminate)
//   hsr: error: plugin 'NAME' called exit(N) in CALL
//
// CALL is the ABI function: create, destroy, render, render_steps, render_fragments, prepare, shade,
// render_lines, or hsr_plugin_entry while a library is loaded (NAME is then the library's path).
// Control characters in NAME are written as '?'. After the line, the temporaries of output files not
// yet complete are removed (atomic_file.hpp), and a signal ends the process as it would have without
// the handler (status 128 + N, a core dump where enabled); an exit() ends it with status
// kPluginEndedProcess. The format is stable: plugin_fault_in() reads it back from a child's stderr.
//
// A fault outside every plugin call is left as it was: no line, the previous action (usually the
// default) takes it. A fault on a thread of the plugin's own (a thread pool inside render) is
// ascribed to a plugin call in progress on another thread, if any. What cannot be caught is not
// reported: SIGKILL (the kernel's out-of-memory killer), _exit(), quick_exit().
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace hsr {

// The exit status of a process whose plugin called exit() during a call.
inline constexpr int kPluginEndedProcess = 3;

// Marks a call into a plugin on this thread for as long as it lives; scopes nest (a host callback
// that calls another plugin). Costs a few relaxed atomic operations and allocates nothing, except
// that the first scope on a thread, once reporting is on, gives the thread an alternate signal stack
// so that a stack overflow in the plugin is reported too. Both strings must outlive the scope (the
// descriptor's name, a string literal).
class PluginCallScope {
public:
    PluginCallScope(const char* plugin, const char* call) noexcept;
    ~PluginCallScope();
    PluginCallScope(const PluginCallScope&) = delete;
    PluginCallScope& operator=(const PluginCallScope&) = delete;

private:
    const char* outer_plugin_;
    const char* outer_call_;
};

// Installs, once per process, the handlers for SIGSEGV, SIGBUS, SIGILL, SIGFPE and SIGABRT (on an
// alternate signal stack) and the exit hook that write the line above. Call it early in main().
void report_plugin_faults();

// Undoes report_plugin_faults() in a child that reports its own way (the plugin probe): the previous
// signal actions come back and the exit hook does nothing.
void stop_reporting_plugin_faults();

// "SIGSEGV", "SIGABRT", ...; "signal N" for one without a usual name, "signal ?" outside 1..64.
// Async-signal-safe: the strings are static.
const char* signal_name(int signal);

// The message (the part after "hsr: error: ") of the last fault line in text captured from a child's
// stderr, e.g. "plugin 'zbuffer' crashed in render (SIGSEGV)"; nullopt when there is none.
std::optional<std::string> plugin_fault_in(std::string_view child_stderr);

}  // namespace hsr
