// hsr C++ SDK: write a plugin as one C++ class plus one export line; this header builds the C tables
// of abi.h around it and keeps C++ (exceptions included) on the plugin's side of the boundary.
//
//   class MyRemover final : public hsr::sdk::HiddenSurfaceRemover {
//   public:
//       static constexpr hsr::sdk::PluginInfo info{"my-remover", "1.0.0", "What it does, one line"};
//       static inline const hsr::sdk::ParamSpec params[] = {
//           hsr::sdk::ParamSpec::boolean("cull-backfaces", false, "skip triangles facing away"),
//       };
//       explicit MyRemover(const hsr::sdk::Params& p) : cull_(p.boolean("cull-backfaces")) {}
//       void render(const hsr::sdk::Scene&, const hsr_camera&, hsr::sdk::VisibilityBuffer&,
//                   hsr::sdk::Counters&) override;
//   };
//   HSR_EXPORT_PLUGIN(MyRemover)
//
// docs/writing-a-plugin.md walks through a complete example. The SDK is this one header (beside abi.h
// and the optional raster, bounds, zpyramid and shading helpers), over 700 lines, so that a plugin
// author has one file to include and to read.
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hsr::sdk {

// Thrown by a plugin for a user-facing problem (bad scene for this algorithm, say); becomes
// HSR_ERROR_INVALID_ARGUMENT with the message. Any other exception becomes HSR_ERROR_INTERNAL.
struct InvalidArgument : std::runtime_error {
    using std::runtime_error::runtime_error;
};
struct Unsupported : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct PluginInfo {
    const char* name;
    const char* version;
    const char* description;
};

// One parameter of a plugin's schema. Construct with the named factories.
struct ParamSpec {
    hsr_param_desc desc;

    static constexpr ParamSpec boolean(const char* name, bool default_value, const char* help) {
        return {{sizeof(hsr_param_desc), name, HSR_PARAM_BOOL, default_value ? "true" : "false", 0, 1,
                 nullptr, help}};
    }
    static constexpr ParamSpec integer(const char* name, const char* default_value, double min,
                                       double max, const char* help) {
        return {{sizeof(hsr_param_desc), name, HSR_PARAM_INT, default_value, min, max, nullptr, help}};
    }
    static constexpr ParamSpec real(const char* name, const char* default_value, double min,
                                    double max, const char* help) {
        return {{sizeof(hsr_param_desc), name, HSR_PARAM_FLOAT, default_value, min, max, nullptr,
                 help}};
    }
    // choices: "a|b|c"; default_value must be one of them.
    static constexpr ParamSpec choice(const char* name, const char* default_value, const char* choices,
                                      const char* help) {
        return {{sizeof(hsr_param_desc), name, HSR_PARAM_ENUM, default_value, 0, 0, choices, help}};
    }
    // default_value: "r/g/b" with channels in [0, 1], or "#rrggbb".
    static constexpr ParamSpec color(const char* name, const char* default_value, const char* help) {
        return {{sizeof(hsr_param_desc), name, HSR_PARAM_COLOR, default_value, 0, 1, nullptr, help}};
    }
};

// ABI 1.5: one phase of the algorithm, for a viewer to highlight the line of pseudocode a step
// executes. A plugin lists them as
//   static inline const hsr::sdk::PhaseSpec phases[] = {{"clear", "clear the buffers"}, ...};
// and names one in every step (Steps::Event::phase, Trace::Event::phase).
struct PhaseSpec {
    const char* name;  // lower-case words joined by '-'
    const char* title; // a few words in English
};

// ABI 1.6: one of the plugin's texts in another language; `key` is one of those listed at
// hsr_translation in abi.h ("description", "param:<name>", "help:<name>", "choice:<param>:<choice>",
// "phase:<name>", "counter:<name>", "buffer:<name>"). A plugin class lists them as
//   static inline const hsr::sdk::TranslationSpec translations[] = {{"ru", "description", "..."}, ...};
struct TranslationSpec {
    const char* language;
    const char* key;
    const char* text;
};

namespace detail {
template <class List>
struct TranslationListSize;
template <std::size_t N>
struct TranslationListSize<TranslationSpec[N]> {
    static constexpr std::size_t value = N;
};
template <std::size_t N>
struct TranslationListSize<std::array<TranslationSpec, N>> {
    static constexpr std::size_t value = N;
};
}  // namespace detail

// Joins lists of translations (C arrays or std::arrays of TranslationSpec) into one std::array, in
// order, for a plugin that adds its own texts to those of the SDK code it uses:
//   static constexpr hsr::sdk::TranslationSpec own_translations[] = {{"ru", "description", "..."}, ...};
//   static constexpr auto translations =
//       hsr::sdk::join_translations(hsr::raster::triangle_counter_translations, own_translations);
template <class... Lists>
constexpr auto join_translations(const Lists&... lists) {
    std::array<TranslationSpec, (detail::TranslationListSize<Lists>::value + ... + 0)> joined{};
    std::size_t next = 0;
    auto append = [&](const auto& list) {
        for (const TranslationSpec& spec : list) joined[next++] = spec;
    };
    (append(lists), ...);
    return joined;
}

// The counter the SDK adds to a render with steps ("steps": how many were taken), in Russian.
// Every hidden-surface remover's table gets it (translation_table), unless the class gives its own.
inline constexpr std::array<TranslationSpec, 1> step_counter_translations{{
    {"ru", "counter:steps", "шагов сделано"},
}};

// ABI 1.5: whether the host asked for step texts in `code` ("ru"); English is the default.
inline bool wants_language(const char* asked, const char* code) {
    return asked != nullptr && code != nullptr && std::strcmp(asked, code) == 0;
}

// The Russian word form that agrees with the count n: `one` for 1, 21, 101 ("пиксель"), `few` for
// 2-4, 22-24 ("пикселя"), `many` for 0, 5-20, 25-30, 111-114 ("пикселей").
inline const char* russian_plural(uint64_t n, const char* one, const char* few, const char* many) {
    const uint64_t last_two = n % 100, last = n % 10;
    if (last_two >= 11 && last_two <= 14) return many;
    if (last == 1) return one;
    if (last >= 2 && last <= 4) return few;
    return many;
}

// The validated values the host passed to create(), looked up by name. Asking for a name that is not
// in the schema, or with the wrong type, throws (a plugin bug, reported as an internal error).
class Params {
public:
    Params(const hsr_param_value* values, uint32_t count) : values_(values), count_(count) {}

    bool boolean(std::string_view name) const { return find(name, HSR_PARAM_BOOL).number != 0.0; }
    int64_t integer(std::string_view name) const {
        return static_cast<int64_t>(find(name, HSR_PARAM_INT).number);
    }
    double real(std::string_view name) const { return find(name, HSR_PARAM_FLOAT).number; }
    // Index of the chosen name within the choices string.
    int choice(std::string_view name) const {
        return static_cast<int>(find(name, HSR_PARAM_ENUM).number);
    }
    glm::vec3 color(std::string_view name) const {
        const hsr_param_value& v = find(name, HSR_PARAM_COLOR);
        return {v.color[0], v.color[1], v.color[2]};
    }

private:
    const hsr_param_value& find(std::string_view name, hsr_param_type type) const {
        for (uint32_t i = 0; i < count_; ++i) {
            const hsr_param_value& v = *HSR_ELEMENT(hsr_param_value, values_, i);
            if (v.name != nullptr && name == v.name) {
                if (v.type != type) throw std::logic_error("parameter '" + std::string(name) + "' read with the wrong type");
                return v;
            }
        }
        throw std::logic_error("parameter '" + std::string(name) + "' is not in the values the host passed");
    }
    const hsr_param_value* values_;
    uint32_t count_;
};

// A column-major float[16] of abi.h as a GLM matrix.
inline glm::mat4 load_matrix(const float (&m)[16]) {
    glm::mat4 r;
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) r[c][row] = m[4 * c + row];
    return r;
}

