// hsr view's server (host/view/server/view_server.hpp), started in this process on a free port of 127.0.0.1 and
// spoken to over HTTP with cpp-httplib's client: every endpoint, the CLI's messages for bad values,
// steps checked against the full render and against the plugin's own counts, compare, uploads and
// their cap, and requests that try to read files outside the served folders. Also the hidden-line
// step option of the framework (LineSettings::stop_after_event).
#include "cli_support.hpp"
#include "test_models.hpp"

#include "view/server/view_server.hpp"
#include "view_test_server.hpp"
#include "view/server/theory_markdown.hpp"
#include "view/server/view_theory.hpp"

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/image.hpp"
#include "hsr/limits.hpp"
#include "hsr/lines.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene_builder.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <optional>
#include <regex>
#include <set>
#include <thread>

#include <unistd.h>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A scratch folder of models: two plain ones, one in a sub-folder, a hidden one, a link that leaves
// the folder, and a .scene file naming a mesh outside it. Beside it, outside, a "secret" model. One
// per process, as ctest runs test cases side by side.
fs::path make_model_folder() {
    const fs::path root = cli::scratch_dir() / fmt::format("view-{}", ::getpid());
    fs::remove_all(root);
    fs::create_directories(root / "models" / "sub");
    fs::create_directories(root / "outside");
    fs::copy_file(test_models::path("cube.obj"), root / "models" / "cube.obj");
    fs::copy_file(test_models::path("tetrahedron.off"), root / "models" / "sub" / "tetrahedron.off");
    fs::copy_file(test_models::path("cube.obj"), root / "models" / ".hidden.obj");
    fs::copy_file(test_models::path("cube.obj"), root / "outside" / "secret.obj");
    fs::create_symlink(root / "outside" / "secret.obj", root / "models" / "link.obj");
    std::ofstream(root / "models" / "escape.scene") << "mesh ../outside/secret.obj\n";
    std::ofstream(root / "models" / "missing.scene") << "mesh sub/missing.obj\n";
    std::ofstream(root / "models" / "inside.scene") << "# a comment\nmesh \"sub/tetrahedron.off\"\nmesh cube.obj\n";
    // A link that stays inside (linked -> a/b), through which ".." leaves: the reader takes ".."
    // first (the served root's parent), while the link resolved first would stay inside.
    fs::create_directories(root / "models" / "a" / "b");
    fs::create_directories(root / "secret");
    fs::create_directory_symlink("a/b", root / "models" / "linked");
    std::ofstream(root / "secret" / "x.obj") << "v 0 0 0\nTOPSECRET line that is not OBJ\n";
    std::ofstream(root / "models" / "leak.scene") << "mesh linked/../../secret/x.obj\n";
    return root;
}

// An answer with arrays (application/vnd.hsr.frame): its JSON and the bytes its arrays point into.
struct FrameWithArrays {
    json body;
    std::string arrays;
};

FrameWithArrays split_frame_answer(const std::string& bytes) {
    REQUIRE(bytes.size() >= 4);
    uint32_t length = 0;
    for (int i = 0; i < 4; ++i) length |= uint32_t(uint8_t(bytes[i])) << (8 * i);
    REQUIRE(bytes.size() >= 4 + length);
    const std::size_t arrays = (4 + length + 3) / 4 * 4;
    return {json::parse(bytes.substr(4, length)), bytes.substr(arrays)};
}

struct RunningServer {
    fs::path root = make_model_folder();
    fs::path third_party = root / "third-party";  // a plugin folder: a plugin with a page beside it
    std::optional<test_view::Server> server;
    int port = 0;

    RunningServer() {
        hsr::host::ViewConfig config;
        config.model_folders = {root / "models", test_models::dir};
        fs::create_directories(third_party);
        fs::copy_file(HSR_THIRD_PARTY_PLUGIN, third_party / "third-party.so");
        std::ofstream(third_party / "third-party.md") << "# A third party's `z-buffer`\n\nEvery pixel, <b>once</b>.\n";
        config.plugin_dirs = {HSR_PLUGIN_DIR, HSR_TEST_PLUGIN_DIR, third_party.string()};
        config.initial_model = root / "models" / "cube.obj";
        config.upload_parent = root;
        port = server.emplace(std::move(config)).port();
        REQUIRE(get("/api/info")->status == 200);  // running: the destructor's stop() will end run()
    }
    ~RunningServer() {
        server.reset();
        std::error_code ec;
        fs::remove_all(root, ec);
    }

    httplib::Client client() const {
        httplib::Client c = server->client();
        c.set_read_timeout(120, 0);
        return c;
    }
    httplib::Result get(const std::string& path) const { return client().Get(path.c_str()); }
    // As a browser asks: it accepts compressed answers, which the server does not send (a large
    // frame compressed with Brotli takes seconds).
    httplib::Result post(const std::string& path, const json& body) const {
        return client().Post(path.c_str(), {{"Accept-Encoding", "gzip, deflate, br"}}, body.dump(), "application/json");
    }
    // A frame or comparison asked with buffers: its arrays come as bytes after the JSON.
    FrameWithArrays post_arrays(const std::string& path, const json& body) const {
        httplib::Result r = post(path, body);
        REQUIRE(r);
        INFO(path << " " << body.dump() << " -> " << r->body.substr(0, 400));
        REQUIRE(r->status == 200);
        CHECK(r->get_header_value("Content-Type") == "application/vnd.hsr.frame");
        return split_frame_answer(r->body);
    }
    // The response as JSON, after checking its status.
    json post_json(const std::string& path, const json& body, int status = 200) const {
        httplib::Result r = post(path, body);
        REQUIRE(r);
        INFO(path << " " << body.dump() << " -> " << r->body.substr(0, 400));
        REQUIRE(r->status == status);
        CHECK(r->get_header_value("Content-Type") == "application/json; charset=utf-8");
        CHECK_FALSE(r->has_header("Content-Encoding"));
        return json::parse(r->body);
    }
    json get_json(const std::string& path, int status = 200) const {
        httplib::Result r = get(path);
        REQUIRE(r);
        INFO(path << " -> " << r->body.substr(0, 400));
        REQUIRE(r->status == status);
        return json::parse(r->body);
    }
};

std::string decode_base64(const std::string& text) {
    std::string out;
    uint32_t bits = 0;
    int count = 0;
    for (char c : text) {
        const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const char* at = std::strchr(digits, c);
        if (c == '=' || at == nullptr) break;
        bits = bits << 6 | uint32_t(at - digits);
        if ((count += 6) >= 8) {
            count -= 8;
            out += char((bits >> count) & 0xff);
        }
    }
    return out;
}

std::string png_bytes(const json& frame) {
    const std::string url = frame.at("png").get<std::string>();
    const std::string prefix = "data:image/png;base64,";
    REQUIRE(url.rfind(prefix, 0) == 0);
    return decode_base64(url.substr(prefix.size()));
}

// The values of an array of the answer ({"array": type, "offset": bytes, "length": values}).
template <class T>
std::vector<T> decode_array(const FrameWithArrays& answer, const json& array) {
    const std::size_t offset = array.at("offset").get<std::size_t>(), length = array.at("length").get<std::size_t>();
    CHECK(offset % 4 == 0);
    REQUIRE(offset + length * sizeof(T) <= answer.arrays.size());
    std::vector<T> values(length);
    std::memcpy(values.data(), answer.arrays.data() + offset, length * sizeof(T));
    return values;
}

