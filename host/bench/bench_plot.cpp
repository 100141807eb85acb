// hsr bench's plot (bench_plot.hpp): the panels' layout on a PlotCanvas, and the Cairo canvas that
// writes them as SVG or PNG.
#include "bench/bench_plot.hpp"

#include "bench/bench_report.hpp"
#include "hsr/error.hpp"

#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>

namespace hsr::bench {

std::vector<double> decade_ticks(double lo, double hi) {
    std::vector<double> ticks;
    if (!(lo > 0) || !(hi > 0) || !std::isfinite(lo) || !std::isfinite(hi)) return ticks;
    int a = int(std::floor(std::log10(lo) + 1e-9)), b = int(std::ceil(std::log10(hi) - 1e-9));
    if (b <= a) b = a + 1;
    for (int e = a; e <= b; ++e) ticks.push_back(std::pow(10.0, e));
    return ticks;
}

std::string tick_label(double v) {
    auto g = [](double x) { return fmt::format("{:.6g}", x); };
    if (v >= 1e9) return g(v / 1e9) + "G";
    if (v >= 1e6) return g(v / 1e6) + "M";
    if (v >= 1e3) return g(v / 1e3) + "k";
    return g(v);
}

namespace {

using Point = PlotCanvas::Point;
using Pen = PlotCanvas::Pen;
using Font = PlotCanvas::Font;
using Anchor = PlotCanvas::Anchor;

constexpr std::array<const char*, 16> palette = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
                                                 "#e377c2", "#17becf", "#7f7f7f", "#bcbd22", "#393b79", "#000000",
                                                 "#637939", "#843c39", "#7b4173", "#8c6d31"};

// One plot, offset down by `dy` (for stacked plots).
void draw_panel(PlotCanvas& canvas, const LogLogPlot& plot, double dy) {
    const double W = plot.width, H = plot.height;
    const double left = 78, right = W - 210, top = dy + 70, bottom = dy + H - 62;

    double xmin = std::numeric_limits<double>::infinity(), xmax = 0, ymin = xmin, ymax = 0;
    for (const PlotSeries& s : plot.series)
        for (auto [x, y] : s.points) {
            if (!(x > 0) || !(y > 0)) continue;
            xmin = std::min(xmin, x), xmax = std::max(xmax, x);
            ymin = std::min(ymin, y), ymax = std::max(ymax, y);
        }
    for (const PlotMiss& miss : plot.misses)
        if (miss.x > 0) xmin = std::min(xmin, miss.x), xmax = std::max(xmax, miss.x);
    if (!(xmax > 0)) xmin = 1, xmax = 10;
    if (!(ymax > 0)) ymin = 1, ymax = 10;
    const std::vector<double> xt = decade_ticks(xmin, xmax), yt = decade_ticks(ymin, ymax);
    const double lx0 = std::log10(xt.front()), lx1 = std::log10(xt.back());
    const double ly0 = std::log10(yt.front()), ly1 = std::log10(yt.back());
    auto X = [&](double x) { return left + (std::log10(x) - lx0) / (lx1 - lx0) * (right - left); };
    auto Y = [&](double y) { return bottom - (std::log10(y) - ly0) / (ly1 - ly0) * (bottom - top); };
    auto vertical = [&](double x, double y0, double y1) { return std::pair{Point{x, y0}, Point{x, y1}}; };
    auto horizontal = [&](double y, double x0, double x1) { return std::pair{Point{x0, y}, Point{x1, y}}; };

    const double middle = (left + right) / 2;
    canvas.text({middle, dy + 28}, plot.title, {18, "#000000", Anchor::middle, true});
    if (!plot.subtitle.empty()) canvas.text({middle, dy + 48}, plot.subtitle, {12, "#555555", Anchor::middle});

    // Grid: decades, and 2..9 within each decade (labelled too at 2 and 5 when the axis is short).
    auto minor_ticks = [](const std::vector<double>& decades, auto&& f) {
        for (std::size_t i = 0; i + 1 < decades.size(); ++i)
            for (int m = 2; m <= 9; ++m) f(decades[i] * m, m);
    };
    const bool label_x_minor = xt.size() <= 3, label_y_minor = yt.size() <= 3;
    std::vector<std::pair<Point, Point>> minor_grid, major_grid;
    minor_ticks(xt, [&](double x, int) { minor_grid.push_back(vertical(X(x), top, bottom)); });
    minor_ticks(yt, [&](double y, int) { minor_grid.push_back(horizontal(Y(y), left, right)); });
    for (double x : xt) major_grid.push_back(vertical(X(x), top, bottom));
    for (double y : yt) major_grid.push_back(horizontal(Y(y), left, right));
    canvas.segments(minor_grid, {"#eeeeee", 1});
    canvas.segments(major_grid, {"#cccccc", 1});

    // Guides: which model sits where.
    std::vector<PlotGuide> guides = plot.guides;
    std::sort(guides.begin(), guides.end(), [](const PlotGuide& a, const PlotGuide& b) { return a.x < b.x; });
    std::vector<std::pair<Point, Point>> guide_lines;
    for (const PlotGuide& g : guides)
        if (g.x > 0) guide_lines.push_back(vertical(X(g.x), top, bottom));
    canvas.segments(guide_lines, {"#999999", 1, "2 3"});
    double last_top = -1e9;
    for (const PlotGuide& g : guides) {
        if (!(g.x > 0)) continue;
        const double x = X(g.x);
        // Labels read upward, left of their line, at the top; one too close to the previous goes
        // to the bottom instead.
        Font font{11, "#555555", Anchor::end, false, true, true};
        if (x - left < 15) {  // at the left frame: right of the line
            canvas.text({x + 11, top + 4}, g.label, font);
            last_top = x + 14;
        } else if (x - last_top >= 15) {
            canvas.text({x - 3, top + 4}, g.label, font);
            last_top = x;
        } else {
            font.anchor = Anchor::start;
            canvas.text({x + 11, bottom - 4}, g.label, font);
        }
    }

    // Axes, ticks, labels.
    canvas.frame({left, top}, right - left, bottom - top, {"#333333", 1});
    std::vector<std::pair<Point, Point>> ticks;
    const Font tick_font{12, "#222222", Anchor::middle}, minor_font{10, "#555555", Anchor::middle};
    for (double x : xt) {
        ticks.push_back(vertical(X(x), bottom, bottom + 6));
        canvas.text({X(x), bottom + 20}, tick_label(x), tick_font);
    }
    minor_ticks(xt, [&](double x, int m) {
        ticks.push_back(vertical(X(x), bottom, bottom + 3));
        if (label_x_minor && (m == 2 || m == 5)) canvas.text({X(x), bottom + 18}, tick_label(x), minor_font);
    });
    for (double y : yt) {
        ticks.push_back(horizontal(Y(y), left - 6, left));
        canvas.text({left - 9, Y(y) + 4}, fmt::format("{:.6g}", y), {12, "#222222", Anchor::end});
    }
    minor_ticks(yt, [&](double y, int m) {
        ticks.push_back(horizontal(Y(y), left - 3, left));
        if (label_y_minor && (m == 2 || m == 5))
            canvas.text({left - 8, Y(y) + 4}, fmt::format("{:.6g}", y), {10, "#555555", Anchor::end});
    });
    canvas.segments(ticks, {"#333333", 1});
    canvas.text({middle, dy + H - 18}, plot.x_label, {13, "#000000", Anchor::middle});
    canvas.text({22, (top + bottom) / 2}, plot.y_label, {13, "#000000", Anchor::middle, false, true});

    // A slope-1 reference: what linear growth in the face count looks like on these axes.
    std::optional<std::pair<double, double>> anchor;
    if (plot.linear_reference && !plot.series.empty())
        for (auto p : plot.series.front().points)
            if (p.first > 0 && p.second > 0 && (!anchor || p.first > anchor->first)) anchor = p;
    const Pen reference_pen{"#888888", 1.2, "8 5"};
    if (anchor) {  // clipped to the frame
        const double c = std::log10(anchor->second) - std::log10(anchor->first);  // log y = log x + c
        const double a = std::max(lx0, ly0 - c), b = std::min(lx1, ly1 - c);
        if (b > a) {
            const double x0 = std::pow(10.0, a), x1 = std::pow(10.0, b);
            canvas.segments({{{X(x0), Y(x0 * std::pow(10.0, c))}, {X(x1), Y(x1 * std::pow(10.0, c))}}},
                            reference_pen);
        } else {
            anchor.reset();
        }
    }

    // The series.
    std::vector<std::string> colors;
    for (std::size_t i = 0; i < plot.series.size(); ++i)
        colors.push_back(plot.series[i].color.empty() ? palette[i % palette.size()] : plot.series[i].color);
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
        const PlotSeries& s = plot.series[i];
        std::vector<std::pair<double, double>> points;
        for (auto p : s.points)
            if (p.first > 0 && p.second > 0) points.push_back(p);
        std::sort(points.begin(), points.end());
        std::vector<Point> line;
        for (auto [x, y] : points) line.emplace_back(X(x), Y(y));
        canvas.polyline(line, {colors[i], 2, s.dash});
        for (Point p : line) canvas.marker(p, colors[i], s.hollow);
    }

