// hsr render with a hidden-surface plugin: the shaded picture as PNG, optionally the depth buffer and
// the depth-complexity and depth-test heat maps, and with --stats the plugin's counters (render.hpp).
// The files are replaced together, once all of them are written (hsr/atomic_file.hpp).
#include "common/options.hpp"
#include "render/render.hpp"
#include "render/standard_streams.hpp"

#include "hsr/atomic_file.hpp"
#include "hsr/camera.hpp"
#include "hsr/data_files.hpp"
#include "hsr/image.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/pixel_data.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace {

using hsr::host::RenderOptions;
using hsr::host::UsageError;

void print_stats(const hsr::Frame& frame, const hsr::HiddenSurfaceRemover& remover,
                 const hsr::LightingModel& lighting, const hsr_scene& scene,
                 const hsr::DepthComplexity* depth_complexity, uint32_t samples) {
    const uint64_t drawn = hsr::drawn_triangle_count(scene);
    std::fprintf(stderr, "%s + %s, %llu triangles", remover.plugin().descriptor.name, lighting.plugin().descriptor.name,
                 static_cast<unsigned long long>(drawn));
    if (scene.instance_count > 0)
        std::fprintf(stderr, " (%u instances of %u stored)", scene.instance_count, scene.triangle_count);
    std::fprintf(stderr, ", %ux%u", frame.width, frame.height);
    if (samples > 1) std::fprintf(stderr, ", %u samples per pixel (times and counters summed over them)", samples);
    std::fprintf(stderr, "\n");
    const double build_ms = double(frame.counter("build-time-us")) / 1000.0;
    int w = 28;  // the name column: as wide as the longest name a plugin reports
    for (const auto& counter : frame.counters) w = std::max(w, int(counter.first.size()));
    std::fprintf(stderr, "  %-*s %10.2f ms\n", w, "visibility time", frame.visibility_ms);
    if (build_ms > 0.0) {
        std::fprintf(stderr, "    %-*s %10.2f ms\n", w - 2, "of which build", build_ms);
        std::fprintf(stderr, "    %-*s %10.2f ms\n", w - 2, "of which render", frame.visibility_ms - build_ms);
    }
    std::fprintf(stderr, "  %-*s %10.2f ms\n", w, "shading time", frame.shading_ms);
    for (const auto& [name, value] : frame.counters)
        std::fprintf(stderr, "  %-*s %10llu\n", w, name.c_str(), static_cast<unsigned long long>(value));
    if (depth_complexity) {
        std::fprintf(stderr, "  %-*s %10.2f (max %u, over %llu covered pixels)\n", w, "depth complexity",
                     depth_complexity->mean_over_covered(), depth_complexity->max,
                     static_cast<unsigned long long>(depth_complexity->covered_pixels));
        if (samples > 1) return;  // the ratios below compare one pass with the pixel centres
        const uint64_t written = frame.counter("pixels-written");
        if (depth_complexity->covered_pixels > 0 && written > 0)
            std::fprintf(stderr, "  %-*s %10.3f\n", w, "overdraw (writes / pixel)",
                         double(written) / double(depth_complexity->covered_pixels));
        const uint64_t tested = frame.counter("pixels-depth-tested");
        if (depth_complexity->fragments > 0)
            std::fprintf(stderr, "  %-*s %10.3f\n", w, "depth tests / surface samples",
                         double(tested) / double(depth_complexity->fragments));
    }
}

// The heat maps of --overdraw-out and --depth-tests-out, both on the scale of the depth complexity.
void write_heat_maps(const RenderOptions& o, const hsr::Frame& frame, const hsr::DepthComplexity& depth_complexity,
                     hsr::AtomicFileSet& files) {
    if (!o.overdraw_out.empty())
        hsr::write_heat_map_png(files.add(o.overdraw_out), frame.width, frame.height, depth_complexity.count,
                                depth_complexity.max);
    if (!o.depth_tests_out.empty())
        hsr::write_heat_map_png(files.add(o.depth_tests_out), frame.width, frame.height, frame.depth_tests,
                                depth_complexity.max);
}

std::string lowercase_extension(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return extension;
}

// --depth-out: the greyscale picture, or the camera-space distance as float32.
void write_depth_out(const std::string& path, const hsr::Picture& picture, hsr::AtomicFileSet& files) {
    const hsr::Frame& frame = picture.frame;
    const std::string extension = lowercase_extension(path);
    if (extension == ".png") {
        hsr::write_depth_png(files.add(path), frame.width, frame.height, frame.depth);
        return;
    }
    const std::vector<float> distance = hsr::camera_depth(frame, picture.camera);
    if (extension == ".npy")
        hsr::write_npy(files.add(path), frame.width, frame.height, 1, distance);
    else if (extension == ".pfm")
        hsr::write_pfm(files.add(path), frame.width, frame.height, 1, distance);
    else
        hsr::write_exr(files.add(path), frame.width, frame.height, {"Z"}, distance);
}

