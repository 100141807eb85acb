// An hsr view server for a test, on a free port of 127.0.0.1 and running on a thread of its own
// until the object goes. Its workers are the built `hsr`; every client it hands out sends its token.
#pragma once

#include "view/server/view_server.hpp"

#include <httplib.h>

#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <utility>

namespace test_view {

class Server {
public:
    // config's worker_executable and token are set here when left empty.
    explicit Server(hsr::host::ViewConfig config) {
        if (config.worker_executable.empty()) config.worker_executable = std::filesystem::path(HSR_BINARY_DIR) / "hsr";
        if (config.token.empty()) config.token = "view-test-token-0123456789abcdef";
        token_ = config.token;
        server_ = std::make_unique<hsr::host::ViewServer>(std::move(config));
        port_ = server_->bind("127.0.0.1", 0);
        thread_ = std::thread([this] { server_->run(); });
    }
    ~Server() {
        server_->stop();
        thread_.join();
    }
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    // Ends the server's jobs in flight and its run, as SIGTERM does; the object may then go.
    void stop() { server_->stop(); }

    int port() const { return port_; }
    const std::string& token() const { return token_; }
    // A client with a long read time-out (a hang fails the test rather than stopping it), with or
    // without the token.
    httplib::Client client(bool with_token = true) const {
        httplib::Client c("127.0.0.1", port_);
        c.set_read_timeout(300, 0);
        if (with_token) c.set_default_headers({{"X-HSR-Token", token_}});
        return c;
    }

private:
    std::unique_ptr<hsr::host::ViewServer> server_;
    std::string token_;
    int port_ = 0;
    std::thread thread_;
};

}  // namespace test_view