    // Cells without a time: crosses on the bottom edge, stacked up where several share a face count.
    auto cross = [&](Point at, const std::string& color) {
        constexpr double r = 4;
        canvas.segments({{{at.first - r, at.second - r}, {at.first + r, at.second + r}},
                         {{at.first - r, at.second + r}, {at.first + r, at.second - r}}},
                        {color, 2});
    };
    std::map<double, int> misses_at;
    for (const PlotMiss& miss : plot.misses)
        if (miss.x > 0) cross({X(miss.x), bottom - 8 - 11 * misses_at[miss.x]++}, miss.color);

    // Legend, right of the plot.
    const double lx = right + 18;
    double ly = top + 8;
    auto entry = [&](const Pen& pen, std::optional<bool> hollow, const std::string& label, const std::string& ink) {
        canvas.segments({horizontal(ly, lx, lx + 28)}, pen);
        if (hollow) canvas.marker({lx + 14, ly}, pen.color, *hollow);
        canvas.text({lx + 36, ly + 4}, label, {12, ink});
        ly += 20;
    };
    for (std::size_t i = 0; i < plot.series.size(); ++i)
        if (plot.series[i].in_legend)
            entry({colors[i], 2, plot.series[i].dash}, plot.series[i].hollow, plot.series[i].label, "#000000");
    if (!plot.notes.empty()) ly += 8;
    for (const LegendNote& note : plot.notes) entry({"#444444", 2, note.dash}, note.hollow, note.label, "#444444");
    if (!plot.misses.empty()) {
        if (plot.notes.empty()) ly += 8;
        cross({lx + 14, ly}, "#444444");
        canvas.text({lx + 36, ly + 4}, plot.miss_label, {12, "#444444"});
        ly += 20;
    }
    if (anchor) {
        if (plot.notes.empty()) ly += 8;
        entry(reference_pen, std::nullopt, "linear in faces", "#555555");
    }
}

