// hsr view: a local web server with the viewer page and its JSON API (view_server.hpp,
// docs/viewer.md): its options, the folders it serves, and a clean stop on SIGINT or SIGTERM.
#include "common/command_line.hpp"
#include "common/commands.hpp"
#include "common/options.hpp"
#include "common/plugins.hpp"
#include "common/threads.hpp"
#include "view/server/view_server.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/program_options.hpp>
#include <fmt/format.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <charconv>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <thread>

namespace po = boost::program_options;
namespace fs = std::filesystem;

extern char** environ;

namespace {

using hsr::host::UsageError;

// The model list's first folder: <prefix>/share/hsr/models beside an installed hsr, else the source
// tree's models/ that the build was made from, if either exists.
fs::path bundled_models_folder() {
    std::error_code ec;
    const fs::path installed =
        fs::path(boost::dll::program_location().parent_path().string()).parent_path() / HSR_INSTALL_MODELS_DIR;
    if (fs::is_directory(installed, ec)) return installed;
    if (fs::is_directory(HSR_SOURCE_MODELS_DIR, ec)) return HSR_SOURCE_MODELS_DIR;
    return {};
}

struct ViewOptions {
    std::string model;
    std::string listen = "127.0.0.1:8080";
    std::vector<std::string> model_dirs;
    std::vector<std::string> plugin_dirs;
    std::vector<std::string> limits;
    int64_t threads = 0;
    int64_t workers = 3;
    double time_limit_seconds = 60;
    int64_t worker_memory_mib = 8192;
    bool open = false;
};

po::options_description view_option_descriptions(ViewOptions& o) {
    po::options_description options(
        "hsr view [MODEL|SCENE] [options]: look at models in a web browser, with every plugin, its parameters and "
        "its steps (docs/viewer.md)");
    options.add_options()
        ("help,h", "show this help")
        ("listen", po::value(&o.listen)->default_value(o.listen),
         "HOST:PORT to serve on (port 0: any free port); anything but 127.0.0.1 or localhost lets other machines in "
         "(with the token of the printed URL)")
        ("models", po::value(&o.model_dirs)->composing(),
         "folder of models to offer (repeatable), besides the source tree's models/ and MODEL's folder")
        ("plugin-path", po::value(&o.plugin_dirs)->composing(), "extra folder to search for plugins (repeatable)")
        ("limit", po::value(&o.limits)->composing(), hsr::describe_limit_option().c_str())
        ("threads", po::value(&o.threads)->default_value(0),
         fmt::format("threads for loading, visibility and shading of each worker, at most {} (0 = one per core)",
                     hsr::host::kMaxThreads).c_str())
        ("workers", po::value(&o.workers)->default_value(o.workers),
         "worker processes that run the plugins, at most this many at once (1 to 64)")
        ("time-limit", po::value(&o.time_limit_seconds)->default_value(o.time_limit_seconds),
         "seconds one request may take in a worker before it is stopped and answered with an error")
        ("worker-memory", po::value(&o.worker_memory_mib)->default_value(o.worker_memory_mib),
         "MiB of address space of one worker (0: no bound); a plugin that needs more fails in its worker alone")
        ("open", po::bool_switch(&o.open), "open the page in the default browser (xdg-open)");
    return options;
}

std::pair<std::string, int> parse_listen(const std::string& text) {
    const std::size_t colon = text.rfind(':');
    int port = -1;
    if (colon != std::string::npos && colon > 0) {
        const char* begin = text.data() + colon + 1;
        const char* end = text.data() + text.size();
        const auto [stop, ec] = std::from_chars(begin, end, port);
        if (ec != std::errc() || stop != end || begin == end) port = -1;
    }
    if (port < 0 || port > 65535)
        throw UsageError("--listen '{}': expected HOST:PORT, e.g. 127.0.0.1:8080 (port 0: any free port)", hsr::printable(text));
    std::string host = text.substr(0, colon);
    if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    return {host, port};
}

void open_in_browser(const std::string& url) {
    pid_t pid = 0;
    const char* argv[] = {"xdg-open", url.c_str(), nullptr};
    // The browser must not inherit the blocked SIGINT and SIGTERM of this process (run_view).
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none;
    sigemptyset(&none);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
    const int failed = posix_spawnp(&pid, "xdg-open", nullptr, &attributes, const_cast<char* const*>(argv), environ);
    posix_spawnattr_destroy(&attributes);
    if (failed != 0) {
        std::fprintf(stderr, "hsr view: could not run xdg-open; open %s yourself\n", url.c_str());
        return;
    }
    std::thread([pid] { waitpid(pid, nullptr, 0); }).detach();
}

}  // namespace

