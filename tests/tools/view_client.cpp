// A client for the real `hsr view` binary on 127.0.0.1 (started here on a free port, stopped with
// SIGTERM, which must end it with status 0):
//   view_client load  HSR MODELS_DIR [sanitized]
//                                      8 threads x 200 requests, mixed valid and invalid, to a server
//                                      bounded to one rendering thread (--threads 1): every valid
//                                      one answered 200, every invalid one 4xx, the server alive after,
//                                      its resident memory back within bounds of where it was after
//                                      warm-up (the figures are printed; not checked for a sanitized
//                                      build, whose allocator keeps freed memory in quarantine)
//   view_client bench HSR MODELS_DIR   50 frames orbiting the bunny at 512x512: median time per frame,
//                                      round trip and server side (docs/viewer.md)
//   view_client memory HSR MODELS_DIR  a 4096x4096 comparison of zbuffer and painter on the bunny, with
//                                      no buffers, the page's and all of them, each from a fresh
//                                      server with one worker: the answer's size and the peak resident
//                                      memory of the server and of the worker
// Exit status 0 when every check holds.
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

struct Server {
    pid_t pid = -1;
    int port = 0;
    std::string token;  // from the printed URL, http://127.0.0.1:PORT/?token=TOKEN

    httplib::Client client() const {
        httplib::Client c("127.0.0.1", port);
        c.set_default_headers({{"X-HSR-Token", token}});
        return c;
    }
};

