// Who may drive hsr view and what a client can hold of it (host/view/server/view_access.hpp): the
// Host check, the token, cross-origin and form posts, bodies nested too deep or sent chunked or
// compressed, a taken port, clients that trickle their requests, and the upload folders of killed
// servers. Requests go out as a browser or an attacker would send them: through cpp-httplib's
// client, or as raw bytes on a socket.
#include "cli_support.hpp"
#include "test_models.hpp"

#include "view/server/view_server.hpp"
#include "view_test_server.hpp"

#include "hsr/error.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <optional>
#include <regex>
#include <thread>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::string test_token = "access-test-token-0123456789abcdef";

fs::path access_model_folder() {
    static std::atomic<int> count{0};
    const fs::path root = cli::scratch_dir() / fmt::format("access-{}-{}", ::getpid(), count++);
    fs::remove_all(root);
    fs::create_directories(root / "models");
    fs::copy_file(test_models::path("cube.obj"), root / "models" / "cube.obj");
    std::ofstream(root / "models" / "broken.obj") << "v 1 2\nf 1 2 3\n";
    return root;
}

struct RunningServer {
    fs::path root = access_model_folder();
    std::optional<test_view::Server> server;
    int port = 0;

    explicit RunningServer(hsr::host::HttpLimits limits = {}) {
        hsr::host::ViewConfig config;
        config.model_folders = {root / "models"};
        config.plugin_dirs = {HSR_PLUGIN_DIR};
        config.upload_parent = root;
        config.token = test_token;
        config.http = limits;
        port = server.emplace(std::move(config)).port();
        REQUIRE(client().Get("/api/info")->status == 200);
    }
    ~RunningServer() {
        server.reset();
        std::error_code ec;
        fs::remove_all(root, ec);
    }

    std::string host() const { return fmt::format("127.0.0.1:{}", port); }
    httplib::Client client(bool with_token = true) const {
        httplib::Client c = server->client(with_token);
        c.set_read_timeout(120, 0);
        return c;
    }
};

// A socket to the server, for requests no polite client sends. Reads give up after two minutes: a
// hang is then a failure rather than a stuck test.
struct RawConnection {
    int fd = -1;

    explicit RawConnection(int port) {
        fd = ::socket(AF_INET, SOCK_STREAM, 0);
        REQUIRE(fd >= 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_port = htons(uint16_t(port));
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0);
        timeval patience{120, 0};
        ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &patience, sizeof(patience));
    }
    ~RawConnection() { ::close(fd); }
    RawConnection(const RawConnection&) = delete;

    // False once the server has closed its side.
    bool send(const std::string& bytes) const {
        std::size_t sent = 0;
        while (sent < bytes.size()) {
            const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
            if (n <= 0) return false;
            sent += std::size_t(n);
        }
        return true;
    }
    // Everything until the server closes (or resets) the connection.
    std::string read_to_end() const {
        std::string text;
        char buffer[4096];
        for (;;) {
            const ssize_t n = ::recv(fd, buffer, sizeof(buffer), 0);
            if (n <= 0) break;
            text.append(buffer, std::size_t(n));
        }
        return text;
    }
    // Neither an answer nor a close has arrived.
    bool open_and_unanswered() const {
        pollfd p{fd, POLLIN, 0};
        return ::poll(&p, 1, 0) == 0;
    }
};

int status_of(const std::string& response) {
    return response.size() > 12 && response.rfind("HTTP/1.", 0) == 0 ? std::stoi(response.substr(9, 3)) : -1;
}

std::string body_of(const std::string& response) {
    const std::size_t end = response.find("\r\n\r\n");
    return end == std::string::npos ? "" : response.substr(end + 4);
}

std::string post_head(const RunningServer& s, const std::string& path, const std::string& type,
                      const std::string& more_headers = "") {
    return fmt::format("POST {} HTTP/1.1\r\nHost: {}\r\nX-HSR-Token: {}\r\nContent-Type: {}\r\n{}\r\n", path, s.host(),
                       test_token, type, more_headers);
}

json small_frame() {
    return {{"model", "0/cube.obj"}, {"algorithm", "zbuffer"}, {"width", 16}, {"height", 16}};
}

// `hsr view ARGS` as a process of its own, with its first line of output; killed with the test.
struct SpawnedView {
    pid_t pid = -1;
    std::string line, error_line;

