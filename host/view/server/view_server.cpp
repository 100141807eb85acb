// hsr view's routes (view_server.hpp). Every handler answers JSON, an error included, and the server
// goes on serving after any error; the page's files come from the binary (view_assets.hpp), never
// from the file system.
#include "view/server/view_server.hpp"

#include "common/options.hpp"
#include "common/plugins.hpp"
#include "view/server/view_access.hpp"
#include "view/server/view_assets.hpp"
#include "view/server/view_frames.hpp"
#include "view/server/view_models.hpp"
#include "view/server/view_request.hpp"
#include "view/server/view_theory.hpp"

#include "hsr/abi.h"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <functional>
#include <new>

namespace fs = std::filesystem;
using nlohmann::json;

const hsr::host::EmbeddedFile* hsr::host::find_embedded_file(std::string_view name) {
    for (std::size_t i = 0; i < embedded_file_count; ++i)
        if (name == embedded_files[i].name) return &embedded_files[i];
    return nullptr;
}

namespace {

using hsr::host::ViewError;

const char* content_type(const std::string& name) {
    const std::string ext = fs::path(name).extension().string();
    if (ext == ".html") return "text/html; charset=utf-8";
    if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
    if (ext == ".css") return "text/css; charset=utf-8";
    if (ext == ".svg") return "image/svg+xml";
    if (ext == ".json") return "application/json";
    if (ext == ".png") return "image/png";
    if (ext == ".ico") return "image/x-icon";
    if (ext == ".md" || ext == ".txt") return "text/plain; charset=utf-8";
    return "application/octet-stream";
}

// The message on one line, whatever a plugin or library put into it.
std::string one_line(std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    std::replace(text.begin(), text.end(), '\r', ' ');
    return text;
}

// Debian's cpp-httplib compresses an "application/json" answer with Brotli at its slowest quality
// for any client that accepts it, as browsers do: 2.4 s for the 7 MB of a 512x512 frame with its
// buffers, against 0.3 s uncompressed on loopback. It leaves a type with parameters alone.
void send_json(httplib::Response& res, int status, const json& body) {
    res.status = status;
    res.set_content(body.dump(-1, ' ', false, json::error_handler_t::replace), "application/json; charset=utf-8");
}

void send_error(httplib::Response& res, int status, const std::string& message, const std::string& field = "") {
    json body{{"error", one_line(message)}};
    if (!field.empty()) body["field"] = field;
    send_json(res, status, body);
}

json parse_body(const httplib::Request& req) { return hsr::host::parse_json_body(req.body); }

json describe_plugin(const hsr::Plugin& plugin, bool steps) {
    const hsr_plugin_descriptor& d = plugin.descriptor;
    json params = json::array();
    for (uint32_t i = 0; i < d.param_count; ++i) {
        const hsr_param_desc& p = hsr::param_desc(d, i);
        json param{{"name", p.name ? p.name : ""}, {"default", p.default_value ? p.default_value : ""},
                   {"help", p.help ? p.help : ""}};
        switch (p.type) {
        case HSR_PARAM_BOOL: param["type"] = "bool"; break;
        case HSR_PARAM_INT: param["type"] = "int"; break;
        case HSR_PARAM_FLOAT: param["type"] = "float"; break;
        case HSR_PARAM_ENUM: param["type"] = "enum"; break;
        case HSR_PARAM_COLOR: param["type"] = "color"; break;
        default: param["type"] = "string"; break;
        }
        if (p.type == HSR_PARAM_INT || p.type == HSR_PARAM_FLOAT) {
            param["min"] = p.min;
            param["max"] = p.max;
        }
        if (p.type == HSR_PARAM_ENUM) param["choices"] = hsr::split_choices(p.choices);
        params.push_back(std::move(param));
    }
    return {{"name", d.name},
            {"version", d.version ? d.version : ""},
            {"description", d.description ? d.description : ""},
            {"abi", fmt::format("{}.{}", d.abi_major, d.abi_minor)},
            {"steps", steps},
            {"params", std::move(params)}};
}

}  // namespace

struct hsr::host::ViewServer::State {
    ViewConfig config;
    hsr::PluginRegistry registry;
    ModelCatalog models;
    FrameRenderer frames;
    json plugins;  // GET /api/plugins, made once
    std::optional<std::string> initial_model;
    uint64_t upload_bytes = hsr::limits().upload_bytes;  // the limit in force when the server started
    ViewHttpServer server;

    explicit State(ViewConfig c)
        : config(std::move(c)),
          registry(scan_plugins(config.plugin_dirs)),
          models(config.model_folders, config.upload_parent.empty() ? fs::temp_directory_path() : config.upload_parent),
          frames(registry, models),
          server(config.token, config.http) {
        plugins = describe_plugins();
        if (!config.initial_model.empty()) {
            std::error_code ec;
            const fs::path wanted = fs::canonical(config.initial_model, ec);
            for (const ModelEntry& entry : models.list())
                if (!ec && entry.path == wanted) initial_model = entry.id;
        }
        std::vector<fs::path> served = models.folders();
        served.push_back(models.upload_folder());
        server.hide_folder_paths(std::move(served));
        routes();
    }

