// The frames of one hsr render and the names of their files (frames.hpp).
#include "render/frames.hpp"

#include "common/options.hpp"
#include "render/options.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>

namespace hsr::host {
namespace {

// A whole finite number, optionally signed ("+30" as well as "30", as the command line's parser took
// it); nullopt when the text is not one.
template <typename Number>
std::optional<Number> parse_number(std::string_view text) {
    if (text.size() > 1 && text[0] == '+' && text[1] != '-') text.remove_prefix(1);
    Number value{};
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

// How many frames a range of `count` values times `others` makes, saturated, against the limit.
void check_frame_count(double count, uint64_t others, const std::string& what) {
    const double total = count * double(others);
    const uint64_t amount = total >= 1.8e19 ? std::numeric_limits<uint64_t>::max() : uint64_t(total);
    hsr::check_limit(&hsr::Limits::frames, amount, what);
}

}  // namespace

std::vector<float> parse_angle_option(const std::string& text, const char* option) {
    const std::size_t first_colon = text.find(':');
    if (first_colon == std::string::npos) {
        const std::optional<float> value = parse_number<float>(text);
        if (!value) throw UsageError("--{} '{}': expected degrees, or A:B:STEP (a range)", option, hsr::printable(text));
        if (!std::isfinite(*value)) throw UsageError("--{} must be a finite number", option);
        return {*value};
    }
    const std::size_t second_colon = text.find(':', first_colon + 1);
    std::optional<double> a, b, step;
    if (second_colon != std::string::npos) {
        a = parse_number<double>(std::string_view(text).substr(0, first_colon));
        b = parse_number<double>(std::string_view(text).substr(first_colon + 1, second_colon - first_colon - 1));
        step = parse_number<double>(std::string_view(text).substr(second_colon + 1));
    }
    if (!a || !b || !step || !std::isfinite(*a) || !std::isfinite(*b) || !std::isfinite(*step))
        throw UsageError("--{} '{}': expected A:B:STEP, three finite numbers of degrees (from A to B by STEP)", option,
                         hsr::printable(text));
    if (*step == 0) throw UsageError("--{} {}: the step must not be 0", option, hsr::printable(text));
    const double steps = (*b - *a) / *step;
    if (steps < 0) throw UsageError("--{} {}: a step of {} never reaches {}", option, text, *step, *b);
    // B counts when a step lands on it up to rounding (0:1:0.1 ends at 1); within the frames limit the
    // quotient's rounding error is far below the tolerance.
    const double count = std::floor(steps + 1e-6) + 1;
    check_frame_count(count, 1, fmt::format("--{} {}", option, text));
    std::vector<float> values;
    values.reserve(std::size_t(count));
    for (uint64_t k = 0; k < uint64_t(count); ++k) values.push_back(float(*a + double(k) * *step));
    return values;
}

std::vector<int64_t> parse_step_option(const std::string& text) {
    const std::size_t dots = text.find("..");
    const std::string_view first_text = std::string_view(text).substr(0, dots);
    const std::optional<int64_t> first = parse_number<int64_t>(first_text);
    const std::optional<int64_t> last =
        dots == std::string::npos ? first : parse_number<int64_t>(std::string_view(text).substr(dots + 2));
    if (!first || !last)
        throw UsageError("--step '{}': expected a step number N, or A..B (the steps A to B)", hsr::printable(text));
    if (*first < 1 || *last < 1) throw UsageError("--step {}: steps count from 1", text);
    if (*last < *first) throw UsageError("--step {}: the range ends before it starts (write {}..{})", text, *last, *first);
    if (*last - *first >= kMaxStepRange)
        throw UsageError("--step {}: {} steps; a range renders at most {} (each step renders the algorithm again)",
                         text, fmt::format("{}", uint64_t(*last - *first) + 1), kMaxStepRange);
    std::vector<int64_t> steps;
    for (int64_t step = *first; step <= *last; ++step) steps.push_back(step);
    return steps;
}

std::vector<FrameView> plan_frames(RenderOptions& o) {
    if (o.was_given("views") && !(o.views >= 1))
        throw UsageError("--views {}: expected the number of frames of a turntable, at least 1", o.views);
    const std::vector<float> yaws = parse_angle_option(o.yaw_text, "yaw");
    const std::vector<float> pitches = parse_angle_option(o.pitch_text, "pitch");
    if (o.was_given("views") && yaws.size() > 1)
        throw UsageError("--views {} turns from one --yaw: give --views or a --yaw range, not both", o.views);
    if (o.was_given("views") && !o.eye.empty()) throw UsageError("--eye replaces --views: give one or the other");
    const std::vector<int64_t> steps = o.was_given("step") ? parse_step_option(o.step_text) : std::vector<int64_t>{0};
    check_frame_count(double(yaws.size()) * double(pitches.size()) * double(steps.size()), uint64_t(o.views),
                      o.was_given("views") ? fmt::format("--views {}", o.views)
                      : steps.size() > 1   ? "--yaw, --pitch and --step"
                                           : "--yaw and --pitch");
    std::vector<FrameView> frames;
    frames.reserve(yaws.size() * pitches.size() * uint64_t(o.views) * steps.size());
    for (float pitch : pitches)
        for (float yaw : yaws)
            for (int64_t k = 0; k < o.views; ++k)
                for (int64_t step : steps) frames.push_back({yaw, pitch, double(k) * (360.0 / double(o.views)), step});
    o.yaw = frames.front().yaw;
    o.pitch = frames.front().pitch;
    o.step = frames.front().step;
    return frames;
}

OutputTemplate::OutputTemplate(const std::string& text, const char* option) {
    std::string* part = &before_;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '%') {
            *part += text[i];
            continue;
        }
        if (i + 1 < text.size() && text[i + 1] == '%') {
            *part += '%';
            ++i;
            continue;
        }
        std::size_t j = i + 1;
        const bool zero_pad = j < text.size() && text[j] == '0';
        if (zero_pad) ++j;
        int width = 0;
        while (j < text.size() && text[j] >= '0' && text[j] <= '9' && width < 100) width = width * 10 + (text[j++] - '0');
        if (j >= text.size() || text[j] != 'd' || width > 20)
            throw UsageError("--{} '{}': a % starts the frame number, %d or %03d (at most 20 wide); write %% for a "
                             "% sign", option, hsr::printable(text));
        if (has_number_)
            throw UsageError("--{} '{}': one frame number (%d) in a name, not two", option, hsr::printable(text));
        has_number_ = true;
        zero_pad_ = zero_pad;
        width_ = width;
        part = &after_;
        i = j;
    }
}

std::string OutputTemplate::name(uint64_t frame) const {
    if (!has_number_) return before_;
    return zero_pad_ ? fmt::format("{}{:0{}}{}", before_, frame, width_, after_)
                     : fmt::format("{}{:>{}}{}", before_, frame, width_, after_);
}

}  // namespace hsr::host
