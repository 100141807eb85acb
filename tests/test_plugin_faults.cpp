// A plugin that crashes, aborts or calls exit() during a call ends the process with one line naming
// it (plugin_faults.hpp): first in forked children of this test, around fake plugin calls, then in
// the hsr executable around the misbehaving test plugins (tests/plugins/misbehaving.cpp). Also the
// errors that are the asker's (error.hpp): a limit hit, a plugin refusing its input.
#include "cli_support.hpp"
#include "hsr/atomic_file.hpp"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/plugin_faults.hpp"
#include "hsr/sanitizers.hpp"
#include "hsr/plugin_registry.hpp"

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

// How a child process ended and what it wrote to stderr.
struct Ending {
    int signal = 0;       // the signal that ended it, or 0
    int status = -1;      // its exit status when it exited
    std::string err;
};

void no_core_dumps() {
    const rlimit none{0, 0};
    ::setrlimit(RLIMIT_CORE, &none);
}

std::string read_all(int fd) {
    std::string text;
    char buffer[4096];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return text;
        text.append(buffer, static_cast<size_t>(n));
    }
}

Ending wait_for(pid_t pid, int err_fd) {
    Ending ending;
    ending.err = read_all(err_fd);
    ::close(err_fd);
    int raw = 0;
    while (::waitpid(pid, &raw, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(raw)) ending.signal = WTERMSIG(raw);
    if (WIFEXITED(raw)) ending.status = WEXITSTATUS(raw);
    return ending;
}

// Runs body in a forked child whose stderr is captured; the child exits 0 if body returns.
Ending in_child(const std::function<void()>& body) {
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::close(fds[0]);
        ::dup2(fds[1], STDERR_FILENO);
        ::close(fds[1]);
        no_core_dumps();
        ::alarm(60);  // a child that hangs ends by SIGALRM, which no check accepts
        body();
        ::_exit(0);
    }
    ::close(fds[1]);
    return wait_for(pid, fds[0]);
}

// Runs `hsr <args>` (split at spaces), its stdout discarded; address_space > 0 bounds its memory.
Ending run_hsr(const std::string& args, rlim_t address_space = 0) {
    std::vector<std::string> words{std::string(HSR_BINARY_DIR) + "/hsr"};
    std::istringstream in(args);
    for (std::string word; in >> word;) words.push_back(word);
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::close(fds[0]);
        ::dup2(fds[1], STDERR_FILENO);
        ::close(fds[1]);
        if (const int null = ::open("/dev/null", O_RDWR); null >= 0) {
            ::dup2(null, STDIN_FILENO);
            ::dup2(null, STDOUT_FILENO);
        }
        no_core_dumps();
        if (address_space > 0) {
            const rlimit bound{address_space, address_space};
            ::setrlimit(RLIMIT_AS, &bound);
        }
        ::alarm(120);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    ::close(fds[1]);
    return wait_for(pid, fds[0]);
}

// As hsr's main() does, in a child that inherited this test's own handlers (Catch's): the default
// actions first, so that "left as it was" means what it means in hsr.
void report_plugin_faults_as_hsr() {
    for (const int signal : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) ::signal(signal, SIG_DFL);
    hsr::report_plugin_faults();
}

__attribute__((no_sanitize("address", "undefined"), noinline)) void write_through_null() {
    volatile int* volatile nowhere = nullptr;
    *nowhere = 1;
}

// Deep enough to overflow any thread's stack (the limit is never reached); the volatile array keeps
// every frame.
__attribute__((no_sanitize("address"), noinline)) int recurse(int depth, int limit) {
    volatile char frame[256];
    frame[depth % 256] = static_cast<char>(depth);
    if (depth == limit) return 0;
    return recurse(depth + 1, limit) + frame[(depth + 1) % 256];
}

void recurse_forever() { recurse(0, std::numeric_limits<int>::max()); }

void require_fault_line(const Ending& e, const std::string& message) {
    INFO("stderr: " << e.err);
    CHECK(e.err == "hsr: error: " + message + "\n");
    CHECK(hsr::plugin_fault_in(e.err) == message);
}

}  // namespace

TEST_CASE("plugin faults: a crash inside a plugin call names the plugin and ends by the signal", "[plugin-faults]") {
    const Ending e = in_child([] {
        report_plugin_faults_as_hsr();
        const hsr::PluginCallScope call("fake", "render");
        write_through_null();
    });
    require_fault_line(e, "plugin 'fake' crashed in render (SIGSEGV)");
    CHECK(e.signal == SIGSEGV);
}

