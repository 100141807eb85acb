#include "hsr/pipeline.hpp"

#include "fragment_assembly.hpp"

#include "hsr/error.hpp"
#include "hsr/fragment_lists.hpp"
#include "hsr/raster.hpp"
#include "hsr/instancing.hpp"
#include "hsr/limits.hpp"
#include "hsr/scene.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <cmath>
#include <limits>
#include <span>

namespace hsr {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void collect_counter(void* context, const char* name, uint64_t value) {
    auto* counters = static_cast<std::vector<std::pair<std::string, uint64_t>>*>(context);
    if (name == nullptr) return;
    for (auto& [n, v] : *counters) {
        if (n == name) {
            v += value;
            return;
        }
    }
    counters->emplace_back(name, value);
}

// Gathers the covered pixels of rows [row_begin, row_end) into fragments. Returns the fragment count.
uint32_t assemble_fragments(const hsr_scene& scene, const Placements& placements, const Frame& frame,
                            uint32_t row_begin, uint32_t row_end, FragmentArrays& out) {
    const bool instanced = !frame.instance.empty();
    uint32_t n = 0;
    const uint32_t w = frame.width;
    for (uint32_t y = row_begin; y < row_end; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            const uint32_t pixel = y * w + x;
            const uint32_t t = frame.face[pixel];
            if (t == HSR_NO_FACE) continue;
            assemble_fragment(scene, placements, t, instanced ? frame.instance[pixel] : kNotInstanced,
                              frame.bary[2 * pixel], frame.bary[2 * pixel + 1], pixel, out, n++);
        }
    }
    return n;
}

}  // namespace

void check_image_size(uint32_t width, uint32_t height) {
    if (width == 0 || height == 0) throw Error("image size {}x{}: width and height must be at least 1", width, height);
    if (width > max_image_side || height > max_image_side)
        throw Error("image size {}x{} is too large (at most {} pixels a side)", width, height, max_image_side);
}

void check_image_pixels(uint32_t width, uint32_t height, uint32_t samples) {
    const uint64_t pixels = uint64_t(width) * height * std::max(samples, 1u);
    if (samples > 1)
        check_limit(&Limits::image_pixels, pixels,
                    fmt::format("image size {}x{} at {} samples per pixel", width, height, samples));
    else
        check_limit(&Limits::image_pixels, pixels, fmt::format("image size {}x{}", width, height));
}

uint64_t Frame::counter(const std::string& name) const {
    for (const auto& [n, v] : counters)
        if (n == name) return v;
    return 0;
}

bool needs_flat_scene(const Plugin& plugin, const hsr_scene& scene) {
    return scene.instance_count > 0 && plugin.descriptor.abi_minor < 1;
}

void check_clip_planes_known(const Plugin& plugin, const hsr_camera& camera) {
    if (camera.clip_plane_count > 0 && plugin.descriptor.abi_minor < 4)
        throw Error("plugin '{}' is built against ABI 1.{}, which has no clip planes (sections came with 1.4)",
                    plugin.descriptor.name, plugin.descriptor.abi_minor);
}