// The camera's section planes (ABI 1.4), world space: a point p is drawn only where
// dot(plane, (p, 1)) >= 0 for every plane. None when the host predates them.
struct ClipPlanes {
    uint32_t count = 0;
    glm::dvec4 plane[HSR_MAX_CLIP_PLANES];

    explicit ClipPlanes(const hsr_camera& camera) {
        if (camera.struct_size < offsetof(hsr_camera, clip_planes) + sizeof camera.clip_planes) return;
        count = camera.clip_plane_count < HSR_MAX_CLIP_PLANES ? camera.clip_plane_count : HSR_MAX_CLIP_PLANES;
        for (uint32_t k = 0; k < count; ++k) {
            const float* p = camera.clip_planes[k];
            plane[k] = glm::dvec4(p[0], p[1], p[2], p[3]);
        }
    }
    bool keeps(const glm::dvec3& p) const {
        for (uint32_t k = 0; k < count; ++k)
            if (glm::dot(plane[k], glm::dvec4(p, 1.0)) < 0.0) return false;
        return true;
    }
};

// For a plugin that cannot draw sections: throws Unsupported when the camera has clip planes.
inline void refuse_clip_planes(const char* plugin, const hsr_camera& camera) {
    if (ClipPlanes(camera).count > 0)
        throw Unsupported(std::string(plugin) + ": clip planes (sections) are not supported by this algorithm");
}

// One placement of triangles in the world (see Scene::placement): world = transform * object, and a
// normal n maps to rotation * n. `instance` is what goes into the visibility buffer's instance array.
struct Placement {
    uint32_t instance = 0;
    uint32_t first_triangle = 0;
    uint32_t triangle_count = 0;
    uint32_t first_vertex = 0;
    uint32_t vertex_count = 0;
    glm::mat4 transform{1.0f};
    glm::mat3 rotation{1.0f};
    float scale = 1.0f;
    glm::vec3 bounds_min{0.0f};  // world space
    glm::vec3 bounds_max{0.0f};
    bool identity = true;  // the scene has no instances: object space is world space
};

// Read-only view of hsr_scene with typed accessors. Cheap to copy.
class Scene {
public:
    explicit Scene(const hsr_scene& s) : s_(&s) {}

    const hsr_scene& raw() const { return *s_; }
    uint32_t vertex_count() const { return s_->vertex_count; }
    uint32_t triangle_count() const { return s_->triangle_count; }
    uint32_t object_count() const { return s_->object_count; }

