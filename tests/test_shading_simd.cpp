// The SIMD shading code against the scalar code it replaces, on every Highway target this CPU runs
// (each forced in turn with hwy::SetSupportedTargetsForTest): the lighting models' per-fragment
// kernel (hsr/shading.hpp) on random fragments, lights and materials, with and without instances;
// the host's fragment assembly and colour-to-byte conversion (framework/src/fragment_assembly.hpp)
// on random frames, with and without instances; and whole pictures of the bunny shaded by the
// lighting plugins through the host, against pictures made here with the scalar code alone. Equal
// means equal bit for bit.
#include "../framework/src/fragment_assembly.hpp"

#include "hsr/camera.hpp"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/shading.hpp"
#include "highway_targets.hpp"
#include "test_models.hpp"

#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

using highway_tests::for_each_target;

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Random triangles with random (unit) corner normals and face colours.
hsr::SceneData random_scene(std::mt19937& rng, uint32_t triangles) {
    std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f), channel(0.0f, 1.0f);
    auto unit = [&] {
        glm::vec3 v;
        do v = {coordinate(rng), coordinate(rng), coordinate(rng)};
        while (glm::dot(v, v) < 1e-4f);
        return glm::normalize(v);
    };
    hsr::SceneData s;
    s.object_names = {"random"};
    s.bounds_min = glm::vec3(-1.0f);
    s.bounds_max = glm::vec3(1.0f);
    for (uint32_t t = 0; t < triangles; ++t) {
        for (int k = 0; k < 3; ++k) {
            s.positions.insert(s.positions.end(), {coordinate(rng), coordinate(rng), coordinate(rng)});
            s.indices.push_back(3 * t + k);
            const glm::vec3 n = unit();
            s.corner_normals.insert(s.corner_normals.end(), {n.x, n.y, n.z});
        }
        const glm::vec3 n = unit();
        s.face_normals.insert(s.face_normals.end(), {n.x, n.y, n.z});
        s.face_colors.insert(s.face_colors.end(), {channel(rng), channel(rng), channel(rng)});
        s.edge_neighbors.insert(s.edge_neighbors.end(), {HSR_NO_NEIGHBOR, HSR_NO_NEIGHBOR, HSR_NO_NEIGHBOR});
        s.face_object.push_back(0);
    }
    return s;
}

// Three placements of every triangle of `data`: turned, scaled and moved.
hsr::SceneData placed_three_times(const hsr::SceneData& data) {
    hsr::SceneData placed = data;
    const uint32_t triangles = uint32_t(data.face_colors.size() / 3), vertices = uint32_t(data.positions.size() / 3);
    for (uint32_t k = 0; k < 3; ++k) {
        const glm::mat3 rotation(
            glm::rotate(glm::mat4(1.0f), 0.7f + float(k), glm::normalize(glm::vec3(1.0f, 2.0f - float(k), 0.5f))));
        placed.instances.push_back(hsr::make_instance(0, triangles, 0, vertices, rotation, 0.6f + 0.7f * float(k),
                                                      glm::vec3(0.3f * float(k), -1.5f, 2.0f), data.bounds_min,
                                                      data.bounds_max));
    }
    return placed;
}

