// The lighting models' specular power (hsr/specular_power.hpp) against independent answers: its
// error against x^y in double precision over dense sets of bases and the exponents of the plugins
// and the docs, and whole pictures (bunny and monkey, Blinn-Phong and Phong, with and without
// instances) shaded through the lighting plugins against pictures shaded here with std::pow (the C
// library's powf): no 8-bit channel may differ by more than 1.
#include "../framework/src/fragment_assembly.hpp"

#include "hsr/camera.hpp"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/shading.hpp"
#include "hsr/specular_power.hpp"
#include "test_models.hpp"

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

constexpr float kExponents[] = {1.0f, 7.3f, 32.0f, 64.0f, 150.0f, 500.5f, 1000.0f};

// The largest (|power - x^y| - 2^-149) / x^y over the floats x in (0, top] whose bit patterns are
// multiples of `stride` or lie within `near_top` patterns of top.
double largest_relative_error(float y, uint32_t stride, uint32_t near_top, float top) {
    const uint32_t top_bits = std::bit_cast<uint32_t>(top);
    double largest = 0.0;
    auto check = [&](uint32_t bits) {
        const float x = std::bit_cast<float>(bits);
        const double exact = std::pow(double(x), double(y));
        const double error = std::fabs(double(hsr::shading::specular_power(x, y)) - exact);
        largest = std::max(largest, (error - 0x1p-149) / exact);
    };
    for (uint32_t bits = stride; bits <= top_bits; bits += stride) check(bits);
    for (uint32_t bits = top_bits - near_top; bits <= top_bits; ++bits) check(bits);
    return largest;
}

struct PowBlinnPhong {  // blinn_phong_specular with std::pow
    static constexpr bool has_specular = true;
    static constexpr hsr::shading::SpecularKind kind = hsr::shading::SpecularKind::blinn;
    float operator()(glm::vec3 n, glm::vec3 l, glm::vec3 v, float shininess) const {
        if (glm::dot(n, l) <= 0.0f) return 0.0f;
        const glm::vec3 sum = l + v;
        const float length_squared = glm::dot(sum, sum);
        if (length_squared <= 0.0f) return 0.0f;
        const float n_dot_h = glm::dot(n, sum) / std::sqrt(length_squared);
        return n_dot_h > 0.0f ? std::pow(n_dot_h, shininess) : 0.0f;
    }
};
struct PowPhong {  // phong_specular with std::pow
    static constexpr bool has_specular = true;
    static constexpr hsr::shading::SpecularKind kind = hsr::shading::SpecularKind::phong;
    float operator()(glm::vec3 n, glm::vec3 l, glm::vec3 v, float shininess) const {
        if (glm::dot(n, l) <= 0.0f) return 0.0f;
        const float r_dot_v = glm::dot(2.0f * glm::dot(n, l) * n - l, v);
        return r_dot_v > 0.0f ? std::pow(r_dot_v, shininess) : 0.0f;
    }
};

}  // namespace

TEST_CASE("specular power: within its relative bound of x^y for every float base up to 1 + 2^-10") {
    // Every 61st float below the top (17 million), and every float of the last 2^20 below it (bases
    // near 1, where large exponents give the highlights).
    for (const float y : kExponents) {
        INFO("exponent " << y);
        const double largest = largest_relative_error(y, 61, 1u << 20, 1.0f + 0x1p-10f);
        CHECK(largest <= hsr::shading::kSpecularPowerRelativeError);
    }
}

TEST_CASE("specular power: exact where the answer is exact, 0 and infinity past the float range") {
    for (const float y : kExponents) {
        INFO("exponent " << y);
        CHECK(hsr::shading::specular_power(1.0f, y) == 1.0f);
        CHECK(hsr::shading::specular_power(0x1p-149f, y) == (y < 1.5f ? 0x1p-149f : 0.0f));
    }
    CHECK(hsr::shading::specular_power(0.5f, 32.0f) == 0x1p-32f);
    CHECK(hsr::shading::specular_power(2.0f, 64.0f) == 0x1p64f);
    CHECK(hsr::shading::specular_power(1e-20f, 1000.0f) == 0.0f);
    CHECK(std::isinf(hsr::shading::specular_power(2.0f, 1000.0f)));
    CHECK(std::isinf(hsr::shading::specular_power(1e30f, 7.3f)));
}