TEST_CASE("plugin faults: abort, SIGBUS, SIGILL and SIGFPE inside a plugin call", "[plugin-faults]") {
    const Ending aborted = in_child([] {
        report_plugin_faults_as_hsr();
        const hsr::PluginCallScope call("fake", "create");
        std::abort();
    });
    require_fault_line(aborted, "plugin 'fake' aborted in create (SIGABRT)");
    CHECK(aborted.signal == SIGABRT);

    for (const int signal : {SIGBUS, SIGILL, SIGFPE}) {
        const Ending e = in_child([signal] {
            report_plugin_faults_as_hsr();
            const hsr::PluginCallScope call("fake", "shade");
            ::raise(signal);
        });
        require_fault_line(e, std::string("plugin 'fake' crashed in shade (SIG") + ::sigabbrev_np(signal) + ")");
        CHECK(e.signal == signal);
    }
}

TEST_CASE("plugin faults: exit() inside a plugin call ends with status 3 and names the plugin", "[plugin-faults]") {
    const Ending e = in_child([] {
        report_plugin_faults_as_hsr();
        const hsr::PluginCallScope call("fake", "create");
        std::exit(0);
    });
    require_fault_line(e, "plugin 'fake' called exit(0) in create");
    CHECK(e.status == hsr::kPluginEndedProcess);
    CHECK(hsr::kPluginEndedProcess == 3);
}

TEST_CASE("plugin faults: outside plugin calls, faults and exit() are left as they were", "[plugin-faults]") {
    const Ending crash = in_child([] {
        report_plugin_faults_as_hsr();
        { const hsr::PluginCallScope call("fake", "render"); }
        write_through_null();
    });
    CHECK(crash.signal == SIGSEGV);
    CHECK(crash.err.empty());

    const Ending aborted = in_child([] {
        report_plugin_faults_as_hsr();
        std::abort();
    });
    CHECK(aborted.signal == SIGABRT);
    CHECK(aborted.err.empty());

    const Ending exited = in_child([] {
        report_plugin_faults_as_hsr();
        { const hsr::PluginCallScope call("fake", "render"); }
        std::exit(7);
    });
    CHECK(exited.status == 7);
    CHECK(exited.err.empty());

    const Ending stopped = in_child([] {
        report_plugin_faults_as_hsr();
        hsr::stop_reporting_plugin_faults();
        const hsr::PluginCallScope call("fake", "render");
        std::exit(5);
    });
    CHECK(stopped.status == 5);
    CHECK(stopped.err.empty());
}

TEST_CASE("plugin faults: nested calls name the innermost, and the outer one again once it returns",
          "[plugin-faults]") {
    const Ending inner = in_child([] {
        report_plugin_faults_as_hsr();
        const hsr::PluginCallScope outer("outer", "render_fragments");
        const hsr::PluginCallScope call("inner", "shade");
        write_through_null();
    });
    require_fault_line(inner, "plugin 'inner' crashed in shade (SIGSEGV)");

    const Ending outer = in_child([] {
        report_plugin_faults_as_hsr();
        const hsr::PluginCallScope outer("outer", "render_fragments");
        { const hsr::PluginCallScope call("inner", "shade"); }
        write_through_null();
    });
    require_fault_line(outer, "plugin 'outer' crashed in render_fragments (SIGSEGV)");
}

TEST_CASE("plugin faults: a stack overflow inside a plugin call is reported", "[plugin-faults]") {
    const Ending e = in_child([] {
        report_plugin_faults_as_hsr();
        const hsr::PluginCallScope call("deep", "render");
        recurse_forever();
    });
    require_fault_line(e, "plugin 'deep' crashed in render (SIGSEGV)");
    CHECK(e.signal == SIGSEGV);

    const Ending on_thread = in_child([] {
        report_plugin_faults_as_hsr();
        std::thread([] {
            const hsr::PluginCallScope call("deep", "shade");
            recurse_forever();
        }).join();
    });
    require_fault_line(on_thread, "plugin 'deep' crashed in shade (SIGSEGV)");
    CHECK(on_thread.signal == SIGSEGV);
}

TEST_CASE("plugin faults: a crash on a thread the plugin started is ascribed to the call in progress",
          "[plugin-faults]") {
    const Ending e = in_child([] {
        report_plugin_faults_as_hsr();
        const hsr::PluginCallScope call("threaded", "render");
        std::thread(write_through_null).join();
    });
    require_fault_line(e, "plugin 'threaded' crashed in render (SIGSEGV)");
    CHECK(e.signal == SIGSEGV);
}

