// The octree-zbuffer plugin's class (octree_zbuffer.cpp: the algorithm, its source, and the build
// of the octrees): its parameters, what it keeps between frames, and its drawing over screen tiles.
// A header, so that octree_zbuffer_steps.cpp can compile the drawing with steps apart
// (hsr::sdk::StepsDrawing).
#pragma once

#include "octree.hpp"
#include "tile_renderer.hpp"

#include "hsr/scene_key.hpp"
#include "hsr/sdk.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

namespace octree_zbuffer {

using hsr::sdk::ParamSpec;

class OctreeZBuffer final : public hsr::sdk::StepwiseRemover<OctreeZBuffer> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "octree-zbuffer", "1.0.0",
        "octree z-buffer (Greene, Kass & Miller 1993): object-space octrees, front to back, culled against a z-pyramid"};
    static inline const ParamSpec params[] = {
        ParamSpec::integer("max-depth", "8", 0, 20, "deepest octree level (the root is level 0)"),
        ParamSpec::integer("leaf-triangles", "64", 1, 65536,
                           "an octree cell with at most this many triangles is not split further"),
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::integer("tile-size", "512", 0, 65536,
                           "pixels per side of the screen tiles drawn in parallel, rounded up to a multiple of "
                           "8 (0: the whole image as one tile)"),
    };

    explicit OctreeZBuffer(const hsr::sdk::Params& p) : cull_backfaces_(p.boolean("cull-backfaces")) {
        build_params_.max_depth = uint32_t(p.integer("max-depth"));
        build_params_.leaf_triangles = uint32_t(p.integer("leaf-triangles"));
        tile_size_ = int32_t((p.integer("tile-size") + 7) / 8 * 8);
    }

    // render_steps (from StepwiseRemover) takes steps in traversal order: each box test of a node (of
    // the instance hierarchy or of an octree), visited or culled, and each triangle of a visible
    // leaf; the whole image as one tile. Compiled in octree_zbuffer_steps.cpp.
    // A step names the last line of the pseudocode (docs/theory/en/octree-zbuffer.md) it reached.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"node-outside", "skip a node whose box lies outside the view"},
        {"node-hidden", "cull a node whose box is hidden behind the z-pyramid"},
        {"node-visit", "visit a node that may show: its children front to back, or its triangles"},
        {"cull", "cull a leaf's triangle that lies outside the view"},
        {"pyramid-test", "test a leaf's triangle against the z-pyramid"},
        {"rasterize", "find the pixel centres the triangle covers"},
        {"depth-test", "compare the triangle's depth with the depth buffer"},
        {"write", "write the nearer pixels and mark their pyramid cells"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "z-буфер с октодеревом (Грин, Касс и Миллер, 1993): октодеревья объектов обходятся от ближних узлов к "
         "дальним и отсекаются по z-пирамиде"},
        {"ru", "param:max-depth", "наибольшая глубина октодерева"},
        {"ru", "help:max-depth", "самый глубокий уровень октодерева (корень — уровень 0)"},
        {"ru", "param:leaf-triangles", "треугольников в листе"},
        {"ru", "help:leaf-triangles", "ячейка октодерева, в которой не больше стольких треугольников, дальше не делится"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не рисовать треугольники, повёрнутые к камере нелицевой стороной"},
        {"ru", "param:tile-size", "размер экранного тайла"},
        {"ru", "help:tile-size",
         "сторона в пикселях экранных тайлов, которые рисуются параллельно; округляется вверх до кратного 8 "
         "(0 — всё изображение одним тайлом)"},
        {"ru", "phase:node-outside", "пропустить узел, оболочка которого лежит вне области видимости"},
        {"ru", "phase:node-hidden", "отбросить узел, оболочка которого закрыта z-пирамидой"},
        {"ru", "phase:node-visit", "обойти узел, который может быть виден: его потомков от ближних к дальним или его треугольники"},
        {"ru", "phase:cull", "отбросить треугольник листа, лежащий вне области видимости"},
        {"ru", "phase:pyramid-test", "проверить треугольник листа по z-пирамиде"},
        {"ru", "phase:rasterize", "найти центры пикселей, которые покрывает треугольник"},
        {"ru", "phase:depth-test", "сравнить глубину треугольника с буфером глубины"},
        {"ru", "phase:write", "записать более близкие пиксели и пометить их ячейки z-пирамиды"},
        {"ru", "counter:triangles-in-culled-nodes", "треугольников в закрытых узлах"},
        {"ru", "counter:triangles-culled-by-pyramid", "треугольников отброшено z-пирамидой"},
        {"ru", "counter:octree-nodes", "узлов октодерева"},
        {"ru", "counter:octree-nodes-visited", "узлов октодерева проверено"},
        {"ru", "counter:octree-nodes-culled", "узлов октодерева закрыто z-пирамидой"},
        {"ru", "counter:octree-nodes-outside", "узлов октодерева вне области видимости"},
        {"ru", "counter:octree-leaves-drawn", "листьев октодерева нарисовано"},
        {"ru", "counter:octree-leaves-deferred", "листьев октодерева отложено"},
        {"ru", "counter:instance-nodes", "узлов иерархии экземпляров"},
        {"ru", "counter:instance-nodes-visited", "узлов иерархии экземпляров проверено"},
        {"ru", "counter:instance-nodes-culled", "узлов иерархии экземпляров закрыто z-пирамидой"},
        {"ru", "counter:instance-nodes-outside", "узлов иерархии экземпляров вне области видимости"},
        {"ru", "counter:placements-visited", "экземпляров обойдено"},
        {"ru", "counter:vertices-transformed", "вершин преобразовано"},
        {"ru", "counter:tiles-tested", "плиток проверено по z-пирамиде"},
        {"ru", "counter:tiles-culled", "плиток отброшено z-пирамидой"},
        {"ru", "counter:pyramid-updates", "обновлений z-пирамиды"},
        {"ru", "step:node-culled", "отсечённый узел"},
        {"ru", "step:node-visited", "посещённый узел"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(
        own_translations, raster::triangle_counter_translations, raster::depth_test_counter_translations,
        raster::zpyramid_buffer_translations, raster::triangle_step_translations,
        hsr::sdk::build_time_counter_translations);

private:
    friend class hsr::sdk::StepwiseRemover<OctreeZBuffer>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());

        hsr::sdk::timed_build(counters, [&] { return prepare(scene); });

        const int32_t width = int32_t(camera.width), height = int32_t(camera.height);
        const int32_t size = Steps::enabled || tile_size_ == 0 ? std::max(width, height) : tile_size_;
        const int32_t across = (width + size - 1) / size, down = (height + size - 1) / size;
        const size_t count = size_t(across) * size_t(down);
        while (tiles_.size() < count) tiles_.push_back(std::make_unique<TileRenderer>(built_));
        auto tile = [&](size_t k) {
            PixelTile t;
            t.x0 = int32_t(k % size_t(across)) * size;
            t.y0 = int32_t(k / size_t(across)) * size;
            t.x1 = std::min(t.x0 + size, width) - 1;
            t.y1 = std::min(t.y0 + size, height) - 1;
            return t;
        };
        if (count == 1) {
            try {
                tiles_[0]->draw(scene, camera, target, cull_backfaces_, tile(0), geometry_.local(), steps);
            } catch (const hsr::sdk::StepLimitReached&) {
                report(counters, 1);
                throw;
            }
        } else {
            // Tiles own disjoint pixels and pyramids: nothing is shared but what was built.
            tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1), [&](const tbb::blocked_range<size_t>& range) {
                for (size_t k = range.begin(); k != range.end(); ++k) {
                    hsr::sdk::NoSteps no_steps;
                    tiles_[k]->draw(scene, camera, target, cull_backfaces_, tile(k), geometry_.local(), no_steps);
                }
            });
        }
        report(counters, count);
    }

    // The counters of the first `count` tiles, summed: a node or triangle that reaches several tiles
    // is counted in each.
    void report(hsr::sdk::Counters& counters, size_t count) const;

    // Builds what is missing for this scene; true when anything was built.
    bool prepare(const hsr::sdk::Scene& scene);

    // Parameters
    bool cull_backfaces_;
    BuildParams build_params_;
    int32_t tile_size_;

    // Built once per scene
    bool has_built_ = false;
    hsr::sdk::SceneKey scene_key_;
    hsr::sdk::InstanceKey instance_key_;
    BuiltScene built_;
    std::map<std::array<uint32_t, 4>, uint32_t> object_of_range_;
    uint64_t drawn_triangles_ = 0;
    uint64_t non_finite_triangles_ = 0;

    // Per frame: one renderer per tile, one geometry stage per thread (both kept between frames).
    std::vector<std::unique_ptr<TileRenderer>> tiles_;
    tbb::enumerable_thread_specific<raster::GeometryStage> geometry_;
};

}  // namespace octree_zbuffer

extern template class hsr::sdk::StepsDrawing<octree_zbuffer::OctreeZBuffer>;
