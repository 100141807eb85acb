// Line drawings as files, drawn with Cairo: SVG (vector, for print and for the web) or PNG
// (anti-aliased). Visible lines solid; hidden ones dashed and lighter, or left out; silhouettes and
// boundaries (the outline) drawn heavier than creases and other edges; penetration lines like
// creases.
#pragma once

#include "hsr/image.hpp"
#include "hsr/lines.hpp"

#include <glm/glm.hpp>

#include <filesystem>
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
};

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

// The drawing as write_line_drawing draws a PNG, as 8-bit RGB pixels (for encode_png, image.hpp).
Image draw_line_image(const LineDrawing& drawing, const LineStyle& style);

// True for the extensions write_line_drawing knows.
bool is_line_drawing_path(const std::filesystem::path& path);

}  // namespace hsr