struct Rgb {
    double r, g, b;
};
Rgb rgb(const std::string& color) {  // "#rrggbb"
    const unsigned long v = color.size() == 7 ? std::stoul(color.substr(1), nullptr, 16) : 0;
    return {double((v >> 16) & 0xff) / 255.0, double((v >> 8) & 0xff) / 255.0, double(v & 0xff) / 255.0};
}

class CairoCanvas : public PlotCanvas {
public:
    explicit CairoCanvas(cairo_t* cr) : cr_(cr) {}

    void fill(Point corner, double width, double height, const std::string& color) override {
        cairo_rectangle(cr_, corner.first, corner.second, width, height);
        set_color(color);
        cairo_fill(cr_);
    }
    void frame(Point corner, double width, double height, const Pen& pen) override {
        // On the pixel grid's half points, as a one-pixel line is sharp there.
        cairo_rectangle(cr_, snap(corner.first), snap(corner.second), std::round(width), std::round(height));
        stroke(pen);
    }
    void segments(const std::vector<std::pair<Point, Point>>& lines, const Pen& pen) override {
        if (lines.empty()) return;
        for (const auto& [a, b] : lines) {
            // Axis-parallel hairlines snapped to the pixel grid like the frame, not blurred over two.
            const bool straight = a.first == b.first || a.second == b.second;
            cairo_move_to(cr_, straight ? snap(a.first) : a.first, straight ? snap(a.second) : a.second);
            cairo_line_to(cr_, straight ? snap(b.first) : b.first, straight ? snap(b.second) : b.second);
        }
        stroke(pen);
    }
    void polyline(const std::vector<Point>& points, const Pen& pen) override {
        if (points.empty()) return;
        for (const Point& p : points) cairo_line_to(cr_, p.first, p.second);
        cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
        stroke(pen);
        cairo_set_line_join(cr_, CAIRO_LINE_JOIN_MITER);
    }
    void marker(Point at, const std::string& color, bool hollow) override {
        cairo_new_sub_path(cr_);
        cairo_arc(cr_, at.first, at.second, 3.5, 0, 2 * M_PI);
        set_color(hollow ? "#ffffff" : color);
        cairo_fill_preserve(cr_);
        stroke({hollow ? color : "#ffffff", hollow ? 1.8 : 0.8});
    }
    void text(Point at, const std::string& text, const Font& font) override {
        if (text.empty()) return;
        cairo_save(cr_);
        cairo_select_font_face(cr_, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                               font.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_font_size(cr_, font.size);
        cairo_translate(cr_, at.first, at.second);
        if (font.upward) cairo_rotate(cr_, -M_PI / 2);
        cairo_text_extents_t extents;
        cairo_text_extents(cr_, text.c_str(), &extents);
        const double shift = font.anchor == Anchor::middle ? extents.x_advance / 2
                             : font.anchor == Anchor::end  ? extents.x_advance
                                                           : 0;
        if (font.halo) {  // outlined as a path; plain text stays glyphs (in an SVG, each glyph drawn once)
            cairo_move_to(cr_, -shift, 0);
            cairo_text_path(cr_, text.c_str());
            cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
            set_color("#ffffff");
            cairo_set_line_width(cr_, 3);
            cairo_stroke(cr_);
        }
        cairo_move_to(cr_, -shift, 0);
        set_color(font.color);
        cairo_show_text(cr_, text.c_str());
        cairo_restore(cr_);
    }

private:
    static double snap(double v) { return std::floor(v) + 0.5; }
    void set_color(const std::string& color) {
        const Rgb c = rgb(color);
        cairo_set_source_rgb(cr_, c.r, c.g, c.b);
    }
    void stroke(const Pen& pen) {
        set_color(pen.color);
        cairo_set_line_width(cr_, pen.width);
        std::vector<double> dash;
        std::istringstream lengths(pen.dash);
        for (double d; lengths >> d;) dash.push_back(d);
        cairo_set_dash(cr_, dash.data(), int(dash.size()), 0);
        cairo_stroke(cr_);
    }
    cairo_t* cr_;
};

struct SurfaceCloser {
    void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextCloser {
    void operator()(cairo_t* c) const { cairo_destroy(c); }
};

cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
    auto& out = *static_cast<std::ostream*>(closure);
    out.write(reinterpret_cast<const char*>(data), length);
    return out ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

void check(cairo_status_t status, const char* what) {
    if (status != CAIRO_STATUS_SUCCESS) throw Error("the plot: {}: {}", what, cairo_status_to_string(status));
}

}  // namespace

std::pair<int, int> picture_size(const std::vector<LogLogPlot>& plots) {
    int width = 0, height = 0;
    for (const LogLogPlot& p : plots) width = std::max(width, p.width), height += p.height;
    if (plots.empty()) width = height = 100;
    return {width, height};
}

void draw_plots(PlotCanvas& canvas, const std::vector<LogLogPlot>& plots) {
    const auto [width, height] = picture_size(plots);
    canvas.fill({0, 0}, width, height, "#ffffff");
    double dy = 0;
    for (const LogLogPlot& p : plots) {
        draw_panel(canvas, p, dy);
        dy += p.height;
    }
}

void write_plot(std::ostream& out, const std::vector<LogLogPlot>& plots, PlotFormat format) {
    const auto [width, height] = picture_size(plots);
    std::unique_ptr<cairo_surface_t, SurfaceCloser> surface(
        format == PlotFormat::svg ? cairo_svg_surface_create_for_stream(write_to_stream, &out, width, height)
                                  : cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height));
    check(cairo_surface_status(surface.get()), "cannot make the surface");
    if (format == PlotFormat::svg) cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_PX);
    {
        std::unique_ptr<cairo_t, ContextCloser> cr(cairo_create(surface.get()));
        CairoCanvas canvas(cr.get());
        draw_plots(canvas, plots);
        check(cairo_status(cr.get()), "drawing failed");
    }
    if (format == PlotFormat::png)
        check(cairo_surface_write_to_png_stream(surface.get(), write_to_stream, &out), "cannot encode the PNG");
    cairo_surface_finish(surface.get());
    check(cairo_surface_status(surface.get()), "cannot write the SVG");
}