    SpawnedView(const std::string& args, const fs::path& temp_dir) {
        int out[2], err[2];
        REQUIRE(::pipe(out) == 0);
        REQUIRE(::pipe(err) == 0);
        pid = ::fork();
        REQUIRE(pid >= 0);
        if (pid == 0) {
            ::prctl(PR_SET_PDEATHSIG, SIGKILL);
            ::dup2(out[1], 1);
            ::dup2(err[1], 2);
            ::setenv("TMPDIR", temp_dir.c_str(), 1);
            const std::string command = std::string(HSR_BINARY_DIR) + "/hsr view " + args;
            ::execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), nullptr);
            ::_exit(127);
        }
        ::close(out[1]);
        ::close(err[1]);
        line = read_line(out[0]);
        ::close(out[0]);
        error_fd = err[0];
    }
    std::string read_error_line() { return read_line(error_fd); }
    void kill(int signal) {
        ::kill(pid, signal);
        ::waitpid(pid, nullptr, 0);
        pid = -1;
    }
    ~SpawnedView() {
        if (pid > 0) kill(SIGKILL);
        ::close(error_fd);
    }

private:
    static std::string read_line(int fd) {
        std::string text;
        char c;
        while (::read(fd, &c, 1) == 1 && c != '\n') text += c;
        return text;
    }
    int error_fd = -1;
};

}  // namespace

TEST_CASE("view access: a Host that is not the server's is refused (DNS rebinding)", "[view]") {
    RunningServer s;
    for (const std::string& host : {std::string("attacker.example"), fmt::format("attacker.example:{}", s.port),
                                    fmt::format("127.0.0.1:{}", s.port + 1), std::string("127.0.0.1"),
                                    fmt::format("localhost.attacker.example:{}", s.port)}) {
        for (const char* path : {"/api/models", "/api/info", "/"}) {
            httplib::Result r = s.client().Get(path, {{"Host", host}});
            REQUIRE(r);
            INFO(host << " " << path << " -> " << r->body);
            CHECK(r->status == 403);
            CHECK_THAT(json::parse(r->body)["error"].get<std::string>(), Catch::Contains("is not this server's"));
        }
    }
    for (const std::string& host : {fmt::format("localhost:{}", s.port), fmt::format("[::1]:{}", s.port),
                                    fmt::format("127.0.0.1:{}", s.port), fmt::format("LocalHost:{}", s.port)}) {
        httplib::Result r = s.client().Get("/api/info", {{"Host", host}});
        REQUIRE(r);
        INFO(host);
        CHECK(r->status == 200);
    }
    // No absolute path of this machine in the listing.
    const json models = json::parse(s.client().Get("/api/models")->body);
    CHECK(models["folders"] == json::array({"models"}));
    CHECK(models.dump().find(s.root.string()) == std::string::npos);
}

TEST_CASE("view access: the API needs the token, from the printed URL's cookie or a header", "[view]") {
    RunningServer s;
    const std::string open_the_url = "open the URL hsr view printed";
    for (const char* path : {"/api/info", "/api/models", "/api/plugins", "/api/theory/zbuffer"}) {
        httplib::Result r = s.client(false).Get(path);
        REQUIRE(r);
        CHECK(r->status == 403);
        CHECK_THAT(json::parse(r->body)["error"].get<std::string>(), Catch::StartsWith("no valid token: " + open_the_url));
        CHECK(s.client(false).Get(path, {{"X-HSR-Token", test_token + "x"}})->status == 403);
        CHECK(s.client(false).Get(path, {{"X-HSR-Token", test_token}})->status == 200);
    }
    CHECK(s.client(false).Post("/api/frame", small_frame().dump(), "application/json")->status == 403);
    // The page itself is no secret.
    CHECK(s.client(false).Get("/")->status == 200);

    // The printed URL: a cookie for this port, and back to the page.
    httplib::Result opened = s.client(false).Get(("/?token=" + test_token).c_str());
    REQUIRE(opened);
    CHECK(opened->status == 303);
    CHECK(opened->get_header_value("Location") == "/");
    const std::string cookie = opened->get_header_value("Set-Cookie");
    CHECK(cookie == fmt::format("hsr_view_token_{}={}; Path=/; HttpOnly; SameSite=Strict", s.port, test_token));
    const std::string sent_cookie = cookie.substr(0, cookie.find(';'));
    CHECK(s.client(false).Get("/api/info", {{"Cookie", "other=1; " + sent_cookie}})->status == 200);
    CHECK(s.client(false).Post("/api/frame", {{"Cookie", sent_cookie}}, small_frame().dump(), "application/json")->status ==
          200);
    CHECK(s.client(false).Get("/api/info", {{"Cookie", fmt::format("hsr_view_token_{}=wrong", s.port)}})->status == 403);
    CHECK(s.client(false).Get("/api/info", {{"Cookie", fmt::format("hsr_view_token_{}={}", s.port + 1, test_token)}})
              ->status == 403);

    httplib::Result wrong = s.client(false).Get("/?token=guess");
    REQUIRE(wrong);
    CHECK(wrong->status == 403);
    CHECK_FALSE(wrong->has_header("Set-Cookie"));
    CHECK_THAT(json::parse(wrong->body)["error"].get<std::string>(), Catch::StartsWith("wrong token: " + open_the_url));
}