namespace {

// Clears the frame's visibility arrays for the camera and points a visibility buffer at them.
hsr_visibility_buffer clear_visibility(const hsr_scene& scene, const hsr_camera& camera,
                                       const HiddenSurfaceRemover& remover, Frame& frame, bool count_depth_tests) {
    check_image_size(camera.width, camera.height);
    if (needs_flat_scene(remover.plugin(), scene))
        throw Error("hidden-surface plugin '{}' is built against ABI 1.0, which has no instances; copy the "
                    "instances out first (flatten_instances)", remover.plugin().descriptor.name);
    check_clip_planes_known(remover.plugin(), camera);
    const size_t pixels = size_t(camera.width) * camera.height;
    frame.width = camera.width;
    frame.height = camera.height;
    frame.depth.assign(pixels, std::numeric_limits<float>::infinity());
    frame.face.assign(pixels, HSR_NO_FACE);
    frame.bary.assign(2 * pixels, 0.0f);
    if (scene.instance_count > 0)
        frame.instance.assign(pixels, 0);
    else
        frame.instance.clear();
    if (count_depth_tests)
        frame.depth_tests.assign(pixels, 0);
    else
        frame.depth_tests.clear();

    hsr_visibility_buffer target{};
    target.struct_size = sizeof target;
    target.width = frame.width;
    target.height = frame.height;
    target.depth = frame.depth.data();
    target.face = frame.face.data();
    target.bary = frame.bary.data();
    target.instance = frame.instance.empty() ? nullptr : frame.instance.data();
    target.depth_tests = frame.depth_tests.empty() ? nullptr : frame.depth_tests.data();
    return target;
}

// A face or instance id the scene does not have is a bug in the plugin; say so rather than shade
// garbage.
void check_visibility(const hsr_scene& scene, const HiddenSurfaceRemover& remover, const Frame& frame) {
    const size_t pixels = size_t(frame.width) * frame.height;
    for (size_t p = 0; p < pixels; ++p) {
        const uint32_t t = frame.face[p];
        if (t != HSR_NO_FACE && t >= scene.triangle_count)
            throw Error("hidden-surface plugin '{}' wrote face {} at pixel ({}, {}), but the scene has {} triangles",
                        remover.plugin().descriptor.name, t, p % frame.width, p / frame.width, scene.triangle_count);
        if (!frame.instance.empty() && t != HSR_NO_FACE && frame.instance[p] >= scene.instance_count)
            throw Error("hidden-surface plugin '{}' wrote instance {} at pixel ({}, {}), but the scene has {} instances",
                        remover.plugin().descriptor.name, frame.instance[p], p % frame.width, p / frame.width,
                        scene.instance_count);
    }
}

// A plugin's string, read up to its NUL or max_bytes, whichever comes first.
std::string_view bounded(const char* text, size_t max_bytes) { return {text, strnlen(text, max_bytes)}; }

// The step sink's context: copies each event into `last` (its buffers only for the step the render
// stops after, which may be large and are of no use otherwise) and says stop at stop_after.
struct StepCollector {
    uint64_t stop_after = 0;
    StepProgress* progress = nullptr;
    const hsr_visibility_buffer* keep_before_of = nullptr;  // set: copy it at step stop_after - 1
    bool has_phases = false;  // the plugin claims ABI 1.5: its events may name a phase
    bool russian = false;     // the texts the host writes for a step without one are in Russian
    StepOutline* outline = nullptr;  // set: every step is added to it
    StepRun run;

    static uint32_t step(void* context, const hsr_step_event* event) {
        auto& self = *static_cast<StepCollector*>(context);
        StepRecord& last = self.run.last;
        const uint64_t index = ++self.run.taken;
        if (self.progress != nullptr) self.progress->steps.store(index, std::memory_order_relaxed);
        const bool stop = index == self.stop_after;
        if (self.keep_before_of != nullptr && index + 1 == self.stop_after) self.run.before = copy_of(*self.keep_before_of);
        last.index = index;
        if (event == nullptr || event->struct_size < offsetof(hsr_step_event, buffer_count) + sizeof(uint32_t)) {
            last.type = "step";
            last.phase.clear();
            last.text = self.russian ? fmt::format("шаг {}", index) : fmt::format("step {}", index);
            last.lines.clear();
            last.roles.clear();
            last.buffers.clear();
            if (self.outline != nullptr) self.outline->add(last.type, "", HSR_NO_LEVEL, [&] { return last.text; });
            self.run.stopped = stop;
            return stop ? 1 : 0;
        }
        last.type = event->type != nullptr ? printable(bounded(event->type, 64), 64) : "step";
        last.phase.clear();
        if (self.has_phases && event->struct_size >= offsetof(hsr_step_event, phase) + sizeof(event->phase) &&
            event->phase != nullptr)
            last.phase = printable(bounded(event->phase, 64), 64);
        last.face = event->face;
        last.instance = event->instance;
        last.level = event->level;
        last.pixels_written = event->pixels_written;
        last.pixels_rejected = event->pixels_rejected;
        if (event->text != nullptr)
            last.text = printable(bounded(event->text, 1024), 300);
        else
            last.text = describe_step(last, self.russian);
        if (self.outline != nullptr) self.outline->add(last.type, last.phase, last.level, [&] { return last.text; });
        const uint32_t lines = event->lines != nullptr ? std::min(event->line_count, max_step_lines) : 0;
        last.lines.assign(event->lines, event->lines + 4 * size_t(lines));
        last.roles.assign(lines, HSR_STEP_SUBJECT);
        if (event->line_roles != nullptr)
            for (uint32_t k = 0; k < lines; ++k) last.roles[k] = std::min<uint32_t>(event->line_roles[k], HSR_STEP_CONTEXT);
        last.buffers.clear();
        if (stop && event->buffers != nullptr) {
            for (uint32_t k = 0; k < std::min(event->buffer_count, max_step_buffers); ++k) {
                const hsr_step_buffer& b = event->buffers[k];
                if (b.values == nullptr || uint64_t(b.width) * b.height > max_step_buffer_values) continue;
                last.buffers.push_back({b.name != nullptr ? printable(bounded(b.name, 64), 64) : fmt::format("buffer-{}", k),
                                        b.width, b.height,
                                        std::vector<float>(b.values, b.values + size_t(b.width) * b.height)});
            }
        }
        self.run.stopped = stop;
        return stop ? 1 : 0;
    }

