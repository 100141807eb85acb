// The OSMesa context, the shaders and the draw call of the llvmpipe yardstick (osmesa_renderer.hpp).
// The fragment shader is LightEnvironment::reflect and ShadedLightingModel::shade_phong of
// hsr/shading.hpp with the normal assembly of framework/src/fragment_assembly.hpp; the face's side
// comes from gl_FrontFacing, so that vertices need no face normal and can be shared.
#define GL_GLEXT_PROTOTYPES 1
#include "bench/llvmpipe/osmesa_renderer.hpp"

#include "hsr/error.hpp"

#include <GL/osmesa.h>
#include <GL/glext.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <unordered_map>

namespace hsr::llvmpipe {
namespace {

// Lights of each kind the shader holds; more is a one-line error.
constexpr size_t max_lights = 16;

const char* const vertex_shader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 corner_normal;
layout(location = 2) in vec3 face_color;
uniform mat4 view_projection;
out vec3 world_position;
out vec3 normal;
flat out vec3 flat_face_color;
void main() {
    world_position = position;
    normal = corner_normal;
    flat_face_color = face_color;
    gl_Position = view_projection * vec4(position, 1.0);
}
)";

// After a preamble that fixes the light counts, the projection and two-sidedness as constants, as an
// application compiles a shader variant for its lights: the loops unroll and the branches fold.
const char* const fragment_shader = R"(
uniform vec3 directional_direction[max(DIRECTIONAL_LIGHTS, 1)];  // unit, toward the light
uniform vec3 directional_radiance[max(DIRECTIONAL_LIGHTS, 1)];   // colour * intensity
uniform vec3 point_position[max(POINT_LIGHTS, 1)];
uniform vec3 point_radiance[max(POINT_LIGHTS, 1)];
uniform vec3 eye;            // perspective
uniform vec3 toward_viewer;  // orthographic
uniform float ambient;
uniform float diffuse;
uniform float specular;
uniform float shininess;
uniform vec3 specular_color;
in vec3 world_position;
in vec3 normal;
flat in vec3 flat_face_color;
out vec4 color;

vec3 n;
vec3 v;
vec3 diffuse_sum = vec3(0.0);
vec3 specular_sum = vec3(0.0);

void add(vec3 l, vec3 radiance) {
    float n_dot_l = dot(n, l);
    if (n_dot_l <= 0.0) return;
    diffuse_sum += radiance * n_dot_l;
    vec3 sum = l + v;
    float length_squared = dot(sum, sum);
    if (length_squared <= 0.0) return;
    float n_dot_h = dot(n, sum) / sqrt(length_squared);
    if (n_dot_h > 0.0) specular_sum += radiance * pow(n_dot_h, shininess);
}

void main() {
    vec3 p = world_position;
#if PERSPECTIVE
    vec3 d = eye - p;
    float length_squared = dot(d, d);
    v = length_squared > 0.0 ? d / sqrt(length_squared) : vec3(0.0);
#else
    v = toward_viewer;
#endif
    // Two-sided: the face's normal points away from the viewer exactly when the triangle, counter-
    // clockwise from the front, is clockwise on screen (!gl_FrontFacing).
    float len = length(normal);
    if (len > 0.0) {
        n = normal / len;
#if TWO_SIDED
        if (!gl_FrontFacing) n = -n;
#endif
    } else {
        // Corner normals that cancel: the face normal, from the position's screen derivatives
        // (whose cross product points toward the viewer).
        n = normalize(cross(dFdx(p), dFdy(p)));
#if !TWO_SIDED
        if (!gl_FrontFacing) n = -n;
#endif
    }
    for (int i = 0; i < DIRECTIONAL_LIGHTS; ++i) add(directional_direction[i], directional_radiance[i]);
    for (int i = 0; i < POINT_LIGHTS; ++i) {
        vec3 to_light = point_position[i] - p;
        float length_squared = dot(to_light, to_light);
        if (length_squared > 0.0) add(to_light / sqrt(length_squared), point_radiance[i]);
    }
    vec3 c = flat_face_color * (ambient + diffuse * diffuse_sum) + specular * specular_color * specular_sum;
    color = vec4(clamp(c, 0.0, 1.0), 1.0);
}
)";

GLuint compile(GLenum type, const std::string& source) {
    const GLuint shader = glCreateShader(type);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        char log[2048] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        throw Error("llvmpipe: the {} shader does not compile: {}", type == GL_VERTEX_SHADER ? "vertex" : "fragment",
                    log);
    }
    return shader;
}

}  // namespace

