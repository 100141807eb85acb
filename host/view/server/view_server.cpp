// hsr view's routes (view_server.hpp). Every handler answers JSON, an error included, and the server
// goes on serving after any error; the page's files come from the binary (view_assets.hpp), never
// from the file system.
#include "view/server/view_server.hpp"

#include "common/child_process.hpp"
#include "common/options.hpp"
#include "view/server/view_access.hpp"
#include "view/server/view_assets.hpp"
#include "view/server/view_models.hpp"
#include "view/server/view_request.hpp"
#include "view/server/view_theory.hpp"
#include "view/server/view_workers.hpp"

#include "hsr/abi.h"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cctype>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
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

}  // namespace

struct hsr::host::ViewServer::State {
    ViewConfig config;
    ModelCatalog models;
    WorkerPool workers;
    // The frame or comparison each page (its X-HSR-Page header) waits for, to cancel when the page
    // sends a newer one or asks to stop.
    struct PageJob {
        std::atomic<bool> cancel{false};
        std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
        std::mutex mutex;
        json progress = nullptr;  // the worker's last progress message, if any
    };
    std::mutex pages_mutex;
    std::map<std::string, std::shared_ptr<PageJob>> page_requests;
    std::optional<std::string> initial_model;
    uint64_t upload_bytes = hsr::limits().upload_bytes;  // the limit in force when the server started
    ViewHttpServer server;