json frame_request(const std::string& model, const std::string& algorithm, int size) {
    return {{"model", model}, {"algorithm", algorithm}, {"params", json::object()}, {"lighting", "blinn-phong"},
            {"camera", {{"yaw", 30}, {"pitch", 20}, {"zoom", 1}, {"projection", "perspective"}, {"fov", 35}}},
            {"width", size}, {"height", size}, {"step", nullptr}, {"buffers", false}};
}

// The CLI's message for the same mistake: hsr render's one-line error without its prefix.
std::string cli_message(const std::string& args, const std::string& tag) {
    const cli::Run run = cli::run_hsr(args, tag);
    REQUIRE(run.status != 0);
    std::string message = run.err.substr(std::string("hsr: error: ").size());
    message = message.substr(0, message.find('\n'));
    const std::string hint = " (see hsr render --help)";
    if (message.ends_with(hint)) message.resize(message.size() - hint.size());
    return message;
}

}  // namespace

TEST_CASE("view: info, models, plugins and the page", "[view]") {
    RunningServer s;
    const json info = s.get_json("/api/info");
    CHECK(info["abi"] == fmt::format("{}.{}", HSR_ABI_MAJOR, HSR_ABI_MINOR));
    CHECK(info["initial_model"] == "0/cube.obj");
    CHECK(info["limits"]["upload_bytes"] == hsr::limits().upload_bytes);
    CHECK(info["limits"]["max_image_side"] == 4096);

    const json models = s.get_json("/api/models");
    REQUIRE(models["folders"].size() == 2);
    CHECK(models["folders"] == json::array({"models", "models"}));  // by name: no path of the machine
    std::vector<std::string> ids;
    for (const json& m : models["models"]) ids.push_back(m["id"]);
    CHECK(std::is_sorted(ids.begin(), ids.end()));
    for (const char* id : {"0/cube.obj", "0/sub/tetrahedron.off", "0/escape.scene", "1/cube.obj", "1/boxes.scene"})
        CHECK(std::count(ids.begin(), ids.end(), id) == 1);
    for (const char* id : {"0/.hidden.obj", "0/link.obj"}) CHECK(std::count(ids.begin(), ids.end(), id) == 0);
    for (const json& m : models["models"])
        if (m["id"] == "0/cube.obj") {
            CHECK(m["bytes"] == fs::file_size(s.root / "models" / "cube.obj"));
            CHECK(m["kind"] == "model");
            CHECK(m["name"] == "cube.obj");
        }

    const json plugins = s.get_json("/api/plugins");
    auto find = [&](const char* kind, const char* name) {
        for (const json& p : plugins[kind])
            if (p["name"] == name) return p;
        FAIL("no plugin " << name << " in " << kind);
        return json();
    };
    const json zbuffer = find("hidden_surface", "zbuffer");
    CHECK(zbuffer["steps"] == true);
    CHECK(zbuffer["abi"] == std::to_string(HSR_ABI_MAJOR) + "." + std::to_string(HSR_ABI_MINOR));
    CHECK(find("hidden_surface", "frozen-1.0")["steps"] == false);
    CHECK(find("hidden_line", "handmade-lines")["steps"] == true);
    find("lighting", "blinn-phong");
    bool depth_test = false;
    for (const json& p : zbuffer["params"])
        if (p["name"] == "depth-test") {
            depth_test = true;
            CHECK(p["type"] == "enum");
            CHECK(p["default"] == "less");
            CHECK(p["choices"] == json({"less", "greater"}));
        }
    CHECK(depth_test);

    httplib::Result page = s.get("/");
    REQUIRE(page);
    CHECK(page->status == 200);
    CHECK(page->get_header_value("Content-Type") == "text/html; charset=utf-8");
    CHECK(page->body == cli::slurp(fs::path(HSR_SOURCE_DIR) / "host/view/web/index.html"));
    CHECK(s.get("/static/index.html")->body == page->body);
    const json missing = s.get_json("/static/no-such-file.js", 404);
    CHECK(missing["error"] == "no file 'no-such-file.js'");
    CHECK(s.get_json("/api/nothing", 404).contains("error"));
}

