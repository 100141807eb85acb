// hsr view's access checks and connection limits (view_access.hpp).
#include "view/server/view_access.hpp"

#include "view/server/view_models.hpp"

#include "hsr/error.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/random.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <optional>

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

using hsr::host::HttpLimits;
using hsr::host::ViewError;

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

std::string trimmed(const std::string& text) {
    const auto begin = text.find_first_not_of(" \t");
    if (begin == std::string::npos) return "";
    return text.substr(begin, text.find_last_not_of(" \t") + 1 - begin);
}

// "text/plain; charset=utf-8" -> "text/plain".
std::string media_type(const std::string& content_type) {
    return lowercase(trimmed(content_type.substr(0, content_type.find(';'))));
}

bool same_secret(const std::string& given, const std::string& token) {
    if (given.size() != token.size()) return false;
    unsigned char differs = 0;  // every byte compared, so that the time taken does not tell how much matched
    for (std::size_t i = 0; i < token.size(); ++i) differs |= static_cast<unsigned char>(given[i] ^ token[i]);
    return differs == 0;
}

bool is_ip_literal(const std::string& host) {
    std::array<unsigned char, sizeof(in6_addr)> address{};
    return inet_pton(AF_INET, host.c_str(), address.data()) == 1 || inet_pton(AF_INET6, host.c_str(), address.data()) == 1;
}

bool is_wildcard(const std::string& host) { return host.empty() || host == "0.0.0.0" || host == "::"; }

std::string url_host(const std::string& host) { return host.find(':') != std::string::npos ? "[" + host + "]" : host; }

void send_refusal(httplib::Response& res, int status, const std::string& message) {
    res.status = status;
    res.set_content(json{{"error", message}}.dump(-1, ' ', false, json::error_handler_t::replace),
                    "application/json; charset=utf-8");
}

// One connection, read and written with the deadlines of HttpLimits; the socket is non-blocking and
// every wait is a poll() until the deadline of the phase at hand, in short slices so that the server's
// stop() ends it at once.
class ConnectionStream final : public httplib::Stream {
public:
    ConnectionStream(socket_t sock, const HttpLimits& limits, const std::atomic<socket_t>& listening)
        : sock_(sock), limits_(limits), listening_(listening), accepted_(Clock::now()) {}

    // Waits for the next request's first byte: the first for HttpLimits::first_request, later ones
    // for keep_alive.
    bool wait_for_request(bool first) {
        if (buffered() > 0) return true;
        return wait(POLLIN, first ? accepted_ + limits_.first_request : Clock::now() + limits_.keep_alive);
    }
    void begin_request(bool first) {
        in_head_ = true;
        head_bytes_ = 0;
        read_deadline_ = first ? accepted_ + limits_.first_request : Clock::now() + limits_.request_head;
        write_deadline_.reset();
        close_after_answer_ = false;
    }
    void headers_complete() {
        in_head_ = false;
        read_deadline_ = Clock::now() + limits_.request_body;
    }
    void close_after_answer() { close_after_answer_ = true; }
    bool must_close() const { return close_after_answer_; }

    // Ends the connection after a refusal without resetting it: unread bytes at close() make the
    // kernel send a reset, which can drop the answer before the client reads it. What the client
    // still sends is read and dropped, for a moment and up to a size.
    void drain_and_close() {
        ::shutdown(sock_, SHUT_WR);
        const Clock::time_point until = Clock::now() + std::chrono::seconds(1);
        std::size_t left = 1 << 20;
        while (left > 0 && wait(POLLIN, until)) {
            const ssize_t n = ::recv(sock_, buffer_.data(), std::min(left, buffer_.size()), 0);
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
            if (n <= 0) break;
            left -= std::size_t(n);
        }
    }

    bool is_readable() const override { return buffered() > 0 || wait(POLLIN, read_deadline_); }
    bool is_writable() const override { return wait(POLLOUT, write_deadline_.value_or(Clock::now() + limits_.response)); }