    glm::vec3 position(uint32_t vertex) const { return load3(s_->positions, vertex); }
    uint32_t index(uint32_t triangle, int corner) const { return s_->indices[3 * triangle + corner]; }
    glm::vec3 corner_position(uint32_t triangle, int corner) const {
        return position(index(triangle, corner));
    }
    glm::vec3 face_normal(uint32_t triangle) const { return load3(s_->face_normals, triangle); }
    glm::vec3 corner_normal(uint32_t triangle, int corner) const {
        return load3(s_->corner_normals, 3 * triangle + corner);
    }
    glm::vec3 face_color(uint32_t triangle) const { return load3(s_->face_colors, triangle); }
    int32_t edge_neighbor(uint32_t triangle, int edge) const {
        return s_->edge_neighbors[3 * triangle + edge];
    }
    uint32_t face_object(uint32_t triangle) const { return s_->face_object[triangle]; }
    glm::vec3 bounds_min() const { return {s_->bounds_min[0], s_->bounds_min[1], s_->bounds_min[2]}; }
    glm::vec3 bounds_max() const { return {s_->bounds_max[0], s_->bounds_max[1], s_->bounds_max[2]}; }

    // Opacity of an object (ABI 1.4): 1 (opaque) when the scene gives none or the host predates it.
    float object_opacity(uint32_t object) const {
        return s_->struct_size >= offsetof(hsr_scene, object_opacity) + sizeof s_->object_opacity &&
                       s_->object_opacity != nullptr
                   ? s_->object_opacity[object]
                   : 1.0f;
    }
    // Whether any object is less than opaque.
    bool has_transparency() const {
        for (uint32_t k = 0; k < object_count(); ++k)
            if (object_opacity(k) < 1.0f) return true;
        return false;
    }

    // Instances (ABI 1.1); 0 when the scene has none or the host predates them.
    uint32_t instance_count() const {
        return s_->struct_size >= offsetof(hsr_scene, instances) + sizeof s_->instances && s_->instances != nullptr
                   ? s_->instance_count
                   : 0;
    }
    const hsr_instance& instance(uint32_t k) const { return *HSR_ELEMENT(hsr_instance, s_->instances, k); }

    // What is drawn, as a list of placements: each instance, or, in a scene without instances, the
    // whole mesh once with the identity transform. Renderers loop over these and need no other case.
    uint32_t placement_count() const { return instance_count() > 0 ? instance_count() : 1; }
    Placement placement(uint32_t k) const {
        Placement p;
        if (instance_count() == 0) {
            p.triangle_count = triangle_count();
            p.vertex_count = vertex_count();
            p.bounds_min = bounds_min();
            p.bounds_max = bounds_max();
            return p;
        }
        const hsr_instance& i = instance(k);
        p.instance = k;
        p.first_triangle = i.first_triangle;
        p.triangle_count = i.triangle_count;
        p.first_vertex = i.first_vertex;
        p.vertex_count = i.vertex_count;
        p.transform = load_matrix(i.transform);
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) p.rotation[c][r] = i.rotation[3 * c + r];
        p.scale = i.scale;
        p.bounds_min = {i.bounds_min[0], i.bounds_min[1], i.bounds_min[2]};
        p.bounds_max = {i.bounds_max[0], i.bounds_max[1], i.bounds_max[2]};
        p.identity = false;
        return p;
    }

private:
    static glm::vec3 load3(const float* a, uint32_t i) { return {a[3 * i], a[3 * i + 1], a[3 * i + 2]}; }
    const hsr_scene* s_;
};

// Mutable view of the visibility buffer.
class VisibilityBuffer {
public:
    explicit VisibilityBuffer(hsr_visibility_buffer& b) : b_(&b) {}
    uint32_t width() const { return b_->width; }
    uint32_t height() const { return b_->height; }
    float* depth() { return b_->depth; }
    uint32_t* face() { return b_->face; }
    float* bary() { return b_->bary; }
    // ABI 1.1: non-NULL exactly when the scene has instances.
    uint32_t* instance() { return has(offsetof(hsr_visibility_buffer, instance)) ? b_->instance : nullptr; }
    // ABI 1.1: NULL unless the host wants per-pixel depth-test counts.
    uint32_t* depth_tests() {
        return has(offsetof(hsr_visibility_buffer, depth_tests)) ? b_->depth_tests : nullptr;
    }
    hsr_visibility_buffer& raw() { return *b_; }

private:
    bool has(size_t field_offset) const { return b_->struct_size >= field_offset + sizeof(void*); }
    hsr_visibility_buffer* b_;
};

// Collects counters during a call and reports them to the host's sink at the end. Plugins keep hot
// counts in local integers and add them here once per triangle, tile or call, not per pixel.
class Counters {
public:
    void add(const char* name, uint64_t value) {
        for (auto& entry : entries_) {
            if (std::strcmp(entry.first, name) == 0) {
                entry.second += value;
                return;
            }
        }
        entries_.emplace_back(name, value);
    }
    void set(const char* name, uint64_t value) {
        for (auto& entry : entries_) {
            if (std::strcmp(entry.first, name) == 0) {
                entry.second = value;
                return;
            }
        }
        entries_.emplace_back(name, value);
    }
    const std::vector<std::pair<const char*, uint64_t>>& entries() const { return entries_; }
    void flush(const hsr_counter_sink* sink) const {
        if (sink == nullptr || sink->report == nullptr) return;
        for (const auto& [name, value] : entries_) sink->report(sink->context, name, value);
    }

private:
    std::vector<std::pair<const char*, uint64_t>> entries_;  // names are string literals
};