int hsr::host::run_view(const std::vector<std::string>& args) {
    ViewOptions o;
    po::options_description options = view_option_descriptions(o);
    po::options_description hidden;
    hidden.add_options()("model", po::value(&o.model));
    po::options_description all;
    all.add(options).add(hidden);
    po::positional_options_description positional;
    positional.add("model", 1);
    po::variables_map vm;
    po::command_line_parser parser(args);
    parser.options(all).positional(positional);
    po::store(hsr::host::parse_command_line(parser, options), vm);
    po::notify(vm);
    if (vm.count("help")) {
        std::cout << options;
        return 0;
    }
    try {
        hsr::set_limits(hsr::limits_from_settings(o.limits));
    } catch (const hsr::Error& e) {
        throw UsageError("{}", e.what());
    }
    const auto [host, port] = parse_listen(o.listen);
    if (o.threads < 0 || o.threads > hsr::host::kMaxThreads)
        throw UsageError("--threads {}: expected 0 (one per core) to {}", o.threads, hsr::host::kMaxThreads);
    if (o.workers < 1 || o.workers > 64) throw UsageError("--workers {}: expected 1 to 64", o.workers);
    if (!(o.time_limit_seconds >= 0.1 && o.time_limit_seconds <= 86400))
        throw UsageError("--time-limit {}: expected 0.1 to 86400 seconds", o.time_limit_seconds);
    if (o.worker_memory_mib < 0 || o.worker_memory_mib > (int64_t(1) << 30))
        throw UsageError("--worker-memory {}: expected 0 (no bound) to {} MiB", o.worker_memory_mib, int64_t(1) << 30);

    ViewConfig config;
    std::error_code ec;
    if (const fs::path bundled = bundled_models_folder(); !bundled.empty()) config.model_folders.push_back(bundled);
    for (const std::string& dir : o.model_dirs) {
        if (!fs::is_directory(dir, ec)) throw hsr::Error("--models '{}': no such folder", hsr::printable(dir));
        config.model_folders.push_back(dir);
    }
    if (!o.model.empty()) {
        if (!fs::is_regular_file(o.model, ec))
            throw hsr::Error("'{}': no such file", hsr::printable(o.model, hsr::kMaxQuotedPathChars));
        const fs::path folder = fs::absolute(o.model).parent_path();
        bool served = false;
        for (const fs::path& f : config.model_folders)
            served = served || fs::equivalent(f, folder, ec);
        if (!served) config.model_folders.push_back(folder);
        config.initial_model = o.model;
    }
    check_plugin_dirs(o.plugin_dirs);  // here, rather than in each worker, whose message would be lost
    config.plugin_dirs = o.plugin_dirs;
    config.limits = o.limits;
    config.threads = o.threads;
    config.workers = static_cast<std::size_t>(o.workers);
    config.time_limit = std::chrono::milliseconds(static_cast<int64_t>(o.time_limit_seconds * 1000));
    config.worker_memory_bytes = static_cast<uint64_t>(o.worker_memory_mib) << 20;

    // SIGINT and SIGTERM wait for a thread of their own (sigwait), which stops the server; every
    // thread started from here on inherits the blocked mask.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    ViewServer server(std::move(config));
    const int bound = server.bind(host, port);
    const std::string address = fmt::format("{}:{}", host.find(':') != std::string::npos ? "[" + host + "]" : host, bound);
    const std::string url = fmt::format("http://{}/?token={}", address, server.token());
    if (!hsr::host::is_loopback_host(host))
        std::cerr << fmt::format("hsr view: warning: {} is reachable from other machines: whoever has the URL below can "
                                 "list and render the served models, upload files and keep this machine busy, and the "
                                 "token travels unencrypted (plain HTTP)", address)
                  << std::endl;
    std::cout << fmt::format("hsr view: serving {} models at {}", server.model_count(), url) << std::endl;
    if (o.open) open_in_browser(url);

    std::atomic<bool> done{false};
    std::thread waiter([&] {
        const timespec tick{0, 200'000'000};
        while (!done) {
            if (sigtimedwait(&stop_signals, nullptr, &tick) > 0) {
                server.stop();
                return;
            }
        }
    });
    const bool served = server.run();
    done = true;
    waiter.join();
    if (!served) throw hsr::Error("hsr view: serving on {} failed", url);
    return 0;
}