TEST_CASE("plugin faults: the output files being written are removed", "[plugin-faults][atomic-outputs]") {
    const fs::path dir = cli::scratch_dir() / "fault-outputs";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto files_after = [&](const std::function<void()>& end) {
        in_child([&] {
            report_plugin_faults_as_hsr();
            hsr::AtomicFile picture(dir / "picture.png");
            picture.stream() << "half a picture";
            const hsr::PluginCallScope call("fake", "render");
            end();
        });
        std::vector<std::string> names;
        for (const fs::directory_entry& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
        return names;
    };
    CHECK(files_after(write_through_null).empty());
    CHECK(files_after([] { std::exit(0); }).empty());
    // With the reporting off the same crash leaves the temporary, as SIGKILL would: the checks above
    // would see one.
    const std::vector<std::string> left = files_after([] {
        hsr::stop_reporting_plugin_faults();
        write_through_null();
    });
    REQUIRE(left.size() == 1);
    CHECK(left[0].starts_with(".picture.png.tmp-"));
}

TEST_CASE("plugin faults: control characters in a plugin's name are not written", "[plugin-faults]") {
    const Ending e = in_child([] {
        report_plugin_faults_as_hsr();
        const hsr::PluginCallScope call("two\nlines", "render");
        std::abort();
    });
    require_fault_line(e, "plugin 'two?lines' aborted in render (SIGABRT)");
}

TEST_CASE("plugin faults: signal names", "[plugin-faults]") {
    for (int signal = 1; signal < 32; ++signal) {
        INFO("signal " << signal);
        const char* abbreviation = ::sigabbrev_np(signal);
        const std::string name = hsr::signal_name(signal);
        if (signal == SIGSTKFLT || signal == SIGPWR)
            CHECK(name == "signal " + std::to_string(signal));
        else
            CHECK(name == std::string("SIG") + abbreviation);
    }
    CHECK(std::string(hsr::signal_name(40)) == "signal 40");
    CHECK(std::string(hsr::signal_name(64)) == "signal 64");
    CHECK(std::string(hsr::signal_name(0)) == "signal ?");
    CHECK(std::string(hsr::signal_name(65)) == "signal ?");
    CHECK(std::string(hsr::signal_name(-1)) == "signal ?");
}

TEST_CASE("plugin faults: the fault line found in a child's stderr", "[plugin-faults]") {
    CHECK(hsr::plugin_fault_in("") == std::nullopt);
    CHECK(hsr::plugin_fault_in("wrote x.png (64x64)\n") == std::nullopt);
    CHECK(hsr::plugin_fault_in("hsr: error: plugin 'x' is unknown\n") == std::nullopt);
    CHECK(hsr::plugin_fault_in("hsr: error: no hidden-surface plugin named 'x'\n") == std::nullopt);
    CHECK(hsr::plugin_fault_in("loaded a\nhsr: error: plugin 'a b' crashed in render (SIGSEGV)\n") ==
          "plugin 'a b' crashed in render (SIGSEGV)");
    CHECK(hsr::plugin_fault_in("hsr: error: plugin 'x' called exit(0) in create") == "plugin 'x' called exit(0) in create");
    CHECK(hsr::plugin_fault_in("hsr: error: plugin 'x' aborted in shade (SIGABRT)\nhsr: error: plugin 'y' crashed in "
                               "render (SIGBUS)\nsomething after\n") == "plugin 'y' crashed in render (SIGBUS)");
    CHECK(hsr::plugin_fault_in("  hsr: error: plugin 'x' crashed in render (SIGSEGV)\n") == std::nullopt);
}

// --------------------------------------------------------------------------------------------------
// The hsr executable and the misbehaving test plugins.

namespace {

std::string cube() { return std::string(HSR_MODELS_DIR) + "/cube.obj"; }

// The temporaries of output files left in dir (".NAME.tmp-PID-RANDOM"); removes them.
std::vector<std::string> take_temporaries(const fs::path& dir) {
    std::vector<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos) names.push_back(e.path().filename());
    for (const std::string& name : names) fs::remove(dir / name);
    return names;
}
std::string misbehaving_dir() { return HSR_MISBEHAVING_PLUGIN_DIR; }

// `hsr render` of the cube with the misbehaving plugin doing `fault` in `when`, into png.
Ending render_misbehaving(const std::string& fault, const std::string& when, const fs::path& png) {
    fs::remove(png);
    take_temporaries(png.parent_path());
    return run_hsr("render " + cube() + " --width 32 --height 32 -o " + png.string() + " --plugin-path " +
                   misbehaving_dir() + " -a misbehaving:fault=" + fault + ",when=" + when);
}

}  // namespace