    static VisibilityState copy_of(const hsr_visibility_buffer& target) {
        const size_t pixels = size_t(target.width) * target.height;
        VisibilityState state;
        state.depth.assign(target.depth, target.depth + pixels);
        state.face.assign(target.face, target.face + pixels);
        if (target.instance != nullptr) state.instance.assign(target.instance, target.instance + pixels);
        if (target.depth_tests != nullptr) state.depth_tests.assign(target.depth_tests, target.depth_tests + pixels);
        return state;
    }

    // The text of a step whose plugin wrote none, from the event's fields.
    static std::string describe_step(const StepRecord& step, bool russian) {
        if (russian) {
            std::string text = step.type == "step" ? fmt::format("шаг {}", step.index)
                                                   : fmt::format("шаг {} ({})", step.index, step.type);
            if (step.face != HSR_NO_FACE) text += fmt::format(": треугольник {}", step.face);
            if (step.pixels_written != 0 || step.pixels_rejected != 0)
                text += fmt::format("; записано пикселей: {}, отброшено: {}", step.pixels_written, step.pixels_rejected);
            return text;
        }
        std::string text = fmt::format("{} {}", step.type, step.index);
        if (step.face != HSR_NO_FACE) text += fmt::format(": triangle {}", step.face);
        if (step.pixels_written != 0 || step.pixels_rejected != 0)
            text += fmt::format(", {} pixels written, {} rejected", step.pixels_written, step.pixels_rejected);
        return text;
    }

    // Bounds on what is copied from a plugin's event.
    static constexpr uint32_t max_step_lines = 1u << 20;
    static constexpr uint32_t max_step_buffers = 64;
    static constexpr uint64_t max_step_buffer_values = uint64_t(max_image_side) * max_image_side;
};

}  // namespace

void resolve_visibility(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                        Frame& frame, bool count_depth_tests) {
    hsr_visibility_buffer target = clear_visibility(scene, camera, remover, frame, count_depth_tests);
    hsr_counter_sink sink{&frame.counters, &collect_counter};
    const auto start = Clock::now();
    remover.render(scene, camera, target, &sink);
    frame.visibility_ms = ms_since(start);
    check_visibility(scene, remover, frame);
}