// One model, many random frames' worth of fragments and lights: the SIMD shade() against the
// scalar loop, for a scene without instances (per-fragment interpolation, the one its shade()
// computes) and for the same triangles placed three times (every interpolation).
template <class Specular>
void check_kernel(const char* name) {
    std::mt19937 rng(std::hash<std::string>{}(name));
    std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f), unit_interval(0.0f, 1.0f);
    const hsr::SceneData data = random_scene(rng, 200);
    const hsr::SceneData placed = placed_three_times(data);
    const hsr_scene raw = data.view(), raw_placed = placed.view();
    const hsr::sdk::Scene scene(raw), placed_scene(raw_placed);
    for (int round = 0; round < 40; ++round) {
        hsr::shading::Material material;
        material.ambient = unit_interval(rng);
        material.diffuse = unit_interval(rng);
        material.specular = unit_interval(rng);
        material.shininess = round % 4 == 0 ? 1000.0f : 1.0f + 200.0f * unit_interval(rng);
        material.specular_color = {unit_interval(rng), unit_interval(rng), unit_interval(rng)};
        material.two_sided = round % 3 != 0;

        std::vector<hsr_light> lights(1 + round % 4);
        for (hsr_light& light : lights) {
            light.type = unit_interval(rng) < 0.5f ? HSR_LIGHT_DIRECTIONAL : HSR_LIGHT_POINT;
            for (int k = 0; k < 3; ++k) {
                light.vector[k] = coordinate(rng);
                light.color[k] = unit_interval(rng);
            }
            light.intensity = 2.0f * unit_interval(rng);
        }
        hsr_shading_context context{};
        context.struct_size = sizeof context;
        context.lights = lights.data();
        context.light_count = uint32_t(lights.size());
        context.projection_type = round % 2 ? HSR_PROJECTION_PERSPECTIVE : HSR_PROJECTION_ORTHOGRAPHIC;
        for (int k = 0; k < 3; ++k) {
            context.eye[k] = 3.0f * coordinate(rng);
            context.view_direction[k] = coordinate(rng);
        }

        // Fragments: random faces, instances, barycentrics, positions and unit normals, a few at the
        // eye point or at a point light (no view or light vector) and with zero normals. More than
        // one block of the instanced path, and not a multiple of any vector.
        const uint32_t n = 1000 + round;
        std::vector<uint32_t> face(n), pixel(n), instance(n);
        std::vector<float> bary(2 * n), position(3 * n), normal(3 * n);
        for (uint32_t i = 0; i < n; ++i) {
            face[i] = rng() % raw.triangle_count;
            instance[i] = rng() % 3;
            pixel[i] = i;
            bary[2 * i] = unit_interval(rng);
            bary[2 * i + 1] = unit_interval(rng);
            glm::vec3 p{coordinate(rng), coordinate(rng), coordinate(rng)};
            glm::vec3 nv = glm::normalize(glm::vec3{coordinate(rng), coordinate(rng), coordinate(rng)});
            if (i % 97 == 0) p = {context.eye[0], context.eye[1], context.eye[2]};
            if (i % 89 == 0) p = {lights[0].vector[0], lights[0].vector[1], lights[0].vector[2]};
            if (i % 83 == 0) nv = glm::vec3(0.0f);
            for (int k = 0; k < 3; ++k) position[3 * i + k] = p[k], normal[3 * i + k] = nv[k];
        }
        auto shade = [&](const hsr::shading::ShadedLightingModel<Specular>& model, bool instanced, bool simd) {
            std::vector<float> color(3 * n, -1.0f);
            hsr_fragment_batch batch{};
            batch.struct_size = sizeof batch;
            batch.count = n;
            batch.face = face.data();
            batch.bary = bary.data();
            batch.position = position.data();
            batch.normal = normal.data();
            batch.pixel = pixel.data();
            batch.color = color.data();
            batch.instance = instanced ? instance.data() : nullptr;
            if (simd)
                model.shade(batch);
            else if (instanced)
                model.shade_instanced_scalar(batch);
            else
                model.shade_phong_scalar(batch);
            return color;
        };
        using hsr::shading::Interpolation;
        for (const bool instanced : {false, true})
            for (const Interpolation interpolation : {Interpolation::flat, Interpolation::gouraud, Interpolation::phong}) {
                if (!instanced && interpolation != Interpolation::phong) continue;
                material.interpolation = interpolation;
                hsr::shading::ShadedLightingModel<Specular> model(material);
                model.prepare(instanced ? placed_scene : scene, context);
                const std::vector<float> reference = shade(model, instanced, false);
                for_each_target([&](int64_t) {
                    INFO(name << ", round " << round << (instanced ? ", instanced" : "") << ", interpolation "
                              << int(interpolation));
                    CHECK(same_bits(shade(model, instanced, true), reference));
                });
            }
    }
}

}  // namespace