struct OsmesaRenderer::State {
    OSMesaContext context = nullptr;
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> buffer;  // the colour buffer OSMesa draws into, rows bottom to top
    GLuint program = 0, vertex_array = 0, vertex_buffer = 0, index_buffer = 0;
    GLsizei index_count = 0;
    size_t vertex_count = 0;
    GLint uniform(const char* name) const { return glGetUniformLocation(program, name); }
};

OsmesaRenderer::OsmesaRenderer(uint32_t width, uint32_t height) : state_(std::make_unique<State>()) {
    State& s = *state_;
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
                              OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    s.context = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!s.context) throw Error("llvmpipe: OSMesa gives no OpenGL 3.3 core context");
    s.width = width;
    s.height = height;
    s.buffer.resize(4 * size_t{width} * height);
    if (!OSMesaMakeCurrent(s.context, s.buffer.data(), GL_UNSIGNED_BYTE, GLsizei(width), GLsizei(height))) {
        OSMesaDestroyContext(s.context);
        throw Error("llvmpipe: OSMesa cannot draw a {}x{} image", width, height);
    }
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (!renderer || !std::strstr(renderer, "llvmpipe")) {
        OSMesaDestroyContext(s.context);
        throw Error("llvmpipe: OSMesa runs '{}', not llvmpipe (is GALLIUM_DRIVER set?)", renderer ? renderer : "?");
    }
    glGenVertexArrays(1, &s.vertex_array);
    glBindVertexArray(s.vertex_array);
    glGenBuffers(1, &s.vertex_buffer);
    glGenBuffers(1, &s.index_buffer);
    glViewport(0, 0, GLsizei(width), GLsizei(height));
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
}

OsmesaRenderer::~OsmesaRenderer() {
    if (state_ && state_->context) OSMesaDestroyContext(state_->context);
}

void OsmesaRenderer::upload(const hsr_scene& scene) {
    if (scene.instance_count > 0) throw Error("llvmpipe: internal error: a scene with instances (flatten it first)");
    State& s = *state_;
    // A vertex per distinct (position, corner normal, face colour), shared through the index buffer
    // as an application would share it; the face colour is flat, from the provoking vertex, which
    // carries the face's own colour.
    constexpr int floats_per_vertex = 9;
    using Key = std::array<uint32_t, 7>;  // position index, then the bits of the normal and colour
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = 1469598103934665603ull;
            for (uint32_t word : k) h = (h ^ word) * 1099511628211ull;
            return size_t(h);
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> vertex_of;
    vertex_of.reserve(3 * size_t{scene.triangle_count} / 2);
    std::vector<float> vertices;
    std::vector<uint32_t> indices(3 * size_t{scene.triangle_count});
    for (uint32_t t = 0; t < scene.triangle_count; ++t) {
        const float* color = scene.face_colors + 3 * size_t{t};
        for (int corner = 0; corner < 3; ++corner) {
            const uint32_t position = scene.indices[3 * size_t{t} + corner];
            const float* normal = scene.corner_normals + 9 * size_t{t} + 3 * corner;
            Key key{position};
            std::memcpy(&key[1], normal, 3 * sizeof(float));
            std::memcpy(&key[4], color, 3 * sizeof(float));
            const auto [it, added] = vertex_of.try_emplace(key, uint32_t(vertices.size() / floats_per_vertex));
            if (added) {
                vertices.insert(vertices.end(), scene.positions + 3 * size_t{position},
                                scene.positions + 3 * size_t{position} + 3);
                vertices.insert(vertices.end(), normal, normal + 3);
                vertices.insert(vertices.end(), color, color + 3);
            }
            indices[3 * size_t{t} + corner] = it->second;
        }
    }
    glBindBuffer(GL_ARRAY_BUFFER, s.vertex_buffer);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, s.index_buffer);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * sizeof(uint32_t)), indices.data(),
                 GL_STATIC_DRAW);
    for (GLuint attribute = 0; attribute < 3; ++attribute) {
        glEnableVertexAttribArray(attribute);
        glVertexAttribPointer(attribute, 3, GL_FLOAT, GL_FALSE, floats_per_vertex * sizeof(float),
                              reinterpret_cast<const void*>(size_t{attribute} * 3 * sizeof(float)));
    }
    s.index_count = GLsizei(indices.size());
    s.vertex_count = vertices.size() / floats_per_vertex;
}

size_t OsmesaRenderer::vertex_count() const { return state_->vertex_count; }

