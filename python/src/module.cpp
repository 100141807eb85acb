// hsr._hsr: the compiled core of the Python package hsr (python/hsr/__init__.py wraps it). Every call
// takes the options of `hsr render` as its command line would give them, so that Python and the
// command line mean the same thing and say the same when something is wrong; the renderer, the
// plugins and the outputs are the host's own (host/render/render.hpp). Work that takes time runs with
// the GIL released.
#include "meshes.hpp"
#include "results.hpp"

#include "common/commands.hpp"
#include "common/plugins.hpp"
#include "common/threads.hpp"
#include "render/jobs.hpp"
#include "render/render.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/plugin_registry.hpp"

#include <boost/program_options/errors.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Python.h>

#include <chrono>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;
namespace fs = std::filesystem;

namespace hsr::python {
namespace {

PyObject* error_type = nullptr;         // hsr.Error
PyObject* usage_error_type = nullptr;   // hsr.UsageError(hsr.Error, ValueError)
PyObject* limit_error_type = nullptr;   // hsr.LimitError(hsr.UsageError)
PyObject* plugin_error_type = nullptr;  // hsr.PluginError(hsr.Error)

// The plugin folders scanned so far, by --plugin-path, for the life of the process: plugins stay
// loaded as long as any object made with them may live.
host::PluginRegistries& registries() {
    static auto* kept = new host::PluginRegistries;
    return *kept;
}
std::mutex registries_mutex;

const PluginRegistry& registry_for(const std::vector<std::string>& plugin_dirs) {
    const std::lock_guard lock(registries_mutex);
    auto found = registries().find(plugin_dirs);
    if (found == registries().end()) found = registries().emplace(plugin_dirs, host::scan_plugins(plugin_dirs)).first;
    return found->second;
}

host::RenderOptions parse_options(const std::vector<std::string>& args) {
    host::check_argument_count(args.size());
    return host::parse_render_options(args);
}

// The job of one frame of the options, with its plugins.
host::RenderJob prepare_frame(const std::vector<std::string>& args) {
    host::RenderOptions options = parse_options(args);
    const PluginRegistry& registry = registry_for(options.plugin_dirs);
    host::RenderJob job = host::prepare_render_plugins(std::move(options), registry);
    if (job.frames.size() != 1)
        throw UsageError("these options make {} frames; render one at a time (a loop over the angles)", job.frames.size());
    job.options.yaw = job.frames[0].yaw;
    job.options.pitch = job.frames[0].pitch;
    job.options.yaw_turn = job.frames[0].yaw_turn;
    return job;
}

std::string plugin_name(const Plugin& plugin) { return plugin.descriptor.name; }

py::object param_value(const hsr_param_desc& desc, const char* text) {
    if (text == nullptr) return py::none();
    try {
        const hsr_param_value value = parse_param_value(desc, text);
        switch (desc.type) {
        case HSR_PARAM_BOOL: return py::bool_(value.number != 0);
        case HSR_PARAM_INT: return py::int_(int64_t(value.number));
        case HSR_PARAM_FLOAT: return py::float_(value.number);
        case HSR_PARAM_COLOR: return py::make_tuple(value.color[0], value.color[1], value.color[2]);
        default: return py::str(text);
        }
    } catch (const Error&) {
        return py::str(text);
    }
}

py::list plugins(const std::vector<std::string>& plugin_dirs) {
    const PluginRegistry& registry = registry_for(plugin_dirs);
    py::list out;
    for (hsr_plugin_kind kind : {HSR_KIND_HIDDEN_SURFACE_REMOVER, HSR_KIND_HIDDEN_LINE_REMOVER, HSR_KIND_LIGHTING_MODEL}) {
        for (const Plugin& p : registry.plugins()) {
            const hsr_plugin_descriptor& d = p.descriptor;
            if (d.kind != kind) continue;
            py::list parameters;
            for (uint32_t i = 0; i < d.param_count; ++i) {
                const hsr_param_desc& desc = param_desc(d, i);
                static const char* const type_names[] = {"bool", "int", "float", "enum", "color"};
                py::dict parameter;
                parameter["name"] = desc.name;
                parameter["type"] = desc.type < 5 ? type_names[desc.type] : "unknown";
                parameter["default"] = param_value(desc, desc.default_value);
                if (desc.type == HSR_PARAM_INT || desc.type == HSR_PARAM_FLOAT) {
                    parameter["min"] = desc.min;
                    parameter["max"] = desc.max;
                }
                if (desc.type == HSR_PARAM_ENUM && desc.choices) parameter["choices"] = split_choices(desc.choices);
                parameter["help"] = desc.help ? desc.help : "";
                parameters.append(parameter);
            }
            py::dict plugin;
            plugin["kind"] = kind_name(d.kind);
            plugin["name"] = d.name;
            plugin["version"] = d.version ? d.version : "";
            plugin["abi"] = py::make_tuple(d.abi_major, d.abi_minor);
            plugin["description"] = d.description ? d.description : "";
            plugin["path"] = p.path.string();
            plugin["parameters"] = parameters;
            out.append(plugin);
        }
    }
    return out;
}

std::shared_ptr<Scene> load(const std::vector<std::string>& args) {
    const host::RenderOptions options = parse_options(args);
    if (!options.limits.empty()) throw UsageError("--limit: hsr.set_limits() sets the limits of the process");
    host::check_render_options(options);
    const SceneSource source = host::scene_source(options);
    auto scene = std::make_shared<Scene>();
    py::gil_scoped_release unlocked;
    const host::ThreadBound thread_bound(options.threads);
    scene->renderer = std::make_shared<Renderer>(LoadedScene::load(source));
    return scene;
}

// The words as one key: the same words mean the same job.
std::string words_key(const std::vector<std::string>& args) {
    std::string key;
    for (const std::string& word : args) (key += word) += '\0';
    return key;
}

std::shared_ptr<Frame> render(Scene& scene, const std::vector<std::string>& args) {
    const std::string key = words_key(args);
    std::unique_ptr<host::RenderJob> job = scene.take_job(key);
    if (!job) {
        job = std::make_unique<host::RenderJob>(prepare_frame(args));
        if (!job->picture)
            throw UsageError("'{}' draws lines: hsr.lines() gives its drawing", parse_plugin_spec(job->options.algorithm).name);
    }
    std::optional<Picture> picture;
    {
        py::gil_scoped_release unlocked;
        picture = host::render_picture(job->options, *scene.renderer, *job->picture);
    }
    auto frame = std::make_shared<Frame>(scene.renderer, std::move(*picture), plugin_name(job->picture->remover->plugin()),
                                         plugin_name(job->picture->lighting->plugin()));
    scene.give_back(key, std::move(job));
    return frame;
}

std::shared_ptr<Lines> lines(const Scene& scene, const std::vector<std::string>& args) {
    host::RenderJob job = prepare_frame(args);
    if (!job.line_drawing)
        throw UsageError("'{}' removes hidden surfaces: hsr.render() gives its picture",
                         parse_plugin_spec(job.options.algorithm).name);
    LineRequest request;
    request.view = host::view_request(job.options);
    request.settings = job.line_drawing->settings;
    auto result = std::make_shared<Lines>();
    {
        py::gil_scoped_release unlocked;
        result->picture = scene.renderer->lines(request, *job.line_drawing->remover);
    }
    result->renderer = scene.renderer;
    result->style = job.line_drawing->style;
    result->algorithm = plugin_name(job.line_drawing->remover->plugin());
    return result;
}

// A run of a hidden-surface algorithm step by step: its plugins kept for every step asked of it.
class StepRun {
public:
    StepRun(std::shared_ptr<Scene> scene, const std::vector<std::string>& args)
        : scene_(std::move(scene)), job_(prepare_frame(args)) {
        if (!job_.picture)
            throw UsageError("'{}' draws lines: its steps are not pictures", parse_plugin_spec(job_.options.algorithm).name);
        if (!job_.picture->remover->has_steps())
            throw Error("plugin '{}' cannot show its steps", plugin_name(job_.picture->remover->plugin()));
        if (host::picture_samples(job_.options, &scene_->loaded()) > 1)
            throw UsageError("steps show one visibility pass: they do not go with samples above 1");
    }