TEST_CASE("shading SIMD: every target's lighting kernel gives the scalar colours") {
    check_kernel<hsr::shading::NoSpecular>("lambert");
    check_kernel<hsr::shading::PhongSpecular>("phong");
    check_kernel<hsr::shading::BlinnPhongSpecular>("blinn-phong");
}

TEST_CASE("shading SIMD: every target's fragment assembly and bytes equal the scalar code's") {
    std::mt19937 rng(18);
    hsr::SceneData data = random_scene(rng, 500);
    // Triangle 0 has no interpolated normal (the face normal stands in); the last triangle, whose
    // corners are the last in memory, comes in below as well.
    std::fill(data.corner_normals.begin(), data.corner_normals.begin() + 9, 0.0f);
    std::uniform_real_distribution<float> unit_interval(0.0f, 1.0f);
    const uint32_t width = 61, height = 9, pixels = width * height;  // not a multiple of any vector
    std::vector<uint32_t> face(pixels);
    std::vector<float> bary(2 * pixels);
    for (uint32_t p = 0; p < pixels; ++p) {
        face[p] = unit_interval(rng) < 0.3f ? HSR_NO_FACE : rng() % data.face_colors.size() / 3;
        bary[2 * p] = unit_interval(rng);
        bary[2 * p + 1] = unit_interval(rng) * (1.0f - bary[2 * p]);
    }
    const uint32_t triangles = uint32_t(data.face_colors.size() / 3);
    for (uint32_t p : {0u, 1u, 17u, 100u, pixels - 1}) face[p] = triangles - 1;
    for (uint32_t p : {2u, 40u, 41u, 300u}) face[p] = 0;
    for (uint32_t p = 128; p < 192; ++p)  // whole vectors covered, on every target
        if (face[p] == HSR_NO_FACE) face[p] = p % triangles;

    // The same faces, once without instances and once as three placements of the triangles, with
    // runs of one instance and single pixels of others.
    const hsr::SceneData placed = placed_three_times(data);
    std::vector<uint32_t> instance(pixels);
    for (uint32_t p = 0; p < pixels; ++p) instance[p] = (p / 23) % 3 == 0 ? rng() % 3 : (p / 23) % 3;

    std::vector<float> colors;
    for (float v : {-1.0f, -0.0f, 0.0f, 1e-9f, 0.5f / 255.0f, 0.99f / 255.0f, 0.5f, 0.998f, 1.0f, 1.5f, NAN, INFINITY})
        colors.push_back(v);
    for (int i = 0; i < 3000; ++i) colors.push_back(1.2f * unit_interval(rng) - 0.1f);
    std::vector<uint8_t> reference_bytes(colors.size());
    for (size_t i = 0; i < colors.size(); ++i) reference_bytes[i] = hsr::color_to_byte(colors[i]);

    for (const bool instanced : {false, true}) {
        INFO((instanced ? "instanced" : "without instances"));
        const hsr_scene scene = (instanced ? placed : data).view();
        const hsr::Placements placements = instanced ? hsr::Placements(scene) : hsr::Placements();
        REQUIRE(placements.transform.size() == (instanced ? 3u : 0u));
        hsr::FragmentArrays reference;
        reference.reserve(pixels);
        uint32_t n = 0;
        for (uint32_t p = 0; p < pixels; ++p)
            if (face[p] != HSR_NO_FACE)
                hsr::assemble_fragment(scene, placements, face[p], instanced ? instance[p] : hsr::kNotInstanced,
                                       bary[2 * p], bary[2 * p + 1], p, reference, n++);
        for_each_target([&](int64_t) {
            hsr::FragmentArrays out;
            out.reserve(pixels);
            for (uint32_t begin : {0u, width, 3 * width}) {
                const uint32_t count = hsr::assemble_covered_pixels(
                    scene, placements, face.data(), instanced ? instance.data() : nullptr, bary.data(), begin, pixels, out);
                uint32_t first = 0;
                while (first < n && reference.pixel[first] < begin) ++first;
                REQUIRE(count == n - first);
                for (uint32_t i = 0; i < count; ++i) {
                    const uint32_t r = first + i;
                    CHECK(out.face[i] == reference.face[r]);
                    CHECK(out.pixel[i] == reference.pixel[r]);
                    if (instanced) CHECK(out.instance[i] == reference.instance[r]);
                    CHECK(std::memcmp(&out.bary[2 * i], &reference.bary[2 * r], 2 * sizeof(float)) == 0);
                    CHECK(std::memcmp(&out.position[3 * i], &reference.position[3 * r], 3 * sizeof(float)) == 0);
                    CHECK(std::memcmp(&out.normal[3 * i], &reference.normal[3 * r], 3 * sizeof(float)) == 0);
                }
            }
            // A chunk at a time, as shade_frame does (chunks of 13 and 64: whole vectors and not):
            // covered pixels [first, first + count) become fragments 0, 1, ...
            for (uint32_t chunk : {13u, 64u}) {
                hsr::FragmentArrays chunked;
                chunked.reserve(pixels, chunk);
                const uint32_t count = hsr::find_covered_pixels(face.data(), instanced ? instance.data() : nullptr, 0,
                                                                pixels, chunked);
                REQUIRE(count == n);
                for (uint32_t first = 0; first < n; first += chunk) {
                    const uint32_t m = std::min(chunk, n - first);
                    hsr::assemble_covered_fragments(scene, placements, instanced, bary.data(), first, m, n, chunked);
                    for (uint32_t i = 0; i < m; ++i) {
                        const uint32_t r = first + i;
                        CHECK(chunked.face[r] == reference.face[r]);
                        CHECK(chunked.pixel[r] == reference.pixel[r]);
                        if (instanced) CHECK(chunked.instance[r] == reference.instance[r]);
                        CHECK(std::memcmp(&chunked.bary[2 * i], &reference.bary[2 * r], 2 * sizeof(float)) == 0);
                        CHECK(std::memcmp(&chunked.position[3 * i], &reference.position[3 * r], 3 * sizeof(float)) ==
                              0);
                        CHECK(std::memcmp(&chunked.normal[3 * i], &reference.normal[3 * r], 3 * sizeof(float)) == 0);
                    }
                }
            }
        });
    }
    for_each_target([&](int64_t) {
        std::vector<uint8_t> bytes(colors.size() + 64);
        hsr::colors_to_bytes(colors.data(), colors.size(), bytes.data());
        bytes.resize(colors.size());
        CHECK(bytes == reference_bytes);
    });
    // The same colours written to pixels: runs of consecutive pixels of every length from 1 to 40
    // (shorter and longer than a vector), with gaps between them that must keep their bytes.
    std::vector<uint32_t> pixel_of;
    for (uint32_t p = 5, run = 1; pixel_of.size() < colors.size() / 3; p += run + 1 + run % 3, run = run % 40 + 1)
        for (uint32_t k = 0; k < run && pixel_of.size() < colors.size() / 3; ++k) pixel_of.push_back(p + k);
    const uint32_t count = uint32_t(pixel_of.size());
    std::vector<uint8_t> reference_rgb(3 * (size_t(pixel_of.back()) + 8), 77);
    for (uint32_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) reference_rgb[3 * size_t(pixel_of[i]) + k] = reference_bytes[3 * size_t(i) + k];
    for_each_target([&](int64_t) {
        std::vector<uint8_t> rgb(reference_rgb.size(), 77);
        hsr::colors_to_pixels(colors.data(), pixel_of.data(), count, rgb.data());
        CHECK(rgb == reference_rgb);
    });
}

