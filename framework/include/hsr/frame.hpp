// What a frame is made with and of: its settings, the visibility buffer the hidden-surface plugin
// fills, the colours, the counters, and the steps when it is rendered step by step (pipeline.hpp
// makes frames; fragment_lists.hpp composites them from fragment lists).
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hsr {

// How far a run step by step has got, for a caller on another thread (a progress line while a long
// step request renders). The renderer sets `total` once it has counted the frame's steps, then
// `steps` counts again from 0 in the run that stops at the step asked for.
struct StepProgress {
    std::atomic<uint64_t> steps{0};  // steps reported so far in the run under way
    std::atomic<uint64_t> total{0};  // the steps of the whole frame; 0 while they are being counted
};

struct FrameSettings {
    glm::vec3 background{1.0f, 1.0f, 1.0f};
    unsigned threads = 0;  // shading threads; 0 = as many as tbb::global_control allows (every core)
    bool count_depth_tests = false;  // ask the remover for per-pixel depth-test counts (Frame::depth_tests)
    // Render step by step (ABI 1.3): stop after this step (1-based; 0 runs every step). Empty: no
    // steps, render() as usual.
    std::optional<uint64_t> stop_after_step;
    // With stop_after_step N: also copy the visibility buffers as step N - 1 left them
    // (StepRun::before), in the same run of the plugin.
    bool keep_step_before = false;
    StepProgress* step_progress = nullptr;  // with stop_after_step: updated at each step
    std::string step_language;              // the step texts' language (ABI 1.5); empty: English
    // Supersampling (render_supersampled_frame; render_frame renders the pixel centres only):
    // visibility and shading once per position of sample_offsets(samples), the colours averaged.
    uint32_t samples = 1;
    // A transparent background: Frame::alpha holds each pixel's coverage and Frame::rgb the colour of
    // what covers it, not composited over the background (straight alpha; black where nothing does).
    bool coverage_alpha = false;
};

// One of a plugin's own buffers at a step (hsr_step_buffer), copied.
struct StepBuffer {
    std::string name;
    uint32_t width = 0, height = 0;
    std::vector<float> values;
};

// One step of a hidden-surface algorithm (hsr_step_event), copied.
struct StepRecord {
    uint64_t index = 0;  // 1-based; 0: no step was taken
    std::string type;
    std::string text;    // the plugin's, or one the host wrote from the fields
    std::string phase;   // one of the plugin's phases (ABI 1.5), or empty
    uint32_t face = HSR_NO_FACE;
    uint32_t instance = 0;
    uint32_t level = HSR_NO_LEVEL;
    std::vector<float> lines;   // 4 per line: x0, y0, x1, y1 in window coordinates
    std::vector<uint32_t> roles;  // an hsr_step_role per line
    uint64_t pixels_written = 0, pixels_rejected = 0;
    std::vector<StepBuffer> buffers;  // only for the step a render stopped after
};

// The visibility buffers of a frame at one moment of a render, copied: empty arrays where the frame
// has none, or before anything was drawn.
struct VisibilityState {
    std::vector<float> depth;
    std::vector<uint32_t> face, instance, depth_tests;
};

// What a render step by step did: how many steps it took, whether it stopped before the end, and
// its last step.
struct StepRun {
    uint64_t taken = 0;
    bool stopped = false;
    StepRecord last;
    // With keep_before: the buffers as the step before the one it stopped after left them (unset
    // when it stopped after step 1 or ran to the end).
    std::optional<VisibilityState> before;
};

struct Frame {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<float> depth;   // visibility buffer, as the plugin left it
    std::vector<uint32_t> face;
    std::vector<float> bary;
    std::vector<uint32_t> instance;     // per pixel; empty unless the scene has instances
    std::vector<uint32_t> depth_tests;  // per pixel; empty unless asked for (FrameSettings)
    std::vector<uint8_t> rgb;   // 3 * width * height, rows top to bottom; with samples, their mean
    // With FrameSettings::coverage_alpha, width * height: 255 times the part of the pixel covered
    // (of its samples, or the a-buffer's coverage times opacity), rounded; else empty.
    std::vector<uint8_t> alpha;
    std::vector<std::pair<std::string, uint64_t>> counters;  // the plugins' and the host's, in order
    std::optional<StepRun> steps;  // when rendered step by step (FrameSettings::stop_after_step)
    double visibility_ms = 0;   // time inside the hidden-surface plugin
    double shading_ms = 0;      // fragment assembly + lighting plugin

    uint64_t counter(const std::string& name) const;  // 0 when absent
};

}  // namespace hsr