TEST_CASE("view: a frame, and the CLI's messages for bad values", "[view]") {
    RunningServer s;
    json request = frame_request("0/cube.obj", "zbuffer", 64);
    request["buffers"] = true;
    const FrameWithArrays answer = s.post_arrays("/api/frame", request);
    const json& frame = answer.body;
    CHECK(frame["kind"] == "surface");
    CHECK(frame["width"] == 64);
    CHECK(frame["stats"]["triangles"] == 12);
    CHECK(frame["stats"]["counters"]["triangles-in"] == 12);
    CHECK(frame["steps"].is_null());
    // The picture decodes to the size asked for: a PNG's IHDR holds it.
    const std::string png = png_bytes(frame);
    REQUIRE(png.size() > 24);
    CHECK(png.substr(1, 3) == "PNG");
    CHECK(uint8_t(png[19]) == 64);
    CHECK(uint8_t(png[23]) == 64);
    // Buffers: each width * height; the covered pixels are those with a face and a finite depth, and
    // each has its face's object (cube.obj: one object, 0).
    const auto depth = decode_array<float>(answer, frame["buffers"]["depth"]);
    const auto face = decode_array<uint32_t>(answer, frame["buffers"]["face"]);
    const auto object = decode_array<uint32_t>(answer, frame["buffers"]["object"]);
    const auto complexity = decode_array<uint32_t>(answer, frame["buffers"]["depth_complexity"]);
    REQUIRE(depth.size() == 64 * 64);
    REQUIRE(face.size() == 64 * 64);
    REQUIRE(complexity.size() == 64 * 64);
    std::size_t covered = 0;
    for (std::size_t p = 0; p < face.size(); ++p) {
        CHECK((face[p] == HSR_NO_FACE) == std::isinf(depth[p]));
        CHECK((face[p] == HSR_NO_FACE) == (complexity[p] == 0));
        CHECK(object[p] == (face[p] == HSR_NO_FACE ? HSR_NO_FACE : 0u));
        if (face[p] != HSR_NO_FACE) {
            CHECK(face[p] < 12);
            ++covered;
        }
    }
    CHECK(covered == frame["stats"]["counters"]["fragments-shaded"]);
    CHECK(frame["buffers"]["instance"].is_null());
    CHECK(frame["buffers"]["region"] == json::array({0, 0, 64, 64}));
    // Four bytes a pixel a buffer on the wire, and the JSON.
    CHECK(answer.arrays.size() == 5 * 64 * 64 * 4);

    // Some buffers over a rectangle, twice in one request: the same values as the whole frame's
    // (depth complexity is then measured over the rectangle around both).
    request["buffers"] = json::array({{{"names", {"face", "depth", "depth_complexity"}}, {"region", {8, 16, 24, 8}}},
                                      {{"names", {"object", "depth_complexity"}}, {"region", {60, 60, 10, 10}}}});
    const FrameWithArrays parts = s.post_arrays("/api/frame", request);
    REQUIRE(parts.body["buffers"].size() == 2);
    const json& tile = parts.body["buffers"][0];
    CHECK(tile["region"] == json::array({8, 16, 24, 8}));
    CHECK(tile["object"].is_null());
    const auto tile_face = decode_array<uint32_t>(parts, tile["face"]);
    const auto tile_depth = decode_array<float>(parts, tile["depth"]);
    const auto tile_complexity = decode_array<uint32_t>(parts, tile["depth_complexity"]);
    REQUIRE(tile_face.size() == 24 * 8);
    REQUIRE(tile_complexity.size() == 24 * 8);
    for (uint32_t y = 0; y < 8; ++y)
        for (uint32_t x = 0; x < 24; ++x) {
            CHECK(tile_face[y * 24 + x] == face[(16 + y) * 64 + 8 + x]);
            CHECK(tile_depth[y * 24 + x] == depth[(16 + y) * 64 + 8 + x]);
            CHECK(tile_complexity[y * 24 + x] == complexity[(16 + y) * 64 + 8 + x]);
        }
    const json& corner = parts.body["buffers"][1];
    CHECK(corner["region"] == json::array({60, 60, 4, 4}));  // clipped to the picture
    CHECK(decode_array<uint32_t>(parts, corner["object"]).size() == 16);
    const auto corner_complexity = decode_array<uint32_t>(parts, corner["depth_complexity"]);
    REQUIRE(corner_complexity.size() == 16);
    for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 0; x < 4; ++x) CHECK(corner_complexity[y * 4 + x] == complexity[(60 + y) * 64 + 60 + x]);
    CHECK(parts.arrays.size() == (3 * 24 * 8 + 2 * 16) * 4);
    // Only the buffers, without the picture.
    request["picture"] = false;
    CHECK(s.post_arrays("/api/frame", request).body["png"].is_null());
    request["picture"] = true;
    for (const json& bad : {json("all"), json::array({"depth"}), json({{"names", {"colour"}}}),
                            json({{"region", {0, 0, 0, 4}}}), json({{"region", {64, 0, 4, 4}}}), json({{"size", 1}})}) {
        request["buffers"] = bad;
        INFO(bad.dump());
        CHECK(s.post_json("/api/frame", request, 400)["field"].get<std::string>().starts_with("buffers"));
    }
    request["buffers"] = false;

    const std::string cube = test_models::path("cube.obj").string();
    struct Case {
        const char* field;
        json value;
        std::string cli_args;
    };
    const Case cases[] = {
        {"params.cull-backfaces", json{{"cull-backfaces", "maybe"}}, "-a zbuffer:cull-backfaces=maybe"},
        {"params.no-such", json{{"no-such", "1"}}, "-a zbuffer:no-such=1"},
        {"lighting_params.interpolation", json{{"interpolation", "glossy"}}, "-l blinn-phong:interpolation=glossy"},
        {"lighting_params.mode", json{{"mode", "glossy"}}, "-l blinn-phong:mode=glossy"},
        {"algorithm", "no-such-plugin", "-a no-such-plugin"},
        {"lighting", "no-such-lighting", "-l no-such-lighting"},
        {"camera.zoom", -1, "--zoom -1"},
        {"camera.fov", 200, "--fov 200"},
        {"camera.eye", json{1, 2}, "--eye 1,2"},
    };
    for (const Case& c : cases) {
        json bad = frame_request("0/cube.obj", "zbuffer", 32);
        const std::string field = c.field;
        if (field.starts_with("params."))
            bad["params"] = c.value;
        else if (field.starts_with("lighting_params."))
            bad["lighting_params"] = c.value;
        else if (field.starts_with("camera."))
            bad["camera"][field.substr(7)] = c.value;
        else
            bad[field] = c.value;
        const json error = s.post_json("/api/frame", bad, 400);
        CHECK(error["field"] == c.field);
        // The folders searched differ (the test's plugin folders), so a missing plugin's message is
        // compared up to the list of them.
        auto before_search = [](std::string message) { return message.substr(0, message.find(" (searched: ")); };
        CHECK(before_search(error["error"]) ==
              before_search(cli_message("render " + cube + " -o x.png " + c.cli_args, "view-cli")));
    }
    json too_large = frame_request("0/cube.obj", "zbuffer", 32);
    too_large["width"] = 5000;
    const json size_error = s.post_json("/api/frame", too_large, 400);
    CHECK(size_error["field"] == "width");
    CHECK(size_error["error"] == "image size 5000x32: each side must be between 1 and 4096");
    CHECK(s.post_json("/api/frame", json{{"model", "0/cube.obj"}, {"step", 0}}, 400)["error"] ==
          cli_message("render " + cube + " -o x.png --step 0", "view-cli"));
    httplib::Result not_json = s.client().Post("/api/frame", "{model:", "application/json");
    REQUIRE(not_json);
    CHECK(not_json->status == 400);
    CHECK_THAT(json::parse(not_json->body)["error"].get<std::string>(), Catch::StartsWith("the request body is not JSON"));

    // A plugin that fails: a JSON error, and the server goes on.
    json failing = frame_request("0/cube.obj", "throwing", 32);
    const json failure = s.post_json("/api/frame", failing, 500);
    CHECK_THAT(failure["error"].get<std::string>(), Catch::Contains("throwing"));
    CHECK(s.post_json("/api/frame", frame_request("0/cube.obj", "zbuffer", 32))["kind"] == "surface");
    // A step request to a plugin without steps.
    json no_steps = frame_request("0/cube.obj", "frozen-1.0", 32);
    no_steps["step"] = 1;
    const json no_steps_error = s.post_json("/api/frame", no_steps, 400);
    CHECK(no_steps_error["field"] == "step");
    CHECK_THAT(no_steps_error["error"].get<std::string>(), Catch::Contains("cannot show its steps"));
}

TEST_CASE("view: zbuffer steps against the full render and the plugin's own counts", "[view]") {
    RunningServer s;
    const std::string bunny = "1/bunny.obj";
    test_models::require_fetched();
    const json full = s.post_json("/api/frame", frame_request(bunny, "zbuffer", 512));
    const uint64_t triangles = full["stats"]["counters"]["triangles-in"];
    CHECK(triangles == 69666);

    // Steps in the middle: zbuffer draws triangle k - 1 at step k. The pixels the server finds
    // written and rejected (from the buffers before and after) are as many as the plugin counted.
    int checked = 0;
    for (uint64_t step : {1u, 2u, 1000u, 20000u, 30001u, 45678u, 50000u, 60000u, 65000u}) {
        json request = frame_request(bunny, "zbuffer", 512);
        request["step"] = step;
        const json frame = s.post_json("/api/frame", request);
        const json& steps = frame["steps"];
        CHECK(steps["total"] == triangles);
        CHECK(steps["current"] == step);
        CHECK(steps["type"] == "triangle");
        CHECK(steps["face"] == step - 1);
        std::smatch m;
        const std::string text = steps["text"];
        INFO(text);
        CHECK(text.rfind(fmt::format("triangle {}:", step - 1), 0) == 0);
        if (std::regex_search(text, m, std::regex(R"((\d+) pixels? written, (\d+) rejected)"))) {
            REQUIRE(steps["written"].is_array());
            REQUIRE(steps["rejected"].is_array());
            CHECK(steps["written"].size() == std::stoul(m[1]));
            CHECK(steps["rejected"].size() == std::stoul(m[2]));
            ++checked;
            // The outline of the triangle: three sides inside the image, around every pixel written.
            REQUIRE(steps["outline"].size() == 3);
            float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f;
            for (const json& line : steps["outline"]) {
                for (int k = 0; k < 4; k += 2) {
                    x0 = std::min(x0, line[k].get<float>()), x1 = std::max(x1, line[k].get<float>());
                    y0 = std::min(y0, line[k + 1].get<float>()), y1 = std::max(y1, line[k + 1].get<float>());
                }
            }
            CHECK(x0 >= 0);
            CHECK(x1 <= 512);
            for (const json& p : steps["written"]) {
                CHECK(p[0].get<float>() + 0.5f >= x0);
                CHECK(p[0].get<float>() + 0.5f <= x1);
                CHECK(p[1].get<float>() + 0.5f >= y0);
                CHECK(p[1].get<float>() + 0.5f <= y1);
            }
        }
    }
    CHECK(checked >= 3);

    // The last step is the full render, to the byte; a step past the end is the last step.
    for (uint64_t step : {triangles, triangles + 5}) {
        json request = frame_request(bunny, "zbuffer", 512);
        request["step"] = step;
        const json last = s.post_json("/api/frame", request);
        CHECK(last["steps"]["current"] == triangles);
        CHECK(png_bytes(last) == png_bytes(full));
    }
}