TEST_CASE("specular power: pictures within 1 of every 8-bit channel shaded with std::pow") {
    struct Case {
        const char* plugin;
        std::vector<hsr::Setting> settings;
        float shininess;  // the plugin's, as docs/lighting.md lists its defaults
    };
    const std::vector<Case> cases = {{"blinn-phong", {}, 64.0f},
                                     {"phong", {}, 32.0f},
                                     {"blinn-phong", {{"shininess", "1000"}}, 1000.0f},
                                     {"phong", {{"shininess", "7.3"}}, 7.3f},
                                     {"blinn-phong", {{"shininess", "150"}, {"specular", "1"}}, 150.0f}};
    uint64_t channels = 0, moved = 0, highlight_channels = 0;
    for (const char* model_name : {"bunny.obj", "monkey.obj"})
        for (const bool instanced : {false, true}) {
            INFO(model_name << (instanced ? ", instanced" : ""));
            const hsr::SceneData loaded = hsr::load_model(test_models::path(model_name).string());
            hsr::InstanceGrid grid;
            grid.columns = 2, grid.rows = 2, grid.yaw_jitter_degrees = 40.0f;
            const hsr::SceneData data = instanced ? hsr::make_instance_grid(loaded, grid) : loaded;
            const hsr_scene scene = data.view();
            hsr::CameraSettings camera_settings;
            camera_settings.width = camera_settings.height = 320;
            const hsr_camera camera = hsr::make_camera(data.bounds_min, data.bounds_max, camera_settings);
            const std::vector<hsr_light> lights = {
                hsr::resolve_light(hsr::parse_light_spec("dir:-0.5,0.6,1,intensity=0.5"), camera),
                hsr::resolve_light(hsr::parse_light_spec("point:0.3,0.2,2,intensity=0.4"), camera)};
            const hsr_shading_context context = hsr::make_shading_context(camera, lights);
            hsr::Frame visible;
            {
                const auto plugins = hsr::load_plugin_library(std::string(HSR_PLUGIN_DIR) + "/hsr-zbuffer.so");
                hsr::HiddenSurfaceRemover zbuffer(plugins.at(0), {});
                hsr::resolve_visibility(scene, camera, zbuffer, visible);
            }
            REQUIRE(visible.instance.empty() != instanced);

            for (const Case& c : cases) {
                INFO(c.plugin << ", shininess " << c.shininess);
                // The reference: assemble_fragment, the scalar loop of the model with std::pow,
                // color_to_byte.
                const hsr::Placements placements = instanced ? hsr::Placements(scene) : hsr::Placements();
                hsr::FragmentArrays arrays;
                arrays.reserve(size_t(visible.width) * visible.height);
                uint32_t n = 0;
                for (uint32_t p = 0; p < visible.width * visible.height; ++p)
                    if (visible.face[p] != HSR_NO_FACE)
                        hsr::assemble_fragment(scene, placements, visible.face[p],
                                               instanced ? visible.instance[p] : hsr::kNotInstanced,
                                               visible.bary[2 * p], visible.bary[2 * p + 1], p, arrays, n++);
                hsr_fragment_batch batch = hsr::fragment_batch(arrays, n, instanced);
                hsr::shading::Material m;  // the plugins' defaults
                m.ambient = 0.1f;
                m.diffuse = 0.8f;
                m.specular = 0.5f;
                m.shininess = c.shininess;
                for (const hsr::Setting& s : c.settings)
                    if (s.first == "specular") m.specular = std::stof(s.second);
                // Also without the specular term, to count the channels the power decides.
                auto shade_reference = [&](auto specular, const hsr::shading::Material& material) {
                    hsr::shading::ShadedLightingModel<decltype(specular)> reference(material);
                    const hsr::sdk::Scene view(scene);
                    reference.prepare(view, context);
                    if (instanced)
                        reference.shade_instanced_scalar(batch);
                    else
                        reference.shade_phong_scalar(batch);
                };
                hsr::shading::Material matte = m;
                matte.specular = 0.0f;
                std::vector<uint8_t> matte_bytes(3 * size_t(n));
                for (const hsr::shading::Material& material : {matte, m}) {
                    if (std::string(c.plugin) == "phong")
                        shade_reference(PowPhong{}, material);
                    else
                        shade_reference(PowBlinnPhong{}, material);
                    if (material.specular == 0.0f)
                        for (size_t i = 0; i < 3 * size_t(n); ++i) matte_bytes[i] = hsr::color_to_byte(arrays.color[i]);
                }

                const auto lighting =
                    hsr::load_plugin_library(std::string(HSR_PLUGIN_DIR) + "/hsr-" + c.plugin + ".so");
                hsr::LightingModel model(lighting.at(0), c.settings);
                hsr::Frame frame = visible;
                hsr::shade_frame(scene, model, context, hsr::FrameSettings{}, frame);
                int largest = 0;
                for (uint32_t i = 0; i < n; ++i)
                    for (int k = 0; k < 3; ++k) {
                        const int expected = hsr::color_to_byte(arrays.color[3 * i + k]);
                        const int made = frame.rgb[3 * size_t(arrays.pixel[i]) + k];
                        largest = std::max(largest, std::abs(made - expected));
                        moved += made != expected;
                        ++channels;
                        highlight_channels += expected != matte_bytes[3 * size_t(i) + k] && expected < 255;
                    }
                CHECK(largest <= 1);
            }
        }
    // The power decided many channels: highlights that are not saturated.
    CHECK(highlight_channels > 10000);
    WARN("channels compared " << channels << ", in unsaturated highlights " << highlight_channels
                                  << ", moved by 1: " << moved);
}