class HiddenSurfaceRemover {
public:
    virtual ~HiddenSurfaceRemover() = default;
    virtual void render(const Scene& scene, const hsr_camera& camera, VisibilityBuffer& target,
                        Counters& counters) = 0;
    // A remover that can show its steps (ABI 1.3) also declares
    //   void render_steps(const Scene&, const hsr_camera&, VisibilityBuffer&, Counters&, Steps&);
    // and the SDK fills IHiddenSurfaceRemover.render_steps with it. The usual shape is one template
    // drawing function, called with NoSteps from render() and with Steps from render_steps(), so that
    // the step code compiles away from render().
    // A remover that returns fragment lists (ABI 1.4: anti-aliasing, transparency) also declares
    //   void render_fragments(const Scene&, const hsr_camera&, VisibilityBuffer&, Counters&, FragmentWriter&);
    // and the SDK fills IHiddenSurfaceRemover.render_fragments with it.
};

// Thrown by Steps::step() when the host wants no more steps; the SDK turns it into HSR_OK. A remover
// that keeps results outside the visibility buffer until the end catches it, writes them, and
// rethrows.
struct StepLimitReached {};

// ABI 1.3: reports the steps of a hidden-surface algorithm (hsr_step_event). Describe a step with
// line(), box() and buffer(), then call step(): it sends the event, forgets the lines and buffers,
// and throws StepLimitReached when the host says stop.
class Steps {
public:
    static constexpr bool enabled = true;
    explicit Steps(const hsr_step_sink& sink) : sink_(&sink) {}

    // What a step did, besides its lines and buffers (see hsr_step_event).
    struct Event {
        const char* type;
        uint32_t face = HSR_NO_FACE;
        uint32_t instance = 0;
        uint32_t level = HSR_NO_LEVEL;
        uint64_t pixels_written = 0;
        uint64_t pixels_rejected = 0;
        const char* phase = nullptr;  // ABI 1.5: one of the plugin's phases
    };

    // ABI 1.5: the language the host wants step texts in ("en", "ru"; nullptr: English).
    const char* language() const { return sink_->language; }
    bool russian() const { return wants_language(sink_->language, "ru"); }

    void line(float x0, float y0, float x1, float y1, hsr_step_role role = HSR_STEP_SUBJECT) {
        lines_.insert(lines_.end(), {x0, y0, x1, y1});
        roles_.push_back(role);
    }
    // The outline of [x0, x1] x [y0, y1] in window coordinates, as four lines.
    void box(float x0, float y0, float x1, float y1, hsr_step_role role = HSR_STEP_SUBJECT) {
        line(x0, y0, x1, y0, role);
        line(x1, y0, x1, y1, role);
        line(x1, y1, x0, y1, role);
        line(x0, y1, x0, y0, role);
    }
    // values must stay valid until step() returns.
    void buffer(const char* name, uint32_t width, uint32_t height, const float* values) {
        buffers_.push_back({sizeof(hsr_step_buffer), width, height, name, values});
    }

    // text: one line for a person (printf format), or nullptr for the host's own.
    template <class... Args>
    void step(const Event& e, const char* format = nullptr, Args... args) {
        hsr_step_event out{};
        out.struct_size = sizeof out;
        out.type = e.type;
        if (format != nullptr) {
            if constexpr (sizeof...(Args) == 0)
                std::snprintf(text_, sizeof text_, "%s", format);
            else
                std::snprintf(text_, sizeof text_, format, args...);
            out.text = text_;
        }
        out.face = e.face;
        out.instance = e.instance;
        out.level = e.level;
        out.line_count = static_cast<uint32_t>(roles_.size());
        out.lines = lines_.empty() ? nullptr : lines_.data();
        out.line_roles = roles_.empty() ? nullptr : roles_.data();
        out.pixels_written = e.pixels_written;
        out.pixels_rejected = e.pixels_rejected;
        out.buffers = buffers_.empty() ? nullptr : buffers_.data();
        out.buffer_count = static_cast<uint32_t>(buffers_.size());
        out.phase = e.phase;
        ++count_;
        const uint32_t stop = sink_->step(sink_->context, &out);
        lines_.clear();
        roles_.clear();
        buffers_.clear();
        if (stop != 0) throw StepLimitReached{};
    }
    uint64_t count() const { return count_; }

private:
    const hsr_step_sink* sink_;
    std::vector<float> lines_;
    std::vector<uint32_t> roles_;
    std::vector<hsr_step_buffer> buffers_;
    char text_[512] = {};  // a line of Russian (two bytes a letter in UTF-8) fits
    uint64_t count_ = 0;
};

// The Steps of a render without steps: every call does nothing and compiles away. Guard the work
// of describing a step with `if constexpr (S::enabled)`.
struct NoSteps {
    static constexpr bool enabled = false;
    const char* language() const { return nullptr; }
    bool russian() const { return false; }
    void line(float, float, float, float, hsr_step_role = HSR_STEP_SUBJECT) {}
    void box(float, float, float, float, hsr_step_role = HSR_STEP_SUBJECT) {}
    void buffer(const char*, uint32_t, uint32_t, const float*) {}
    template <class... Args>
    void step(const Steps::Event&, const char* = nullptr, Args...) {}
    uint64_t count() const { return 0; }
};

template <class Derived>
class StepsDrawing;