TEST_CASE("view access: cross-origin and form posts are refused", "[view]") {
    RunningServer s;
    const std::string frame = small_frame().dump();
    // What a page of another site can send without a preflight: text/plain, and forms.
    struct Case {
        std::string path, type, origin;
        int status;
    };
    const std::string own = "http://" + s.host();
    for (const Case& c : {Case{"/api/frame", "text/plain", "http://attacker.example", 403},
                          Case{"/api/frame", "text/plain", "null", 403},
                          Case{"/api/frame", "text/plain", own, 415},
                          Case{"/api/frame", "text/plain;charset=UTF-8", "", 415},
                          Case{"/api/compare", "application/x-www-form-urlencoded", "http://attacker.example", 403},
                          Case{"/api/upload", "application/x-www-form-urlencoded", "http://attacker.example", 403},
                          Case{"/api/upload", "multipart/form-data; boundary=x", own, 415},
                          Case{"/api/upload", "text/plain", "", 415},
                          Case{"/api/frame", "application/json", "http://127.0.0.1:1", 403},
                          Case{"/api/frame", "application/json", own, 200},
                          Case{"/api/frame", "Application/JSON; charset=utf-8", "", 200}}) {
        httplib::Headers headers;
        if (!c.origin.empty()) headers.emplace("Origin", c.origin);
        httplib::Result r = s.client().Post(c.path.c_str(), headers, frame, c.type.c_str());
        REQUIRE(r);
        INFO(c.path << " " << c.type << " from '" << c.origin << "' -> " << r->body.substr(0, 200));
        CHECK(r->status == c.status);
        if (c.status != 200) CHECK(json::parse(r->body).contains("error"));
    }
    httplib::Result cross_site = s.client().Post("/api/frame", {{"Sec-Fetch-Site", "cross-site"}}, frame, "application/json");
    REQUIRE(cross_site);
    CHECK(cross_site->status == 403);
    CHECK(s.client().Post("/api/frame", {{"Sec-Fetch-Site", "same-origin"}}, frame, "application/json")->status == 200);
}