TEST_CASE("view: hidden-line steps are the plugin's trace events", "[view]") {
    RunningServer s;
    json request = frame_request("0/cube.obj", "handmade-lines", 64);
    request["edges"] = "all";
    const json full = s.post_json("/api/frame", request);
    CHECK(full["kind"] == "lines");
    CHECK(full["buffers"].is_null());
    const uint64_t edges = full["stats"]["counters"]["edges-requested"];
    CHECK(edges == 12);  // "all" leaves out the diagonals inside the square faces
    request["step"] = 4;
    const json step = s.post_json("/api/frame", request);
    CHECK(step["steps"]["total"] == edges);  // handmade-lines: one "edge-begin" per edge
    CHECK(step["steps"]["current"] == 4);
    CHECK(step["steps"]["type"] == "edge-begin");
    CHECK(step["steps"]["text"] == "edge-begin: edge 3, qi 0, t 0");
    REQUIRE(step["steps"]["lines"].size() == 1);
    CHECK(step["steps"]["lines"][0][4] == 0);
    request["step"] = edges;
    CHECK(png_bytes(s.post_json("/api/frame", request)) == png_bytes(full));
}

TEST_CASE("view: roberts and appel steps send the plugin's lines with roles and its text", "[view]") {
    RunningServer s;
    for (const char* algorithm : {"roberts", "appel"}) {
        INFO(algorithm);
        json request = frame_request("0/cube.obj", algorithm, 64);
        request["edges"] = "all";
        request["step"] = 2;
        const json steps = s.post_json("/api/frame", request)["steps"];
        const std::string text = steps["text"];
        // roberts: its one body, then edge 0; appel: the seed, then the first edge walked.
        CHECK(steps["type"] == "edge-begin");
        CHECK(text.find(std::string(algorithm) == "roberts" ? "edge 0 of body 0" : "starts with QI") != std::string::npos);
        CHECK(text.find(':') != std::string::npos);  // the plugin's words, not "type: field, field"
        REQUIRE(steps["lines"].size() > 0);
        for (const json& line : steps["lines"]) {
            REQUIRE(line.size() == 5);
            CHECK(line[4].get<int>() >= HSR_STEP_SUBJECT);
            CHECK(line[4].get<int>() <= HSR_STEP_CONTEXT);
        }
        // The figure the page draws the step from: the edge under test, numbers for the labels.
        REQUIRE(steps["figure"].is_object());
        CHECK(steps["figure"]["algorithm"] == algorithm);
        REQUIRE(steps["figure"]["edge"].is_object());
        if (std::string(algorithm) == "roberts") CHECK(steps["figure"]["edge"]["index"] == 0);
        CHECK(steps["figure"]["labels"]["edges"].size() == 12);
        CHECK(steps["figure"]["background"] == json::array({255, 255, 255}));
        request["step"] = 1;
        const json first = s.post_json("/api/frame", request)["steps"];
        if (std::string(algorithm) == "appel") CHECK(first["text"].get<std::string>().find("contour edges") != std::string::npos);
        else CHECK(first["text"].get<std::string>().rfind("body 0: 6 planes", 0) == 0);
    }
}

TEST_CASE("lines: stop_after_event keeps the segments emitted before the next event", "[view]") {
    hsr::PluginRegistry registry;
    registry.scan_directory(HSR_TEST_PLUGIN_DIR);
    hsr::HiddenLineRemover remover(registry.find(HSR_KIND_HIDDEN_LINE_REMOVER, "handmade-lines"), {});
    const hsr::SceneData cube = hsr::load_model(test_models::path("cube.obj"));
    hsr::CameraSettings view;
    view.width = view.height = 64;
    view.yaw_degrees = 30;
    view.pitch_degrees = 20;
    const hsr_camera camera = hsr::make_camera(cube.bounds_min, cube.bounds_max, view);
    hsr::LineSettings settings;
    settings.edges = hsr::EdgeSelection::kAll;
    const hsr::LineDrawing whole = hsr::render_lines(cube.view(), camera, remover, settings);
    const uint64_t edges = whole.edges.size();
    REQUIRE(edges > 6);
    CHECK(whole.trace_events == 0);  // not asked for
    CHECK_FALSE(whole.stopped_at);
    // handmade-lines sends event e, then after every third edge a batch of those three segments:
    // before event k + 1 it has emitted 3 * floor(k / 3) segments.
    for (uint64_t k = 1; k <= edges + 1; ++k) {
        settings.stop_after_event = k;
        const hsr::LineDrawing part = hsr::render_lines(cube.view(), camera, remover, settings);
        INFO("k = " << k);
        CHECK(part.trace_events == edges);
        if (k <= edges) {
            REQUIRE(part.stopped_at);
            CHECK(part.stopped_at->index == k);
            CHECK(part.stopped_at->type == "edge-begin");
            CHECK(part.stopped_at->edge == k - 1);
            CHECK(part.segments.size() == (k == edges ? edges : 3 * (k / 3)));
        } else {
            CHECK_FALSE(part.stopped_at);
            CHECK(part.segments.size() == edges);
        }
    }
}

TEST_CASE("view: compare two plugins' visibility", "[view]") {
    RunningServer s;
    json a = frame_request("0/cube.obj", "zbuffer", 48);
    json b = a;
    b["params"] = {{"depth-test", "greater"}};
    a["buffers"] = b["buffers"] = true;
    const FrameWithArrays answer = s.post_arrays("/api/compare", {{"a", a}, {"b", b}});
    const json& result = answer.body;
    const auto face_a = decode_array<uint32_t>(answer, result["a"]["buffers"]["face"]);
    const auto face_b = decode_array<uint32_t>(answer, result["b"]["buffers"]["face"]);
    REQUIRE(face_a.size() == face_b.size());
    uint64_t differing = 0;
    for (std::size_t p = 0; p < face_a.size(); ++p) differing += face_a[p] != face_b[p];
    CHECK(differing > 0);
    CHECK(result["differing_pixels"] == differing);
    CHECK(png_bytes({{"png", result["diff_png"]}}).substr(1, 3) == "PNG");
    CHECK(s.post_arrays("/api/compare", {{"a", a}, {"b", a}}).body["differing_pixels"] == 0);
    json other_size = a;
    other_size["width"] = 40;
    CHECK(s.post_json("/api/compare", {{"a", a}, {"b", other_size}}, 400)["field"] == "b.width");
    json bad = a;
    bad["params"] = {{"depth-test", "sideways"}};
    CHECK(s.post_json("/api/compare", {{"a", a}, {"b", bad}}, 400)["field"] == "b.params.depth-test");
}