void resolve_visibility_steps(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                              Frame& frame, uint64_t stop_after, bool count_depth_tests, bool keep_before,
                              StepProgress* progress, const std::string& language, StepOutline* outline) {
    hsr_visibility_buffer target = clear_visibility(scene, camera, remover, frame, count_depth_tests);
    hsr_counter_sink sink{&frame.counters, &collect_counter};
    StepCollector collector;
    collector.stop_after = stop_after;
    collector.progress = progress;
    if (progress != nullptr) progress->steps.store(0, std::memory_order_relaxed);
    if (keep_before) collector.keep_before_of = &target;
    collector.has_phases = remover.plugin().descriptor.abi_minor >= 5;
    collector.russian = language == "ru";
    collector.outline = outline;
    const hsr_step_sink steps{&collector, &StepCollector::step, language.empty() ? nullptr : language.c_str()};
    const auto start = Clock::now();
    remover.render_steps(scene, camera, target, &sink, steps);
    frame.visibility_ms = ms_since(start);
    check_visibility(scene, remover, frame);
    frame.steps = std::move(collector.run);
}

void shade_frame(const hsr_scene& scene, LightingModel& lighting, const hsr_shading_context& context,
                 const FrameSettings& settings, Frame& frame) {
    if (needs_flat_scene(lighting.plugin(), scene))
        throw Error("lighting plugin '{}' is built against ABI 1.0, which has no instances; copy the instances "
                    "out first (flatten_instances)", lighting.plugin().descriptor.name);
    if (scene.instance_count > 0 && frame.instance.size() != frame.face.size())
        throw Error("the scene has instances but the visibility buffer has no instance ids");
    const Placements placements(scene);
    const auto start = Clock::now();
    lighting.prepare(scene, context);
    const size_t pixels = size_t(frame.width) * frame.height;
    frame.rgb.resize(3 * pixels);
    std::vector<uint8_t> background_row(3 * size_t(frame.width));
    if (!settings.coverage_alpha)
        for (size_t x = 0; x < frame.width; ++x)
            for (int k = 0; k < 3; ++k) background_row[3 * x + k] = color_to_byte(settings.background[k]);

    // Bands of rows, shaded a chunk of fragments at a time. Each thread writes only its bands'
    // pixels, so nothing is shared but the counters.
    const bool instanced = !frame.instance.empty();
    const bool simd_assembly = fits_simd_assembly(scene);
    std::atomic<uint64_t> fragments{0}, batches{0};
    // Shades covered pixels [first, first + count) of a band, whose fragments `arrays` holds from
    // 0 on, and writes their bytes to their pixels.
    auto shade_chunk = [&](FragmentArrays& arrays, uint32_t first, uint32_t count) {
        hsr_fragment_batch batch = chunk_batch(arrays, first, count, instanced);
        lighting.shade(batch);
        colors_to_pixels(arrays.color.data(), arrays.pixel.data() + first, count, frame.rgb.data());
    };
    for_each_band(frame.height, settings.threads, [&](uint32_t row_begin, uint32_t row_end, FragmentArrays& arrays) {
        const uint32_t pixel_begin = row_begin * frame.width, pixel_end = row_end * frame.width;
        for (uint32_t y = row_begin; y < row_end; ++y)
            std::memcpy(&frame.rgb[3 * size_t(y) * frame.width], background_row.data(), background_row.size());
        const size_t band_pixels = size_t(kRowsPerBand) * frame.width;
        if (!simd_assembly) {
            arrays.reserve(band_pixels);
            const uint32_t n = assemble_fragments(scene, placements, frame, row_begin, row_end, arrays);
            if (n == 0) return;
            shade_chunk(arrays, 0, n);
            fragments += n;
            ++batches;
            return;
        }
        // The band's covered pixels, then their fragments a chunk at a time: assembled, shaded and
        // written while the chunk's arrays are in the L1 cache.
        arrays.reserve(band_pixels, kFragmentsPerChunk);
        const uint32_t n = find_covered_pixels(frame.face.data(), instanced ? frame.instance.data() : nullptr,
                                               pixel_begin, pixel_end, arrays);
        if (n == 0) return;
        for (uint32_t first = 0; first < n; first += kFragmentsPerChunk) {
            const uint32_t count = std::min(kFragmentsPerChunk, n - first);
            assemble_covered_fragments(scene, placements, instanced, frame.bary.data(), first, count, n, arrays);
            shade_chunk(arrays, first, count);
            ++batches;
        }
        fragments += n;
    });

    if (settings.coverage_alpha) {
        frame.alpha.resize(pixels);
        for (size_t i = 0; i < pixels; ++i) frame.alpha[i] = frame.face[i] == HSR_NO_FACE ? 0 : 255;
    }
    frame.counters.emplace_back("fragments-shaded", fragments.load());
    frame.counters.emplace_back("shading-batches", batches.load());
    frame.shading_ms = ms_since(start);
}