// A remover whose steps come from the code that renders: derive from StepwiseRemover<Derived> and
// define (private, with `friend class hsr::sdk::StepwiseRemover<Derived>;`)
//   template <class StepsT>
//   void render_with(const Scene&, const hsr_camera&, VisibilityBuffer&, Counters&, StepsT& steps);
// render() calls it with NoSteps, so that the step code compiles away, and render_steps() (ABI 1.3)
// with Steps, through StepsDrawing<Derived> (below), which can be compiled in a translation unit of
// its own. Derived may also declare render_fragments (ABI 1.4) and draw its fragments with NoSteps.
template <class Derived>
class StepwiseRemover : public HiddenSurfaceRemover {
public:
    void render(const Scene& scene, const hsr_camera& camera, VisibilityBuffer& target, Counters& counters) final {
        NoSteps no_steps;
        static_cast<Derived*>(this)->render_with(scene, camera, target, counters, no_steps);
    }
    void render_steps(const Scene& scene, const hsr_camera& camera, VisibilityBuffer& target, Counters& counters,
                      Steps& steps) {
        StepsDrawing<Derived>::render_with(static_cast<Derived&>(*this), scene, camera, target, counters, steps);
    }

private:
    friend class StepsDrawing<Derived>;
    static void render_with_steps(Derived& remover, const Scene& scene, const hsr_camera& camera,
                                  VisibilityBuffer& target, Counters& counters, Steps& steps) {
        remover.render_with(scene, camera, target, counters, steps);
    }
};

// The Steps instantiation of a StepwiseRemover's render_with. Where render() and render_steps()
// share helpers, instantiating both in one translation unit can change how the compiler inlines
// render()'s (a helper called once becomes one called twice). To compile the steps apart, put the
// plugin's class in a header (in a named namespace: both units must name the same class), end the
// header with
//   extern template class hsr::sdk::StepsDrawing<MyRemover>;
// and instantiate it in a second source file of the plugin that includes the header:
//   template class hsr::sdk::StepsDrawing<MyRemover>;
template <class Derived>
class StepsDrawing {
public:
    static void render_with(Derived& remover, const Scene& scene, const hsr_camera& camera,
                            VisibilityBuffer& target, Counters& counters, Steps& steps);
};

// Not inline: under an `extern template` declaration, compilers still instantiate inline functions
// (to inline them), and with this one everything it draws with Steps.
template <class Derived>
void StepsDrawing<Derived>::render_with(Derived& remover, const Scene& scene, const hsr_camera& camera,
                                        VisibilityBuffer& target, Counters& counters, Steps& steps) {
    StepwiseRemover<Derived>::render_with_steps(remover, scene, camera, target, counters, steps);
}

// ABI 1.2: the edges a hidden-line remover is asked for (see hsr_line_request).
class LineRequest {
public:
    explicit LineRequest(const hsr_line_request& r) : r_(&r) {}
    const hsr_line_request& raw() const { return *r_; }
    uint32_t edge_count() const { return r_->edge_count; }
    uint32_t vertex(uint32_t edge, int end) const { return r_->edge_vertices[2 * edge + end]; }
    uint32_t face(uint32_t edge, int side) const { return r_->edge_faces[2 * edge + side]; }  // HSR_NO_FACE
    uint32_t flags(uint32_t edge) const { return r_->edge_flags[edge]; }
    bool want_hidden() const { return r_->want_hidden != 0; }

private:
    const hsr_line_request* r_;
};

// Collects segments and hands them to the host's sink in batches (never one by one).
class SegmentWriter {
public:
    static constexpr uint32_t kBatch = 4096;
    explicit SegmentWriter(const hsr_segment_sink& sink) : sink_(&sink) {}
    // (x0, y0)-(x1, y1) in window coordinates; qi 0 = visible, > 0 hidden behind qi faces, -1 hidden.
    void add(glm::vec2 a, glm::vec2 b, uint32_t edge, uint32_t flags, int32_t qi) {
        points_.insert(points_.end(), {a.x, a.y, b.x, b.y});
        edge_.push_back(edge);
        flags_.push_back(flags);
        qi_.push_back(qi);
        ++emitted_;
        if (edge_.size() >= kBatch) flush();
    }
    void flush() {
        if (edge_.empty()) return;
        hsr_segment_batch batch{};
        batch.struct_size = sizeof batch;
        batch.count = static_cast<uint32_t>(edge_.size());
        batch.points = points_.data();
        batch.edge = edge_.data();
        batch.flags = flags_.data();
        batch.qi = qi_.data();
        const hsr_status status = sink_->emit(sink_->context, &batch);
        points_.clear();
        edge_.clear();
        flags_.clear();
        qi_.clear();
        if (status != HSR_OK) throw std::runtime_error("the host refused a batch of segments");
    }
    uint64_t emitted() const { return emitted_; }

private:
    const hsr_segment_sink* sink_;
    std::vector<float> points_;
    std::vector<uint32_t> edge_, flags_;
    std::vector<int32_t> qi_;
    uint64_t emitted_ = 0;
};