// A PNG of the answer as RGB pixels, read back through a file as hsr reads PNG files.
std::vector<uint8_t> png_pixels(const std::string& png, const std::string& name) {
    const std::filesystem::path file = std::filesystem::temp_directory_path() / name;
    std::ofstream(file, std::ios::binary) << png;
    const hsr::Image image = hsr::read_png_rgb(file);
    std::filesystem::remove(file);
    return image.pixels;
}

TEST_CASE("view: compare two line drawings, and not a line drawing with a picture", "[view]") {
    RunningServer s;
    json a = frame_request("0/cube.obj", "roberts", 64);
    json b = a;
    b["algorithm"] = "appel";
    b["hidden"] = "dashed";
    const json result = s.post_json("/api/compare", {{"a", a}, {"b", b}});
    const std::vector<uint8_t> pixels_a = png_pixels(png_bytes(result["a"]), "hsr_compare_a.png");
    const std::vector<uint8_t> pixels_b = png_pixels(png_bytes(result["b"]), "hsr_compare_b.png");
    REQUIRE(pixels_a.size() == 64 * 64 * 3);
    REQUIRE(pixels_b.size() == pixels_a.size());
    uint64_t differing = 0;
    for (std::size_t p = 0; p < pixels_a.size(); p += 3)
        differing += std::memcmp(&pixels_a[p], &pixels_b[p], 3) != 0;
    CHECK(differing > 0);  // b draws the three hidden edges dashed
    CHECK(result["differing_pixels"] == differing);
    CHECK(result["a"]["kind"] == "lines");
    CHECK(png_bytes({{"png", result["diff_png"]}}).substr(1, 3) == "PNG");
    CHECK(s.post_json("/api/compare", {{"a", a}, {"b", a}})["differing_pixels"] == 0);

    const json surfaces = frame_request("0/cube.obj", "zbuffer", 64);
    const json refused = s.post_json("/api/compare", {{"a", a}, {"b", surfaces}}, 400);
    CHECK(refused["field"] == "b.algorithm");
    const std::string message = refused["error"].get<std::string>();
    INFO(message);
    CHECK(message.find("'roberts' draws lines") != std::string::npos);
    CHECK(message.find("'zbuffer' fills surfaces") != std::string::npos);
    CHECK(s.post_json("/api/compare", {{"a", surfaces}, {"b", a}}, 400)["field"] == "b.algorithm");
}

TEST_CASE("view: uploads, and their cap", "[view]") {
    hsr::Limits limits;
    limits.upload_bytes = 2000;
    hsr::set_limits(limits);
    RunningServer s;
    const std::string cube = cli::slurp(test_models::path("cube.obj"));
    REQUIRE(cube.size() < 2000);
    httplib::Headers headers{{"X-File-Name", "my cube.obj"}};
    httplib::Result r = s.client().Post("/api/upload", headers, cube, "application/octet-stream");
    REQUIRE(r);
    REQUIRE(r->status == 200);
    const std::string id = json::parse(r->body)["id"];
    CHECK(std::regex_match(id, std::regex(R"(upload/\d+/my cube\.obj)")));
    CHECK(s.post_json("/api/frame", frame_request(id, "zbuffer", 32))["stats"]["triangles"] == 12);
    const json models = s.get_json("/api/models")["models"];
    INFO(models.dump());
    CHECK(std::count_if(models.begin(), models.end(), [&](const json& m) { return m["id"] == id; }) == 1);

    // A glTF file whose buffer is a data: URI stands alone: one triangle, (0,0,0), (1,0,0), (0,1,0).
    const std::string triangle_gltf =
        R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
        R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],)"
        R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
        R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
    httplib::Result gltf =
        s.client().Post("/api/upload", {{"X-File-Name", "triangle.gltf"}}, triangle_gltf, "application/octet-stream");
    REQUIRE(gltf);
    REQUIRE(gltf->status == 200);
    CHECK(s.post_json("/api/frame", frame_request(json::parse(gltf->body)["id"], "zbuffer", 32))["stats"]["triangles"] == 1);

    httplib::Result large = s.client().Post("/api/upload", headers, std::string(3000, 'v'), "application/octet-stream");
    REQUIRE(large);
    CHECK(large->status == 413);
    CHECK(json::parse(large->body)["error"] ==
          "upload: 3000 bytes, over the limit of 2000 (raise it with --limit upload-bytes=N)");
    for (const char* name : {"../../evil.obj", ".hidden.obj", "notes.txt", ""}) {
        httplib::Result refused = s.client().Post("/api/upload", {{"X-File-Name", name}}, cube, "application/octet-stream");
        REQUIRE(refused);
        INFO(name << ": " << refused->body);
        CHECK(refused->status == 400);
    }
    hsr::set_limits(hsr::Limits{});
    CHECK(s.get_json("/api/info")["limits"]["upload_bytes"] == 2000);  // as when the server started
}

TEST_CASE("view: the scene editor's text, its uploads and its meshes", "[view]") {
    RunningServer s;
    const std::string text = "# a comment\nmesh \"sub/tetrahedron.off\"\nmesh cube.obj\n";
    httplib::Result got = s.get("/api/scene-text?model=0/inside.scene");
    REQUIRE(got);
    CHECK(got->status == 200);
    CHECK(got->body == text);
    CHECK(s.get("/api/scene-text?model=0/cube.obj")->status == 400);
    CHECK(s.get("/api/scene-text?model=0/nothing.scene")->status == 404);

    const auto upload = [&](const std::string& body, const httplib::Headers& headers) {
        httplib::Result r = s.client().Post("/api/upload", headers, body, "application/octet-stream");
        REQUIRE(r);
        INFO(r->body);
        REQUIRE(r->status == 200);
        return json::parse(r->body)["id"].get<std::string>();
    };
    const auto frame_status = [&](const std::string& id) {
        httplib::Result r = s.client().Post("/api/frame", frame_request(id, "zbuffer", 16).dump(), "application/json");
        REQUIRE(r);
        return r->status;
    };
    // Alone, its relative meshes are looked for among the uploads, where they are not.
    const std::string alone = upload(text, {{"X-File-Name", "edited.scene"}});
    CHECK(frame_status(alone) == 400);
    // Edited from 0/inside.scene, they are that scene's: the tetrahedron and the cube; the upload
    // it replaces is gone.
    const std::string based = upload(text, {{"X-File-Name", "edited.scene"}, {"X-Base-Model", "0/inside.scene"}, {"X-Replaces", alone}});
    CHECK(s.post_json("/api/frame", frame_request(based, "zbuffer", 16))["stats"]["triangles"] == 4 + 12);
    const json models = s.get_json("/api/models")["models"];
    CHECK(std::none_of(models.begin(), models.end(), [&](const json& m) { return m["id"] == alone; }));
    // Still nothing outside the served folders.
    const std::string escape = upload("mesh ../outside/secret.obj\n", {{"X-File-Name", "edited.scene"}, {"X-Base-Model", "0/inside.scene"}});
    CHECK(frame_status(escape) != 200);
    httplib::Result bad_base = s.client().Post("/api/upload", {{"X-File-Name", "e.scene"}, {"X-Base-Model", "0/cube.obj"}}, text,
                                               "application/octet-stream");
    REQUIRE(bad_base);
    CHECK(bad_base->status == 400);
}