    // The picture after step `step` (1-based; past the end: the last), the step, and how many the
    // whole run has.
    py::tuple step(uint64_t step) {
        if (step < 1) throw UsageError("steps count from 1");
        std::optional<Picture> picture;
        {
            py::gil_scoped_release unlocked;
            const std::lock_guard lock(mutex_);
            host::RenderOptions options = job_.options;
            options.step = int64_t(step);
            options.given.insert("step");
            PictureRequest request = host::picture_request(options, scene_->loaded());
            request.step_context = true;
            const host::ThreadBound thread_bound(options.threads);
            picture = scene_->renderer->picture(request, *job_.picture->remover, *job_.picture->lighting);
        }
        const StepRecord record = picture->frame.steps ? picture->frame.steps->last : StepRecord{};
        const uint64_t total = picture->step_total;
        const uint64_t shown = picture->step_shown;
        auto frame = std::make_shared<Frame>(scene_->renderer, std::move(*picture),
                                             plugin_name(job_.picture->remover->plugin()),
                                             plugin_name(job_.picture->lighting->plugin()));
        py::dict record_dict = step_record_dict(record);
        record_dict["index"] = shown;
        py::array_t<float> step_lines({py::ssize_t(record.lines.size() / 4), py::ssize_t(4)});
        std::copy(record.lines.begin(), record.lines.end(), step_lines.mutable_data());
        record_dict["lines"] = step_lines;
        record_dict["roles"] = record.roles;
        py::dict buffers;
        for (const StepBuffer& b : record.buffers) {
            py::array_t<float> values({py::ssize_t(b.height), py::ssize_t(b.width)});
            std::copy(b.values.begin(), b.values.end(), values.mutable_data());
            buffers[py::str(b.name)] = values;
        }
        record_dict["buffers"] = buffers;
        return py::make_tuple(frame, record_dict, total);
    }

private:
    std::shared_ptr<Scene> scene_;
    host::RenderJob job_;
    std::mutex mutex_;  // a plugin instance renders one step at a time
};

std::string scene_key(const std::vector<std::string>& args) { return host::scene_load_key(parse_options(args)); }

// Each command run as `hsr render ARGS` runs it, each scene loaded once for the commands that share
// it; each command's error message, or None. The process's limits are the commands' own while they
// run (--limit), and put back afterwards.
std::vector<std::optional<std::string>> render_commands(const std::vector<std::vector<std::string>>& commands) {
    py::gil_scoped_release unlocked;
    const Limits saved = limits();
    std::vector<std::optional<std::string>> errors(commands.size());
    std::vector<host::RenderJob> jobs;
    std::vector<std::size_t> job_command;
    for (std::size_t i = 0; i < commands.size(); ++i) {
        try {
            host::check_argument_count(commands[i].size());
            std::vector<fs::path> files;
            host::RenderJob job = [&] {
                const std::lock_guard lock(registries_mutex);
                return host::prepare_render_job(commands[i], registries(), files);
            }();
            if (job.options.model == "-" || job.options.output == "-")
                throw UsageError("standard input and output ('-') are for the command line");
            job.origin = fmt::format("command {}", i + 1);
            jobs.push_back(std::move(job));
            job_command.push_back(i);
        } catch (const std::exception& e) {
            errors[i] = host::message_line(e.what());
        }
    }
    try {
        const std::vector<std::optional<std::string>> kept = host::run_jobs_keeping_errors(jobs);
        for (std::size_t j = 0; j < jobs.size(); ++j) errors[job_command[j]] = kept[j];
    } catch (...) {
        set_limits(saved);
        throw;
    }
    set_limits(saved);
    return errors;
}

// The options rendered again and again as hsr bench renders them (a FrameLoop: one camera, the
// plugins made once, the buffers reused), each frame's wall time measured, for
// python/bench/python_overhead.py to set against hsr.render() in the same process.
class FrameLoopTimer {
public:
    FrameLoopTimer(std::shared_ptr<Scene> scene, const std::vector<std::string>& args)
        : scene_(std::move(scene)), job_(prepare_frame(args)) {
        if (!job_.picture) throw UsageError("a hidden-surface plugin expected");
        const Renderer& renderer = *scene_->renderer;
        camera_ = renderer.camera(host::view_request(job_.options));
        const PictureRequest request = host::picture_request(job_.options, renderer.loaded());
        lights_ = renderer.lights(request.lights, camera_);
        FrameSettings settings;
        settings.background = request.background ? *request.background : default_background_color();
        view_ = renderer.loaded().scene().view();
        loop_.emplace(view_, camera_, make_shading_context(camera_, lights_), settings, *job_.picture->remover,
                      *job_.picture->lighting);
    }

