#include "hsr/line_image.hpp"

#include "hsr/atomic_file.hpp"
#include "hsr/error.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

namespace hsr {
namespace {

std::string lower_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// ".svg" or ".png"; any other is an hsr::Error.
std::string drawing_extension(const std::filesystem::path& path) {
    const std::string ext = lower_extension(path);
    if (ext != ".svg" && ext != ".png")
        throw Error("{}: a line drawing is written as .svg or .png, not '{}'", printable(path.string(), kMaxQuotedPathChars),
                    printable(ext));
    return ext;
}

bool is_outline(uint32_t flags) { return (flags & (HSR_EDGE_SILHOUETTE | HSR_EDGE_BOUNDARY)) != 0; }

// Strokes every segment that `take` selects as paths of at most `path_segments` segments each (an
// SVG gets one path element, not one per segment). Rasterizing one path costs more than linear
// time in its overlapping segments: 408,594 segments of a scrambled mesh took Cairo 6 s as one
// path into a 128x128 PNG, 1 s as paths of 4,096.
template <class Take>
uint64_t stroke(cairo_t* cr, const LineDrawing& d, Take take, glm::vec3 color, double width, bool dashed,
                const LineStyle& style, uint64_t path_segments) {
    cairo_set_source_rgb(cr, color.r, color.g, color.b);
    cairo_set_line_width(cr, width);
    if (dashed) {
        const double pattern[2] = {style.dash, style.gap};
        cairo_set_dash(cr, pattern, 2, 0.0);
    } else {
        cairo_set_dash(cr, nullptr, 0, 0.0);
    }
    uint64_t n = 0;
    for (const LineSegment& s : d.segments) {
        if (!take(s)) continue;
        cairo_move_to(cr, s.a.x, s.a.y);
        cairo_line_to(cr, s.b.x, s.b.y);
        if (++n % path_segments == 0) cairo_stroke(cr);
    }
    if (n % path_segments != 0) cairo_stroke(cr);
    return n;
}

LineImageStats draw(cairo_t* cr, const LineDrawing& d, const LineStyle& style, uint64_t path_segments) {
    cairo_set_source_rgb(cr, style.background.r, style.background.g, style.background.b);
    cairo_paint(cr);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    LineImageStats stats;
    // Hidden lines first, under the visible ones; then other visible edges; the outline on top.
    if (style.hidden == HiddenLines::kDashed)
        stats.hidden = stroke(cr, d, [](const LineSegment& s) { return s.qi != 0; }, style.hidden_ink,
                              style.hidden_width, true, style, path_segments);
    stats.visible = stroke(cr, d, [](const LineSegment& s) { return s.qi == 0 && !is_outline(s.flags); }, style.ink,
                           style.line_width, false, style, path_segments);
    stats.outline = stroke(cr, d, [](const LineSegment& s) { return s.qi == 0 && is_outline(s.flags); }, style.ink,
                           style.outline_width, false, style, path_segments);
    stats.visible += stats.outline;
    return stats;
}

cairo_status_t write_to_file(void* file, const unsigned char* data, unsigned int length) {
    return std::fwrite(data, 1, length, static_cast<std::FILE*>(file)) == length ? CAIRO_STATUS_SUCCESS
                                                                                 : CAIRO_STATUS_WRITE_ERROR;
}

struct SurfaceCloser {
    void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextCloser {
    void operator()(cairo_t* c) const { cairo_destroy(c); }
};

}  // namespace

bool is_line_drawing_path(const std::filesystem::path& path) {
    const std::string ext = lower_extension(path);
    return ext == ".svg" || ext == ".png";
}

namespace {

// The drawing as SVG or PNG (ext), its bytes handed to `write`; `what` names it in messages.
LineImageStats encode_line_drawing(cairo_write_func_t write, void* closure, const std::string& ext,
                                   const std::string& what, const LineDrawing& drawing, const LineStyle& style) {
    if (drawing.width == 0 || drawing.height == 0) throw Error("{}: the drawing has no size", what);
    std::unique_ptr<cairo_surface_t, SurfaceCloser> surface(
        ext == ".svg" ? cairo_svg_surface_create_for_stream(write, closure, drawing.width, drawing.height)
                      : cairo_image_surface_create(CAIRO_FORMAT_RGB24, int(drawing.width), int(drawing.height)));
    if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
        throw Error("{}: cannot write: {}", what, cairo_status_to_string(cairo_surface_status(surface.get())));
    if (ext == ".svg") cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_PX);  // 1 unit = 1 pixel
    LineImageStats stats;
    {
        std::unique_ptr<cairo_t, ContextCloser> cr(cairo_create(surface.get()));
        stats = draw(cr.get(), drawing, style, ext == ".svg" ? UINT64_MAX : 4096);
        if (cairo_status(cr.get()) != CAIRO_STATUS_SUCCESS)
            throw Error("{}: drawing failed: {}", what, cairo_status_to_string(cairo_status(cr.get())));
    }
    if (ext == ".png") {
        const cairo_status_t status = cairo_surface_write_to_png_stream(surface.get(), write, closure);
        if (status != CAIRO_STATUS_SUCCESS) throw Error("{}: cannot write: {}", what, cairo_status_to_string(status));
    } else {
        cairo_surface_finish(surface.get());
        if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
            throw Error("{}: cannot write: {}", what, cairo_status_to_string(cairo_surface_status(surface.get())));
    }
    return stats;
}

cairo_status_t append_to_string(void* text, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(text)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

}  // namespace

LineImageStats write_line_drawing(AtomicFile& file, const LineDrawing& drawing, const LineStyle& style) {
    const std::filesystem::path& path = file.target();
    return encode_line_drawing(write_to_file, file.stdio(), drawing_extension(path),
                               printable(path.string(), kMaxQuotedPathChars), drawing, style);
}

std::string line_drawing_svg(const LineDrawing& drawing, const LineStyle& style) {
    std::string svg;
    encode_line_drawing(append_to_string, &svg, ".svg", "the SVG drawing", drawing, style);
    return svg;
}

Image draw_line_image(const LineDrawing& drawing, const LineStyle& style) {
    if (drawing.width == 0 || drawing.height == 0) throw Error("the line drawing has no size");
    std::unique_ptr<cairo_surface_t, SurfaceCloser> surface(
        cairo_image_surface_create(CAIRO_FORMAT_RGB24, int(drawing.width), int(drawing.height)));
    if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
        throw Error("cannot draw the lines: {}", cairo_status_to_string(cairo_surface_status(surface.get())));
    {
        std::unique_ptr<cairo_t, ContextCloser> cr(cairo_create(surface.get()));
        draw(cr.get(), drawing, style, 4096);
        if (cairo_status(cr.get()) != CAIRO_STATUS_SUCCESS)
            throw Error("drawing failed: {}", cairo_status_to_string(cairo_status(cr.get())));
    }
    cairo_surface_flush(surface.get());
    Image image;
    image.width = drawing.width;
    image.height = drawing.height;
    image.channels = 3;
    image.pixels.resize(size_t(image.width) * image.height * 3);
    const unsigned char* data = cairo_image_surface_get_data(surface.get());
    const size_t stride = size_t(cairo_image_surface_get_stride(surface.get()));
    for (uint32_t y = 0; y < image.height; ++y) {
        const auto* row = reinterpret_cast<const uint32_t*>(data + y * stride);  // 0xXXRRGGBB, native order
        uint8_t* out = &image.pixels[size_t(y) * image.width * 3];
        for (uint32_t x = 0; x < image.width; ++x) {
            out[3 * x] = uint8_t(row[x] >> 16);
            out[3 * x + 1] = uint8_t(row[x] >> 8);
            out[3 * x + 2] = uint8_t(row[x]);
        }
    }
    return image;
}

LineImageStats write_line_drawing(const std::filesystem::path& path, const LineDrawing& drawing,
                                  const LineStyle& style) {
    drawing_extension(path);  // checked before a file is made
    AtomicFile file(path);
    const LineImageStats stats = write_line_drawing(file, drawing, style);
    file.commit();
    return stats;
}

}  // namespace hsr
