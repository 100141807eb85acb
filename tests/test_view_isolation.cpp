// hsr view against plugins that crash, abort, exit, throw, run out of memory or loop forever
// (tests/plugins/misbehaving.cpp), in create and in render: each such request is answered with an
// error naming the plugin and what happened, and the server goes on serving every other request.
#include "test_models.hpp"

#include "view_test_server.hpp"

#include "hsr/sanitizers.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <future>
#include <unistd.h>
#include <thread>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::string kToken = "isolation-test-token";

hsr::host::ViewConfig isolation_config(std::chrono::milliseconds time_limit, std::size_t workers,
                                       const std::vector<fs::path>& more_folders) {
    hsr::host::ViewConfig config;
    config.model_folders = {test_models::dir};
    config.model_folders.insert(config.model_folders.end(), more_folders.begin(), more_folders.end());
    config.plugin_dirs = {HSR_PLUGIN_DIR, HSR_MISBEHAVING_PLUGIN_DIR};
    config.time_limit = time_limit;
    config.workers = workers;
    config.worker_memory_bytes = uint64_t(2) << 30;
    config.token = kToken;
    return config;
}

struct IsolationServer {
    test_view::Server server;
    int port;

    explicit IsolationServer(std::chrono::milliseconds time_limit, std::size_t workers = 2,
                             const std::vector<fs::path>& more_folders = {})
        : server(isolation_config(time_limit, workers, more_folders)), port(server.port()) {}

    httplib::Result get(const std::string& path) const {
        httplib::Client c("127.0.0.1", port);
        c.set_read_timeout(300, 0);
        return c.Get(path.c_str(), {{"X-HSR-Token", kToken}});
    }
    httplib::Result frame(const std::string& algorithm, const json& params, int size = 64,
                          const std::string& page = "", const std::string& model = "0/cube.obj",
                          const json& step = nullptr) const {
        const json body{{"model", model},
                        {"step", step},
                        {"algorithm", algorithm},
                        {"params", params},
                        {"lighting", "blinn-phong"},
                        {"camera", {{"yaw", 30}, {"pitch", 20}, {"zoom", 1}}},
                        {"width", size},
                        {"height", size}};
        httplib::Client c("127.0.0.1", port);
        c.set_read_timeout(300, 0);
        httplib::Headers headers{{"X-HSR-Token", kToken}};
        if (!page.empty()) headers.emplace("X-HSR-Page", page);
        return c.Post("/api/frame", headers, body.dump(), "application/json");
    }
    json progress(const std::string& page) const {
        httplib::Client c("127.0.0.1", port);
        const httplib::Result r = c.Get("/api/progress", {{"X-HSR-Page", page}, {"X-HSR-Token", kToken}});
        REQUIRE(r);
        REQUIRE(r->status == 200);
        return json::parse(r->body);
    }
    httplib::Result cancel(const std::string& page) const {
        httplib::Client c("127.0.0.1", port);
        return c.Post("/api/cancel", {{"X-HSR-Page", page}, {"X-HSR-Token", kToken}}, "{}", "application/json");
    }
    // A plain frame still renders: the server and the other workers are unharmed.
    void serves_others() const {
        const httplib::Result r = frame("zbuffer", json::object());
        REQUIRE(r);
        CHECK(r->status == 200);
        CHECK(json::parse(r->body).contains("png"));
    }
};

std::string error_of(const httplib::Result& r) { return json::parse(r->body).at("error").get<std::string>(); }

}  // namespace

TEST_CASE("view isolation: a plugin that kills its worker answers one request with why", "[view][isolation]") {
    IsolationServer server(std::chrono::seconds(60));
    struct Case {
        const char* fault;
        const char* what;  // in the message
    };
    const Case cases[] = {{"segfault", "crashed"}, {"abort", "SIGABRT"}, {"exit", "exit(0)"}};
    for (const char* when : {"create", "render"}) {
        for (const Case& c : cases) {
            INFO(c.fault << " in " << when);
            const httplib::Result r = server.frame("misbehaving", {{"fault", c.fault}, {"when", when}});
            REQUIRE(r);
            CHECK(r->status == 500);
            const std::string error = error_of(r);
            CHECK_THAT(error, Catch::Contains("plugin 'misbehaving'") && Catch::Contains(c.what) &&
                                  Catch::Contains(std::string("in ") + when));
            CHECK(error.find('\n') == std::string::npos);
            server.serves_others();
        }
    }
}