    ssize_t read(char* ptr, size_t size) override {
        if (in_head_ && head_bytes_ >= limits_.head_bytes) return -1;
        while (buffered() == 0) {
            if (!wait(POLLIN, read_deadline_)) {
                close_after_answer_ = true;  // what is left of the request would be read as the next one
                return -1;
            }
            const ssize_t n = ::recv(sock_, buffer_.data(), buffer_.size(), 0);
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
            if (n <= 0) return n < 0 ? -1 : 0;
            begin_ = 0;
            end_ = std::size_t(n);
        }
        std::size_t n = std::min(size, buffered());
        if (in_head_) {
            n = std::min(n, limits_.head_bytes - head_bytes_);
            head_bytes_ += n;
        }
        std::memcpy(ptr, buffer_.data() + begin_, n);
        begin_ += n;
        return ssize_t(n);
    }

    // All of it or nothing: cpp-httplib does not retry the rest of a short write of a header line.
    ssize_t write(const char* ptr, size_t size) override {
        if (!write_deadline_) write_deadline_ = Clock::now() + limits_.response;
        std::size_t sent = 0;
        while (sent < size) {
            if (!wait(POLLOUT, *write_deadline_)) return -1;
            const ssize_t n = ::send(sock_, ptr + sent, size - sent, MSG_NOSIGNAL);
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
            if (n < 0) return -1;
            sent += std::size_t(n);
        }
        return ssize_t(size);
    }

    void get_remote_ip_and_port(std::string& ip, int& port) const override {
        address_of(::getpeername, ip, port);
    }
    void get_local_ip_and_port(std::string& ip, int& port) const override {
        address_of(::getsockname, ip, port);
    }
    socket_t socket() const override { return sock_; }

private:
    std::size_t buffered() const { return end_ - begin_; }

    bool wait(short events, Clock::time_point deadline) const {
        constexpr auto slice = std::chrono::milliseconds(200);
        for (;;) {
            if (listening_ == INVALID_SOCKET) return false;  // the server stops
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
            if (left.count() <= 0) return false;
            pollfd fd{sock_, events, 0};
            const int ready = ::poll(&fd, 1, int(std::min(left, std::chrono::milliseconds(slice)).count()));
            if (ready > 0) return true;  // an error or hang-up too: the read or write that follows tells
            if (ready < 0 && errno != EINTR) return false;
        }
    }

    void address_of(int (*get)(int, sockaddr*, socklen_t*), std::string& ip, int& port) const {
        sockaddr_storage address{};
        socklen_t length = sizeof(address);
        std::array<char, INET6_ADDRSTRLEN> text{};
        if (get(sock_, reinterpret_cast<sockaddr*>(&address), &length) != 0) return;
        if (address.ss_family == AF_INET) {
            const auto* v4 = reinterpret_cast<const sockaddr_in*>(&address);
            inet_ntop(AF_INET, &v4->sin_addr, text.data(), text.size());
            port = ntohs(v4->sin_port);
        } else if (address.ss_family == AF_INET6) {
            const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&address);
            inet_ntop(AF_INET6, &v6->sin6_addr, text.data(), text.size());
            port = ntohs(v6->sin6_port);
        }
        ip = text.data();
    }

    socket_t sock_;
    const HttpLimits& limits_;
    const std::atomic<socket_t>& listening_;
    Clock::time_point accepted_;
    Clock::time_point read_deadline_;
    std::optional<Clock::time_point> write_deadline_;
    bool in_head_ = true;
    std::size_t head_bytes_ = 0;
    bool close_after_answer_ = false;
    std::array<char, 16 * 1024> buffer_{};
    std::size_t begin_ = 0, end_ = 0;
};

// The connection this thread serves, for the pre-routing handler, which cpp-httplib calls on the
// same thread once a request's headers are read.
thread_local ConnectionStream* current_connection = nullptr;