// Hands fragment lists (ABI 1.4, hsr_pixel_fragments) to the host in batches. Add each pixel's
// fragments one after another, nearest first; a batch ends only between pixels.
class FragmentWriter {
public:
    static constexpr uint32_t kBatch = 8192;
    FragmentWriter(const hsr_fragment_sink& sink, bool instanced) : sink_(&sink), instanced_(instanced) {}
    void add(uint32_t pixel, uint32_t face, uint32_t instance, float depth, uint32_t coverage, float b1, float b2) {
        if (pixel != last_pixel_ && pixel_.size() >= kBatch) flush();
        last_pixel_ = pixel;
        pixel_.push_back(pixel);
        face_.push_back(face);
        instance_.push_back(instance);
        depth_.push_back(depth);
        coverage_.push_back(coverage);
        bary_.push_back(b1);
        bary_.push_back(b2);
        ++emitted_;
    }
    void flush() {
        if (pixel_.empty()) return;
        hsr_pixel_fragments batch{};
        batch.struct_size = sizeof batch;
        batch.count = static_cast<uint32_t>(pixel_.size());
        batch.pixel = pixel_.data();
        batch.face = face_.data();
        batch.instance = instanced_ ? instance_.data() : nullptr;
        batch.depth = depth_.data();
        batch.coverage = coverage_.data();
        batch.bary = bary_.data();
        const hsr_status status = sink_->emit(sink_->context, &batch);
        pixel_.clear();
        face_.clear();
        instance_.clear();
        depth_.clear();
        coverage_.clear();
        bary_.clear();
        if (status != HSR_OK) throw std::runtime_error("the host refused a batch of fragments");
    }
    uint64_t emitted() const { return emitted_; }

private:
    const hsr_fragment_sink* sink_;
    bool instanced_;
    uint32_t last_pixel_ = 0xFFFFFFFFu;
    std::vector<uint32_t> pixel_, face_, instance_, coverage_;
    std::vector<float> depth_, bary_;
    uint64_t emitted_ = 0;
};

// The optional step events (hsr_trace_event). Check enabled() before building an event's data.
class Trace {
public:
    // With `segments`, every event first hands the host the segments found so far, so that the
    // host sees segments and events in the order they were found (the viewer draws step k from the
    // segments before event k + 1). Without a trace, segments go in full batches as usual.
    explicit Trace(const hsr_trace_sink* sink, SegmentWriter* segments = nullptr)
        : sink_(sink != nullptr && sink->event != nullptr ? sink : nullptr), segments_(segments) {}
    bool enabled() const { return sink_ != nullptr; }
    struct Event {
        const char* type;
        uint32_t edge = HSR_NO_EDGE;
        uint32_t face = HSR_NO_FACE;
        uint32_t object = HSR_NO_OBJECT;
        int32_t qi = -1;
        double t0 = std::numeric_limits<double>::quiet_NaN();
        double t1 = std::numeric_limits<double>::quiet_NaN();
        const char* phase = nullptr;  // ABI 1.5: one of the plugin's phases
    };
    // ABI 1.5: the language the host wants step texts in ("en", "ru"; nullptr: English).
    const char* language() const { return sink_ != nullptr ? sink_->language : nullptr; }
    bool russian() const { return sink_ != nullptr && wants_language(sink_->language, "ru"); }
    // A line for the next emit() to show (window coordinates); guard the work of finding it with
    // enabled().
    void line(float x0, float y0, float x1, float y1, hsr_step_role role = HSR_STEP_SUBJECT) const {
        if (sink_ == nullptr) return;
        lines_.insert(lines_.end(), {x0, y0, x1, y1});
        roles_.push_back(role);
    }
    // text: one line for a person (printf format), or nullptr for the host's own.
    template <class... Args>
    void emit(const Event& e, const char* format = nullptr, Args... args) const {
        if (sink_ == nullptr) return;
        if (segments_ != nullptr) segments_->flush();
        hsr_trace_event out{};
        out.struct_size = sizeof out;
        out.type = e.type;
        out.edge = e.edge;
        out.face = e.face;
        out.object = e.object;
        out.qi = e.qi;
        out.t0 = e.t0;
        out.t1 = e.t1;
        if (format != nullptr) {
            if constexpr (sizeof...(Args) == 0)
                std::snprintf(text_, sizeof text_, "%s", format);
            else
                std::snprintf(text_, sizeof text_, format, args...);
            out.text = text_;
        }
        out.line_count = static_cast<uint32_t>(roles_.size());
        out.lines = lines_.empty() ? nullptr : lines_.data();
        out.line_roles = roles_.empty() ? nullptr : roles_.data();
        out.phase = e.phase;
        sink_->event(sink_->context, &out);
        lines_.clear();
        roles_.clear();
    }

private:
    const hsr_trace_sink* sink_;
    SegmentWriter* segments_;
    // The lines and text under construction: filled through a const Trace, as emit() is const.
    mutable std::vector<float> lines_;
    mutable std::vector<uint32_t> roles_;
    mutable char text_[256] = {};
};

// A hidden-line algorithm (ABI 1.2): finds the visible (and on request hidden) pieces of the requested
// edges. The scene has no instances (the host copies them out).
class HiddenLineRemover {
public:
    virtual ~HiddenLineRemover() = default;
    virtual void render_lines(const Scene& scene, const hsr_camera& camera, const LineRequest& request,
                              SegmentWriter& segments, const Trace& trace, Counters& counters) = 0;
};

class LightingModel {
public:
    virtual ~LightingModel() = default;
    virtual void prepare(const Scene& scene, const hsr_shading_context& context) = 0;
    // Must be thread-safe: it only reads what prepare() built. The host calls it from oneTBB's
    // worker threads, several batches at once, as many as --threads allows.
    virtual void shade(hsr_fragment_batch& batch) const = 0;
};