void resolve_fragments(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                       Frame& frame, FragmentLists& lists, bool count_depth_tests) {
    hsr_visibility_buffer target = clear_visibility(scene, camera, remover, frame, count_depth_tests);
    hsr_counter_sink counters{&frame.counters, &collect_counter};
    FragmentCollector collector(scene, camera.width, camera.height);
    const hsr_fragment_sink sink = collector.sink();
    const auto start = Clock::now();
    try {
        remover.render_fragments(scene, camera, target, &counters, sink);
    } catch (const Error&) {
        const std::string message =
            fmt::format("hidden-surface plugin '{}' returned {}", remover.plugin().descriptor.name, collector.problem());
        if (collector.over_limit()) throw LimitError(message);
        if (!collector.problem().empty()) throw Error(message);
        throw;
    }
    frame.visibility_ms = ms_since(start);
    check_visibility(scene, remover, frame);
    collector.finish(lists);
    frame.counters.emplace_back("fragments", lists.size());
}

bool has_transparency(const hsr_scene& scene) {
    const sdk::Scene view(scene);
    return view.has_transparency();
}

Frame render_frame(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                   LightingModel& lighting, const hsr_shading_context& context, const FrameSettings& settings) {
    Frame frame;
    if (remover.has_fragments() && !settings.stop_after_step) {
        FragmentLists lists;
        resolve_fragments(scene, camera, remover, frame, lists, settings.count_depth_tests);
        shade_fragments(scene, lighting, context, settings, lists, frame);
        return frame;
    }
    if (has_transparency(scene))
        throw Error("the scene has objects that are not opaque, but hidden-surface plugin '{}' finds one surface per "
                    "pixel; transparency needs fragment lists (-a a-buffer)", remover.plugin().descriptor.name);
    auto resolve = [&](const hsr_scene& view) {
        if (settings.stop_after_step)
            resolve_visibility_steps(view, camera, remover, frame, *settings.stop_after_step, settings.count_depth_tests,
                                     settings.keep_step_before, settings.step_progress, settings.step_language);
        else
            resolve_visibility(view, camera, remover, frame, settings.count_depth_tests);
    };
    if (needs_flat_scene(remover.plugin(), scene) || needs_flat_scene(lighting.plugin(), scene)) {
        // A plugin built against ABI 1.0 cannot see instances: both get the copied-out triangles,
        // so that face ids mean the same to both.
        const SceneData flat = flatten_instances(scene);
        const hsr_scene flat_view = flat.view();
        resolve(flat_view);
        shade_frame(flat_view, lighting, context, settings, frame);
        return frame;
    }
    resolve(scene);
    shade_frame(scene, lighting, context, settings, frame);
    return frame;
}

bool is_sample_count(uint32_t samples) {
    return samples == 1 || samples == 2 || samples == 4 || samples == 8 || samples == 16;
}

