// The fault line of a plugin that ends the process (plugin_faults.hpp); the output files being
// written are removed as the process ends. Everything the signal handlers and the exit hook run is
// async-signal-safe: atomics, write(2), unlink(2), sigaction(2), raise(3), _exit(2), and text built
// in a fixed buffer on the stack.
#include "hsr/plugin_faults.hpp"

#include "hsr/atomic_file.hpp"

#include <signal.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstddef>
#include <mutex>

namespace hsr {
namespace {

constexpr std::array<int, 5> kFatalSignals = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};

// The call in progress on this thread. Atomics, so that the handler (which may interrupt the
// thread between two stores) reads whole values; relaxed, with signal fences for the order.
constinit thread_local std::atomic<const char*> thread_plugin{nullptr};
constinit thread_local std::atomic<const char*> thread_call{nullptr};
constinit thread_local bool thread_has_alternate_stack = false;

// The call entered last on any thread, and how many are in progress: the guess for a fault on a
// thread the plugin started itself.
std::atomic<int> calls_in_progress{0};
std::atomic<const char*> last_plugin{nullptr};
std::atomic<const char*> last_call{nullptr};

std::atomic<bool> armed{false};
std::atomic<bool> reported{false};  // one line per process, even when two threads fault at once
struct sigaction previous_actions[kFatalSignals.size()];

static_assert(std::atomic<const char*>::is_always_lock_free && std::atomic<int>::is_always_lock_free &&
              std::atomic<bool>::is_always_lock_free);

// A signal stack of the thread's own, released when the thread ends. A thread that already has one
// (AddressSanitizer gives threads theirs) keeps it.
class AlternateStack {
public:
    AlternateStack() {
        stack_t current{};
        if (::sigaltstack(nullptr, &current) != 0 || (current.ss_flags & SS_DISABLE) == 0) return;
        const size_t size = std::max<size_t>(64 * 1024, SIGSTKSZ);
        void* memory = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (memory == MAP_FAILED) return;
        stack_t stack{};
        stack.ss_sp = memory;
        stack.ss_size = size;
        if (::sigaltstack(&stack, nullptr) != 0) {
            ::munmap(memory, size);
            return;
        }
        memory_ = memory;
        size_ = size;
    }
    ~AlternateStack() {
        if (memory_ == nullptr) return;
        stack_t off{};
        off.ss_flags = SS_DISABLE;
        ::sigaltstack(&off, nullptr);
        ::munmap(memory_, size_);
    }
    AlternateStack(const AlternateStack&) = delete;
    AlternateStack& operator=(const AlternateStack&) = delete;

private:
    void* memory_ = nullptr;
    size_t size_ = 0;
};

void give_thread_alternate_stack() {
    static thread_local AlternateStack stack;
    thread_has_alternate_stack = true;
}

// One line of text in a fixed buffer; what does not fit is cut.
class Line {
public:
    void add(const char* text, size_t max_chars = sizeof text_) {
        if (text == nullptr) text = "?";
        for (size_t i = 0; i < max_chars && text[i] != '\0' && size_ < sizeof text_ - 1; ++i) {
            const unsigned char c = static_cast<unsigned char>(text[i]);
            text_[size_++] = c < 0x20 || c == 0x7f ? '?' : static_cast<char>(c);
        }
    }
    void add_number(long long value) {
        char digits[24];
        size_t count = 0;
        unsigned long long magnitude = value < 0 ? 0ull - static_cast<unsigned long long>(value) : value;
        do {
            digits[count++] = static_cast<char>('0' + magnitude % 10);
            magnitude /= 10;
        } while (magnitude != 0);
        if (value < 0) digits[count++] = '-';
        while (count > 0 && size_ < sizeof text_ - 1) text_[size_++] = digits[--count];
    }
    void write_to_stderr() {
        text_[size_++] = '\n';  // add() leaves room for it
        size_t done = 0;
        while (done < size_) {
            const ssize_t n = ::write(STDERR_FILENO, text_ + done, size_ - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) return;
            done += static_cast<size_t>(n);
        }
    }

private:
    char text_[512];
    size_t size_ = 0;
};

constexpr size_t kMaxNameChars = 200;

struct CallInProgress {
    const char* plugin = nullptr;
    const char* call = nullptr;
};

CallInProgress call_in_progress(bool or_on_another_thread) {
    std::atomic_signal_fence(std::memory_order_seq_cst);
    CallInProgress here{thread_plugin.load(std::memory_order_relaxed), thread_call.load(std::memory_order_relaxed)};
    if (here.plugin != nullptr || !or_on_another_thread || calls_in_progress.load(std::memory_order_relaxed) <= 0)
        return here;
    return {last_plugin.load(std::memory_order_relaxed), last_call.load(std::memory_order_relaxed)};
}

// Writes the line for a fault in a plugin call, then lets the signal end the process as it would
// have: a fault the processor raised happens again when the handler returns, under the restored
// action, so that a core dump shows where it was; a signal that was sent (abort(), kill) is sent again.
void on_fatal_signal(int signal, siginfo_t* info, void*) {
    const auto* const found = std::find(kFatalSignals.begin(), kFatalSignals.end(), signal);
    struct sigaction next {};
    next.sa_handler = SIG_DFL;
    sigemptyset(&next.sa_mask);
    const CallInProgress call = call_in_progress(true);
    if (call.plugin == nullptr || !armed.load(std::memory_order_relaxed)) {
        if (found != kFatalSignals.end()) next = previous_actions[found - kFatalSignals.begin()];
    } else if (!reported.exchange(true)) {
        Line line;
        line.add("hsr: error: plugin '");
        line.add(call.plugin, kMaxNameChars);
        line.add(signal == SIGABRT ? "' aborted in " : "' crashed in ");
        line.add(call.call, kMaxNameChars);
        line.add(" (");
        line.add(signal_name(signal));
        line.add(")");
        line.write_to_stderr();
        remove_temporaries_now();
    }
    ::sigaction(signal, &next, nullptr);
    if (info == nullptr || info->si_code <= 0) ::raise(signal);  // delivered when the handler returns
}

void on_process_exit(int status, void*) {
    if (!armed.load(std::memory_order_relaxed)) return;
    const CallInProgress call = call_in_progress(false);
    if (call.plugin == nullptr || reported.exchange(true)) return;
    Line line;
    line.add("hsr: error: plugin '");
    line.add(call.plugin, kMaxNameChars);
    line.add("' called exit(");
    line.add_number(status);
    line.add(") in ");
    line.add(call.call, kMaxNameChars);
    line.write_to_stderr();
    remove_temporaries_now();
    ::_exit(kPluginEndedProcess);
}

struct SignalText {
    char text[12];
};

constexpr std::array<SignalText, 65> numbered_signal_names() {
    std::array<SignalText, 65> names{};
    for (int n = 0; n < static_cast<int>(names.size()); ++n) {
        char* out = names[n].text;
        size_t i = 0;
        for (const char* prefix = "signal "; *prefix != '\0'; ++prefix) out[i++] = *prefix;
        if (n >= 10) out[i++] = static_cast<char>('0' + n / 10);
        out[i++] = static_cast<char>('0' + n % 10);
        out[i] = '\0';
    }
    return names;
}

constexpr std::array<SignalText, 65> numbered_names = numbered_signal_names();

}  // namespace

