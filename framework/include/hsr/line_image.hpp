// Line drawings as files, drawn with Cairo: SVG (vector, for print and for the web) or PNG
// (anti-aliased). Visible lines solid; hidden ones dashed and lighter, or left out; silhouettes and
// boundaries (the outline) drawn heavier than creases and other edges; penetration lines like
// creases.
#pragma once

#include "hsr/image.hpp"
#include "hsr/lines.hpp"

#include <glm/glm.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace hsr {

enum class HiddenLines { kHidden, kDashed };

struct LineStyle {
    HiddenLines hidden = HiddenLines::kHidden;
    glm::vec3 background{1.0f, 1.0f, 1.0f};
    glm::vec3 ink{0.08f, 0.08f, 0.1f};         // visible lines
    glm::vec3 hidden_ink{0.55f, 0.55f, 0.6f};  // dashed hidden lines
    double line_width = 1.0;                   // pixels
    double outline_width = 2.0;                // silhouettes and boundaries
    double hidden_width = 0.75;
    double dash = 4.0, gap = 3.0;              // dashed hidden lines, pixels

    // The inks for a dark background (relative_luminance below 0.5).
    static constexpr glm::vec3 light_ink{0.92f, 0.92f, 0.9f};
    static constexpr glm::vec3 light_hidden_ink{0.5f, 0.5f, 0.55f};

    // Every width, dash and gap times `factor`: the style of lines `factor` times as heavy.
    void scale_widths(double factor) {
        for (double* length : {&line_width, &outline_width, &hidden_width, &dash, &gap}) *length *= factor;
    }
};

// The relative luminance of an sRGB colour (ITU-R BT.709 weights on the stored values): 0 black,
// 1 white; what decides whether lines are drawn dark or light.
inline float relative_luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// Counts of what was drawn, for messages.
struct LineImageStats {
    uint64_t visible = 0, hidden = 0, outline = 0;
};

class AtomicFile;

// By the target's extension: .svg or .png (any other is an hsr::Error), into an AtomicFile
// (hsr/atomic_file.hpp) that the caller commits, or, given a path, into a file of its own committed
// at once. Throws hsr::Error when the file cannot be written.
LineImageStats write_line_drawing(AtomicFile& file, const LineDrawing& drawing, const LineStyle& style);
LineImageStats write_line_drawing(const std::filesystem::path& path, const LineDrawing& drawing,
                                  const LineStyle& style);

// The SVG file write_line_drawing writes, as text.
std::string line_drawing_svg(const LineDrawing& drawing, const LineStyle& style);

// The drawing as write_line_drawing draws a PNG, as 8-bit RGB pixels (for encode_png, image.hpp).
Image draw_line_image(const LineDrawing& drawing, const LineStyle& style);

// True for the extensions write_line_drawing knows.
bool is_line_drawing_path(const std::filesystem::path& path);

}  // namespace hsr