std::vector<LogLogPlot> plot_results(const std::vector<Result>& results) {
    std::vector<std::pair<uint32_t, uint32_t>> sizes;
    std::vector<std::string> algorithms;
    for (const Result& r : results) {
        index_of(sizes, std::make_pair(r.width, r.height));
        index_of(algorithms, r.algorithm);
    }
    std::vector<LogLogPlot> plots;
    for (const auto& size : sizes) {
        auto at_size = [&](const Result& r) { return std::make_pair(r.width, r.height) == size; };
        LogLogPlot plot;
        unsigned reps = 0;
        bool any_deep = false, any_single = false;
        for (const Result& r : results)
            if (at_size(r) && r.measured()) {
                reps = std::max(reps, r.repetitions);
                (r.instances > 0 ? any_deep : any_single) = true;
            }
        plot.title = fmt::format("Render time against face count, {}x{}", size.first, size.second);
        plot.subtitle = fmt::format("visibility (hidden-surface plugin), build excluded; median of {} run{}", reps,
                                    reps == 1 ? "" : "s");
        plot.x_label = "faces drawn (log scale)";
        plot.y_label = "render time, ms (log scale)";
        for (bool deep : {false, true})
            for (std::size_t a = 0; a < algorithms.size(); ++a) {
                PlotSeries series;
                series.label = deep ? algorithms[a] + ", deep scenes" : algorithms[a];
                series.color = palette[a % palette.size()];
                series.dash = deep ? "6 4" : "";
                series.hollow = deep;
                series.in_legend = !deep || !any_single;
                for (const Result& r : results)
                    if (r.algorithm == algorithms[a] && at_size(r) && r.measured() && (r.instances > 0) == deep)
                        series.points.emplace_back(double(r.faces), std::max(r.visibility.median, 1e-3));
                if (!series.points.empty()) plot.series.push_back(std::move(series));
            }
        // The colour of an algorithm with no time at all is still explained.
        for (std::size_t a = 0; a < algorithms.size(); ++a) {
            const bool plotted = std::any_of(plot.series.begin(), plot.series.end(), [&](const PlotSeries& s) {
                return s.color == palette[a % palette.size()] && s.in_legend;
            });
            const bool missed = std::any_of(results.begin(), results.end(), [&](const Result& r) {
                return r.algorithm == algorithms[a] && at_size(r) && !r.measured();
            });
            if (!plotted && missed) plot.series.push_back({algorithms[a], {}, "", palette[a % palette.size()]});
        }
        for (const Result& r : results)
            if (at_size(r) && !r.measured())
                plot.misses.push_back({double(r.faces), palette[index_of(algorithms, r.algorithm) % palette.size()]});
        plot.miss_label = "no time (see the table)";
        if (any_deep && any_single) {
            plot.notes.push_back({"", false, "single models"});
            plot.notes.push_back({"6 4", true, "deep scenes"});
        }
        std::map<uint64_t, std::string> guides;
        for (const Result& r : results) {
            if (std::make_pair(r.width, r.height) != size) continue;
            std::string& label = guides[r.faces];
            if (label.find(r.model) == std::string::npos) label += (label.empty() ? "" : ", ") + r.model;
        }
        for (const auto& [faces, label] : guides) plot.guides.push_back({double(faces), label});
        plots.push_back(std::move(plot));
    }
    return plots;
}

}  // namespace hsr::bench