PluginCallScope::PluginCallScope(const char* plugin, const char* call) noexcept
    : outer_plugin_(thread_plugin.load(std::memory_order_relaxed)),
      outer_call_(thread_call.load(std::memory_order_relaxed)) {
    if (!thread_has_alternate_stack && armed.load(std::memory_order_relaxed)) give_thread_alternate_stack();
    thread_call.store(call, std::memory_order_relaxed);
    thread_plugin.store(plugin, std::memory_order_relaxed);
    last_call.store(call, std::memory_order_relaxed);
    last_plugin.store(plugin, std::memory_order_relaxed);
    calls_in_progress.fetch_add(1, std::memory_order_relaxed);
    std::atomic_signal_fence(std::memory_order_seq_cst);
}

PluginCallScope::~PluginCallScope() {
    std::atomic_signal_fence(std::memory_order_seq_cst);
    calls_in_progress.fetch_sub(1, std::memory_order_relaxed);
    thread_plugin.store(outer_plugin_, std::memory_order_relaxed);
    thread_call.store(outer_call_, std::memory_order_relaxed);
}

void report_plugin_faults() {
    static std::once_flag once;
    std::call_once(once, [] {
        give_thread_alternate_stack();
        for (size_t i = 0; i < kFatalSignals.size(); ++i) {
            struct sigaction action {};
            action.sa_sigaction = &on_fatal_signal;
            action.sa_flags = SA_SIGINFO | SA_ONSTACK;
            sigemptyset(&action.sa_mask);
            ::sigaction(kFatalSignals[i], &action, &previous_actions[i]);
        }
        ::on_exit(&on_process_exit, nullptr);
        armed.store(true);
    });
}