void OsmesaRenderer::set_view(const hsr_camera& camera, const hsr_shading_context& context,
                              const BlinnPhongMaterial& material, glm::vec3 background) {
    State& s = *state_;
    std::vector<glm::vec3> directional_direction, directional_radiance, point_position, point_radiance;
    for (uint32_t i = 0; i < context.light_count; ++i) {
        const hsr_light& light = *HSR_ELEMENT(hsr_light, context.lights, i);
        const glm::vec3 vector{light.vector[0], light.vector[1], light.vector[2]};
        const glm::vec3 radiance = glm::vec3{light.color[0], light.color[1], light.color[2]} * light.intensity;
        if (light.type == HSR_LIGHT_DIRECTIONAL) {
            directional_direction.push_back(vector / glm::length(vector));
            directional_radiance.push_back(radiance);
        } else {
            point_position.push_back(vector);
            point_radiance.push_back(radiance);
        }
    }
    if (directional_direction.size() > max_lights || point_position.size() > max_lights)
        throw Error("llvmpipe: at most {} directional and {} point lights", max_lights, max_lights);
    const bool perspective = context.projection_type == HSR_PROJECTION_PERSPECTIVE;
    const std::string preamble =
        fmt::format("#version 330 core\n#define DIRECTIONAL_LIGHTS {}\n#define POINT_LIGHTS {}\n#define PERSPECTIVE {}\n"
                    "#define TWO_SIDED {}\n",
                    directional_direction.size(), point_position.size(), perspective ? 1 : 0,
                    material.two_sided ? 1 : 0);
    if (s.program) glDeleteProgram(s.program);
    s.program = glCreateProgram();
    glAttachShader(s.program, compile(GL_VERTEX_SHADER, vertex_shader));
    glAttachShader(s.program, compile(GL_FRAGMENT_SHADER, preamble + fragment_shader));
    glLinkProgram(s.program);
    GLint ok = GL_FALSE;
    glGetProgramiv(s.program, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) throw Error("llvmpipe: the shaders do not link");
    glUseProgram(s.program);
    glUniformMatrix4fv(s.uniform("view_projection"), 1, GL_FALSE, camera.view_projection);
    if (!directional_direction.empty()) {
        glUniform3fv(s.uniform("directional_direction"), GLsizei(directional_direction.size()), &directional_direction[0].x);
        glUniform3fv(s.uniform("directional_radiance"), GLsizei(directional_radiance.size()), &directional_radiance[0].x);
    }
    if (!point_position.empty()) {
        glUniform3fv(s.uniform("point_position"), GLsizei(point_position.size()), &point_position[0].x);
        glUniform3fv(s.uniform("point_radiance"), GLsizei(point_radiance.size()), &point_radiance[0].x);
    }
    const glm::vec3 view_direction{context.view_direction[0], context.view_direction[1], context.view_direction[2]};
    const glm::vec3 toward_viewer = -view_direction / glm::length(view_direction);
    glUniform3f(s.uniform("eye"), context.eye[0], context.eye[1], context.eye[2]);
    glUniform3f(s.uniform("toward_viewer"), toward_viewer.x, toward_viewer.y, toward_viewer.z);
    glUniform1f(s.uniform("ambient"), material.ambient);
    glUniform1f(s.uniform("diffuse"), material.diffuse);
    glUniform1f(s.uniform("specular"), material.specular);
    glUniform1f(s.uniform("shininess"), material.shininess);
    glUniform3f(s.uniform("specular_color"), material.specular_color.x, material.specular_color.y,
                material.specular_color.z);
    glClearColor(background.r, background.g, background.b, 0.0f);
}

void OsmesaRenderer::draw_frame() {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawElements(GL_TRIANGLES, state_->index_count, GL_UNSIGNED_INT, nullptr);
    glFinish();
}

std::vector<uint8_t> OsmesaRenderer::read_rgba() const {
    const State& s = *state_;
    const size_t row = 4 * size_t{s.width};
    std::vector<uint8_t> out(s.buffer.size());
    for (uint32_t y = 0; y < s.height; ++y)
        std::copy_n(s.buffer.data() + (s.height - 1 - y) * row, row, out.data() + y * row);
    return out;
}

std::string OsmesaRenderer::description() const {
    auto text = [](GLenum name) {
        const char* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s ? s : "?");
    };
    return text(GL_RENDERER) + ", " + text(GL_VERSION);
}

}  // namespace hsr::llvmpipe
