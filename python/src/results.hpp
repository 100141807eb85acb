// What the Python module hands back: a scene with its renderer, a shaded frame, a line drawing and a
// step, each owning hsr's own buffers, which the numpy arrays it gives out view without copying.
#pragma once

#include "render/render.hpp"

#include "hsr/image.hpp"
#include "hsr/line_image.hpp"
#include "hsr/renderer.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace hsr::python {

namespace py = pybind11;

// A loaded scene and the renderer that renders it, shared by every frame made from it; and the
// plugins of its last renders, made once for the same options and used again as hsr bench uses
// them (their buffers kept), one render at a time each. They live as long as the scene, so that a
// plugin's structures built for this scene never meet another.
struct Scene {
    std::shared_ptr<Renderer> renderer;

    const LoadedScene& loaded() const { return renderer->loaded(); }

    // A job prepared for these words before and now idle, or none.
    std::unique_ptr<host::RenderJob> take_job(const std::string& words);
    // The job back, for the next render with the same words.
    void give_back(const std::string& words, std::unique_ptr<host::RenderJob> job);

private:
    static constexpr std::size_t kMaxKeptOptions = 16, kMaxKeptPerOptions = 4;
    std::mutex jobs_mutex_;
    std::map<std::string, std::vector<std::unique_ptr<host::RenderJob>>> idle_jobs_;
};

// One shaded picture. Its arrays are views of the picture's buffers, and keep the frame alive; the
// per-pixel data (depth, ids, normals) is worked out on first use and kept.
class Frame {
public:
    Frame(std::shared_ptr<Renderer> renderer, Picture picture, std::string algorithm, std::string lighting);

    uint32_t width() const { return picture_.frame.width; }
    uint32_t height() const { return picture_.frame.height; }
    const Picture& picture() const { return picture_; }
    // RGB, or RGBA with a transparent background.
    int channels() const { return picture_.frame.alpha.empty() ? 3 : 4; }
    const std::vector<uint8_t>& pixels();
    const std::vector<float>& depth();
    const std::vector<int32_t>& ids();
    const std::vector<float>& normals();
    py::dict stats() const;

private:
    std::shared_ptr<Renderer> renderer_;  // keeps the scene picture_.scene points into
    Picture picture_;
    std::string algorithm_, lighting_;
    std::vector<uint8_t> rgba_;
    std::optional<std::vector<float>> depth_, normals_;
    std::optional<std::vector<int32_t>> ids_;
};

// One line drawing, with the style its SVG and PNG are drawn in.
struct Lines {
    std::shared_ptr<Renderer> renderer;  // keeps the flat scene the drawing refers to
    LinePicture picture;
    LineStyle style;
    std::string algorithm;

    py::dict stats() const;
};

// An array viewing `data` (shape and strides in elements of T's size unless byte_strides), which
// keeps `owner` alive; read-only, so that what hsr computed cannot be changed behind its back.
template <typename T>
py::array view_of(const T* data, std::vector<py::ssize_t> shape, py::handle owner,
                  std::vector<py::ssize_t> byte_strides = {}) {
    if (byte_strides.empty()) {
        byte_strides.assign(shape.size(), py::ssize_t(sizeof(T)));
        for (std::size_t i = shape.size(); i-- > 1;) byte_strides[i - 1] = byte_strides[i] * shape[i];
    }
    py::array array(py::dtype::of<T>(), std::move(shape), std::move(byte_strides), data, owner);
    py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return array;
}

// A step of a hidden-surface algorithm as a dict: index, type, text, face, instance, level and the
// pixels it wrote and rejected.
py::dict step_record_dict(const StepRecord& step);

// The classes above as Python types, added to the module.
void bind_results(py::module_& module);

}  // namespace hsr::python