// --id-out: .npy int32 (object, face, instance), or a 16-bit RGBA PNG: R and G the face within its
// object (high and low 16 bits), B the object, A the instance; 65535 in every channel where no face
// is drawn (the face's -1 as 32 bits).
void write_id_out(const std::string& path, const hsr::Picture& picture, hsr::AtomicFileSet& files) {
    const hsr::Frame& frame = picture.frame;
    const std::vector<int32_t> ids = hsr::pixel_ids(frame, picture.scene);
    if (lowercase_extension(path) == ".npy") {
        hsr::write_npy(files.add(path), frame.width, frame.height, 3, ids);
        return;
    }
    std::vector<uint16_t> samples(4 * size_t(frame.width) * frame.height);
    for (size_t i = 0; i < size_t(frame.width) * frame.height; ++i) {
        const int32_t object = ids[3 * i], instance = ids[3 * i + 2];
        if (object > 0xfffe || instance > 0xfffe)
            throw hsr::Error("--id-out '{}': {} {} does not fit a 16-bit PNG channel (write .npy instead)",
                             hsr::printable(path, hsr::kMaxQuotedPathChars), object > 0xfffe ? "object" : "instance",
                             object > 0xfffe ? object : instance);
        const uint32_t face = uint32_t(ids[3 * i + 1]);
        samples[4 * i] = uint16_t(face >> 16);
        samples[4 * i + 1] = uint16_t(face & 0xffff);
        samples[4 * i + 2] = uint16_t(object);
        samples[4 * i + 3] = uint16_t(instance);
    }
    hsr::write_png16(files.add(path), frame.width, frame.height, 4, samples);
}

// --normal-out: float32 x, y, z, or an 8-bit PNG of (n + 1) / 2 (black where no face is drawn).
void write_normal_out(const std::string& path, const hsr::Picture& picture, hsr::AtomicFileSet& files) {
    const hsr::Frame& frame = picture.frame;
    const std::vector<float> normals = hsr::camera_normals(frame, picture.scene, picture.camera);
    const std::string extension = lowercase_extension(path);
    if (extension == ".npy") {
        hsr::write_npy(files.add(path), frame.width, frame.height, 3, normals);
    } else if (extension == ".pfm") {
        hsr::write_pfm(files.add(path), frame.width, frame.height, 3, normals);
    } else if (extension == ".exr") {
        hsr::write_exr(files.add(path), frame.width, frame.height, {"R", "G", "B"}, normals);
    } else {
        std::vector<uint8_t> rgb(normals.size(), 0);
        for (size_t i = 0; i < frame.face.size(); ++i)
            if (frame.face[i] != HSR_NO_FACE)
                for (int c = 0; c < 3; ++c)
                    rgb[3 * i + c] = uint8_t(std::lround(std::clamp((normals[3 * i + c] + 1.0f) * 0.5f, 0.0f, 1.0f) * 255.0f));
        hsr::write_png(files.add(path), frame.width, frame.height, 3, rgb);
    }
}

// The picture's pixels: RGB, or RGBA with the coverage of --background none.
std::vector<uint8_t> picture_pixels(const hsr::Frame& frame, int& channels) {
    channels = frame.alpha.empty() ? 3 : 4;
    if (channels == 3) return frame.rgb;
    std::vector<uint8_t> rgba(4 * frame.alpha.size());
    for (size_t i = 0; i < frame.alpha.size(); ++i) {
        std::copy_n(&frame.rgb[3 * i], 3, &rgba[4 * i]);
        rgba[4 * i + 3] = frame.alpha[i];
    }
    return rgba;
}

void print_heat_maps_written(const RenderOptions& o, const hsr::DepthComplexity& depth_complexity) {
    if (!o.overdraw_out.empty())
        std::fprintf(stderr, "wrote %s (depth complexity heat map: black 0 ... pale yellow %u)\n",
                     hsr::printable(o.overdraw_out, std::string::npos).c_str(), depth_complexity.max);
    if (!o.depth_tests_out.empty())
        std::fprintf(stderr, "wrote %s (depth tests heat map: black 0 ... pale yellow %u)\n",
                     hsr::printable(o.depth_tests_out, std::string::npos).c_str(), depth_complexity.max);
}

}  // namespace

