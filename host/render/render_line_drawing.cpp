// hsr render with a hidden-line plugin: the visible edges drawn as SVG or PNG in the line style of
// --line-color, --line-width and --hidden (docs/line-drawings.md), optionally the
// algorithm's steps as a JSON-lines trace, and with --stats its counters (render.hpp). The trace
// streams into a temporary file during the render; both files are replaced together, once the
// drawing is written too (hsr/atomic_file.hpp).
#include "common/options.hpp"
#include "render/render.hpp"

#include "hsr/atomic_file.hpp"
#include "hsr/error.hpp"
#include "hsr/line_image.hpp"
#include "hsr/lines.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace {

using hsr::host::UsageError;

void print_line_stats(const hsr::LineDrawing& drawing, const hsr::HiddenLineRemover& remover,
                      const hsr_scene& scene) {
    std::fprintf(stderr, "%s, %u triangles, %zu edges asked for, %ux%u\n", remover.plugin().descriptor.name,
                 scene.triangle_count, drawing.edges.size(), drawing.width, drawing.height);
    std::fprintf(stderr, "  %-28s %10.2f ms\n", "hidden-line time", drawing.lines_ms);
    for (const auto& [name, value] : drawing.counters)
        std::fprintf(stderr, "  %-28s %10llu\n", name.c_str(), static_cast<unsigned long long>(value));
}

}  // namespace

hsr::LineStyle hsr::host::make_line_style(const RenderOptions& o) {
    hsr::LineStyle style;
    if (o.hidden_lines == "hidden")
        style.hidden = hsr::HiddenLines::kHidden;
    else if (o.hidden_lines == "dashed")
        style.hidden = hsr::HiddenLines::kDashed;
    else
        throw UsageError("--hidden '{}': expected 'dashed' or 'hidden'", hsr::printable(o.hidden_lines));
    if (o.was_given("background")) style.background = parse_color_option(o.background, "background");
    if (!o.line_color.empty()) {
        style.ink = parse_color_option(o.line_color, "line-color");
        style.hidden_ink = 0.5f * (style.ink + style.background);
    } else if (hsr::relative_luminance(style.background) < 0.5f) {
        style.ink = hsr::LineStyle::light_ink;
        style.hidden_ink = hsr::LineStyle::light_hidden_ink;
    }
    if (!(o.line_width > 0.0 && o.line_width <= max_line_width))
        throw UsageError("--line-width {}: expected more than 0 and at most {} pixels", o.line_width, max_line_width);
    style.scale_widths(o.line_width);
    return style;
}

void hsr::host::render_line_drawing(const RenderOptions& o, const hsr::Renderer& renderer, LineDrawingPlugin& plugin,
                                    const std::filesystem::path& output) {
    hsr::LineRequest request;
    request.view = view_request(o);
    request.settings = plugin.settings;
    hsr::AtomicFileSet files;
    if (!o.trace.empty()) request.settings.trace = &files.add(o.trace).stream();
    const hsr::LinePicture picture = renderer.lines(request, *plugin.remover);
    const hsr::LineDrawing& drawing = picture.drawing;
    const hsr_scene& scene_view = picture.scene;
    const hsr::LineStyle& style = plugin.style;
    const hsr::LineImageStats drawn = hsr::write_line_drawing(files.add(output), drawing, style);
    files.commit();
    if (o.stats) print_line_stats(drawing, *plugin.remover, scene_view);
    if (!o.trace.empty())
        std::fprintf(stderr, "wrote %s (%llu steps)\n", hsr::printable(o.trace, std::string::npos).c_str(),
                     static_cast<unsigned long long>(drawing.trace_events));
    std::fprintf(stderr, "wrote %s (%ux%u, %llu visible segments%s, %zu edges, %.1f ms)\n",
                 hsr::printable(output.string(), std::string::npos).c_str(), drawing.width, drawing.height,
                 static_cast<unsigned long long>(drawn.visible),
                 style.hidden == hsr::HiddenLines::kDashed ? fmt::format(" and {} hidden", drawn.hidden).c_str() : "",
                 drawing.edges.size(), drawing.lines_ms);
}