TEST_CASE("view: nothing outside the served folders is read", "[view]") {
    RunningServer s;
    const std::string secret = (s.root / "outside" / "secret.obj").string();
    for (const std::string& id : {std::string("0/../outside/secret.obj"), std::string("0/%2e%2e/outside/secret.obj"),
                                  std::string("0/sub/../../outside/secret.obj"), secret, "/" + secret, "0//" + secret,
                                  std::string("0/link.obj"), std::string("0/.hidden.obj"), std::string("9/cube.obj"),
                                  std::string("upload/1/cube.obj"), std::string("0/")}) {
        const json error = s.post_json("/api/frame", frame_request(id, "zbuffer", 16), 404);
        CHECK(error["error"] == fmt::format("no model '{}'", hsr::printable(id, hsr::kMaxQuotedPathChars)));
        CHECK(error["field"] == "model");
    }
    const json escape = s.post_json("/api/frame", frame_request("0/escape.scene", "zbuffer", 16), 400);
    CHECK_THAT(escape["error"].get<std::string>(), Catch::Contains("lies outside the folders hsr view serves"));
    const json leak = s.post_json("/api/frame", frame_request("0/leak.scene", "zbuffer", 16), 400);
    CHECK_THAT(leak["error"].get<std::string>(),
               Catch::Contains("lies outside the folders hsr view serves") && !Catch::Contains("TOPSECRET"));
    // A mesh inside that is missing is the reader's to report; meshes inside are read.
    const json missing = s.post_json("/api/frame", frame_request("0/missing.scene", "zbuffer", 16), 400);
    CHECK_THAT(missing["error"].get<std::string>(), !Catch::Contains("outside"));
    CHECK(s.post_json("/api/frame", frame_request("0/inside.scene", "zbuffer", 16))["stats"]["triangles"] == 4 + 12);
    for (const char* path : {"/static/../../../CMakeLists.txt", "/static/%2e%2e/%2e%2e/host/view.cpp", "/static/..%2f..%2fsetup.sh",
                             "/static//etc/passwd", "/api/theory/..%2f..%2fREADME", "/api/theory/%2e%2e"}) {
        httplib::Result r = s.get(path);
        REQUIRE(r);
        INFO(path << " -> " << r->status << " " << r->body.substr(0, 200));
        CHECK((r->status == 404 || r->status == 400));
        CHECK(r->body.find("hsr") == std::string::npos);  // none of those files' text
    }
}

TEST_CASE("view: theory pages", "[view]") {
    RunningServer s;
    const json zbuffer = s.get_json("/api/theory/zbuffer");
    // docs/theory/en/zbuffer.md, or the page made from the plugin while there is none
    const fs::path page = fs::path(HSR_SOURCE_DIR) / "docs/theory/en/zbuffer.md";
    if (fs::exists(page)) {
        const std::string markdown = cli::slurp(page);
        REQUIRE(markdown.rfind("# ", 0) == 0);
        std::string title = markdown.substr(2, markdown.find('\n') - 2);
        std::erase(title, '`');
        CHECK(zbuffer["title"] == title);
        CHECK(zbuffer["source"] == "built-in");
    } else {
        CHECK(zbuffer["title"] == "zbuffer");
        CHECK(zbuffer["source"] == "generated");
        // The generated page links to the implementation notes, served by the viewer.
        CHECK_THAT(zbuffer["html"].get<std::string>(), Catch::Contains("href=\"/docs/algorithms/zbuffer.md\""));
    }
    CHECK_THAT(zbuffer["html"].get<std::string>(), Catch::StartsWith("<h1>"));
    CHECK(zbuffer["language"] == "en");
    const json russian = s.get_json("/api/theory/zbuffer?lang=ru");
    CHECK(russian["language"] == (fs::exists(fs::path(HSR_SOURCE_DIR) / "docs/theory/ru/zbuffer.md") || !fs::exists(page) ? "ru" : "en"));
    // The docs the pages link to: a Markdown page as HTML, a figure as it is, nothing outside docs/.
    httplib::Result notes = s.get("/docs/algorithms/zbuffer.md");
    REQUIRE(notes);
    CHECK(notes->status == 200);
    CHECK_THAT(notes->get_header_value("Content-Type"), Catch::StartsWith("text/html"));
    CHECK_THAT(notes->body, Catch::Contains("<table>"));
    httplib::Result figure = s.get("/docs/images/bench.svg");
    REQUIRE(figure);
    CHECK(figure->status == 200);
    CHECK(figure->get_header_value("Content-Type") == "image/svg+xml");
    for (const char* bad : {"/docs/../README.md", "/docs/%2e%2e/README.md", "/docs/algorithms/../../README.md", "/docs/nothing.md",
                            "/docs//etc/passwd", "/docs/./abi.md"}) {
        httplib::Result r = s.get(bad);
        REQUIRE(r);
        INFO(bad << " -> " << r->status);
        CHECK((r->status == 404 || r->status == 400));
    }
    // A plugin without a page: one made from its description and parameters.
    const json made = s.get_json("/api/theory/throwing");
    CHECK(made["title"] == "throwing");
    const json made_lines = s.get_json("/api/theory/handmade-lines");
    CHECK(made_lines["title"] == "handmade-lines");
    CHECK_THAT(made_lines["html"].get<std::string>(), Catch::StartsWith("<h1>handmade-lines</h1>"));
    CHECK_THAT(made["html"].get<std::string>(), Catch::Contains("throws on purpose (test plugin)"));
    CHECK_THAT(made["html"].get<std::string>(), Catch::Contains("throw-in"));
    CHECK(s.get_json("/api/theory/no-such-plugin", 404)["error"] == "no plugin 'no-such-plugin'");
    // A third-party plugin's own page, beside its library; its raw HTML dropped.
    const json beside = s.get_json("/api/theory/third-party");
    CHECK(beside["title"] == "A third party's z-buffer");
    CHECK_THAT(beside["html"].get<std::string>(), Catch::Contains("<h1>A third party’s <code>z-buffer</code></h1>") ||
                                                  Catch::Contains("<h1>A third party's <code>z-buffer</code></h1>"));
    CHECK_THAT(beside["html"].get<std::string>(), Catch::Contains("Every pixel, "));
    CHECK(beside["html"].get<std::string>().find("<b>") == std::string::npos);
    // Safe mode: raw HTML and javascript: links are dropped.
    const std::string html = hsr::host::render_page("a <script>alert(1)</script> [x](javascript:alert(1))\n", {});
    CHECK(html.find("<script>") == std::string::npos);
    CHECK(html.find("javascript:") == std::string::npos);
}