// Whether some [ or { of the text opens deeper than limit, strings skipped.
bool nests_deeper_than(const std::string& text, int limit) {
    int depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > limit) return true;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return false;
}

}  // namespace

json hsr::host::parse_json_body(const std::string& body) {
    // nlohmann's parser does not recurse, but copying, comparing and dump() do: a value nested
    // 100,000 deep overflows the stack long after parsing.
    if (nests_deeper_than(body, max_json_depth))
        throw ViewError(400, "", fmt::format("the request body nests deeper than {} levels", max_json_depth));
    try {
        return json::parse(body);
    } catch (const json::parse_error& e) {
        throw ViewError(400, "", fmt::format("the request body is not JSON (at byte {})", e.byte));
    } catch (const json::out_of_range&) {
        throw ViewError(400, "", "the request body holds a number too large for a double");
    } catch (const json::exception&) {
        throw ViewError(400, "", "the request body is not JSON");
    }
}

std::string hsr::host::random_token() {
    std::array<unsigned char, 32> bytes{};
    std::size_t filled = 0;
    while (filled < bytes.size()) {
        const ssize_t n = ::getrandom(bytes.data() + filled, bytes.size() - filled, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw hsr::Error("hsr view: cannot draw a random token ({})", std::strerror(errno));
        filled += std::size_t(n);
    }
    std::string hex;
    for (unsigned char b : bytes) hex += fmt::format("{:02x}", b);
    return hex;
}

bool hsr::host::is_loopback_host(const std::string& host) {
    const std::string name = lowercase(host);
    if (name == "localhost" || name == "::1") return true;
    in_addr v4{};
    return inet_pton(AF_INET, name.c_str(), &v4) == 1 && (ntohl(v4.s_addr) >> 24) == 127;
}

hsr::host::ViewHttpServer::ViewHttpServer(std::string token, HttpLimits limits)
    : token_(token.empty() ? random_token() : std::move(token)), limits_(limits) {
    const std::size_t threads = limits_.connections;
    new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    // cpp-httplib's default sets SO_REUSEPORT, with which a second server on the same port listens
    // too and the kernel shares the connections between them. SO_REUSEADDR alone lets a restart
    // bind while old connections linger, and refuses a port another socket listens on.
    set_socket_options([](socket_t sock) {
        int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    });
    set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
        if (current_connection != nullptr) current_connection->headers_complete();
        if (admit(req, res)) return HandlerResponse::Unhandled;
        // The body, if any, is still unread: the connection cannot carry another request.
        res.set_header("Connection", "close");
        if (current_connection != nullptr) current_connection->close_after_answer();
        return HandlerResponse::Handled;
    });
    // cpp-httplib calls this with the answer's headers made: its length changes with the body.
    set_post_routing_handler([this](const httplib::Request&, httplib::Response& res) {
        if (res.status < 400 || !hide_paths(res.body)) return;
        res.headers.erase("Content-Length");
        res.set_header("Content-Length", std::to_string(res.body.size()));
    });
}

int hsr::host::ViewHttpServer::listen_on(const std::string& host, int port) {
    listen_host_ = lowercase(host);
    errno = 0;
    const int bound = port == 0 ? bind_to_any_port(host) : (bind_to_port(host, port) ? port : -1);
    const int error = errno;
    if (bound <= 0) {
        const std::string where = fmt::format("{}:{}", url_host(host), port);
        if (error == EADDRINUSE)
            throw hsr::Error("{} is in use: another hsr view? try --listen {}:0", where, url_host(host));
        throw hsr::Error("cannot listen on {} ({})", where,
                         error != 0 ? std::strerror(error) : "not an address of this machine");
    }
    port_ = bound;
    return bound;
}

std::string hsr::host::ViewHttpServer::cookie_name() const { return fmt::format("hsr_view_token_{}", port_); }