    double frame_ms() {
        py::gil_scoped_release unlocked;
        const auto start = std::chrono::steady_clock::now();
        loop_->render();
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }

private:
    std::shared_ptr<Scene> scene_;
    host::RenderJob job_;
    hsr_camera camera_{};
    std::vector<hsr_light> lights_;
    hsr_scene view_{};
    std::optional<FrameLoop> loop_;
};

// What a batch needs to know of one `hsr render` command line before it runs it elsewhere: every
// file it writes (absolute, links resolved, each frame's), its model's name, whether it draws with
// a hidden-surface plugin and whether it sets --threads. The command is checked as hsr render checks
// it (a mistake raises); nothing is written, and the process's limits stay as they were.
py::dict command_plan(const std::vector<std::string>& args) {
    host::check_argument_count(args.size());
    std::vector<fs::path> files;
    std::optional<host::RenderJob> job;
    {
        py::gil_scoped_release unlocked;
        const Limits saved = limits();
        try {
            const std::lock_guard lock(registries_mutex);
            job.emplace(host::prepare_render_job(args, registries(), files));
        } catch (...) {
            set_limits(saved);
            throw;
        }
        set_limits(saved);
    }
    std::vector<std::string> paths;
    for (const fs::path& file : files) paths.push_back(file.string());
    py::dict plan;
    plan["files"] = paths;
    plan["model"] = host::model_path(job->options).stem().string();
    plan["hidden_surface"] = job->picture.has_value();
    plan["threads_given"] = job->options.was_given("threads");
    return plan;
}

py::dict limits_dict() {
    py::dict out;
    for (const LimitInfo& info : limit_table()) out[py::str(info.name)] = limits().*info.value;
    return out;
}

void set_limit_settings(const std::vector<std::string>& settings) {
    try {
        set_limits(limits_from_settings(settings));
    } catch (const Error& e) {
        throw UsageError("{}", e.what());
    }
}

PyObject* new_exception(const char* name, const char* doc, PyObject* bases) {
    PyObject* type = PyErr_NewExceptionWithDoc(name, doc, bases, nullptr);
    if (type == nullptr) throw py::error_already_set();
    return type;
}

void add_exceptions(py::module_& m) {
    error_type = new_exception("hsr.Error", "Anything hsr could not do; the message is the command line's.", PyExc_Exception);
    py::object usage_bases = py::make_tuple(py::handle(error_type), py::handle(PyExc_ValueError));
    usage_error_type = new_exception("hsr.UsageError", "A mistake in what was asked: an option, a value, an array.",
                                     usage_bases.ptr());
    limit_error_type = new_exception("hsr.LimitError", "A request over one of the limits on work (hsr.set_limits).",
                                     usage_error_type);
    plugin_error_type = new_exception("hsr.PluginError", "A plugin failed, or refused its input.", error_type);
    m.add_object("Error", py::handle(error_type));
    m.add_object("UsageError", py::handle(usage_error_type));
    m.add_object("LimitError", py::handle(limit_error_type));
    m.add_object("PluginError", py::handle(plugin_error_type));
    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            std::rethrow_exception(thrown);
        } catch (const LimitError& e) {
            PyErr_SetString(limit_error_type, host::message_line(e.what()).c_str());
        } catch (const UsageError& e) {
            PyErr_SetString(usage_error_type, host::message_line(e.what()).c_str());
        } catch (const boost::program_options::error& e) {
            PyErr_SetString(usage_error_type, host::message_line(e.what()).c_str());
        } catch (const PluginError& e) {
            PyErr_SetString(plugin_error_type, host::message_line(e.what()).c_str());
        } catch (const Error& e) {
            PyErr_SetString(error_type, host::message_line(e.what()).c_str());
        }
    });
}

}  // namespace
}  // namespace hsr::python

