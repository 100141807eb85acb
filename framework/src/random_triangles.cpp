// Random triangles for hidden-surface exercises (random_triangles.hpp).
#include "hsr/random_triangles.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/scene_builder.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace hsr {
namespace {

// Uniform in [0, 1): the top 53 bits of one mt19937_64 output, exactly representable in a double.
class UnitRandom {
public:
    explicit UnitRandom(uint64_t seed) : engine_(seed) {}
    double next() { return double(engine_() >> 11) * 0x1.0p-53; }
    double between(double lo, double hi) { return lo + (hi - lo) * next(); }

private:
    std::mt19937_64 engine_;
};

// HSV (h in [0, 1)) to RGB.
glm::vec3 hsv_to_rgb(double h, double s, double v) {
    const double h6 = h * 6.0;
    const int sector = int(h6) % 6;
    const double f = h6 - std::floor(h6);
    const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    const double rgb[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
    return {float(rgb[sector][0]), float(rgb[sector][1]), float(rgb[sector][2])};
}

}  // namespace

SceneData make_random_triangles(uint64_t count, uint64_t seed) {
    if (count == 0) throw Error("random triangles: the count must be at least 1");
    check_limit(&Limits::stored_triangles, count, "random triangles");
    check_limit(&Limits::triangles, count, "random triangles");
    if (count > UINT32_MAX / 3) throw Error("random triangles: {} is more than a scene can index", count);
    UnitRandom random(seed);
    std::vector<glm::vec3> positions;
    positions.reserve(3 * count);
    std::vector<glm::vec3> colors;
    colors.reserve(count);
    const double extent = random_triangles_extent;
    // Hues step by the golden ratio from a random start, so that every triangle has its own hue and
    // neighbours in the list differ strongly; saturation and value vary a little.
    const double hue_start = random.next();
    for (uint64_t i = 0; i < count; ++i) {
        // Sizes from a tenth of the cube's side to most of it, log-uniform: many small triangles,
        // some large ones that cut through the others.
        const double radius = extent * 0.1 * std::exp(random.next() * std::log(8.0));
        glm::dvec3 centre;
        for (int k = 0; k < 3; ++k) centre[k] = random.between(-extent + radius, extent - radius);
        glm::dvec3 corner[3];
        for (;;) {  // redraw a sliver: smallest height under a tenth of the longest side, or a tiny one
            for (glm::dvec3& c : corner)
                for (int k = 0; k < 3; ++k) c[k] = centre[k] + radius * random.between(-1.0, 1.0);
            const double area2 = glm::length(glm::cross(corner[1] - corner[0], corner[2] - corner[0]));
            const double longest = std::max({glm::length(corner[1] - corner[0]), glm::length(corner[2] - corner[1]),
                                             glm::length(corner[0] - corner[2])});
            if (longest > 0.5 * radius && area2 / longest > 0.1 * longest) break;
        }
        for (const glm::dvec3& c : corner) positions.emplace_back(c);
        colors.push_back(hsv_to_rgb(std::fmod(hue_start + double(i) * 0.6180339887498949, 1.0),
                                    random.between(0.45, 0.85), random.between(0.7, 0.95)));
    }
    std::vector<uint32_t> indices(3 * count);
    for (uint32_t k = 0; k < indices.size(); ++k) indices[k] = k;
    SceneBuilder builder;
    MeshOptions options;
    options.name = "random triangles";
    options.crease_angle_degrees = 0.0f;
    builder.add_triangles(positions, indices, options);
    SceneData scene = builder.build();
    if (scene.triangle_count() != count)
        throw Error("random triangles: {} of {} triangles were dropped while building the scene",
                    count - scene.triangle_count(), count);
    for (uint64_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) scene.face_colors[3 * i + k] = colors[i][k];
    return scene;
}

}  // namespace hsr