TEST_CASE("plugin faults: hsr render names a misbehaving plugin and ends as it did", "[plugin-faults][cli]") {
    // A folder of its own: ctest runs the other cases at the same time, and their outputs' temporaries
    // must not be counted (or removed) here.
    const fs::path dir = cli::scratch_dir() / "misbehaving";
    fs::create_directories(dir);
    const fs::path png = dir / "misbehaving.png";

    const Ending fine = render_misbehaving("none", "render", png);
    INFO("stderr: " << fine.err);
    CHECK(fine.status == 0);
    CHECK(fs::exists(png));

    for (const std::string when : {"create", "render"}) {
        const Ending crash = render_misbehaving("segfault", when, png);
        require_fault_line(crash, "plugin 'misbehaving' crashed in " + when + " (SIGSEGV)");
        CHECK(crash.signal == SIGSEGV);
        CHECK_FALSE(fs::exists(png));
        CHECK(take_temporaries(png.parent_path()).empty());

        const Ending aborted = render_misbehaving("abort", when, png);
        require_fault_line(aborted, "plugin 'misbehaving' aborted in " + when + " (SIGABRT)");
        CHECK(aborted.signal == SIGABRT);
        CHECK_FALSE(fs::exists(png));

        const Ending exited = render_misbehaving("exit", when, png);
        require_fault_line(exited, "plugin 'misbehaving' called exit(0) in " + when);
        CHECK(exited.status == 3);
        CHECK_FALSE(fs::exists(png));
        CHECK(take_temporaries(png.parent_path()).empty());

        const Ending thrown = render_misbehaving("throw", when, png);
        INFO("stderr: " << thrown.err);
        CHECK(thrown.status == 1);
        CHECK(thrown.err == "hsr: error: hidden-surface plugin 'misbehaving' let an exception escape from " + when +
                                " across the C ABI\n");
        CHECK(hsr::plugin_fault_in(thrown.err) == std::nullopt);
        CHECK_FALSE(fs::exists(png));
    }
}

TEST_CASE("plugin faults: a plugin that writes where malloc failed to give it 10 GiB is named", "[plugin-faults][cli]") {
    if (hsr::kAddressSanitizer) {
        WARN("left out: AddressSanitizer reserves more address space than the bound this test sets");
        return;
    }
    // Under a 2 GiB bound on the address space malloc returns NULL, and the plugin writes there.
    const fs::path png = cli::scratch_dir() / "allocates.png";
    fs::remove(png);
    const Ending e = run_hsr("render " + cube() + " --width 32 --height 32 -o " + png.string() + " --plugin-path " +
                                 misbehaving_dir() + " -a misbehaving:fault=allocate",
                             rlim_t(2) << 30);
    require_fault_line(e, "plugin 'misbehaving' crashed in render (SIGSEGV)");
    CHECK(e.signal == SIGSEGV);
    CHECK_FALSE(fs::exists(png));
}

TEST_CASE("plugin faults: a --jobs file names the plugin of the line that crashed", "[plugin-faults][cli]") {
    const fs::path dir = cli::scratch_dir() / "fault-jobs";
    fs::create_directories(dir);
    const auto job = [&](const std::string& png, const std::string& algorithm) {
        return cube() + " --width 32 --height 32 -o " + (dir / png).string() + " --plugin-path " + misbehaving_dir() +
               " -a " + algorithm + "\n";
    };
    const auto run_jobs = [&](const std::string& name, const std::string& lines) {
        const fs::path file = dir / name;
        std::ofstream(file) << lines;
        for (const char* png : {"first.png", "second.png"}) fs::remove(dir / png);
        take_temporaries(dir);
        return run_hsr("render --jobs " + file.string());
    };
    const auto error_lines = [](const std::string& err) {
        size_t count = 0;
        for (size_t at = 0; (at = err.find("hsr: error: ", at)) != std::string::npos; ++at) ++count;
        return count;
    };

    // The first line's frame is written before the second line's plugin crashes in render.
    const Ending crash = run_jobs("crash.jobs", job("first.png", "zbuffer") + job("second.png", "misbehaving:fault=segfault"));
    INFO("stderr: " << crash.err);
    CHECK(crash.signal == SIGSEGV);
    CHECK(error_lines(crash.err) == 1);
    CHECK(crash.err.ends_with("\nhsr: error: plugin 'misbehaving' crashed in render (SIGSEGV)\n"));
    CHECK(hsr::plugin_fault_in(crash.err) == "plugin 'misbehaving' crashed in render (SIGSEGV)");
    CHECK_FALSE(fs::exists(dir / "second.png"));
    CHECK(take_temporaries(dir).empty());  // the files still being written when it crashed

    // Every line's plugin is made while the file is checked, before anything renders.
    const Ending in_create = run_jobs("create.jobs", job("first.png", "zbuffer") +
                                                         job("second.png", "misbehaving:fault=abort,when=create"));
    require_fault_line(in_create, "plugin 'misbehaving' aborted in create (SIGABRT)");
    CHECK(in_create.signal == SIGABRT);
    CHECK_FALSE(fs::exists(dir / "first.png"));

    const Ending exited = run_jobs("exit.jobs", job("first.png", "misbehaving:fault=exit"));
    CHECK(exited.status == 3);
    CHECK(error_lines(exited.err) == 1);
    CHECK(hsr::plugin_fault_in(exited.err) == "plugin 'misbehaving' called exit(0) in render");
    CHECK(take_temporaries(dir).empty());

    // An exception is an error like another: that line fails, the others run.
    const Ending thrown = run_jobs("throw.jobs", job("first.png", "misbehaving:fault=throw") + job("second.png", "zbuffer"));
    INFO("stderr: " << thrown.err);
    CHECK(thrown.status == 1);
    CHECK_THAT(thrown.err, Catch::Contains("throw.jobs:1: hidden-surface plugin 'misbehaving' let an exception escape "
                                           "from render across the C ABI\n"));
    CHECK_THAT(thrown.err, Catch::EndsWith("hsr: error: 1 of 2 jobs failed (the errors above)\n"));
    CHECK(hsr::plugin_fault_in(thrown.err) == std::nullopt);
    CHECK(fs::exists(dir / "second.png"));
}