Server start_server(const std::string& hsr, const std::string& model, const std::vector<std::string>& options = {}) {
    int out[2];
    if (pipe(out) != 0) throw std::runtime_error("pipe");
    std::vector<std::string> args{hsr, "view", model, "--listen", "127.0.0.1:0"};
    args.insert(args.end(), options.begin(), options.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    Server s;
    s.pid = fork();
    if (s.pid < 0) throw std::runtime_error("fork");
    if (s.pid == 0) {
        // The server goes when this client goes, however it ends: a test must not leave it behind.
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        dup2(out[1], 1);
        close(out[0]);
        close(out[1]);
        execv(hsr.c_str(), argv.data());
        _exit(127);
    }
    close(out[1]);
    std::string line;
    char c;
    while (read(out[0], &c, 1) == 1 && c != '\n') line += c;
    close(out[0]);
    std::printf("%s\n", line.c_str());
    const std::size_t colon = line.rfind(':'), token = line.find("/?token=");
    if (line.find("hsr view: serving ") != 0 || colon == std::string::npos || token == std::string::npos)
        throw std::runtime_error("no port and token in: " + line);
    s.port = std::stoi(line.substr(colon + 1));
    s.token = line.substr(token + 8);
    return s;
}

int stop_server(const Server& s) {
    kill(s.pid, SIGTERM);
    int status = 0;
    waitpid(s.pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// A field of /proc/PID/status in KiB: VmRSS (resident now) or VmHWM (the peak).
long status_kib(pid_t pid, const char* field = "VmRSS:") {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind(field, 0) == 0) return std::stol(line.substr(std::strlen(field)));
    return -1;
}

long rss_kib(pid_t pid) { return status_kib(pid); }

std::vector<pid_t> children_of(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children");
    std::vector<pid_t> out;
    for (pid_t child; in >> child;) out.push_back(child);
    return out;
}

json frame(const std::string& model, const std::string& algorithm, int size, double yaw) {
    return {{"model", model}, {"algorithm", algorithm}, {"params", json::object()},
            {"camera", {{"yaw", yaw}, {"pitch", 20}, {"zoom", 1}}}, {"width", size}, {"height", size}};
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
}

// One request of the mix; returns whether it was answered as it should be (valid: 200, invalid: 4xx).
bool one_request(httplib::Client& client, std::mt19937& random, const std::vector<std::string>& algorithms,
                 std::atomic<int>& valid, std::atomic<int>& invalid) {
    const int kind = int(random() % 12);
    const double yaw = double(random() % 360);
    const std::string algorithm = algorithms[random() % algorithms.size()];
    bool should_succeed = kind < 8;
    auto post = [&](const json& request) { return client.Post("/api/frame", request.dump(), "application/json"); };
    auto send = [&]() -> httplib::Result {
        switch (kind) {
        case 0: return client.Get("/api/info");
        case 1: return client.Get("/api/models");
        case 2: return client.Get("/api/plugins");
        case 3: return client.Get(("/api/theory/" + algorithm).c_str());
        case 4: {
            json request = frame("0/cube.obj", "zbuffer", 64, yaw);
            request["step"] = 1 + random() % 12;
            return post(request);
        }
        case 5: case 6: case 7: return post(frame(kind == 5 ? "0/monkey.obj" : "0/cube.obj", algorithm, 96, yaw));
        case 8: {
            json request = frame("0/cube.obj", "zbuffer", 64, yaw);
            request["params"] = {{"depth-test", "sideways"}};
            return post(request);
        }
        case 9: return post(frame("0/../../etc/passwd", "zbuffer", 64, yaw));
        case 10: return client.Post("/api/frame", "{\"model\": [", "application/json");
        default: return post(frame("0/cube.obj", "zbuffer", 100000, yaw));
        }
    };
    httplib::Result r = send();
    (should_succeed ? valid : invalid)++;
    const bool right = r && (should_succeed ? r->status == 200 : (r->status >= 400 && r->status < 500));
    static std::atomic<int> reported{0};
    if (!right && reported++ < 5)
        std::printf("wrong answer to request kind %d (%s): %s\n", kind, algorithm.c_str(),
                    r ? (std::to_string(r->status) + " " + r->body.substr(0, 200)).c_str()
                      : ("no answer: " + httplib::to_string(r.error())).c_str());
    return right;
}

int run_load(const std::string& hsr, const std::string& models, bool check_memory) {
    if (!fs::exists(fs::path(models) / "monkey.obj")) {
        std::printf("models not fetched: run models/fetch-models.sh\n");
        return 0;
    }
    const Server server = start_server(hsr, (fs::path(models) / "cube.obj").string(), {"--threads", "1"});
    httplib::Client probe = server.client();
    probe.set_read_timeout(60, 0);
    std::vector<std::string> algorithms;
    httplib::Result plugins = probe.Get("/api/plugins");
    if (!plugins || plugins->status != 200) {
        std::printf("FAIL: /api/plugins\n");
        stop_server(server);
        return 1;
    }
    // Every hidden-surface plugin, and appel, the hidden-line plugin that takes any mesh (roberts
    // wants convex bodies, floating-horizon a grid surface: they refuse the monkey, rightly).
    const json described = json::parse(plugins->body);
    for (const json& p : described["hidden_surface"]) algorithms.push_back(p["name"]);
    for (const json& p : described["hidden_line"])
        if (p["name"] == "appel") algorithms.push_back(p["name"]);
    std::printf("algorithms: %zu\n", algorithms.size());
    if (algorithms.empty()) {
        std::printf("FAIL: no plugins\n");
        stop_server(server);
        return 1;
    }
    const long rss_start = rss_kib(server.pid);

    constexpr int threads = 8, per_thread = 200;
    std::atomic<int> failures{0}, valid{0}, invalid{0};
    auto client_thread = [&](int seed, int requests) {
        httplib::Client client = server.client();
        client.set_read_timeout(120, 0);
        std::mt19937 random(seed);
        for (int i = 0; i < requests; ++i)
            if (!one_request(client, random, algorithms, valid, invalid)) ++failures;
    };
    client_thread(1000, 60);  // warm-up: models loaded, plugins made, caches filled
    const long rss_warm = rss_kib(server.pid);
    failures = 0, valid = 0, invalid = 0;
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> clients;
    for (int t = 0; t < threads; ++t) clients.emplace_back(client_thread, t + 1, per_thread);
    for (std::thread& c : clients) c.join();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const long rss_after = rss_kib(server.pid);
    httplib::Result alive = probe.Get("/api/info");
    const bool is_alive = alive && alive->status == 200;
    const int exit_status = stop_server(server);
    std::printf("%d requests (%d valid, %d invalid) in %.1f s: %d answered wrongly\n", threads * per_thread,
                valid.load(), invalid.load(), seconds, failures.load());
    std::printf("resident memory: %ld KiB at start, %ld KiB after warm-up, %ld KiB after the load\n", rss_start,
                rss_warm, rss_after);
    std::printf("alive after: %s; exit status on SIGTERM: %d\n", is_alive ? "yes" : "no", exit_status);
    // Within 64 MiB of the warmed-up size: the caches are bounded, and nothing grows per request.
    const bool memory_ok = !check_memory || rss_after <= rss_warm + 64 * 1024;
    if (!memory_ok) std::printf("FAIL: memory grew by %ld KiB\n", rss_after - rss_warm);
    return failures == 0 && is_alive && exit_status == 0 && memory_ok ? 0 : 1;
}

int run_bench(const std::string& hsr, const std::string& models) {
    const Server server = start_server(hsr, (fs::path(models) / "bunny.obj").string());
    httplib::Client client = server.client();
    client.set_read_timeout(60, 0);
    std::vector<double> round_trip, server_side, visibility, shading, encode;
    for (int i = -5; i < 50; ++i) {
        const auto start = std::chrono::steady_clock::now();
        httplib::Result r = client.Post("/api/frame", frame("0/bunny.obj", "zbuffer", 512, 7.2 * i).dump(), "application/json");
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        if (!r || r->status != 200) {
            std::printf("FAIL: frame %d\n", i);
            stop_server(server);
            return 1;
        }
        if (i < 0) continue;  // warm-up
        const json stats = json::parse(r->body)["stats"];
        round_trip.push_back(ms);
        visibility.push_back(stats["visibility_ms"]);
        shading.push_back(stats["shading_ms"]);
        encode.push_back(stats["encode_ms"]);
        server_side.push_back(stats["visibility_ms"].get<double>() + stats["shading_ms"].get<double>() +
                              stats["encode_ms"].get<double>());
    }
    stop_server(server);
    std::printf("bunny, zbuffer + blinn-phong, 512x512, 50 frames orbiting, medians:\n");
    std::printf("  round trip (request, render, PNG, base64, JSON, response) %.1f ms = %.0f frames/s\n",
                median(round_trip), 1000.0 / median(round_trip));
    std::printf("  server side: visibility %.1f + shading %.1f + PNG and base64 %.1f = %.1f ms\n", median(visibility),
                median(shading), median(encode), median(server_side));
    return 0;
}

int run_memory(const std::string& hsr, const std::string& models) {
    const json tile = {{"names", {"depth", "face", "instance", "object", "depth_tests", "depth_complexity"}},
                       {"region", {2016, 2016, 64, 64}}};
    const std::pair<const char*, json> choices[] = {
        {"none", false},
        {"the page's: the depth view over the picture, all six over a 64x64 tile", json::array({{{"names", {"depth"}}}, tile})},
        {"all six over the whole picture (\"buffers\": true)", true}};
    std::printf("bunny, POST /api/compare of zbuffer and painter at 4096x4096, peak resident memory (VmHWM):\n");
    bool all_answered = true;
    for (const auto& choice : choices) {
        const char* label = choice.first;
        const json& buffers = choice.second;
        const Server server = start_server(hsr, (fs::path(models) / "bunny.obj").string(), {"--workers", "1"});
        httplib::Client client = server.client();
        client.set_read_timeout(300, 0);
        auto side = [&](const char* algorithm) {
            json q = frame("0/bunny.obj", algorithm, 4096, 30);
            q["buffers"] = buffers;
            return q;
        };
        const httplib::Result r =
            client.Post("/api/compare", json{{"a", side("zbuffer")}, {"b", side("painter")}}.dump(), "application/json");
        const bool answered = r && r->status == 200;
        all_answered = all_answered && answered;
        long worker = 0;
        for (pid_t child : children_of(server.pid)) worker = std::max(worker, status_kib(child, "VmHWM:"));
        const long server_peak = status_kib(server.pid, "VmHWM:");
        stop_server(server);
        if (!answered) {
            std::printf("FAIL: %s: %s\n", label, r ? std::to_string(r->status).c_str() : "no answer");
            continue;
        }
        std::printf("  buffers %s: answer %.1f MB, server %ld MB, worker %ld MB\n", label, double(r->body.size()) / 1e6,
                    server_peak / 1024, worker / 1024);
    }
    return all_answered ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    const bool sanitized = argc == 5 && std::string(argv[4]) == "sanitized";
    const std::string mode = argc > 1 ? argv[1] : "";
    if ((argc != 4 && !sanitized) || (mode != "load" && mode != "bench" && mode != "memory")) {
        std::fprintf(stderr, "usage: view_client load|bench|memory HSR MODELS_DIR [sanitized]\n");
        return 2;
    }
    signal(SIGPIPE, SIG_IGN);
    setvbuf(stdout, nullptr, _IOLBF, 0);
    try {
        if (mode == "load") return run_load(argv[2], argv[3], !sanitized);
        return mode == "bench" ? run_bench(argv[2], argv[3]) : run_memory(argv[2], argv[3]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "view_client: %s\n", e.what());
        return 1;
    }
}
