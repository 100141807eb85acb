// Many frames from one hsr render: the views that --views, --yaw A:B:STEP and --pitch A:B:STEP ask
// for, and the output names that a frame-number template (-o frame-%03d.png) gives each of them.
// docs/many-frames.md shows them in use.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hsr::host {

struct RenderOptions;

// The angles of one frame: --yaw and --pitch (each a value of its range), and the turn of a
// turntable (--views) that is added to the yaw, the command line's or a .scene file's.
struct FrameView {
    float yaw = 0, pitch = 0;
    double yaw_turn = 0;  // degrees
    int64_t step = 0;     // --step of this frame (0: the whole render)
};

// The most steps one --step A..B renders: each step renders the algorithm again up to it.
inline constexpr int64_t kMaxStepRange = 1000;

// --step's value, "N" or "A..B" (A <= B, both from 1, at most kMaxStepRange steps): the steps, in
// order; a mistake is a UsageError.
std::vector<int64_t> parse_step_option(const std::string& text);

// An angle option's value, "A" or "A:B:STEP": A, A + STEP, ... while not past B (B itself when a
// step lands on it). STEP may be negative, not 0; the count is checked against the frames limit.
std::vector<float> parse_angle_option(const std::string& text, const char* option);

// Every frame of the options, in order: the pitches' range outermost, then the yaws', then the
// turns of --views, then the steps of --step A..B. Checks --views and the ranges and sets o.yaw and o.pitch to the first frame's
// angles and o.step to its step; a mistake is a UsageError, too many frames an hsr::Error naming the frames limit.
std::vector<FrameView> plan_frames(RenderOptions& o);

// An output name with at most one frame number in it, printf-style: %d, %5d or %05d (zero-padded to
// the width), and %% for a % sign. Any other % is a UsageError naming the option.
class OutputTemplate {
public:
    OutputTemplate() = default;
    OutputTemplate(const std::string& text, const char* option);

    bool has_number() const { return has_number_; }
    // The name of frame `frame` (0 for the first).
    std::string name(uint64_t frame) const;

private:
    std::string before_, after_;
    bool has_number_ = false, zero_pad_ = false;
    int width_ = 0;
};

}  // namespace hsr::host