TEST_CASE("plugin faults: a plugin that crashes in create harms no command that does not make it",
          "[plugin-faults][cli]") {
    const Ending listing = run_hsr("plugins --plugin-path " + misbehaving_dir());
    INFO("stderr: " << listing.err);
    CHECK(listing.status == 0);

    const fs::path png = cli::scratch_dir() / "beside-crashes-in-create.png";
    fs::remove(png);
    const Ending render = run_hsr("render " + cube() + " --width 32 --height 32 -o " + png.string() + " --plugin-path " +
                                  misbehaving_dir());
    INFO("stderr: " << render.err);
    CHECK(render.status == 0);
    CHECK(fs::exists(png));

    const Ending asked = run_hsr("render " + cube() + " --width 32 --height 32 -o " + png.string() + " --plugin-path " +
                                 misbehaving_dir() + " -a crashes-in-create");
    require_fault_line(asked, "plugin 'crashes-in-create' crashed in create (SIGSEGV)");
    CHECK(asked.signal == SIGSEGV);
}

// --------------------------------------------------------------------------------------------------
// Errors that are the asker's.

TEST_CASE("plugin faults: a limit hit and a plugin refusing its input are the asker's errors", "[plugin-faults]") {
    try {
        hsr::check_limit(&hsr::Limits::lights, hsr::limits().lights + 1, "lights");
        FAIL("no error");
    } catch (const hsr::Error& e) {
        CHECK(dynamic_cast<const hsr::LimitError*>(&e) != nullptr);
        CHECK(hsr::is_client_error(e));
    }
    CHECK(hsr::is_client_error(hsr::UsageError("a mistake")));
    CHECK(hsr::is_client_error(hsr::PluginError(HSR_ERROR_INVALID_ARGUMENT, "refused")));
    CHECK(hsr::is_client_error(hsr::PluginError(HSR_ERROR_UNSUPPORTED, "cannot")));
    CHECK_FALSE(hsr::is_client_error(hsr::PluginError(HSR_ERROR_INTERNAL, "failed")));
    CHECK_FALSE(hsr::is_client_error(hsr::PluginError(HSR_ERROR_OUT_OF_MEMORY, "out of memory")));
    CHECK_FALSE(hsr::is_client_error(hsr::Error("a file cannot be read")));

    // Adding where it happened keeps the type.
    try {
        hsr::rethrow_with_message(hsr::PluginError(HSR_ERROR_UNSUPPORTED, "cannot"), "x.scene: cannot");
    } catch (const hsr::PluginError& e) {
        CHECK(e.status == HSR_ERROR_UNSUPPORTED);
        CHECK(std::string(e.what()) == "x.scene: cannot");
    }
    try {
        hsr::rethrow_with_message(hsr::LimitError("over"), "x.scene:3: over");
    } catch (const hsr::Error& e) {
        CHECK(dynamic_cast<const hsr::LimitError*>(&e) != nullptr);
    }
}