    json describe_plugins() {
        json out{{"hidden_surface", json::array()}, {"hidden_line", json::array()}, {"lighting", json::array()}};
        for (const hsr::Plugin& p : registry.plugins()) {
            switch (p.descriptor.kind) {
            case HSR_KIND_HIDDEN_SURFACE_REMOVER: {
                // has_steps() is a property of an instance's table; a default instance tells.
                bool steps = false;
                try {
                    steps = hsr::HiddenSurfaceRemover(p, {}).has_steps();
                } catch (const hsr::Error&) {
                }
                out["hidden_surface"].push_back(describe_plugin(p, steps));
                break;
            }
            case HSR_KIND_HIDDEN_LINE_REMOVER: out["hidden_line"].push_back(describe_plugin(p, true)); break;
            case HSR_KIND_LIGHTING_MODEL: out["lighting"].push_back(describe_plugin(p, false)); break;
            default: break;
            }
        }
        return out;
    }

    // Runs a handler, turning whatever it throws into a JSON error.
    static void guarded(httplib::Response& res, const std::function<void()>& handler) {
        try {
            handler();
        } catch (const ViewError& e) {
            send_error(res, e.status, e.what(), e.field);
        } catch (const json::exception&) {
            send_error(res, 400, "a field of the request has the wrong type");
        } catch (const std::bad_alloc&) {
            send_error(res, 500, "out of memory");
        } catch (const std::exception& e) {
            send_error(res, 500, e.what());
        }
    }

    void serve_file(const std::string& name, httplib::Response& res) {
        const EmbeddedFile* file = find_embedded_file("web/" + name);
        if (file == nullptr) throw ViewError(404, "", fmt::format("no file '{}'", hsr::printable(name)));
        res.set_content(reinterpret_cast<const char*>(file->bytes), file->size, content_type(name));
    }

    void routes() {
        server.set_payload_max_length(upload_bytes);
        server.Get("/", [this](const httplib::Request&, httplib::Response& res) {
            guarded(res, [&] { serve_file("index.html", res); });
        });
        server.Get(R"(/static/(.+))", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] { serve_file(req.matches[1].str(), res); });
        });
        server.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
            guarded(res, [&] { send_json(res, 200, info()); });
        });
        server.Get("/api/models", [this](const httplib::Request&, httplib::Response& res) {
            guarded(res, [&] {
                json folders = json::array(), list = json::array();
                for (const fs::path& folder : models.folders()) folders.push_back(folder.filename().string());
                for (const ModelEntry& m : models.list())
                    list.push_back({{"id", m.id}, {"name", m.name}, {"bytes", m.bytes}, {"kind", m.scene ? "scene" : "model"}});
                send_json(res, 200, {{"folders", folders}, {"models", list}});
            });
        });
        server.Get("/api/plugins", [this](const httplib::Request&, httplib::Response& res) {
            guarded(res, [&] { send_json(res, 200, plugins); });
        });
        server.Get(R"(/api/theory/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] { send_json(res, 200, theory_page(registry, req.matches[1].str())); });
        });
        server.Post("/api/upload", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                if (req.body.size() > upload_bytes) throw ViewError(413, "", upload_too_large(req.body.size()));
                if (req.body.empty()) throw ViewError(400, "", "upload: the body is empty (send the model file's bytes)");
                const std::string id = models.add_upload(req.get_header_value("X-File-Name"), req.body);
                send_json(res, 200, {{"id", id}});
            });
        });
        server.Post("/api/frame", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] { send_json(res, 200, frames.frame(parse_body(req))); });
        });
        server.Post("/api/compare", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] { send_json(res, 200, frames.compare(parse_body(req))); });
        });
        // What no handler answered (404, 405) and bodies over the limit (413), as JSON too.
        server.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
            if (!res.body.empty()) return;
            if (res.status == 413) {
                uint64_t length = 0;
                const std::string header = req.get_header_value("Content-Length");
                std::from_chars(header.data(), header.data() + header.size(), length);
                send_error(res, 413, upload_too_large(length));
            } else if (res.status == 404) {
                send_error(res, 404, fmt::format("no such page '{}'", hsr::printable(req.path)));
            } else {
                const int status = res.status;
                send_error(res, status, fmt::format("HTTP {} for {} {}", status, req.method, hsr::printable(req.path)));
            }
        });
    }

    // check_limit's message, for the limit the server started with.
    std::string upload_too_large(uint64_t bytes) const {
        if (bytes > upload_bytes)
            return fmt::format("upload: {} bytes, over the limit of {} (raise it with --limit upload-bytes=N)", bytes,
                               upload_bytes);
        return fmt::format("upload: the body is over the limit of {} bytes (raise it with --limit upload-bytes=N)",
                           upload_bytes);
    }

    json info() const {
        return {{"version", HSR_VERSION},
                {"abi", fmt::format("{}.{}", HSR_ABI_MAJOR, HSR_ABI_MINOR)},
                {"limits", {{"upload_bytes", upload_bytes},
                            {"max_image_side", view_max_image_side},
                            {"image_pixels", hsr::limits().image_pixels}}},
                {"initial_model", initial_model ? json(*initial_model) : json(nullptr)}};
    }
};

hsr::host::ViewServer::ViewServer(ViewConfig config) : state_(std::make_unique<State>(std::move(config))) {}

hsr::host::ViewServer::~ViewServer() { stop(); }

int hsr::host::ViewServer::bind(const std::string& host, int port) { return state_->server.listen_on(host, port); }

bool hsr::host::ViewServer::run() { return state_->server.listen_after_bind(); }

void hsr::host::ViewServer::stop() { state_->server.stop(); }

std::size_t hsr::host::ViewServer::model_count() const { return state_->models.list().size(); }

const std::string& hsr::host::ViewServer::token() const { return state_->server.token(); }