namespace detail {

inline void write_error(hsr_error* error, const char* message) {
    if (error == nullptr) return;
    std::snprintf(error->message, sizeof error->message, "%s", message);
}

// Runs f, turning every exception into a status code and a message.
template <class F>
hsr_status guarded(hsr_error* error, F&& f) noexcept {
    try {
        f();
        return HSR_OK;
    } catch (const InvalidArgument& e) {
        write_error(error, e.what());
        return HSR_ERROR_INVALID_ARGUMENT;
    } catch (const Unsupported& e) {
        write_error(error, e.what());
        return HSR_ERROR_UNSUPPORTED;
    } catch (const std::bad_alloc&) {
        write_error(error, "out of memory");
        return HSR_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        write_error(error, e.what());
        return HSR_ERROR_INTERNAL;
    } catch (...) {
        write_error(error, "unknown exception inside the plugin");
        return HSR_ERROR_INTERNAL;
    }
}

template <class T>
hsr_status create(const hsr_param_value* params, uint32_t count, void** instance, hsr_error* error) {
    return guarded(error, [&] {
        if (instance == nullptr) throw InvalidArgument("create: instance pointer is NULL");
        *instance = new T(Params(params, count));
    });
}

template <class T>
void destroy(void* instance) {
    delete static_cast<T*>(instance);
}

template <class T>
hsr_status render(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                  hsr_visibility_buffer* target, const hsr_counter_sink* sink, hsr_error* error) {
    return guarded(error, [&] {
        if (instance == nullptr || scene == nullptr || camera == nullptr || target == nullptr)
            throw InvalidArgument("render: NULL argument");
        Scene scene_view(*scene);
        VisibilityBuffer buffer(*target);
        Counters counters;
        static_cast<T*>(instance)->render(scene_view, *camera, buffer, counters);
        counters.flush(sink);
    });
}

template <class T>
concept HasSteps = requires(T& remover, const Scene& scene, const hsr_camera& camera, VisibilityBuffer& target,
                            Counters& counters, Steps& steps) {
    remover.render_steps(scene, camera, target, counters, steps);
};

template <class T>
hsr_status render_steps(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                        hsr_visibility_buffer* target, const hsr_counter_sink* sink, const hsr_step_sink* step_sink,
                        hsr_error* error) {
    return guarded(error, [&] {
        if (instance == nullptr || scene == nullptr || camera == nullptr || target == nullptr ||
            step_sink == nullptr || step_sink->step == nullptr)
            throw InvalidArgument("render_steps: NULL argument");
        Scene scene_view(*scene);
        VisibilityBuffer buffer(*target);
        Counters counters;
        Steps steps(*step_sink);
        try {
            static_cast<T*>(instance)->render_steps(scene_view, *camera, buffer, counters, steps);
        } catch (const StepLimitReached&) {
        }
        counters.set("steps", steps.count());
        counters.flush(sink);
    });
}

template <class T>
constexpr auto render_steps_entry() {
    using Entry = decltype(IHiddenSurfaceRemover::render_steps);
    if constexpr (HasSteps<T>)
        return Entry{&render_steps<T>};
    else
        return Entry{nullptr};
}

template <class T>
concept HasFragments = requires(T& remover, const Scene& scene, const hsr_camera& camera, VisibilityBuffer& target,
                                Counters& counters, FragmentWriter& fragments) {
    remover.render_fragments(scene, camera, target, counters, fragments);
};

template <class T>
hsr_status render_fragments(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                            hsr_visibility_buffer* target, const hsr_counter_sink* sink,
                            const hsr_fragment_sink* fragment_sink, hsr_error* error) {
    return guarded(error, [&] {
        if (instance == nullptr || scene == nullptr || camera == nullptr || target == nullptr ||
            fragment_sink == nullptr || fragment_sink->emit == nullptr)
            throw InvalidArgument("render_fragments: NULL argument");
        Scene scene_view(*scene);
        VisibilityBuffer buffer(*target);
        Counters counters;
        FragmentWriter writer(*fragment_sink, scene_view.instance_count() > 0);
        static_cast<T*>(instance)->render_fragments(scene_view, *camera, buffer, counters, writer);
        writer.flush();
        counters.flush(sink);
    });
}

template <class T>
constexpr auto render_fragments_entry() {
    using Entry = decltype(IHiddenSurfaceRemover::render_fragments);
    if constexpr (HasFragments<T>)
        return Entry{&render_fragments<T>};
    else
        return Entry{nullptr};
}

template <class T>
hsr_status render_lines(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                        const hsr_line_request* request, const hsr_segment_sink* segments,
                        const hsr_trace_sink* trace, const hsr_counter_sink* sink, hsr_error* error) {
    return guarded(error, [&] {
        if (instance == nullptr || scene == nullptr || camera == nullptr || request == nullptr ||
            segments == nullptr || segments->emit == nullptr)
            throw InvalidArgument("render_lines: NULL argument");
        Scene scene_view(*scene);
        if (scene_view.instance_count() > 0)
            throw InvalidArgument("render_lines: the host must copy instances out for a hidden-line remover");
        SegmentWriter writer(*segments);
        Counters counters;
        static_cast<T*>(instance)->render_lines(scene_view, *camera, LineRequest(*request), writer,
                                                Trace(trace, &writer), counters);
        writer.flush();
        counters.set("segments", writer.emitted());
        counters.flush(sink);
    });
}

template <class T>
hsr_status prepare(void* instance, const hsr_scene* scene, const hsr_shading_context* context,
                   hsr_error* error) {
    return guarded(error, [&] {
        if (instance == nullptr || scene == nullptr || context == nullptr)
            throw InvalidArgument("prepare: NULL argument");
        static_cast<T*>(instance)->prepare(Scene(*scene), *context);
    });
}

template <class T>
hsr_status shade(const void* instance, hsr_fragment_batch* batch, hsr_error* error) {
    return guarded(error, [&] {
        if (instance == nullptr || batch == nullptr) throw InvalidArgument("shade: NULL argument");
        static_cast<const T*>(instance)->shade(*batch);
    });
}

inline const void* no_extension(const char*) { return nullptr; }

template <class T>
constexpr hsr_plugin_kind kind_of() {
    if constexpr (std::is_base_of_v<HiddenSurfaceRemover, T>)
        return HSR_KIND_HIDDEN_SURFACE_REMOVER;
    else if constexpr (std::is_base_of_v<HiddenLineRemover, T>)
        return HSR_KIND_HIDDEN_LINE_REMOVER;
    else {
        static_assert(std::is_base_of_v<LightingModel, T>,
                      "a plugin class derives from hsr::sdk::HiddenSurfaceRemover, HiddenLineRemover or LightingModel");
        return HSR_KIND_LIGHTING_MODEL;
    }
}

template <class T>
const void* interface_table() {
    if constexpr (kind_of<T>() == HSR_KIND_HIDDEN_SURFACE_REMOVER) {
        static const IHiddenSurfaceRemover table{sizeof(IHiddenSurfaceRemover), &create<T>, &destroy<T>,
                                                 &render<T>, &no_extension, render_steps_entry<T>(),
                                                 render_fragments_entry<T>()};
        return &table;
    } else if constexpr (kind_of<T>() == HSR_KIND_HIDDEN_LINE_REMOVER) {
        static const IHiddenLineRemover table{sizeof(IHiddenLineRemover), &create<T>, &destroy<T>,
                                              &render_lines<T>, &no_extension};
        return &table;
    } else {
        static const ILightingModel table{sizeof(ILightingModel), &create<T>, &destroy<T>,
                                          &prepare<T>, &shade<T>, &no_extension};
        return &table;
    }
}

template <class T>
const hsr_param_desc* param_table(uint32_t& count) {
    static const std::vector<hsr_param_desc> table = [] {
        std::vector<hsr_param_desc> descs;
        for (const ParamSpec& spec : T::params) descs.push_back(spec.desc);
        return descs;
    }();
    count = static_cast<uint32_t>(table.size());
    return table.empty() ? nullptr : table.data();
}

template <class T>
const hsr_phase_desc* phase_table(uint32_t& count) {
    if constexpr (requires { T::phases; }) {
        static const std::vector<hsr_phase_desc> table = [] {
            std::vector<hsr_phase_desc> descs;
            for (const PhaseSpec& spec : T::phases) descs.push_back({sizeof(hsr_phase_desc), spec.name, spec.title});
            return descs;
        }();
        count = static_cast<uint32_t>(table.size());
        return table.empty() ? nullptr : table.data();
    } else {
        count = 0;
        return nullptr;
    }
}

template <class T>
const hsr_translation* translation_table(uint32_t& count) {
    static const std::vector<hsr_translation> table = [] {
        std::vector<hsr_translation> entries;
        auto add = [&](const TranslationSpec& spec) {
            for (const hsr_translation& t : entries)
                if (std::strcmp(t.language, spec.language) == 0 && std::strcmp(t.key, spec.key) == 0) return;
            entries.push_back({sizeof(hsr_translation), spec.language, spec.key, spec.text});
        };
        if constexpr (requires { T::translations; })
            for (const TranslationSpec& spec : T::translations) add(spec);
        if constexpr (kind_of<T>() == HSR_KIND_HIDDEN_SURFACE_REMOVER)
            for (const TranslationSpec& spec : step_counter_translations) add(spec);
        return entries;
    }();
    count = static_cast<uint32_t>(table.size());
    return table.empty() ? nullptr : table.data();
}

template <class T>
const hsr_plugin_descriptor* descriptor() {
    static const hsr_plugin_descriptor d = [] {
        hsr_plugin_descriptor out{};
        out.struct_size = sizeof(hsr_plugin_descriptor);
        out.api = HSR_API_NAME;
        out.abi_major = HSR_ABI_MAJOR;
        out.abi_minor = HSR_ABI_MINOR;
        out.kind = kind_of<T>();
        out.name = T::info.name;
        out.version = T::info.version;
        out.description = T::info.description;
        out.params = param_table<T>(out.param_count);
        out.interface_table = interface_table<T>();
        out.phases = phase_table<T>(out.phase_count);
        out.translations = translation_table<T>(out.translation_count);
        return out;
    }();
    return &d;
}

}  // namespace detail
}  // namespace hsr::sdk

namespace hsr::sdk::detail {
template <class... Plugins>
const hsr_plugin_descriptor* descriptor_at(uint32_t index) {
    const hsr_plugin_descriptor* all[] = {descriptor<Plugins>()...};
    return index < sizeof...(Plugins) ? all[index] : nullptr;
}
}  // namespace hsr::sdk::detail

// The library's one exported symbol, describing the plugin classes it holds (usually one). A plugin
// class with no parameters declares: static inline const std::array<hsr::sdk::ParamSpec, 0> params{};
#define HSR_EXPORT_PLUGINS(...)                                                                     \
    extern "C" HSR_EXPORT const hsr_plugin_descriptor* hsr_plugin_entry(uint32_t index) {           \
        return ::hsr::sdk::detail::descriptor_at<__VA_ARGS__>(index);                              \
    }
#define HSR_EXPORT_PLUGIN(PluginClass) HSR_EXPORT_PLUGINS(PluginClass)