TEST_CASE("view: frames from several clients at once", "[view]") {
    RunningServer s;
    std::vector<std::thread> clients;
    std::atomic<int> ok{0};
    for (int t = 0; t < 4; ++t)
        clients.emplace_back([&, t] {
            for (int i = 0; i < 5; ++i) {
                json request = frame_request("0/cube.obj", t % 2 ? "zbuffer" : "handmade-lines", 32 + t);
                request["camera"]["yaw"] = 10 * i;
                httplib::Result r = s.post("/api/frame", request);
                if (r && r->status == 200) ++ok;
            }
        });
    for (std::thread& c : clients) c.join();
    CHECK(ok == 20);
}

TEST_CASE("view: the command line", "[view]") {
    const cli::Run help = cli::run_hsr("view --help", "view-help");
    CHECK(help.status == 0);
    CHECK_THAT(help.out, Catch::Contains("127.0.0.1:8080"));  // loopback unless told otherwise
    cli::require_one_line_error(cli::run_hsr("view --listen nonsense", "view-listen"),
                                "--listen 'nonsense': expected HOST:PORT");
    cli::require_one_line_error(cli::run_hsr("view --listen 127.0.0.1:70000", "view-port"), "expected HOST:PORT");
    cli::require_one_line_error(cli::run_hsr("view --models /no/such/folder --listen 127.0.0.1:0", "view-models"),
                                "--models '/no/such/folder': no such folder");
    cli::require_one_line_error(cli::run_hsr("view /no/such.obj --listen 127.0.0.1:0", "view-model"),
                                "'/no/such.obj': no such file");
    cli::require_one_line_error(cli::run_hsr("view --limit upload-bytes=0 --listen 127.0.0.1:0", "view-limit"),
                                "--limit upload-bytes: '0' is not a whole number of at least 1");
    cli::require_one_line_error(cli::run_hsr("view --listen 192.0.2.1:0", "view-address"), "cannot listen on 192.0.2.1:0");
}

TEST_CASE("view: scene_z of a pixel-camera scene is the scene's own z", "[view]") {
    RunningServer s;
    // models/zbuffer-exercise.scene on its 32 x 32 raster: a rectangle (10..25) x (5..25) at z = 10
    // and a triangle through it; pixel (column, row from the top) has its centre at
    // x = column + 0.5, y = 32 - row - 0.5 (y up).
    json request = frame_request("1/zbuffer-exercise.scene", "zbuffer", 30);
    request["buffers"] = json{{"names", {"scene_z", "depth"}}};
    const FrameWithArrays answer = s.post_arrays("/api/frame", request);
    CHECK(answer.body["pixel_camera"] == true);
    REQUIRE(answer.body["width"] == 32);
    REQUIRE(answer.body["height"] == 32);
    REQUIRE(answer.body["buffers"]["scene_z"].is_object());
    const std::vector<float> z = decode_array<float>(answer, answer.body["buffers"]["scene_z"]);
    REQUIRE(z.size() == 32 * 32);

    const double ax = 15, ay = 15, az = 15, bx = 30, by = 10, bz = 5, cx = 25, cy = 25, cz = 5;
    // The triangle's plane z = az + gx (x - ax) + gy (y - ay), from its two edges from a.
    const double ux = bx - ax, uy = by - ay, uz = bz - az, vx = cx - ax, vy = cy - ay, vz = cz - az;
    const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    const double gx = -nx / nz, gy = -ny / nz;
    // Where (x, y) lies in the triangle: its smallest barycentric weight (negative outside).
    auto inside_triangle = [&](double x, double y) {
        const double area = ux * vy - uy * vx;
        const double wb = ((x - ax) * vy - (y - ay) * vx) / area, wc = (ux * (y - ay) - uy * (x - ax)) / area;
        return std::min({wb, wc, 1.0 - wb - wc});
    };
    int rectangle_pixels = 0, triangle_pixels = 0, empty_pixels = 0;
    for (int row = 0; row < 32; ++row) {
        for (int column = 0; column < 32; ++column) {
            const double x = column + 0.5, y = 32 - row - 0.5;
            const float shown = z[std::size_t(row) * 32 + column];
            INFO("pixel " << column << ", " << row << ": z " << shown);
            const bool in_rectangle = x > 10 && x < 25 && y > 5 && y < 25;
            const double weight = inside_triangle(x, y);
            if (std::abs(weight) < 1e-6) continue;  // on the triangle's edge: the fill rule decides
            const double plane_z = az + gx * (x - ax) + gy * (y - ay);
            if (weight > 0 && in_rectangle && std::abs(plane_z - 10) < 1e-4) continue;  // a tie: either may win
            if (weight > 0 && (!in_rectangle || plane_z > 10)) {
                CHECK(shown == Approx(plane_z).margin(1e-4));
                CHECK(shown >= 5);
                CHECK(shown <= 15);
                ++triangle_pixels;
            } else if (in_rectangle) {
                CHECK(shown == 10.0f);  // exactly: the exercise's number
                ++rectangle_pixels;
            } else {
                CHECK(std::isinf(shown));
                CHECK(shown < 0);
                ++empty_pixels;
            }
        }
    }
    CHECK(rectangle_pixels > 200);
    CHECK(triangle_pixels > 40);
    CHECK(empty_pixels > 400);

    // Other cameras have no scene z: the grid keeps the window depth.
    json cube = frame_request("0/cube.obj", "zbuffer", 32);
    cube["buffers"] = json{{"names", {"scene_z", "depth"}}};
    const FrameWithArrays other = s.post_arrays("/api/frame", cube);
    CHECK(other.body["pixel_camera"] == false);
    CHECK(other.body["buffers"]["scene_z"].is_null());
    CHECK(other.body["buffers"]["depth"].is_object());
}