void hsr::host::ViewHttpServer::hide_folder_paths(std::vector<fs::path> folders) {
    path_replacements_.clear();
    auto escaped = [](const std::string& text) {
        const std::string quoted = json(text).dump(-1, ' ', false, json::error_handler_t::replace);
        return quoted.substr(1, quoted.size() - 2);
    };
    for (const fs::path& folder : folders) {
        std::error_code ec;
        std::vector<fs::path> spellings{folder.lexically_normal()};
        const fs::path canonical = fs::canonical(folder, ec);
        if (!ec && canonical != spellings.front()) spellings.push_back(canonical);
        for (fs::path spelling : spellings) {
            std::string text = spelling.string();
            while (text.size() > 1 && text.back() == '/') text.pop_back();
            if (text.empty() || text == "/") continue;
            path_replacements_.emplace_back(escaped(text + "/"), "");
            path_replacements_.emplace_back(escaped(text), escaped(spelling.filename().string()));
        }
    }
    // The longest first, so that a folder inside another is replaced as itself.
    std::stable_sort(path_replacements_.begin(), path_replacements_.end(),
                     [](const auto& a, const auto& b) { return a.first.size() > b.first.size(); });
}

bool hsr::host::ViewHttpServer::hide_paths(std::string& body) const {
    bool changed = false;
    for (const auto& [path, replacement] : path_replacements_) {
        for (std::size_t at = body.find(path); at != std::string::npos; at = body.find(path, at + replacement.size())) {
            body.replace(at, path.size(), replacement);
            changed = true;
        }
    }
    return changed;
}

bool hsr::host::ViewHttpServer::process_and_close_socket(socket_t sock) {
    ::fcntl(sock, F_SETFL, ::fcntl(sock, F_GETFL) | O_NONBLOCK);
    ConnectionStream connection(sock, limits_, svr_sock_);
    current_connection = &connection;
    bool served = false;
    for (std::size_t request = 0; request < keep_alive_max_count_; ++request) {
        const bool first = request == 0;
        if (!connection.wait_for_request(first)) break;
        connection.begin_request(first);
        bool closed = false;
        served = process_request(connection, request + 1 == keep_alive_max_count_, closed, nullptr);
        if (!served || closed || connection.must_close()) break;
    }
    current_connection = nullptr;
    if (connection.must_close()) connection.drain_and_close();
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return served;
}

bool hsr::host::ViewHttpServer::host_is_ours(const std::string& host_header) const {
    std::string name = lowercase(trimmed(host_header));
    int port = 80;
    const std::size_t colon = name.rfind(':');
    const std::size_t bracket = name.rfind(']');
    if (colon != std::string::npos && (bracket == std::string::npos || colon > bracket)) {
        const std::string digits = name.substr(colon + 1);
        if (digits.empty() || digits.size() > 5 || !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); })) return false;
        port = std::stoi(digits);
        name = name.substr(0, colon);
    }
    if (name.size() > 2 && name.front() == '[' && name.back() == ']') name = name.substr(1, name.size() - 2);
    if (port != port_ || name.empty()) return false;
    if (name == listen_host_ || name == "localhost" || name == "127.0.0.1" || name == "::1") return true;
    // Listening on every address, the name the user typed is not known; an address is never a
    // rebound DNS name, and this machine's own name is the user's.
    if (is_wildcard(listen_host_)) {
        std::array<char, 256> own{};
        if (is_ip_literal(name)) return true;
        if (::gethostname(own.data(), own.size() - 1) == 0 && name == lowercase(own.data())) return true;
    }
    return false;
}

