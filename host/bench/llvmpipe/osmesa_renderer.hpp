// An hsr scene drawn by Mesa's llvmpipe through OSMesa (an OpenGL 3.3 core context rendering into
// memory): per-pixel Blinn-Phong in a GLSL fragment shader with the formulas of hsr/shading.hpp
// (Blinn, SIGGRAPH 1977), depth test "less", no culling. The yardstick of bench/llvmpipe/main.cpp.
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hsr::llvmpipe {

// The coefficients of the blinn-phong lighting plugin (hsr/shading.hpp's Material).
struct BlinnPhongMaterial {
    float ambient = 0.1f, diffuse = 0.8f, specular = 0.5f, shininess = 64.0f;
    glm::vec3 specular_color{1.0f};
    bool two_sided = true;
};

class OsmesaRenderer {
public:
    // The context and its width x height colour (RGBA8) and depth (24-bit) buffers; llvmpipe takes
    // its thread count from LP_NUM_THREADS, read here. Throws hsr::Error when OSMesa refuses.
    OsmesaRenderer(uint32_t width, uint32_t height);
    ~OsmesaRenderer();
    OsmesaRenderer(const OsmesaRenderer&) = delete;
    OsmesaRenderer& operator=(const OsmesaRenderer&) = delete;

    // The triangles into a vertex buffer (position, corner normal, face colour) and an index
    // buffer, once. The scene must have no instances.
    void upload(const hsr_scene& scene);
    size_t vertex_count() const;  // distinct vertices uploaded
    // Camera, lights, viewer and material as uniforms; the background as the clear colour.
    void set_view(const hsr_camera& camera, const hsr_shading_context& context, const BlinnPhongMaterial& material,
                  glm::vec3 background);
    // One complete frame: clear, draw, glFinish.
    void draw_frame();
    // The frame as RGBA, rows top to bottom; alpha is 255 where a triangle was drawn, 0 elsewhere.
    std::vector<uint8_t> read_rgba() const;
    // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6".
    std::string description() const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace hsr::llvmpipe
