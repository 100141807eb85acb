#include "hsr/fragment_lists.hpp"

#include "fragment_assembly.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <numeric>

namespace hsr {

FragmentCollector::FragmentCollector(const hsr_scene& scene, uint32_t width, uint32_t height)
    : scene_(&scene), width_(width), height_(height), seen_(size_t(width) * height, 0) {}

hsr_status FragmentCollector::emit(void* context, const hsr_pixel_fragments* batch) {
    auto& self = *static_cast<FragmentCollector*>(context);
    if (!self.problem_.empty()) return HSR_ERROR_INVALID_ARGUMENT;
    try {
        self.problem_ = batch == nullptr ? "a NULL batch of fragments" : self.check(*batch);
    } catch (const LimitError& e) {
        self.problem_ = e.what();
        self.over_limit_ = true;
    } catch (const Error& e) {
        self.problem_ = e.what();
    }
    return self.problem_.empty() ? HSR_OK : HSR_ERROR_INVALID_ARGUMENT;
}

std::string FragmentCollector::check(const hsr_pixel_fragments& b) {
    if (b.struct_size < sizeof(hsr_pixel_fragments)) return "a batch of fragments smaller than ABI 1.4's";
    if (b.count == 0) return {};
    const bool instanced = scene_->instance_count > 0;
    if (b.pixel == nullptr || b.face == nullptr || b.depth == nullptr || b.coverage == nullptr || b.bary == nullptr ||
        (instanced && b.instance == nullptr))
        return "a batch of fragments with a NULL array";
    check_limit(&Limits::fragments, uint64_t(face_.size()) + b.count, "the fragment lists of this frame");
    const size_t pixels = size_t(width_) * height_;
    for (uint32_t i = 0; i < b.count; ++i) {
        const uint32_t p = b.pixel[i];
        if (p >= pixels) return fmt::format("a fragment at pixel index {}, outside the {}x{} image", p, width_, height_);
        const bool starts_pixel = i == 0 || b.pixel[i - 1] != p;
        if (starts_pixel) {
            if (seen_[p]) return fmt::format("the fragments of pixel ({}, {}) come in two runs", p % width_, p / width_);
            seen_[p] = 1;
        }
        if (b.face[i] >= scene_->triangle_count)
            return fmt::format("a fragment of face {}, but the scene has {} triangles", b.face[i], scene_->triangle_count);
        if (instanced && b.instance[i] >= scene_->instance_count)
            return fmt::format("a fragment of instance {}, but the scene has {}", b.instance[i], scene_->instance_count);
        if (b.coverage[i] == 0) return fmt::format("a fragment at pixel ({}, {}) covers no sample", p % width_, p / width_);
        if (!std::isfinite(b.depth[i]) || !std::isfinite(b.bary[2 * i]) || !std::isfinite(b.bary[2 * i + 1]))
            return fmt::format("a fragment at pixel ({}, {}) with a depth or barycentric that is not finite", p % width_,
                               p / width_);
    }
    pixel_.insert(pixel_.end(), b.pixel, b.pixel + b.count);
    face_.insert(face_.end(), b.face, b.face + b.count);
    if (instanced) instance_.insert(instance_.end(), b.instance, b.instance + b.count);
    depth_.insert(depth_.end(), b.depth, b.depth + b.count);
    coverage_.insert(coverage_.end(), b.coverage, b.coverage + b.count);
    bary_.insert(bary_.end(), b.bary, b.bary + 2 * size_t(b.count));
    return {};
}

void FragmentCollector::finish(FragmentLists& out) {
    const size_t pixels = size_t(width_) * height_;
    out.width = width_;
    out.height = height_;
    out.first.assign(pixels + 1, 0);
    for (uint32_t p : pixel_) ++out.first[p + 1];
    std::partial_sum(out.first.begin(), out.first.end(), out.first.begin());
    const size_t n = face_.size();
    const bool instanced = !instance_.empty();
    out.face.resize(n);
    out.instance.resize(instanced ? n : 0);
    out.coverage.resize(n);
    out.depth.resize(n);
    out.bary.resize(2 * n);
    std::vector<uint32_t> next(out.first.begin(), out.first.end() - 1);
    for (size_t i = 0; i < n; ++i) {
        const uint32_t at = next[pixel_[i]]++;
        out.face[at] = face_[i];
        if (instanced) out.instance[at] = instance_[i];
        out.coverage[at] = coverage_[i];
        out.depth[at] = depth_[i];
        out.bary[2 * size_t(at)] = bary_[2 * i];
        out.bary[2 * size_t(at) + 1] = bary_[2 * i + 1];
    }
    // Nearest first, as the plugin promised; sorting here (stably, by insertion: the lists come
    // sorted and short) makes the composite depend on depths alone, not on that promise.
    for (size_t p = 0; p < pixels; ++p) {
        for (uint32_t i = out.first[p] + 1; i < out.first[p + 1]; ++i) {
            for (uint32_t j = i; j > out.first[p] && out.depth[j] < out.depth[j - 1]; --j) {
                std::swap(out.face[j], out.face[j - 1]);
                if (instanced) std::swap(out.instance[j], out.instance[j - 1]);
                std::swap(out.coverage[j], out.coverage[j - 1]);
                std::swap(out.depth[j], out.depth[j - 1]);
                std::swap(out.bary[2 * size_t(j)], out.bary[2 * size_t(j - 1)]);
                std::swap(out.bary[2 * size_t(j) + 1], out.bary[2 * size_t(j - 1) + 1]);
            }
        }
    }
}

namespace {

float clamp01(float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; }  // NaN: 0

uint8_t to_byte(float v) { return static_cast<uint8_t>(clamp01(v) * 255.0f + 0.5f); }

// Opacity of each triangle's object, or empty when everything is opaque.
std::vector<float> face_opacity(const hsr_scene& scene) {
    if (scene.struct_size < offsetof(hsr_scene, object_opacity) + sizeof scene.object_opacity ||
        scene.object_opacity == nullptr)
        return {};
    std::vector<float> opacity(scene.triangle_count);
    for (uint32_t t = 0; t < scene.triangle_count; ++t) {
        const uint32_t object = scene.face_object[t];
        opacity[t] = object < scene.object_count ? clamp01(scene.object_opacity[object]) : 1.0f;
    }
    return opacity;
}

// What the fragments of a pixel add up to: their colours weighted by what each sample shows of
// them (premultiplied, over nothing), and the part of the pixel the background shows through (0..1).
struct CompositedPixel {
    glm::vec3 premultiplied;
    float background_weight;
};

// Composites the shaded fragments [begin, end) of one pixel (colours at `color`, 3 per fragment
// from `begin`) front to back, sample by sample.
CompositedPixel composite_pixel(const FragmentLists& lists, uint32_t begin, uint32_t end, const float* color,
                                const std::vector<float>& opacity) {
    constexpr int kSamples = HSR_COVERAGE_SAMPLES;
    float transmitted[kSamples];
    std::fill_n(transmitted, kSamples, 1.0f);
    glm::vec3 sum(0.0f);
    uint32_t opaque_samples = 0;  // samples an opaque fragment has closed
    for (uint32_t f = begin; f < end && opaque_samples != ~0u; ++f) {
        const float alpha = opacity.empty() ? 1.0f : opacity[lists.face[f]];
        const glm::vec3 c(clamp01(color[3 * (f - begin)]), clamp01(color[3 * (f - begin) + 1]),
                          clamp01(color[3 * (f - begin) + 2]));
        uint32_t mask = lists.coverage[f] & ~opaque_samples;
        float weight = 0.0f;  // summed transmittance of the samples this fragment shows in
        while (mask != 0) {
            const int s = std::countr_zero(mask);
            mask &= mask - 1;
            weight += transmitted[s];
            transmitted[s] *= 1.0f - alpha;
        }
        sum += (alpha * weight) * c;
        if (alpha >= 1.0f) opaque_samples |= lists.coverage[f];
    }
    float background_weight = 0.0f;
    for (int s = 0; s < kSamples; ++s) background_weight += transmitted[s];
    return {sum / float(kSamples), background_weight / float(kSamples)};
}

}  // namespace

void shade_fragments(const hsr_scene& scene, LightingModel& lighting, const hsr_shading_context& context,
                     const FrameSettings& settings, const FragmentLists& lists, Frame& frame) {
    const auto start = std::chrono::steady_clock::now();
    lighting.prepare(scene, context);
    const Placements placements(scene);
    const std::vector<float> opacity = face_opacity(scene);
    const bool instanced = !lists.instance.empty();
    frame.rgb.resize(3 * size_t(lists.width) * lists.height);
    if (settings.coverage_alpha) frame.alpha.resize(size_t(lists.width) * lists.height);

    std::atomic<uint64_t> batches{0};
    for_each_band(lists.height, settings.threads, [&](uint32_t row_begin, uint32_t row_end, FragmentArrays& arrays) {
        const size_t pixel_begin = size_t(row_begin) * lists.width, pixel_end = size_t(row_end) * lists.width;
        const uint32_t begin = lists.first[pixel_begin], end = lists.first[pixel_end];
        const uint32_t n = end - begin;
        if (n > 0) {
            arrays.reserve(n);
            for (size_t p = pixel_begin; p < pixel_end; ++p)
                for (uint32_t f = lists.first[p]; f < lists.first[p + 1]; ++f)
                    assemble_fragment(scene, placements, lists.face[f], instanced ? lists.instance[f] : kNotInstanced,
                                      lists.bary[2 * size_t(f)], lists.bary[2 * size_t(f) + 1], uint32_t(p), arrays,
                                      f - begin);
            hsr_fragment_batch batch = fragment_batch(arrays, n, instanced);
            lighting.shade(batch);
            ++batches;
        }
        for (size_t p = pixel_begin; p < pixel_end; ++p) {
            const CompositedPixel pixel =
                composite_pixel(lists, lists.first[p], lists.first[p + 1],
                                arrays.color.data() + 3 * size_t(lists.first[p] - begin), opacity);
            glm::vec3 c = pixel.premultiplied + pixel.background_weight * settings.background;
            if (settings.coverage_alpha) {
                const float alpha = 1.0f - pixel.background_weight;
                frame.alpha[p] = to_byte(alpha);
                c = alpha > 0.0f ? pixel.premultiplied / alpha : glm::vec3(0.0f);
            }
            for (int k = 0; k < 3; ++k) frame.rgb[3 * p + k] = to_byte(c[k]);
        }
    });

    frame.counters.emplace_back("fragments-shaded", lists.size());
    frame.counters.emplace_back("shading-batches", batches.load());
    frame.shading_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace hsr