bool hsr::host::ViewHttpServer::has_token(const httplib::Request& req) const {
    if (req.has_header("X-HSR-Token")) return same_secret(req.get_header_value("X-HSR-Token"), token_);
    const std::string wanted = cookie_name() + "=";
    for (std::size_t i = 0; i < req.get_header_value_count("Cookie"); ++i) {
        const std::string cookies = req.get_header_value("Cookie", i);
        std::size_t at = 0;
        while (at < cookies.size()) {
            const std::size_t end = std::min(cookies.find(';', at), cookies.size());
            const std::string cookie = trimmed(cookies.substr(at, end - at));
            if (cookie.compare(0, wanted.size(), wanted) == 0 && same_secret(cookie.substr(wanted.size()), token_))
                return true;
            at = end + 1;
        }
    }
    return false;
}

bool hsr::host::ViewHttpServer::admit(const httplib::Request& req, httplib::Response& res) const {
    const std::string host = req.get_header_value("Host");
    if (!host_is_ours(host)) {
        send_refusal(res, 403, fmt::format("the Host '{}' is not this server's: open http://{}:{}/ (or localhost)",
                                           hsr::printable(host), url_host(listen_host_), port_));
        return false;
    }
    const std::string open_url = fmt::format("open the URL hsr view printed when it started (http://{}/?token=...)", host);
    if (req.path == "/" && req.has_param("token")) {
        if (!same_secret(req.get_param_value("token"), token_)) {
            send_refusal(res, 403, "wrong token: " + open_url);
            return false;
        }
        res.set_header("Set-Cookie", fmt::format("{}={}; Path=/; HttpOnly; SameSite=Strict", cookie_name(), token_));
        res.set_header("Cache-Control", "no-store");
        res.set_redirect("/", 303);
        return false;
    }
    if (req.path.rfind("/api/", 0) == 0 && !has_token(req)) {
        send_refusal(res, 403, "no valid token: " + open_url);
        return false;
    }
    if (req.method == "GET" || req.method == "HEAD") return true;

    // Whatever changes state or makes the server work comes from the page itself.
    if (req.has_header("Origin") && lowercase(req.get_header_value("Origin")) != "http://" + lowercase(trimmed(host))) {
        send_refusal(res, 403, fmt::format("{} {}: a request from another site ('{}') is refused", req.method,
                                           hsr::printable(req.path), hsr::printable(req.get_header_value("Origin"))));
        return false;
    }
    const std::string site = req.get_header_value("Sec-Fetch-Site");
    if (!site.empty() && site != "same-origin" && site != "none") {
        send_refusal(res, 403, fmt::format("{} {}: a request from another site (Sec-Fetch-Site: {}) is refused",
                                           req.method, hsr::printable(req.path), hsr::printable(site)));
        return false;
    }
    const char* wanted_type = req.path == "/api/upload" ? "application/octet-stream" : "application/json";
    const std::string type = media_type(req.get_header_value("Content-Type"));
    if (type != wanted_type) {
        send_refusal(res, 415, fmt::format("{} {}: the body must be {}, not '{}'", req.method, hsr::printable(req.path),
                                           wanted_type, hsr::printable(type)));
        return false;
    }
    // The size limit counts what Content-Length announces; a chunked or compressed body would be
    // read, or inflated, whole before anything could count it.
    if (req.has_header("Transfer-Encoding")) {
        send_refusal(res, 411, fmt::format("{} {}: send the body with a Content-Length; chunked bodies are refused",
                                           req.method, hsr::printable(req.path)));
        return false;
    }
    const std::string encoding = lowercase(trimmed(req.get_header_value("Content-Encoding")));
    if (!encoding.empty() && encoding != "identity") {
        send_refusal(res, 415, fmt::format("{} {}: compressed bodies (Content-Encoding: {}) are refused; send it as it is",
                                           req.method, hsr::printable(req.path), hsr::printable(encoding)));
        return false;
    }
    // cpp-httplib would read a body over the limit to its end before answering 413; the error
    // handler words the answer.
    if (req.get_header_value<uint64_t>("Content-Length") > payload_max_length_) {
        res.status = 413;
        return false;
    }
    return true;
}
