// Fragment lists (ABI 1.4): a remover that returns every pixel's surface fragments with their
// coverage masks (Carpenter's A-buffer) lets the host shade each fragment with any lighting model and
// composite them front to back per coverage sample, with the objects' opacities: anti-aliased
// edges and transparency, in any order of input.
#pragma once

#include "hsr/abi.h"
#include "hsr/frame.hpp"
#include "hsr/plugin_registry.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hsr {

// Every pixel's fragments, nearest first, in compressed rows: pixel p's fragments are the indices
// [first[p], first[p + 1]).
struct FragmentLists {
    uint32_t width = 0, height = 0;
    std::vector<uint32_t> first;  // width * height + 1
    std::vector<uint32_t> face, instance, coverage;  // instance empty unless the scene has instances
    std::vector<float> depth, bary;                  // bary: 2 per fragment

    uint64_t size() const { return face.size(); }
};

// The hsr_fragment_sink handed to a remover: checks each batch against the scene and the image
// (ids in range, a pixel in one batch only, coverage non-empty, depths finite), keeps it within the
// `fragments` limit, and at finish() sorts the lists into FragmentLists.
class FragmentCollector {
public:
    FragmentCollector(const hsr_scene& scene, uint32_t width, uint32_t height);
    hsr_fragment_sink sink() { return {this, &emit}; }
    // What was wrong with a batch the sink refused, or empty.
    const std::string& problem() const { return problem_; }
    // Whether that problem is the `fragments` limit: the asker's to raise, not the plugin's fault.
    bool over_limit() const { return over_limit_; }
    void finish(FragmentLists& out);

private:
    static hsr_status emit(void* context, const hsr_pixel_fragments* batch);
    std::string check(const hsr_pixel_fragments& batch);

    const hsr_scene* scene_;
    uint32_t width_, height_;
    std::vector<uint8_t> seen_;  // per pixel: its fragments have come
    std::vector<uint32_t> pixel_, face_, instance_, coverage_;
    std::vector<float> depth_, bary_;
    std::string problem_;
    bool over_limit_ = false;
};

// Shades every fragment with the lighting model and composites each pixel's fragments front to back
// for each of its HSR_COVERAGE_SAMPLES samples, each fragment's colour weighted by its object's
// opacity, over the background; a pixel's colour is the mean of its samples. Fills frame.rgb.
void shade_fragments(const hsr_scene& scene, LightingModel& lighting, const hsr_shading_context& context,
                     const FrameSettings& settings, const FragmentLists& lists, Frame& frame);

}  // namespace hsr