std::vector<glm::vec2> sample_offsets(uint32_t samples) {
    // In sixteenths of a pixel from the centre, as the Direct3D and Vulkan specifications list them.
    static constexpr int8_t two[][2] = {{4, 4}, {-4, -4}};
    static constexpr int8_t four[][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
    static constexpr int8_t eight[][2] = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
    static constexpr int8_t sixteen[][2] = {{1, 1},   {-1, -3}, {-3, 2}, {4, -1}, {-5, -2}, {2, 5},
                                            {5, 3},   {3, -5},  {-2, 6}, {0, -7}, {-4, -6}, {-6, 4},
                                            {-8, 0},  {7, -4},  {6, 7},  {-7, -8}};
    std::span<const int8_t[2]> table;
    switch (samples) {
    case 1: return {glm::vec2(0.0f)};
    case 2: table = two; break;
    case 4: table = four; break;
    case 8: table = eight; break;
    case 16: table = sixteen; break;
    default: throw Error("{} samples: expected 1, 2, 4, 8 or 16", samples);
    }
    std::vector<glm::vec2> offsets;
    for (const auto& o : table) offsets.emplace_back(float(o[0]) / 16.0f, float(o[1]) / 16.0f);
    return offsets;
}

hsr_camera offset_camera(const hsr_camera& camera, glm::vec2 offset) {
    // Window x = (ndc x + 1) w / 2 and y = (1 - ndc y) h / 2: moving what lies at centre + offset to
    // the centre moves NDC by (-2 dx / w, +2 dy / h), i.e. clip x += shift_x * w_clip (and y alike),
    // which is the translation T applied after the projection: P' = T P.
    const double shift_x = -2.0 * double(offset.x) / double(camera.width);
    const double shift_y = 2.0 * double(offset.y) / double(camera.height);
    hsr_camera shifted = camera;
    for (float* m : {shifted.projection, shifted.view_projection})
        for (int c = 0; c < 4; ++c) {  // column-major: m[4 c + row]
            m[4 * c] = float(double(m[4 * c]) + shift_x * double(m[4 * c + 3]));
            m[4 * c + 1] = float(double(m[4 * c + 1]) + shift_y * double(m[4 * c + 3]));
        }
    return shifted;
}

Frame render_supersampled_frame(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                               LightingModel& lighting, const hsr_shading_context& context,
                               const FrameSettings& settings) {
    if (settings.samples <= 1) return render_frame(scene, camera, remover, lighting, context, settings);
    const std::vector<glm::vec2> offsets = sample_offsets(settings.samples);
    if (settings.stop_after_step) throw Error("steps are of one visibility pass: render them with 1 sample");
    if (settings.count_depth_tests) throw Error("depth-test counts are of one visibility pass: count them with 1 sample");
    Frame frame;
    // With coverage alpha, colours are summed weighted by their alpha (premultiplied), so that the
    // mean colour is that of what covers the pixel, not of the black left where nothing does.
    std::vector<uint32_t> sum, alpha_sum;
    for (std::size_t k = 0; k < offsets.size(); ++k) {
        Frame sample = render_frame(scene, offset_camera(camera, offsets[k]), remover, lighting, context, settings);
        if (k == 0) sum.assign(sample.rgb.size(), 0);
        if (settings.coverage_alpha) {
            if (k == 0) alpha_sum.assign(sample.alpha.size(), 0);
            for (std::size_t p = 0; p < alpha_sum.size(); ++p) {
                const uint32_t a = sample.alpha[p];
                alpha_sum[p] += a;
                for (int c = 0; c < 3; ++c) sum[3 * p + c] += a * sample.rgb[3 * p + c];
            }
        } else {
            for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += sample.rgb[i];
        }
        for (const auto& [name, value] : sample.counters) collect_counter(&frame.counters, name.c_str(), value);
        frame.visibility_ms += sample.visibility_ms;
        frame.shading_ms += sample.shading_ms;
        if (k == 0) {
            frame.width = sample.width;
            frame.height = sample.height;
            frame.depth = std::move(sample.depth);
            frame.face = std::move(sample.face);
            frame.bary = std::move(sample.bary);
            frame.instance = std::move(sample.instance);
        }
    }
    const uint32_t n = uint32_t(offsets.size());
    frame.rgb.resize(sum.size());
    if (settings.coverage_alpha) {
        frame.alpha.resize(alpha_sum.size());
        for (std::size_t p = 0; p < alpha_sum.size(); ++p) {
            const uint32_t a = alpha_sum[p];
            frame.alpha[p] = uint8_t((a + n / 2) / n);
            for (int c = 0; c < 3; ++c) frame.rgb[3 * p + c] = a == 0 ? 0 : uint8_t((sum[3 * p + c] + a / 2) / a);
        }
        return frame;
    }
    for (std::size_t i = 0; i < sum.size(); ++i) frame.rgb[i] = uint8_t((sum[i] + n / 2) / n);
    return frame;
}

hsr_shading_context make_shading_context(const hsr_camera& camera, const std::vector<hsr_light>& lights) {
    hsr_shading_context context{};
    context.struct_size = sizeof context;
    context.lights = lights.data();
    context.light_count = static_cast<uint32_t>(lights.size());
    context.projection_type = camera.projection_type;
    std::copy(std::begin(camera.eye), std::end(camera.eye), context.eye);
    std::copy(std::begin(camera.view_direction), std::end(camera.view_direction), context.view_direction);
    return context;
}

}  // namespace hsr