TEST_CASE("view isolation: an exception across the ABI is one request's error", "[view][isolation]") {
    IsolationServer server(std::chrono::seconds(60));
    for (const char* when : {"create", "render"}) {
        const httplib::Result r = server.frame("misbehaving", {{"fault", "throw"}, {"when", when}});
        REQUIRE(r);
        CHECK(r->status >= 400);
        CHECK_THAT(error_of(r), Catch::Contains("misbehaving"));
        server.serves_others();
    }
}

TEST_CASE("view isolation: a plugin that asks for 10 GB fails in its worker alone", "[view][isolation]") {
    if (hsr::kAddressSanitizer) return;  // AddressSanitizer needs its address space unbounded: no bound to hit
    IsolationServer server(std::chrono::seconds(60));
    const httplib::Result r = server.frame("misbehaving", {{"fault", "allocate"}, {"when", "render"}});
    REQUIRE(r);
    CHECK(r->status == 500);
    CHECK_THAT(error_of(r), Catch::Contains("plugin 'misbehaving'"));
    server.serves_others();
}

TEST_CASE("view isolation: a plugin that loops forever is stopped at the time limit", "[view][isolation]") {
    IsolationServer server(std::chrono::seconds(2));
    const httplib::Result r = server.frame("misbehaving", {{"fault", "loop"}, {"when", "render"}});
    REQUIRE(r);
    CHECK(r->status == 504);
    CHECK_THAT(error_of(r), Catch::Contains("'misbehaving'") && Catch::Contains("time limit of 2 s"));
    server.serves_others();
}

TEST_CASE("view isolation: other clients are served while a plugin loops", "[view][isolation]") {
    IsolationServer server(std::chrono::seconds(600), 2);
    auto looping = std::async(std::launch::async, [&] {
        return server.frame("misbehaving", {{"fault", "loop"}, {"when", "render"}});
    });
    // The other worker answers, again and again, while the first still loops.
    for (int i = 0; i < 3; ++i) server.serves_others();
    CHECK(looping.wait_for(std::chrono::seconds(0)) == std::future_status::timeout);
    // Stopping the server stops the looping worker: the request is answered, not left hanging.
    server.server.stop();
    const httplib::Result r = looping.get();
    if (r) CHECK(r->status == 503);
}

TEST_CASE("view isolation: a plugin whose first instance crashes is left out, not fatal", "[view][isolation]") {
    IsolationServer server(std::chrono::seconds(60));
    const httplib::Result r = server.get("/api/plugins");
    REQUIRE(r);
    REQUIRE(r->status == 200);
    const json plugins = json::parse(r->body);
    std::vector<std::string> names;
    for (const json& p : plugins.at("hidden_surface")) names.push_back(p.at("name").get<std::string>());
    CHECK(std::find(names.begin(), names.end(), "crashes-in-create") == names.end());
    CHECK(std::find(names.begin(), names.end(), "misbehaving") != names.end());
    CHECK(std::find(names.begin(), names.end(), "zbuffer") != names.end());
    server.serves_others();
}