void stop_reporting_plugin_faults() {
    if (!armed.exchange(false)) return;
    for (size_t i = 0; i < kFatalSignals.size(); ++i) ::sigaction(kFatalSignals[i], &previous_actions[i], nullptr);
}

const char* signal_name(int signal) {
    switch (signal) {
    case SIGHUP: return "SIGHUP";
    case SIGINT: return "SIGINT";
    case SIGQUIT: return "SIGQUIT";
    case SIGILL: return "SIGILL";
    case SIGTRAP: return "SIGTRAP";
    case SIGABRT: return "SIGABRT";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGKILL: return "SIGKILL";
    case SIGUSR1: return "SIGUSR1";
    case SIGSEGV: return "SIGSEGV";
    case SIGUSR2: return "SIGUSR2";
    case SIGPIPE: return "SIGPIPE";
    case SIGALRM: return "SIGALRM";
    case SIGTERM: return "SIGTERM";
    case SIGCHLD: return "SIGCHLD";
    case SIGCONT: return "SIGCONT";
    case SIGSTOP: return "SIGSTOP";
    case SIGTSTP: return "SIGTSTP";
    case SIGTTIN: return "SIGTTIN";
    case SIGTTOU: return "SIGTTOU";
    case SIGURG: return "SIGURG";
    case SIGXCPU: return "SIGXCPU";
    case SIGXFSZ: return "SIGXFSZ";
    case SIGVTALRM: return "SIGVTALRM";
    case SIGPROF: return "SIGPROF";
    case SIGWINCH: return "SIGWINCH";
    case SIGPOLL: return "SIGPOLL";
    case SIGSYS: return "SIGSYS";
    }
    if (signal < 1 || signal >= static_cast<int>(numbered_names.size())) return "signal ?";
    return numbered_names[static_cast<size_t>(signal)].text;
}

std::optional<std::string> plugin_fault_in(std::string_view child_stderr) {
    constexpr std::string_view error_prefix = "hsr: error: ";
    constexpr std::string_view fault_prefix = "hsr: error: plugin '";
    std::optional<std::string> found;
    while (!child_stderr.empty()) {
        const size_t end = child_stderr.find('\n');
        const std::string_view line = child_stderr.substr(0, end);
        child_stderr.remove_prefix(end == std::string_view::npos ? child_stderr.size() : end + 1);
        if (!line.starts_with(fault_prefix)) continue;
        const std::string_view rest = line.substr(fault_prefix.size());
        for (std::string_view what : {"' crashed in ", "' aborted in ", "' called exit("})
            if (rest.find(what) != std::string_view::npos) found = std::string(line.substr(error_prefix.size()));
    }
    return found;
}

}  // namespace hsr