TEST_CASE("view: the outline of a run's steps", "[view]") {
    RunningServer s;
    // Leaves of one triangle, seen from close by: some nodes lie outside the view and are culled.
    json request = frame_request("1/boxes.scene", "octree-zbuffer", 96);
    request["params"] = {{"leaf-triangles", 1}};
    request["camera"]["zoom"] = 3;
    const json outline = s.post_json("/api/steps", request);
    const uint64_t total = outline["total"];
    REQUIRE(total > 0);
    CHECK(outline["truncated"] == false);
    CHECK(outline["width"] == 96);
    CHECK(outline["triangles"] == 36);

    // The runs tile the steps 1..total in order, and two runs side by side differ in kind.
    const json& runs = outline["runs"];
    REQUIRE(runs.size() > 1);
    uint64_t next = 1;
    for (std::size_t k = 0; k < runs.size(); ++k) {
        const json& run = runs[k];
        CHECK(run[0] == next);
        CHECK(run[1] > 0);
        next += run[1].get<uint64_t>();
        if (k > 0) {
            const json& before = runs[k - 1];
            CHECK((run[2] != before[2] || run[3] != before[3] || run[4] != before[4]));
        }
    }
    CHECK(next == total + 1);

    // The frame's total is the outline's; the frames of a few steps say what the runs say.
    std::vector<uint64_t> culled_runs;
    for (std::size_t k = 0; k < runs.size(); ++k)
        if (runs[k][2] == "node-culled") culled_runs.push_back(k);
    REQUIRE(!culled_runs.empty());
    std::vector<std::size_t> asked = {0, culled_runs.front(), culled_runs.back(), culled_runs[culled_runs.size() / 2]};
    int culled_seen = 0, others_seen = 0;
    for (std::size_t k : asked) {
        const uint64_t first = runs[k][0], count = runs[k][1];
        for (uint64_t step : {first, first + count - 1, first + count}) {
            if (step > total) continue;
            std::size_t owner = 0;  // the run that holds the step
            while (owner + 1 < runs.size() && runs[owner + 1][0].get<uint64_t>() <= step) ++owner;
            json step_request = request;
            step_request["step"] = step;
            const json frame = s.post_arrays("/api/frame", step_request).body;  // the z-pyramid comes as arrays
            INFO("step " << step << ": " << frame["steps"]["text"]);
            CHECK(frame["steps"]["total"] == total);
            CHECK(frame["steps"]["type"] == runs[owner][2]);
            CHECK(frame["steps"]["phase"] == runs[owner][3]);
            (frame["steps"]["type"] == "node-culled" ? culled_seen : others_seen) += 1;
        }
    }
    CHECK(culled_seen >= 2);
    CHECK(others_seen >= 1);

    // The first step of each phase and of each type is where its first run starts.
    REQUIRE(outline["firsts"].is_object());
    int phases = 0;
    for (const auto& [name, first] : outline["firsts"].items()) {
        const bool phase = name.rfind("phase:", 0) == 0;
        phases += phase;
        const std::string value = name.substr(name.find(':') + 1);
        const json* first_run = nullptr;
        for (const json& run : runs)
            if (run[phase ? 3 : 2] == value) {
                first_run = &run;
                break;
            }
        INFO(name);
        REQUIRE(first_run != nullptr);
        CHECK(first["step"] == (*first_run)[0]);
        CHECK_FALSE(first["text"].get<std::string>().empty());
    }
    std::set<std::string> named_phases;
    for (const json& run : runs)
        if (!run[3].is_null()) named_phases.insert(run[3].get<std::string>());
    CHECK(phases == int(named_phases.size()));
    CHECK(outline["firsts"].contains("type:node-culled"));

    // Asked in Russian, the texts are the plugin's Russian ones; the runs do not change.
    json russian = request;
    russian["language"] = "ru";
    const json outline_ru = s.post_json("/api/steps", russian);
    CHECK(outline_ru["runs"] == runs);
    CHECK(outline_ru["firsts"]["type:node-culled"]["step"] == outline["firsts"]["type:node-culled"]["step"]);

    // A hidden-line plugin's steps are its trace events.
    json lines = frame_request("0/cube.obj", "handmade-lines", 64);
    lines["edges"] = "all";
    const json line_outline = s.post_json("/api/steps", lines);
    CHECK(line_outline["total"] == 12);
    REQUIRE(line_outline["runs"].size() == 1);
    CHECK(line_outline["runs"][0][0] == 1);
    CHECK(line_outline["runs"][0][1] == 12);
    CHECK(line_outline["runs"][0][2] == "edge-begin");
    CHECK(line_outline["runs"][0][4].is_null());

    // Mistakes are answered as /api/frame answers them.
    json bad = request;
    bad["algorithm"] = "no-such-plugin";
    CHECK(s.post_json("/api/steps", bad, 400)["field"] == "algorithm");
    bad = request;
    bad["model"] = "no-such-model";
    CHECK(s.post_json("/api/steps", bad, 404)["field"] == "model");
    bad = request;
    bad["language"] = "fr";
    CHECK(s.post_json("/api/steps", bad, 400)["field"] == "language");
}

TEST_CASE("view: steps from..to as a ZIP of PNGs", "[view]") {
    RunningServer s;
    json request = frame_request("0/cube.obj", "zbuffer", 96);
    request["from"] = 2;
    request["to"] = 6;
    httplib::Result r = s.post("/api/steps-zip", request);
    REQUIRE(r);
    INFO(r->body.substr(0, 400));
    REQUIRE(r->status == 200);
    CHECK(r->get_header_value("Content-Type") == "application/zip");
    CHECK(r->get_header_value("Content-Disposition") == "attachment; filename=\"zbuffer-steps-2-6.zip\"");

    // Python's zipfile reads the archive independently: its names, and every entry's CRC checked.
    const fs::path zip = cli::write_file("steps.zip", r->body);
    const fs::path unpacked = cli::scratch_dir() / "steps-unpacked";
    fs::remove_all(unpacked);
    const fs::path listing = cli::scratch_dir() / "steps-listing.txt";
    const std::string command = fmt::format(
        "/usr/bin/python3 -c \"import sys, zipfile; z = zipfile.ZipFile(sys.argv[1]); bad = z.testzip(); "
        "print(bad if bad else 'ok'); [print(i.filename, i.compress_type, i.file_size) for i in z.infolist()]; "
        "z.extractall(sys.argv[2])\" '{}' '{}' > '{}'",
        zip.string(), unpacked.string(), listing.string());
    REQUIRE(std::system(command.c_str()) == 0);
    std::istringstream lines(cli::slurp(listing));
    std::string line;
    std::getline(lines, line);
    CHECK(line == "ok");
    std::vector<std::string> names;
    while (std::getline(lines, line)) {
        std::istringstream words(line);
        std::string name;
        int method = -1;
        words >> name >> method;
        CHECK(method == 0);  // stored
        names.push_back(name);
    }
    CHECK(names == std::vector<std::string>{"step-001.png", "step-002.png", "step-003.png", "step-004.png", "step-005.png"});

    // Each entry a PNG of the size asked; the last one is /api/frame's picture at step 6, pixel for
    // pixel, and the first (step 2) is a different one.
    std::vector<hsr::Image> pictures;
    for (const std::string& name : names) {
        pictures.push_back(hsr::read_png_rgb(unpacked / name));
        CHECK(pictures.back().width == 96);
        CHECK(pictures.back().height == 96);
    }
    json at_to = frame_request("0/cube.obj", "zbuffer", 96);
    at_to["step"] = 6;
    const fs::path frame_png = cli::write_file("step-6.png", png_bytes(s.post_json("/api/frame", at_to)));
    const hsr::Image expected = hsr::read_png_rgb(frame_png);
    CHECK(pictures.back().pixels == expected.pixels);
    CHECK(pictures.front().pixels != expected.pixels);

    // Ranges refused with one line: backward, over 200 steps, not numbers; a model that is not there.
    auto refused = [&](json body, int status, const std::string& field, const std::string& words) {
        const json answer = s.post_json("/api/steps-zip", body, status);
        CHECK(answer["field"] == field);
        const std::string message = answer["error"];
        CHECK(message.find('\n') == std::string::npos);
        CHECK_THAT(message, Catch::Contains(words));
    };
    json backward = request;
    backward["from"] = 7;
    refused(backward, 400, "to", "7..6 ends before it starts");
    json many = request;
    many["from"] = 1;
    many["to"] = 201;
    refused(many, 400, "to", "201 steps; one archive holds at most 200");
    many["language"] = "ru";
    refused(many, 400, "to", "не больше 200");
    json zero = request;
    zero["from"] = 0;
    refused(zero, 400, "from", "from 1");
    json text = request;
    text["to"] = "6";
    refused(text, 400, "to", "step numbers");
    json big = frame_request("0/cube.obj", "zbuffer", 2048);
    big["from"] = 1;
    big["to"] = 100;
    refused(big, 400, "to", "pixels, over the limit");
    json missing = request;
    missing["model"] = "0/nothing.obj";
    refused(missing, 404, "model", "no model");
}