namespace hsr {

uint64_t drawn_triangle_count(const hsr_scene& scene) {
    if (scene.instance_count == 0) return scene.triangle_count;
    uint64_t n = 0;
    for (uint32_t k = 0; k < scene.instance_count; ++k) n += HSR_ELEMENT(hsr_instance, scene.instances, k)->triangle_count;
    return n;
}

DepthComplexity measure_depth_complexity(const hsr_scene& scene, const hsr_camera& camera,
                                         const std::optional<PixelRegion>& region) {
    check_image_size(camera.width, camera.height);
    const PixelRegion r = region.value_or(PixelRegion{0, 0, camera.width, camera.height});
    if (r.width == 0 || r.height == 0 || r.x >= camera.width || r.y >= camera.height ||
        r.width > camera.width - r.x || r.height > camera.height - r.y)
        throw Error("depth complexity: the region {}x{} at ({}, {}) is not inside the {}x{} picture", r.width, r.height,
                    r.x, r.y, camera.width, camera.height);
    DepthComplexity result;
    result.x = r.x;
    result.y = r.y;
    result.width = r.width;
    result.height = r.height;
    result.count.assign(size_t(r.width) * r.height, 0);
    if (scene.triangle_count == 0) return result;

    std::vector<float> depth(1), bary(2);
    uint32_t face = 0;
    hsr_visibility_buffer target{};
    target.struct_size = sizeof target;
    target.width = camera.width;
    target.height = camera.height;
    target.depth = depth.data();  // only checked for NULL by validate_frame
    target.face = &face;
    target.bary = bary.data();
    try {
        raster::validate_frame("depth complexity", scene, camera, target);
    } catch (const sdk::InvalidArgument& e) {
        throw Error("{}", e.what());
    }

    raster::GeometryStage geometry;
    geometry.begin_frame(scene, camera, false);
    const sdk::Scene view(scene);
    uint32_t* const count = result.count.data();
    const int32_t x0 = int32_t(r.x), y0 = int32_t(r.y);
    const int32_t x1 = int32_t(r.x + r.width - 1), y1 = int32_t(r.y + r.height - 1);
    const size_t width = r.width;
    for (uint32_t k = 0; k < view.placement_count(); ++k) {
        const sdk::Placement placement = view.placement(k);
        geometry.place(placement);
        for (uint32_t t = placement.first_triangle; t < placement.first_triangle + placement.triangle_count; ++t)
            geometry.process(t, [&](const raster::TriangleSetup& s) {
                const int32_t from_x = std::max(s.min_x, x0), to_x = std::min(s.max_x, x1);
                const int32_t from_y = std::max(s.min_y, y0), to_y = std::min(s.max_y, y1);
                if (from_x > to_x || from_y > to_y) return;
                raster::for_each_covered_pixel_in(s, from_x, from_y, to_x, to_y, [&](int32_t x, int32_t y, double, double) {
                    ++count[size_t(y - y0) * width + size_t(x - x0)];
                });
            });
    }
    for (uint32_t c : result.count) {
        result.fragments += c;
        result.covered_pixels += c > 0;
        result.max = std::max(result.max, c);
    }
    return result;
}

}  // namespace hsr
