// hsr bench's plot of its results (measure.hpp): render time against face count on log-log axes,
// one panel per image size, drawn with Cairo as SVG or PNG.
#pragma once

#include "bench/measure.hpp"

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace hsr::bench {

// A log-log line plot. Colours are "#rrggbb"; dashes are "on off ..." lengths in pixels.
struct PlotSeries {
    std::string label;
    std::vector<std::pair<double, double>> points;  // (x, y), both > 0; drawn sorted by x
    std::string dash;                                // empty for solid
    std::string color;                               // empty: the next colour of the palette
    bool hollow = false;                             // markers drawn as rings
    bool in_legend = true;
};
struct PlotGuide {  // a labelled vertical line: which model sits at which face count
    double x = 0;
    std::string label;
};
struct LegendNote {  // a grey legend entry explaining a line style
    std::string dash;
    bool hollow = false;
    std::string label;
};
struct PlotMiss {  // a point with no y (a cell without a time): a cross on the bottom edge at x
    double x = 0;
    std::string color;
};
struct LogLogPlot {
    std::string title, subtitle, x_label, y_label;
    std::vector<PlotSeries> series;
    std::vector<PlotGuide> guides;
    std::vector<LegendNote> notes;
    std::vector<PlotMiss> misses;  // explained in the legend as miss_label
    std::string miss_label;
    bool linear_reference = true;  // a dashed slope-1 line through the first series' last point
    int width = 900, height = 600;
};

// Render time (median, build excluded) against faces drawn, one plot per resolution: one line per
// algorithm through the single models, and a dashed one in the same colour through the deep
// scenes (grids of instances, whose cost an occlusion-culling algorithm need not pay in full); a
// guide per model. A cell without a time (refused, crashed, timed out) is a cross in its algorithm's
// colour on the bottom edge at its face count, never a point.
std::vector<LogLogPlot> plot_results(const std::vector<Result>& results);

// What a plot is drawn on: write_plot's Cairo surfaces, or anything else (a test's recorder). Points
// are pixels from the picture's top left corner.
class PlotCanvas {
public:
    using Point = std::pair<double, double>;
    struct Pen {
        std::string color{};
        double width = 1;
        std::string dash{};  // empty for solid
    };
    enum class Anchor { start, middle, end };  // which end of the text sits at its point
    struct Font {
        double size = 12;
        std::string color = "#222222";
        Anchor anchor = Anchor::start;
        bool bold = false;
        bool upward = false;  // turned to read from bottom to top
        bool halo = false;    // a white outline keeps it legible over lines
    };
    virtual ~PlotCanvas() = default;
    virtual void fill(Point corner, double width, double height, const std::string& color) = 0;
    virtual void frame(Point corner, double width, double height, const Pen& pen) = 0;
    virtual void segments(const std::vector<std::pair<Point, Point>>& lines, const Pen& pen) = 0;
    virtual void polyline(const std::vector<Point>& points, const Pen& pen) = 0;  // a series' line
    virtual void marker(Point at, const std::string& color, bool hollow) = 0;   // a series' point
    virtual void text(Point at, const std::string& text, const Font& font) = 0; // at: the baseline
};

// The whole picture: the plots stacked one under the other, as wide as the widest.
std::pair<int, int> picture_size(const std::vector<LogLogPlot>& plots);
void draw_plots(PlotCanvas& canvas, const std::vector<LogLogPlot>& plots);

enum class PlotFormat { svg, png };
// Throws hsr::Error when Cairo cannot draw or encode the picture.
void write_plot(std::ostream& out, const std::vector<LogLogPlot>& plots, PlotFormat format);

// Axis helpers, exposed for the tests: the powers of ten spanning [lo, hi] (lo rounded down, hi up)
// and a short tick label for the face axis (0.01, 0.1, 1, 10, 100, 1k, 10k, 100k, 1M, ...; the
// time axis is labelled in plain numbers).
std::vector<double> decade_ticks(double lo, double hi);
std::string tick_label(double value);

}  // namespace hsr::bench