TEST_CASE("shading SIMD: bunny pictures from every target equal the scalar code's") {
    const hsr::SceneData data = hsr::load_model(test_models::path("bunny.obj").string());
    const hsr_scene scene = data.view();
    hsr::CameraSettings camera_settings;
    camera_settings.width = camera_settings.height = 384;
    const hsr_camera camera = hsr::make_camera(data.bounds_min, data.bounds_max, camera_settings);
    const std::vector<hsr_light> lights = {hsr::resolve_light(hsr::parse_light_spec("dir:-0.5,0.6,1"), camera),
                                           hsr::resolve_light(hsr::parse_light_spec("point:0.3,0.2,2"), camera)};
    const hsr_shading_context context = hsr::make_shading_context(camera, lights);

    hsr::Frame visible;
    {
        const auto plugins = hsr::load_plugin_library(std::string(HSR_PLUGIN_DIR) + "/hsr-zbuffer.so");
        hsr::HiddenSurfaceRemover zbuffer(plugins.at(0), {});
        hsr::resolve_visibility(scene, camera, zbuffer, visible);
    }

    struct Case {
        const char* plugin;
        std::vector<hsr::Setting> settings;
    };
    for (const Case& c : {Case{"blinn-phong", {}}, Case{"phong", {}}, Case{"lambert", {{"interpolation", "phong"}}},
                          Case{"blinn-phong", {{"two-sided", "false"}, {"shininess", "900"}}}}) {
        INFO(c.plugin);
        // The scalar picture: assemble_fragment, the scalar loop of a model with the plugin's
        // material (its defaults, as docs/lighting.md lists them), color_to_byte.
        const hsr::sdk::Scene view(scene);
        const auto lighting = hsr::load_plugin_library(std::string(HSR_PLUGIN_DIR) + "/hsr-" + c.plugin + ".so");
        hsr::LightingModel model(lighting.at(0), c.settings);
        std::vector<uint8_t> expected(3 * size_t(visible.width) * visible.height);
        {
            hsr::FrameSettings settings;
            hsr::FragmentArrays arrays;
            arrays.reserve(size_t(visible.width) * visible.height);
            uint32_t n = 0;
            const hsr::Placements none;
            for (uint32_t p = 0; p < visible.width * visible.height; ++p) {
                if (visible.face[p] == HSR_NO_FACE) {
                    for (int k = 0; k < 3; ++k) expected[3 * p + k] = hsr::color_to_byte(settings.background[k]);
                    continue;
                }
                hsr::assemble_fragment(scene, none, visible.face[p], hsr::kNotInstanced, visible.bary[2 * p],
                                       visible.bary[2 * p + 1], p, arrays, n++);
            }
            hsr_fragment_batch batch = hsr::fragment_batch(arrays, n, false);
            auto shade_scalar = [&](auto specular) {
                using Specular = decltype(specular);
                hsr::shading::Material m;
                const std::string name = c.plugin;
                m.two_sided = true;
                m.ambient = 0.1f;
                m.diffuse = 0.8f;
                m.specular = 0.5f;
                m.shininess = name == "phong" ? 32.0f : 64.0f;
                for (const hsr::Setting& s : c.settings) {
                    if (s.first == "two-sided") m.two_sided = s.second == "true";
                    if (s.first == "shininess") m.shininess = std::stof(s.second);
                }
                hsr::shading::ShadedLightingModel<Specular> scalar(m);
                scalar.prepare(view, context);
                scalar.shade_phong_scalar(batch);
            };
            const std::string name = c.plugin;
            if (name == "lambert")
                shade_scalar(hsr::shading::NoSpecular{});
            else if (name == "phong")
                shade_scalar(hsr::shading::PhongSpecular{});
            else
                shade_scalar(hsr::shading::BlinnPhongSpecular{});
            for (uint32_t i = 0; i < n; ++i)
                for (int k = 0; k < 3; ++k) expected[3 * arrays.pixel[i] + k] = hsr::color_to_byte(arrays.color[3 * i + k]);
        }
        for_each_target([&](int64_t) {
            for (unsigned threads : {1u, 2u}) {
                hsr::FrameSettings settings;
                settings.threads = threads;
                hsr::Frame frame = visible;
                hsr::shade_frame(scene, model, context, settings, frame);
                CHECK(frame.rgb == expected);
            }
        });
    }
}
