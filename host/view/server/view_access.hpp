// Who may drive hsr view and how much a client may hold of it (docs/viewer.md, "Access and limits"):
// the Host check against DNS rebinding, the per-run token, same-origin and Content-Type checks on
// POSTs, refusal of bodies the size cap cannot see (chunked, compressed), answers without the
// machine's paths, JSON parsed only when it nests shallowly, and connections that must send their
// request within a time limit.
#pragma once

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace hsr::host {

// What one connection may take of the server.
struct HttpLimits {
    std::chrono::milliseconds first_request{10'000};  // from accepting a connection to its request's end of headers
    std::chrono::milliseconds request_head{10'000};   // from a request's first byte to its end of headers
    std::chrono::milliseconds request_body{60'000};   // from the end of headers to the body's last byte
    std::chrono::milliseconds response{120'000};      // from the answer's first byte to its last
    std::chrono::milliseconds keep_alive{5'000};      // idle between two requests of a connection
    std::size_t head_bytes = 64 * 1024;               // request line and headers together
    std::size_t connections = 64;                     // served at once; more wait to be accepted
};

// The deepest a JSON request body may nest.
constexpr int max_json_depth = 64;

// A request body as JSON; ViewError 400 in our own words when it is not JSON, nests deeper than
// max_json_depth (checked on the text, before anything recurses into it) or holds a number out of
// range.
nlohmann::json parse_json_body(const std::string& body);

// 32 random bytes from the kernel's generator, as hex.
std::string random_token();

// 127.0.0.1, ::1, localhost and the rest of 127.0.0.0/8.
bool is_loopback_host(const std::string& host);

// The cpp-httplib server of hsr view. Every request passes the access checks before its body is
// read; a refused request ends its connection, as its body may still be unread. The pre- and
// post-routing handlers are this class's own: setting others would drop the checks.
//
// Slow clients: cpp-httplib's read timeout counts from one read to the next, so a client that sends
// a byte every few seconds holds a thread forever. Here each connection is read through a stream of
// our own (ConnectionStream in view_access.cpp) that gives each phase of a request one deadline
// (HttpLimits) and a byte cap for its headers: a client that has not sent its whole request by then
// loses its connection and its thread. With that, HttpLimits::connections threads are enough: a
// client that trickles holds one for at most first_request + request_body, and 32 of them leave the
// rest free for others.
class ViewHttpServer : public httplib::Server {
public:
    // An empty token: a random one (random_token()).
    ViewHttpServer(std::string token, HttpLimits limits);

    // Binds host:port (0: any free port) without sharing it (no SO_REUSEPORT), for the Host check
    // too; returns the port. Throws hsr::Error "HOST:PORT is in use: another hsr view? ..." when
    // another socket listens there.
    int listen_on(const std::string& host, int port);

    const std::string& token() const { return token_; }
    // The name of the cookie that holds the token; the port is in it, as cookies do not tell ports apart.
    std::string cookie_name() const;

    // Error answers name these folders' files relative to them; a folder alone by its name.
    void hide_folder_paths(std::vector<std::filesystem::path> folders);

private:
    bool process_and_close_socket(socket_t sock) override;

    // Whether the request may go on; if not, res holds the refusal (or, for GET /?token=, the redirect).
    bool admit(const httplib::Request& req, httplib::Response& res) const;
    bool host_is_ours(const std::string& host_header) const;
    bool has_token(const httplib::Request& req) const;
    bool hide_paths(std::string& body) const;  // whether it changed anything

    std::string token_;
    HttpLimits limits_;
    std::string listen_host_;
    int port_ = 0;
    std::vector<std::pair<std::string, std::string>> path_replacements_;  // JSON-escaped prefix -> what stands for it
};

}  // namespace hsr::host