uint32_t hsr::host::picture_samples(const RenderOptions& o, const hsr::LoadedScene* scene) {
    const uint32_t samples = o.was_given("samples")                     ? uint32_t(o.samples)
                             : scene && scene->file() && scene->file()->samples ? *scene->file()->samples
                                                                              : 1u;
    if (samples > 1)
        for (const char* option : {"depth-out", "id-out", "normal-out", "depth-tests-out", "step"})
            if (o.was_given(option))
                throw UsageError("--{} shows one visibility pass: it does not go with {} samples (render it with "
                                 "--samples 1)", option, samples);
    return samples;
}

hsr::PictureRequest hsr::host::picture_request(const RenderOptions& o, const hsr::LoadedScene& scene) {
    hsr::PictureRequest request;
    request.view = view_request(o);
    for (const std::string& text : o.lights) request.lights.push_back(hsr::parse_light_spec(text));
    if (transparent_background(o))
        request.transparent_background = true;
    else if (o.was_given("background"))
        request.background = parse_color_option(o.background, "background");
    request.samples = picture_samples(o, &scene);
    request.threads = unsigned(o.threads);
    request.count_depth_tests = !o.depth_tests_out.empty();
    request.depth_complexity = o.stats || !o.overdraw_out.empty() || !o.depth_tests_out.empty();
    if (o.was_given("step")) request.step = uint64_t(o.step);
    return request;
}

hsr::Picture hsr::host::render_picture(const RenderOptions& o, hsr::Renderer& renderer, PicturePlugins& plugins) {
    const hsr::PictureRequest request = picture_request(o, renderer.loaded());
    const ThreadBound thread_bound(o.threads);
    return renderer.picture(request, *plugins.remover, *plugins.lighting);
}

void hsr::host::write_picture(const RenderOptions& o, const hsr::Picture& picture, const PicturePlugins& plugins,
                              const std::filesystem::path& output) {
    const hsr::Frame& frame = picture.frame;
    const hsr::DepthComplexity* depth_complexity = picture.depth_complexity.get();
    const hsr_scene& scene_view = picture.scene;
    hsr::AtomicFileSet files;
    int channels = 3;
    const std::vector<uint8_t> pixels = picture_pixels(frame, channels);
    const bool to_stdout = output == "-";
    if (!to_stdout) hsr::write_png(files.add(output), frame.width, frame.height, channels, pixels);
    if (!o.depth_out.empty()) write_depth_out(o.depth_out, picture, files);
    if (!o.id_out.empty()) write_id_out(o.id_out, picture, files);
    if (!o.normal_out.empty()) write_normal_out(o.normal_out, picture, files);
    if (depth_complexity) write_heat_maps(o, frame, *depth_complexity, files);
    // Standard output before the files are renamed into place: a closed pipe leaves them as they were.
    if (to_stdout) write_standard_output(hsr::encode_picture_png(frame.width, frame.height, channels, pixels));
    files.commit();
    for (const auto& [option, path] : {std::pair<const char*, const std::string&>{"depth-out", o.depth_out},
                                       {"id-out", o.id_out},
                                       {"normal-out", o.normal_out}})
        if (!path.empty())
            std::fprintf(stderr, "wrote %s (--%s)\n", hsr::printable(path, std::string::npos).c_str(), option);
    if (depth_complexity) print_heat_maps_written(o, *depth_complexity);
    if (o.stats) print_stats(frame, *plugins.remover, *plugins.lighting, scene_view, depth_complexity,
                            picture.samples);
    if (frame.steps) {
        if (frame.steps->stopped)
            std::fprintf(stderr, "step %llu: %s\n", static_cast<unsigned long long>(frame.steps->last.index),
                         frame.steps->last.text.c_str());
        else
            std::fprintf(stderr, "hsr: the algorithm ended after step %llu, before step %lld: the picture is complete\n",
                         static_cast<unsigned long long>(frame.steps->taken), static_cast<long long>(o.step));
    }
    if (frame.counter("fragments-shaded") == 0)
        std::fprintf(stderr, "hsr: warning: no triangle covers a pixel centre: the picture is empty (is the model "
                             "too small, too far away or flat edge-on at this size?)\n");
    std::fprintf(stderr, "wrote %s (%ux%u, %llu triangles, %.1f ms visibility + %.1f ms shading)\n",
                 to_stdout ? "the picture to standard output" : hsr::printable(output.string(), std::string::npos).c_str(), frame.width, frame.height,
                 static_cast<unsigned long long>(hsr::drawn_triangle_count(scene_view)), frame.visibility_ms,
                 frame.shading_ms);
}
