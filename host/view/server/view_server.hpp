// hsr view's HTTP server (cpp-httplib): the embedded page, and the JSON API of docs/viewer.md ("The
// HTTP API") over the model catalog (view_models.hpp) and the frame renderer (view_frames.hpp). A
// class of its own so that a test can start it on a free port, talk to it and stop it.
#pragma once

#include "view/server/view_access.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hsr::host {

struct ViewConfig {
    std::vector<std::filesystem::path> model_folders;  // a model id starts with the folder's index
    std::vector<std::string> plugin_dirs;              // searched besides the default ones
    std::filesystem::path initial_model;  // a file in one of the folders, or empty: GET /api/info initial_model
    std::filesystem::path upload_parent;               // where the uploads folder is made (default: temp)
    // The workers that run the plugins (view_workers.hpp).
    std::filesystem::path worker_executable;           // hsr (default: the running executable)
    std::vector<std::string> limits;                   // --limit NAME=N, for the workers
    int64_t threads = 0;                               // --threads of each worker
    std::size_t workers = 3;                           // at most this many at once
    std::chrono::milliseconds time_limit{std::chrono::seconds(60)};  // of one request's work
    uint64_t worker_memory_bytes = uint64_t(8) << 30;  // address space of a worker; 0 for no bound
    std::string token;                                 // the page's and API's secret; empty: a random one
    HttpLimits http;                                   // what one connection may take
};

class ViewServer {
public:
    // Starts a worker, which scans and describes the plugins; the limits in force (hsr/limits.hpp)
    // and those of the config bound every request.
    explicit ViewServer(ViewConfig config);
    ~ViewServer();
    ViewServer(const ViewServer&) = delete;
    ViewServer& operator=(const ViewServer&) = delete;

    // Binds host:port (port 0: any free port) and returns the port; throws hsr::Error if it cannot
    // (ViewHttpServer::listen_on).
    int bind(const std::string& host, int port);
    // Serves until stop(), from any thread; returns false if serving failed.
    bool run();
    void stop();

    // The models listed now, for the line hsr view prints.
    std::size_t model_count() const;
    // What GET /?token= and every /api/ request must carry (docs/viewer.md, "Access").
    const std::string& token() const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace hsr::host