    explicit State(ViewConfig c)
        : config(std::move(c)),
          models(config.model_folders, config.upload_parent.empty() ? fs::temp_directory_path() : config.upload_parent),
          workers(worker_settings(config, models)),
          server(config.token, config.http) {
        workers.plugins();
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

    static WorkerSettings worker_settings(const ViewConfig& config, const ModelCatalog& models) {
        WorkerSettings settings;
        settings.executable = config.worker_executable.empty() ? running_executable() : config.worker_executable;
        settings.plugin_dirs = config.plugin_dirs;
        settings.read_folders = models.read_folders();
        settings.limits = config.limits;
        settings.threads = config.threads;
        settings.max_workers = config.workers;
        settings.time_limit = config.time_limit;
        settings.memory_bytes = config.worker_memory_bytes;
        return settings;
    }

    // The entries of the models a frame or compare request names, for the worker, which opens
    // nothing else; an id that names no model is left for the worker to answer 404 about.
    json job_models(const std::vector<const json*>& requests) const {
        json out = json::object();
        for (const json* request : requests) {
            const std::string id = string_field(request, "model");
            if (id.empty()) continue;
            try {
                const ModelEntry entry = models.find(id);
                out[id] = {{"name", entry.name}, {"path", entry.path.string()}, {"bytes", entry.bytes}, {"scene", entry.scene}};
            } catch (const ViewError&) {
            }
        }
        return out;
    }

    // A string field of a request, or "" when there is none.
    static std::string string_field(const json* request, const char* field) {
        if (request == nullptr || !request->is_object()) return "";
        const auto it = request->find(field);
        return it != request->end() && it->is_string() ? it->get<std::string>() : "";
    }

    // "rendering 'model' with 'algorithm'", for the messages of a job that went wrong.
    static std::string doing(const json* request) {
        return fmt::format("rendering '{}' with '{}'", hsr::printable(string_field(request, "model")),
                           hsr::printable(string_field(request, "algorithm")));
    }

    // The page a request comes from: X-HSR-Page, a token the page makes (at most 64 letters, digits
    // and '-'), or "" for a client that sends none.
    static std::string page_of(const httplib::Request& req) {
        std::string page = req.get_header_value("X-HSR-Page");
        const bool plain = page.size() <= 64 && std::all_of(page.begin(), page.end(), [](char c) {
                               return std::isalnum(static_cast<unsigned char>(c)) || c == '-';
                           });
        return plain ? page : "";
    }

    // The request in flight for a page while it lives: a newer one from the same page cancels it.
    class PageRequest {
    public:
        PageRequest(State& state, std::string page) : state_(state), page_(std::move(page)) {
            if (page_.empty()) return;
            std::lock_guard lock(state_.pages_mutex);
            std::shared_ptr<PageJob>& slot = state_.page_requests[page_];
            if (slot) slot->cancel = true;
            slot = job_;
        }
        ~PageRequest() {
            if (page_.empty()) return;
            std::lock_guard lock(state_.pages_mutex);
            const auto it = state_.page_requests.find(page_);
            if (it != state_.page_requests.end() && it->second == job_) state_.page_requests.erase(it);
        }
        PageRequest(const PageRequest&) = delete;
        PageRequest& operator=(const PageRequest&) = delete;
        const std::atomic<bool>* cancel() const { return &job_->cancel; }
        std::function<void(const json&)> on_progress() const {
            return [job = job_](const json& progress) {
                std::lock_guard lock(job->mutex);
                job->progress = progress;
            };
        }

    private:
        State& state_;
        std::string page_;
        std::shared_ptr<PageJob> job_ = std::make_shared<PageJob>();
    };

    // What set_content does, without copying a body that may be hundreds of MB.
    static void send(httplib::Response& res, Answer answer) {
        res.status = answer.status;
        res.body = std::move(answer.body);
        res.set_header("Content-Type", answer.content_type);
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
        // The docs built in (theory pages, implementation notes, figures), which the theory pages link to.
        server.Get(R"(/docs/(.+))", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                hsr::host::DocFile doc = hsr::host::doc_file(req.matches[1].str());
                res.set_content(std::move(doc.body), doc.content_type);
            });
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
            guarded(res, [&] { send_json(res, 200, workers.plugins()); });
        });
        server.Get(R"(/api/theory/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                const std::string name = req.matches[1].str();
                const std::string language = req.get_param_value("lang") == "ru" ? "ru" : "en";
                send(res, workers.call({{"op", "theory"}, {"name", name}, {"language", language}}, "",
                                       fmt::format("making the page of '{}'", hsr::printable(name))));
            });
        });
        // The text of a served .scene model, for the page's scene editor; ?lang=ru: its messages in Russian.
        server.Get("/api/scene-text", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                const hsr::Language language = hsr::language_from_code(req.get_param_value("lang"));
                res.set_content(models.scene_text(req.get_param_value("model"), upload_bytes, language), "text/plain; charset=utf-8");
            });
        });
        // ?lang=ru: the messages in Russian (the scene editor's uploads, on a page in Russian).
        server.Post("/api/upload", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                const hsr::Language language = hsr::language_from_code(req.get_param_value("lang"));
                if (req.body.size() > upload_bytes) throw ViewError(413, "", upload_too_large(req.body.size(), language));
                if (req.body.empty())
                    throw ViewError(400, "", hsr::say(language, "upload: the body is empty (send the model file's bytes)",
                                                      "загрузка: тело запроса пусто (пришлите содержимое файла модели)"));
                const std::string id = models.add_upload(req.get_header_value("X-File-Name"), req.body,
                                                         req.get_header_value("X-Replaces"),
                                                         req.get_header_value("X-Base-Model"), language);
                send_json(res, 200, {{"id", id}});
            });
        });
        server.Post("/api/frame", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                json request = parse_body(req);
                json models = job_models({&request});
                const std::string affinity = string_field(&request, "model");
                const std::string what = doing(&request);
                const PageRequest page(*this, page_of(req));
                send(res, workers.call({{"op", "frame"}, {"request", std::move(request)}, {"models", std::move(models)}},
                                       affinity, what, page.cancel(), page.on_progress()));
            });
        });
        // The outline of a frame request's steps; a newer one from the same page cancels it, but
        // it leaves the page's frame in flight alone.
        server.Post("/api/steps", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                json request = parse_body(req);
                json models = job_models({&request});
                const std::string affinity = string_field(&request, "model");
                const std::string what = "outlining the steps of " + doing(&request).substr(std::string("rendering ").size());
                const std::string page_id = page_of(req);
                const PageRequest page(*this, page_id.empty() ? "" : page_id + "-steps");
                send(res, workers.call({{"op", "steps"}, {"request", std::move(request)}, {"models", std::move(models)}},
                                       affinity, what, page.cancel()));
            });
        });
        // Steps from..to of a frame request as a ZIP of PNGs, named after the algorithm and the range
        // for the browser to save; a newer one from the same page cancels it.
        server.Post("/api/steps-zip", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                json request = parse_body(req);
                json models = job_models({&request});
                const std::string affinity = string_field(&request, "model");
                const std::string what = "exporting the steps of " + doing(&request).substr(std::string("rendering ").size());
                std::string name = string_field(&request, "algorithm");
                for (char& c : name)
                    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
                const auto number = [&](const char* field) {
                    const auto it = request.is_object() ? request.find(field) : request.end();
                    return it != request.end() && it->is_number_integer() ? it->dump() : std::string("0");
                };
                const std::string file = fmt::format("{}-steps-{}-{}.zip", name.substr(0, 64), number("from"), number("to"));
                const std::string page_id = page_of(req);
                const PageRequest page(*this, page_id.empty() ? "" : page_id + "-zip");
                Answer answer = workers.call({{"op", "steps-zip"}, {"request", std::move(request)}, {"models", std::move(models)}},
                                             affinity, what, page.cancel());
                const bool ok = answer.status == 200;
                send(res, std::move(answer));
                if (ok) res.set_header("Content-Disposition", fmt::format("attachment; filename=\"{}\"", file));
            });
        });
        server.Post("/api/compare", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                json request = parse_body(req);
                const json* a = request.is_object() && request.contains("a") ? &request["a"] : nullptr;
                const json* b = request.is_object() && request.contains("b") ? &request["b"] : nullptr;
                json models = job_models({a, b});
                const std::string what = fmt::format("comparing: {} and {}", doing(a), doing(b));
                const std::string affinity = string_field(a, "model");
                const PageRequest page(*this, page_of(req));
                send(res, workers.call({{"op", "compare"}, {"request", std::move(request)}, {"models", std::move(models)}},
                                       affinity, what, page.cancel()));
            });
        });
        // The page's Stop: its frame or comparison in flight, if any, ends with 409.
        server.Post("/api/cancel", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                const std::string page = page_of(req);
                if (page.empty()) throw ViewError(400, "", "cancel: the X-HSR-Page header names no page");
                bool cancelled = false;
                {
                    std::lock_guard lock(pages_mutex);
                    const auto it = page_requests.find(page);
                    if (it != page_requests.end()) cancelled = !it->second->cancel.exchange(true);
                }
                send_json(res, 200, {{"cancelled", cancelled}});
            });
        });
        // How far the page's frame in flight has got: {"running": false}, or its time so far and,
        // for a step request, the worker's last progress ({"steps": k, "total": n}).
        server.Get("/api/progress", [this](const httplib::Request& req, httplib::Response& res) {
            guarded(res, [&] {
                const std::string page = page_of(req);
                if (page.empty()) throw ViewError(400, "", "progress: the X-HSR-Page header names no page");
                std::shared_ptr<PageJob> job;
                {
                    std::lock_guard lock(pages_mutex);
                    const auto it = page_requests.find(page);
                    if (it != page_requests.end()) job = it->second;
                }
                if (!job) {
                    send_json(res, 200, {{"running", false}});
                    return;
                }
                const double ms =
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - job->start).count();
                std::lock_guard lock(job->mutex);
                send_json(res, 200, {{"running", true}, {"ms", std::round(ms)}, {"progress", job->progress}});
            });
        });
        // What no handler answered (404, 405) and bodies over the limit (413), as JSON too.
        server.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
            if (!res.body.empty()) return;
            if (res.status == 413) {
                uint64_t length = 0;
                const std::string header = req.get_header_value("Content-Length");
                std::from_chars(header.data(), header.data() + header.size(), length);
                send_error(res, 413, upload_too_large(length, hsr::language_from_code(req.get_param_value("lang"))));
            } else if (res.status == 404) {
                send_error(res, 404, fmt::format("no such page '{}'", hsr::printable(req.path)));
            } else {
                const int status = res.status;
                send_error(res, status, fmt::format("HTTP {} for {} {}", status, req.method, hsr::printable(req.path)));
            }
        });
    }

    // check_limit's message, for the limit the server started with.
    std::string upload_too_large(uint64_t bytes, hsr::Language language) const {
        if (bytes > upload_bytes)
            return hsr::say(language, "upload: {} bytes, over the limit of {} (raise it with --limit upload-bytes=N)",
                            "загрузка: {} байт — больше предела {} (его поднимает флаг --limit upload-bytes=N)", bytes,
                            upload_bytes);
        return hsr::say(language, "upload: the body is over the limit of {} bytes (raise it with --limit upload-bytes=N)",
                        "загрузка: тело запроса больше предела в {} байт (его поднимает флаг --limit upload-bytes=N)",
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

void hsr::host::ViewServer::stop() {
    state_->workers.shutdown();
    state_->server.stop();
}

std::size_t hsr::host::ViewServer::model_count() const { return state_->models.list().size(); }

const std::string& hsr::host::ViewServer::token() const { return state_->server.token(); }