TEST_CASE("view access: JSON nested 100,000 deep, 1e400 and fields of the wrong type are 400s", "[view]") {
    RunningServer s;
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    const std::string deep_objects = [] {
        std::string text;
        for (int i = 0; i < 100000; ++i) text += "{\"a\":";
        return text + "1" + std::string(100000, '}');
    }();
    const std::string nested_camera = "{\"model\": \"0/cube.obj\", \"camera\": {\"eye\": " + deep + "}}";
    for (const char* path : {"/api/frame", "/api/compare"}) {
        for (const std::string& body : {deep, deep_objects, nested_camera, "{\"a\": " + nested_camera + ", \"b\": {}}"}) {
            httplib::Result r = s.client().Post(path, body, "application/json");
            REQUIRE(r);
            CHECK(r->status == 400);
            CHECK(json::parse(r->body)["error"] == "the request body nests deeper than 64 levels");
            REQUIRE(s.client().Get("/api/info")->status == 200);
        }
    }
    // The upload endpoint stores bytes and parses no JSON; a model file that deep is the reader's.
    httplib::Result upload = s.client().Post("/api/upload", {{"X-File-Name", "deep.obj"}}, deep, "application/octet-stream");
    REQUIRE(upload);
    CHECK(upload->status == 200);
    httplib::Result deep_model =
        s.client().Post("/api/frame", json{{"model", json::parse(upload->body)["id"]}}.dump(), "application/json");
    REQUIRE(deep_model);
    CHECK(deep_model->status == 400);
    // 64 levels are fine for the parser; the field's check answers.
    const std::string deep_ok = std::string(62, '[') + std::string(62, ']');
    httplib::Result shallow = s.client().Post(
        "/api/frame", "{\"model\": \"0/cube.obj\", \"camera\": {\"eye\": " + deep_ok + "}}", "application/json");
    REQUIRE(shallow);
    CHECK(shallow->status == 400);
    CHECK(json::parse(shallow->body)["field"] == "camera.eye");

    for (const char* number : {"1e400", "-1e400", "1e99999999999"}) {
        httplib::Result r = s.client().Post(
            "/api/frame", fmt::format("{{\"model\": \"0/cube.obj\", \"width\": {}}}", number), "application/json");
        REQUIRE(r);
        INFO(number << " -> " << r->body);
        CHECK(r->status == 400);
        CHECK(json::parse(r->body)["error"] == "the request body holds a number too large for a double");
    }
    httplib::Result broken = s.client().Post("/api/frame", "{\"model\": \"0/cube.obj\",", "application/json");
    REQUIRE(broken);
    CHECK(broken->status == 400);
    CHECK(json::parse(broken->body)["error"] == "the request body is not JSON (at byte 24)");

    const json good = small_frame();
    struct Wrong {
        const char* field;
        json value;
    };
    for (const Wrong& w : {Wrong{"model", 5}, Wrong{"algorithm", json::array()}, Wrong{"lighting", true},
                           Wrong{"params", json::array()}, Wrong{"params", "x"}, Wrong{"lighting_params", 3},
                           Wrong{"width", "16"}, Wrong{"height", json::object()}, Wrong{"camera", 3},
                           Wrong{"camera", json::array()}, Wrong{"step", "1"}, Wrong{"step", 1.5}, Wrong{"buffers", 1},
                           Wrong{"edges", 1}, Wrong{"hidden", json::array()}}) {
        json request = good;
        request[w.field] = w.value;
        const json answer = json::parse(s.client().Post("/api/frame", request.dump(), "application/json")->body);
        INFO(request.dump() << " -> " << answer.dump());
        CHECK(answer["field"] == w.field);
    }
    for (const char* name : {"yaw", "pitch", "zoom", "fov", "projection", "eye"}) {
        for (const json& value : {json::object(), json(true), json::array({"1", 2, 3})}) {
            if (std::string(name) != "eye" && value.is_array()) continue;
            json request = good;
            request["camera"] = {{name, value}};
            httplib::Result r = s.client().Post("/api/frame", request.dump(), "application/json");
            REQUIRE(r);
            INFO(request.dump() << " -> " << r->body);
            CHECK(r->status == 400);
            CHECK(json::parse(r->body)["field"] == fmt::format("camera.{}", name));
        }
    }
    json params = good;
    params["params"] = {{"tile", json::array()}};
    CHECK(json::parse(s.client().Post("/api/frame", params.dump(), "application/json")->body)["field"] == "params.tile");
    for (const json& compare : {json{{"a", 1}, {"b", good}}, json{{"a", good}}, json::array()}) {
        httplib::Result r = s.client().Post("/api/compare", compare.dump(), "application/json");
        REQUIRE(r);
        CHECK(r->status == 400);
    }
    CHECK(s.client().Post("/api/frame", good.dump(), "application/json")->status == 200);
}