TEST_CASE("view isolation: the page's Stop and a newer request cancel a long one", "[view][isolation]") {
    IsolationServer server(std::chrono::seconds(600), 2);
    SECTION("Stop") {
        auto looping = std::async(std::launch::async, [&] {
            return server.frame("misbehaving", {{"fault", "loop"}, {"when", "render"}}, 64, "page-1");
        });
        // Until the request is in flight, there is nothing to cancel.
        bool cancelled = false;
        for (int attempt = 0; attempt < 1000 && !cancelled; ++attempt) {
            const httplib::Result r = server.cancel("page-1");
            REQUIRE(r);
            REQUIRE(r->status == 200);
            cancelled = json::parse(r->body).at("cancelled") == true;
            if (!cancelled) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        REQUIRE(cancelled);
        const httplib::Result r = looping.get();
        REQUIRE(r);
        CHECK(r->status == 409);
        CHECK_THAT(error_of(r), Catch::Contains("cancelled"));
    }
    SECTION("a newer request from the same page") {
        auto looping = std::async(std::launch::async, [&] {
            return server.frame("misbehaving", {{"fault", "loop"}, {"when", "render"}}, 64, "page-2");
        });
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        const httplib::Result newer = server.frame("zbuffer", json::object(), 64, "page-2");
        REQUIRE(newer);
        CHECK(newer->status == 200);
        if (looping.wait_for(std::chrono::seconds(30)) != std::future_status::ready) {
            server.cancel("page-2");  // not to hang the test
            FAIL("the newer request from the same page did not cancel the older one");
        }
        const httplib::Result r = looping.get();
        REQUIRE(r);
        CHECK(r->status == 409);
    }
    SECTION("another page's request is not touched") {
        const httplib::Result other = server.frame("zbuffer", json::object(), 64, "page-3");
        REQUIRE(other);
        CHECK(other->status == 200);
        CHECK(json::parse(server.cancel("page-4")->body)["cancelled"] == false);
    }
    server.serves_others();
}

// A folder of scenes of many bunnies, removed at the end.
struct BunnyScenes {
    fs::path folder = fs::temp_directory_path() / ("hsr-view-isolation-" + std::to_string(::getpid()));
    BunnyScenes() {
        fs::create_directories(folder);
        const std::string bunny = (test_models::dir / "bunny.obj").string();
        // 7 million triangles once copied out for a hidden-line plugin: over the stored-triangles
        // limit of 5 million.
        std::ofstream(folder / "bunnies.scene") << "mesh " << bunny << "\nrepeat 10 10 1\n";
        // 28 million triangles, one step each for zbuffer: seconds of steps.
        std::ofstream(folder / "many-bunnies.scene") << "mesh " << bunny << "\nrepeat 20 20 1\n";
    }
    ~BunnyScenes() {
        std::error_code ec;
        fs::remove_all(folder, ec);
    }
};

TEST_CASE("view isolation: what the request must change is a 400, not a 500", "[view][isolation]") {
    const BunnyScenes scenes;
    IsolationServer server(std::chrono::seconds(60), 2, {scenes.folder});
    // roberts refuses a body that is not convex (the monkey).
    const httplib::Result roberts = server.frame("roberts", json::object(), 64, "", "0/monkey.obj");
    REQUIRE(roberts);
    CHECK(roberts->status == 400);
    CHECK_THAT(error_of(roberts), Catch::Contains("convex"));
    const httplib::Result appel = server.frame("appel", json::object(), 64, "", "1/bunnies.scene");
    REQUIRE(appel);
    CHECK(appel->status == 400);
    CHECK_THAT(error_of(appel), Catch::Contains("over the limit"));
    server.serves_others();
}

TEST_CASE("view isolation: a long step request reports its progress and is stopped", "[view][isolation]") {
    const BunnyScenes scenes;
    IsolationServer server(std::chrono::seconds(600), 2, {scenes.folder});
    CHECK(server.progress("page-6")["running"] == false);
    auto stepping = std::async(std::launch::async, [&] {
        return server.frame("zbuffer", json::object(), 64, "page-6", "1/many-bunnies.scene", 100'000'000);
    });
    // The worker counts the steps first: the progress says how many so far, the total not yet.
    json seen;
    for (int attempt = 0; attempt < 3000 && seen.is_null(); ++attempt) {
        const json progress = server.progress("page-6");
        if (progress["running"] == true && progress["progress"].is_object() && progress["progress"]["steps"] > 0)
            seen = progress;
        else
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    REQUIRE_FALSE(seen.is_null());
    CHECK(seen["ms"].get<double>() > 0);
    CHECK(seen["progress"]["total"] == 0);
    CHECK(json::parse(server.cancel("page-6")->body)["cancelled"] == true);
    const httplib::Result r = stepping.get();
    REQUIRE(r);
    CHECK(r->status == 409);
    CHECK(server.progress("page-6")["running"] == false);
    server.serves_others();
}