PYBIND11_MODULE(_hsr, m) {
    using namespace hsr::python;
    m.doc() = "The compiled core of hsr; use the package hsr.";
    add_exceptions(m);
    bind_results(m);
    py::class_<StepRun, std::shared_ptr<StepRun>>(m, "StepRun")
        .def(py::init<std::shared_ptr<Scene>, const std::vector<std::string>&>())
        .def("step", &StepRun::step);
    m.def("set_builtin_plugin_dirs", [](const std::vector<std::string>& dirs) {
        hsr::host::set_builtin_plugin_dirs(std::vector<fs::path>(dirs.begin(), dirs.end()));
    });
    m.def("plugins", &plugins);
    m.def("load", &load);
    m.def("scene_from_meshes", &scene_from_meshes);
    m.def("render", &render);
    m.def("lines", &lines);
    m.def("limits", &limits_dict);
    m.def("set_limits", &set_limit_settings);
    m.def("split_job_line", [](const std::string& line) { return hsr::host::split_job_line(line); });
    m.def("job_line_arguments", [](const std::vector<std::string>& words, const std::string& folder,
                                   const std::vector<std::string>& defaults) {
        return hsr::host::job_line_arguments(words, folder, defaults);
    });
    m.def("scene_key", &scene_key);
    m.def("command_plan", &command_plan);
    m.def("render_commands", &render_commands);
    py::class_<FrameLoopTimer>(m, "_FrameLoopTimer")
        .def(py::init<std::shared_ptr<Scene>, const std::vector<std::string>&>())
        .def("frame_ms", &FrameLoopTimer::frame_ms);
}