TEST_CASE("view access: chunked and compressed bodies are refused before they are read", "[view]") {
    RunningServer s;
    {
        // A chunk announced at 4 GiB: refused on its headers, not read.
        RawConnection c(s.port);
        c.send(post_head(s, "/api/frame", "application/json", "Transfer-Encoding: chunked\r\n") + "100000000\r\n" +
               std::string(64 * 1024, ' '));
        const std::string answer = c.read_to_end();
        INFO(answer.substr(0, 400));
        CHECK(status_of(answer) == 411);
        CHECK(json::parse(body_of(answer))["error"] ==
              "POST /api/frame: send the body with a Content-Length; chunked bodies are refused");
    }
    {
        RawConnection c(s.port);
        c.send(post_head(s, "/api/upload", "application/octet-stream", "X-File-Name: a.obj\r\nTransfer-Encoding: chunked\r\n") +
               "10\r\n0123456789abcdef\r\n0\r\n\r\n");
        CHECK(status_of(c.read_to_end()) == 411);
    }
    // cpp-httplib's own client, compressing its body with gzip as it is told to.
    httplib::Client gzip = s.client();
    gzip.set_compress(true);
    json large = small_frame();
    large["padding"] = std::string(1 << 20, 'x');
    httplib::Result compressed = gzip.Post("/api/frame", large.dump(), "application/json");
    REQUIRE(compressed);
    CHECK(compressed->status == 415);
    CHECK(json::parse(compressed->body)["error"] ==
          "POST /api/frame: compressed bodies (Content-Encoding: gzip) are refused; send it as it is");
    for (const char* encoding : {"br", "deflate", "x-unknown"}) {
        RawConnection c(s.port);
        c.send(post_head(s, "/api/frame", "application/json",
                         fmt::format("Content-Encoding: {}\r\nContent-Length: 4\r\n", encoding)) + "abcd");
        CHECK(status_of(c.read_to_end()) == 415);
    }
    // A Content-Length over the limit is refused on its headers too.
    RawConnection over(s.port);
    over.send(post_head(s, "/api/upload", "application/octet-stream", "X-File-Name: a.obj\r\nContent-Length: 100000000000\r\n") +
              std::string(64 * 1024, 'v'));
    CHECK(status_of(over.read_to_end()) == 413);
    CHECK(s.client().Get("/api/info")->status == 200);
}

TEST_CASE("view access: a taken port is an error", "[view]") {
    RunningServer s;
    hsr::host::ViewConfig config;
    config.plugin_dirs = {HSR_PLUGIN_DIR};
    config.worker_executable = fs::path(HSR_BINARY_DIR) / "hsr";
    config.upload_parent = s.root;
    hsr::host::ViewServer second(config);
    try {
        second.bind("127.0.0.1", s.port);
        FAIL("a second server listens on the port of the first");
    } catch (const hsr::Error& e) {
        CHECK(std::string(e.what()) ==
              fmt::format("127.0.0.1:{} is in use: another hsr view? try --listen 127.0.0.1:0", s.port));
    }
    CHECK(s.client().Get("/api/info")->status == 200);
}

