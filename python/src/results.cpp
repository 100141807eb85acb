// The Python types of what hsr renders (results.hpp): Scene, Frame and Lines, whose numpy arrays view
// hsr's own buffers.
#include "results.hpp"

#include "hsr/error.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/pixel_data.hpp"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>

namespace hsr::python {
namespace {

py::dict counters_dict(const std::vector<std::pair<std::string, uint64_t>>& counters) {
    py::dict out;
    for (const auto& [name, value] : counters) out[py::str(name)] = value;
    return out;
}

py::tuple vec3_tuple(glm::vec3 v) { return py::make_tuple(v.x, v.y, v.z); }

std::string lower_extension(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return extension;
}

// One field of every segment of a drawing, viewed in place.
template <typename T>
py::array segment_field(py::object self, const T LineSegment::*field) {
    const std::vector<LineSegment>& segments = self.cast<Lines&>().picture.drawing.segments;
    return view_of(segments.empty() ? nullptr : &(segments[0].*field), {py::ssize_t(segments.size())}, self,
                   {py::ssize_t(sizeof(LineSegment))});
}

}  // namespace

py::dict step_record_dict(const StepRecord& step) {
    py::dict out;
    out["index"] = step.index;
    out["type"] = step.type;
    out["text"] = step.text;
    out["face"] = step.face == HSR_NO_FACE ? py::object(py::none()) : py::object(py::int_(step.face));
    out["instance"] = step.instance;
    out["level"] = step.level == HSR_NO_LEVEL ? py::object(py::none()) : py::object(py::int_(step.level));
    out["pixels_written"] = step.pixels_written;
    out["pixels_rejected"] = step.pixels_rejected;
    return out;
}

std::unique_ptr<host::RenderJob> Scene::take_job(const std::string& words) {
    const std::lock_guard lock(jobs_mutex_);
    const auto found = idle_jobs_.find(words);
    if (found == idle_jobs_.end() || found->second.empty()) return nullptr;
    std::unique_ptr<host::RenderJob> job = std::move(found->second.back());
    found->second.pop_back();
    return job;
}

void Scene::give_back(const std::string& words, std::unique_ptr<host::RenderJob> job) {
    const std::lock_guard lock(jobs_mutex_);
    if (idle_jobs_.size() >= kMaxKeptOptions && !idle_jobs_.count(words)) idle_jobs_.clear();
    std::vector<std::unique_ptr<host::RenderJob>>& idle = idle_jobs_[words];
    if (idle.size() < kMaxKeptPerOptions) idle.push_back(std::move(job));
}

Frame::Frame(std::shared_ptr<Renderer> renderer, Picture picture, std::string algorithm, std::string lighting)
    : renderer_(std::move(renderer)), picture_(std::move(picture)), algorithm_(std::move(algorithm)),
      lighting_(std::move(lighting)) {}

const std::vector<uint8_t>& Frame::pixels() {
    const hsr::Frame& frame = picture_.frame;
    if (frame.alpha.empty()) return frame.rgb;
    if (rgba_.empty()) {
        rgba_.resize(4 * frame.alpha.size());
        for (std::size_t i = 0; i < frame.alpha.size(); ++i) {
            std::memcpy(&rgba_[4 * i], &frame.rgb[3 * i], 3);
            rgba_[4 * i + 3] = frame.alpha[i];
        }
    }
    return rgba_;
}

const std::vector<float>& Frame::depth() {
    if (!depth_) depth_ = camera_depth(picture_.frame, picture_.camera);
    return *depth_;
}

const std::vector<int32_t>& Frame::ids() {
    if (!ids_) ids_ = pixel_ids(picture_.frame, picture_.scene);
    return *ids_;
}

const std::vector<float>& Frame::normals() {
    if (!normals_) normals_ = camera_normals(picture_.frame, picture_.scene, picture_.camera);
    return *normals_;
}

py::dict Frame::stats() const {
    const hsr::Frame& frame = picture_.frame;
    py::dict out;
    out["algorithm"] = algorithm_;
    out["lighting"] = lighting_;
    out["width"] = frame.width;
    out["height"] = frame.height;
    out["samples"] = picture_.samples;
    out["triangles"] = drawn_triangle_count(picture_.scene);
    out["instances"] = picture_.scene.instance_count;
    out["visibility_ms"] = frame.visibility_ms;
    out["shading_ms"] = frame.shading_ms;
    out["counters"] = counters_dict(frame.counters);
    if (frame.steps) {
        out["steps_taken"] = frame.steps->taken;
        out["stopped_early"] = frame.steps->stopped;
    }
    return out;
}

py::dict Lines::stats() const {
    const LineDrawing& drawing = picture.drawing;
    py::dict out;
    out["algorithm"] = algorithm;
    out["width"] = drawing.width;
    out["height"] = drawing.height;
    out["edges"] = drawing.edges.size();
    out["segments"] = drawing.segments.size();
    out["lines_ms"] = drawing.lines_ms;
    out["counters"] = counters_dict(drawing.counters);
    return out;
}

static_assert(offsetof(LineSegment, b) == 2 * sizeof(float), "a segment's four coordinates are viewed as one row");

void bind_results(py::module_& m) {
    py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A loaded scene (see hsr.Scene).")
        .def_property_readonly("source", [](const Scene& s) { return s.loaded().source_name(); })
        .def_property_readonly("triangle_count",
                               [](const Scene& s) { return drawn_triangle_count(s.loaded().scene().view()); })
        .def_property_readonly("stored_triangle_count", [](const Scene& s) { return s.loaded().scene().triangle_count(); })
        .def_property_readonly("vertex_count", [](const Scene& s) { return s.loaded().scene().vertex_count(); })
        .def_property_readonly("instance_count", [](const Scene& s) { return s.loaded().scene().instances.size(); })
        .def_property_readonly("object_names", [](const Scene& s) { return s.loaded().scene().object_names; })
        .def_property_readonly("bounds",
                               [](const Scene& s) {
                                   const SceneData& d = s.loaded().scene();
                                   return py::make_tuple(vec3_tuple(d.bounds_min), vec3_tuple(d.bounds_max));
                               })
        .def_property_readonly("warnings", [](const Scene& s) { return s.loaded().scene().warnings; })
        .def_property_readonly("cameras", [](const Scene& s) {
            std::vector<std::string> names;
            for (const ModelCamera& camera : s.loaded().cameras()) names.push_back(camera.name);
            return names;
        });

    py::class_<Frame, std::shared_ptr<Frame>>(m, "Frame", "A shaded picture (see hsr.Frame).")
        .def_property_readonly("width", &Frame::width)
        .def_property_readonly("height", &Frame::height)
        .def_property_readonly("color",
                               [](py::object self) {
                                   Frame& f = self.cast<Frame&>();
                                   return view_of(f.pixels().data(), {f.height(), f.width(), f.channels()}, self);
                               })
        .def_property_readonly("depth",
                               [](py::object self) {
                                   Frame& f = self.cast<Frame&>();
                                   return view_of(f.depth().data(), {f.height(), f.width()}, self);
                               })
        .def_property_readonly("face_id",
                               [](py::object self) {
                                   Frame& f = self.cast<Frame&>();
                                   return view_of(f.ids().data(), {f.height(), f.width(), 3}, self);
                               })
        .def_property_readonly("normal",
                               [](py::object self) {
                                   Frame& f = self.cast<Frame&>();
                                   return view_of(f.normals().data(), {f.height(), f.width(), 3}, self);
                               })
        .def_property_readonly("stats", &Frame::stats)
        .def("save",
             [](Frame& f, const std::filesystem::path& path) {
                 if (lower_extension(path) != ".png")
                     throw UsageError("Frame.save '{}': a picture is saved as .png (numpy.save writes the arrays)",
                                      printable(path.string(), kMaxQuotedPathChars));
                 const std::vector<uint8_t>& pixels = f.pixels();
                 py::gil_scoped_release unlocked;
                 write_png(path, f.width(), f.height(), f.channels(), pixels);
             })
        .def("_repr_png_", [](Frame& f) {
            const std::vector<uint8_t> png = encode_png(f.width(), f.height(), f.channels(), f.pixels());
            return py::bytes(reinterpret_cast<const char*>(png.data()), png.size());
        });

    py::class_<Lines, std::shared_ptr<Lines>>(m, "Lines", "A line drawing (see hsr.Lines).")
        .def_property_readonly("width", [](const Lines& l) { return l.picture.drawing.width; })
        .def_property_readonly("height", [](const Lines& l) { return l.picture.drawing.height; })
        .def_property_readonly("segments",
                               [](py::object self) {
                                   const auto& segments = self.cast<Lines&>().picture.drawing.segments;
                                   return view_of(segments.empty() ? nullptr : &segments[0].a.x,
                                                  {py::ssize_t(segments.size()), 4}, self,
                                                  {py::ssize_t(sizeof(LineSegment)), py::ssize_t(sizeof(float))});
                               })
        .def_property_readonly("qi", [](py::object self) { return segment_field(self, &LineSegment::qi); })
        .def_property_readonly("edge", [](py::object self) { return segment_field(self, &LineSegment::edge); })
        .def_property_readonly("flags", [](py::object self) { return segment_field(self, &LineSegment::flags); })
        .def_property_readonly("stats", &Lines::stats)
        .def("svg",
             [](const Lines& l) {
                 std::string svg;
                 {
                     py::gil_scoped_release unlocked;
                     svg = line_drawing_svg(l.picture.drawing, l.style);
                 }
                 return svg;
             })
        .def("save",
             [](const Lines& l, const std::filesystem::path& path) {
                 if (!is_line_drawing_path(path))
                     throw UsageError("Lines.save '{}': a line drawing is saved as .svg or .png",
                                      printable(path.string(), kMaxQuotedPathChars));
                 py::gil_scoped_release unlocked;
                 write_line_drawing(path, l.picture.drawing, l.style);
             })
        .def("_repr_svg_", [](const Lines& l) { return line_drawing_svg(l.picture.drawing, l.style); });
}

}  // namespace hsr::python