TEST_CASE("view access: 32 clients trickling their headers do not hold the server", "[view]") {
    hsr::host::HttpLimits limits;
    limits.first_request = std::chrono::minutes(10);  // the tricklers stay for the whole test
    limits.request_head = std::chrono::minutes(10);
    RunningServer s(limits);
    std::vector<std::unique_ptr<RawConnection>> tricklers;
    for (int i = 0; i < 32; ++i) {
        tricklers.push_back(std::make_unique<RawConnection>(s.port));
        REQUIRE(tricklers.back()->send("GET /api/info HTTP/1.1\r\nHost: " + s.host() + "\r\nX-Trickle: "));
    }
    std::atomic<bool> done{false};
    std::thread trickle([&] {
        while (!done) {
            for (const auto& t : tricklers) t->send("x");
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
    });
    // A client that asks now is answered, while each trickler is still served its thread.
    httplib::Result r = s.client().Get("/api/info");
    REQUIRE(r);
    CHECK(r->status == 200);
    CHECK(s.client().Post("/api/frame", small_frame().dump(), "application/json")->status == 200);
    for (const auto& t : tricklers) CHECK(t->open_and_unanswered());
    done = true;
    trickle.join();
}

TEST_CASE("view access: a request not sent in time loses its connection", "[view]") {
    hsr::host::HttpLimits limits;
    limits.first_request = std::chrono::seconds(1);
    limits.request_head = std::chrono::seconds(1);
    limits.request_body = std::chrono::seconds(1);
    limits.head_bytes = 16 * 1024;
    RunningServer s(limits);
    auto trickled = [&](const std::string& start) {
        RawConnection c(s.port);
        REQUIRE(c.send(start));
        std::atomic<bool> done{false};
        std::thread trickle([&] {
            while (!done && c.send("x")) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        });
        const std::string answer = c.read_to_end();  // until the server closes: it would trickle forever
        done = true;
        trickle.join();
        return answer;
    };
    // Headers sent a byte at a time: closed without an answer, or with a 400 for the headers cut short.
    const std::string head = trickled("GET /api/info HTTP/1.1\r\nHost: " + s.host() + "\r\nX-Trickle: ");
    CHECK(status_of(head) != 200);
    // A body sent a byte at a time.
    const std::string body = trickled(post_head(s, "/api/frame", "application/json", "Content-Length: 100000\r\n") + "{");
    CHECK(status_of(body) != 200);
    // Headers longer than the cap, sent at once.
    RawConnection long_head(s.port);
    long_head.send("GET /api/info HTTP/1.1\r\nHost: " + s.host() + "\r\nX-Long: " + std::string(64 * 1024, 'a'));
    CHECK(status_of(long_head.read_to_end()) != 200);
    // A connection that sends nothing.
    RawConnection silent(s.port);
    CHECK(silent.read_to_end().empty());
    CHECK(s.client().Get("/api/info")->status == 200);
}

TEST_CASE("view access: answers name files relative to their served folder", "[view]") {
    RunningServer s;
    httplib::Result r = s.client().Post("/api/frame", json{{"model", "0/broken.obj"}}.dump(), "application/json");
    REQUIRE(r);
    INFO(r->body);
    CHECK(r->status == 400);
    CHECK(r->body.find(s.root.string()) == std::string::npos);
    CHECK_THAT(json::parse(r->body)["error"].get<std::string>(), Catch::Contains("broken.obj"));
}

TEST_CASE("view access: the printed URL carries the token, and other machines are warned of", "[view]") {
    const fs::path temp = cli::scratch_dir() / fmt::format("url-{}", ::getpid());
    fs::create_directories(temp);
    {
        SpawnedView view("--listen 127.0.0.1:0 " + test_models::path("cube.obj").string(), temp);
        std::smatch m;
        REQUIRE(std::regex_match(view.line, m,
                                 std::regex(R"(hsr view: serving \d+ models at http://127\.0\.0\.1:(\d+)/\?token=([0-9a-f]{64}))")));
        httplib::Client c("127.0.0.1", std::stoi(m[1]));
        CHECK(c.Get("/api/info")->status == 403);
        CHECK(c.Get("/api/info", {{"X-HSR-Token", m[2].str()}})->status == 200);
        CHECK(c.Get(("/?token=" + m[2].str()).c_str())->status == 303);
    }
    {
        SpawnedView view("--listen 0.0.0.0:0 " + test_models::path("cube.obj").string(), temp);
        std::smatch m;
        REQUIRE(std::regex_match(view.line, m, std::regex(R"(hsr view: serving \d+ models at http://0\.0\.0\.0:(\d+)/\?token=[0-9a-f]{64})")));
        CHECK(view.read_error_line() ==
              fmt::format("hsr view: warning: 0.0.0.0:{} is reachable from other machines: whoever has the URL below "
                          "can list and render the served models, upload files and keep this machine busy, and the "
                          "token travels unencrypted (plain HTTP)", m[1].str()));
    }
    fs::remove_all(temp);
}

TEST_CASE("view access: the upload folders of killed servers are removed at the next start", "[view]") {
    const fs::path temp = cli::scratch_dir() / fmt::format("stale-{}", ::getpid());
    fs::remove_all(temp);
    fs::create_directories(temp);
    SpawnedView killed("--listen 127.0.0.1:0 " + test_models::path("cube.obj").string(), temp);
    REQUIRE(killed.line.find("serving") != std::string::npos);
    const fs::path left = temp / fmt::format("hsr-view-uploads-{}-", killed.pid);
    killed.kill(SIGKILL);
    std::vector<fs::path> stale;
    for (const fs::directory_entry& e : fs::directory_iterator(temp))
        if (e.path().string().rfind(left.string(), 0) == 0) stale.push_back(e.path());
    REQUIRE(stale.size() == 1);
    // A folder of a server that still runs (this test's parent stands for it) stays, and so does
    // anything else.
    const fs::path running = temp / fmt::format("hsr-view-uploads-{}-abcdef", ::getppid());
    const fs::path other = temp / "hsr-view-uploads-notapid";
    fs::create_directories(running);
    fs::create_directories(other);

    hsr::host::ViewConfig config;
    config.plugin_dirs = {HSR_PLUGIN_DIR};
    config.worker_executable = fs::path(HSR_BINARY_DIR) / "hsr";
    config.upload_parent = temp;
    {
        hsr::host::ViewServer next(config);
        CHECK_FALSE(fs::exists(stale.front()));
        CHECK(fs::exists(running));
        CHECK(fs::exists(other));
        int own = 0;
        for (const fs::directory_entry& e : fs::directory_iterator(temp))
            own += e.path().filename().string().rfind(fmt::format("hsr-view-uploads-{}-", ::getpid()), 0) == 0;
        CHECK(own == 1);
    }
    fs::remove_all(temp);
}
