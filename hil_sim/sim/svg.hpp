#pragma once
// A tiny SVG writer (no library) and the simulator's plots: the XY view of a
// scene and its run, a generic line chart, and an HTML index of the suite.
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sim/box_geometry.hpp"
#include "sim/world.hpp"

namespace hil::sim::svg {

// One palette for every plot (colour-blind friendly, Okabe-Ito based).
namespace colour {
inline constexpr const char* kEgo = "#0072B2";
inline constexpr const char* kEgoTrace = "#56B4E9";
inline constexpr const char* kStatic = "#5f5f5f";
inline constexpr const char* kDynamic = "#D55E00";
inline constexpr const char* kPedestrian = "#CC79A7";
inline constexpr const char* kRoadEdge = "#222222";
inline constexpr const char* kLaneLine = "#b0b0b0";
inline constexpr const char* kReference = "#009E73";
inline constexpr const char* kRoadFill = "#f2f2ee";
inline constexpr const char* kGrid = "#e4e4e4";
inline constexpr const char* kText = "#222222";
// Series colours for line charts, in order.
inline constexpr const char* kSeries[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                          "#E69F00", "#56B4E9", "#000000"};
}  // namespace colour

struct Style {
  Style(std::string stroke_ = "none", std::string fill_ = "none", double stroke_width_ = 1.5,
        double opacity_ = 1.0, std::string dash_ = "")
      : stroke(std::move(stroke_)), fill(std::move(fill_)), stroke_width(stroke_width_),
        opacity(opacity_), dash(std::move(dash_)) {}
  std::string stroke = "none";
  std::string fill = "none";
  double stroke_width = 1.5;  // [px]
  double opacity = 1.0;
  std::string dash;           // e.g. "6 4"
};

struct LegendEntry {
  std::string label;
  Style style;
  bool swatch_box = false;  // filled box instead of a line sample
};

class Canvas {
 public:
  Canvas(double width_px, double height_px);
  // Data window and plot area margins (px). equal_aspect keeps 1 m = 1 m,
  // growing the smaller data range symmetrically.
  void set_view(double x0, double x1, double y0, double y1, bool equal_aspect,
                double margin_left = 70, double margin_right = 20, double margin_top = 44,
                double margin_bottom = 52);
  double px(double x) const;
  double py(double y) const;
  double scale_x() const { return sx_; }  // [px per data unit]
  double x0() const { return x0_; }
  double x1() const { return x1_; }
  double y0() const { return y0_; }
  double y1() const { return y1_; }

  void title(const std::string& text);
  void axes(const std::string& x_label, const std::string& y_label, bool grid = true);
  void polyline(std::span<const Point2> pts, const Style& st);
  void polygon(std::span<const Point2> pts, const Style& st);
  void box(const OrientedBox& b, const Style& st);
  void circle(double x, double y, double r_px, const Style& st);
  void text(double x, double y, const std::string& s, double size_px = 12,
            const char* anchor = "start", const char* colour = colour::kText);
  void text_px(double x_px, double y_px, const std::string& s, double size_px = 12,
               const char* anchor = "start", const char* colour = colour::kText,
               const std::string& extra = "");
  void legend(std::span<const LegendEntry> entries);  // top-right inside the plot area
  void raw(const std::string& element);
  // Elements drawn after begin_clip() and before end_clip() are clipped to the plot area.
  void begin_clip();
  void end_clip();

  std::string str() const;
  bool save(const std::string& path) const;

 private:
  double w_, h_;
  double ml_ = 70, mr_ = 20, mt_ = 44, mb_ = 52;
  double x0_ = 0, x1_ = 1, y0_ = 0, y1_ = 1;
  double sx_ = 1, sy_ = 1;
  std::string body_;
};

std::string escape_xml(const std::string& s);
// "Nice" tick positions (1-2-5 steps) covering [lo, hi], about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target = 8);

struct EgoTraceSample {
  double t = 0.0;  // [s]
  Pose pose;       // rear axle
  double v = 0.0;  // [m/s]
};

struct XyPlotOptions {
  std::string title;               // default: the scene's name and tags
  double width_px = 1400;
  double ego_footprint_dt = 0.5;   // [s]
  double dynamic_footprint_dt = 1.0;  // [s]
  double t_end = -1.0;             // [s] < 0: the scene's duration (or 12 s)
};

// XY view: drivable area and lane lines, reference line, obstacles (static
// filled; dynamic as footprints over time with fading opacity), the ego's
// footprints every ego_footprint_dt along `trace` (or its initial box).
std::string plot_scene_xy(const World& world, std::span<const EgoTraceSample> trace,
                          const XyPlotOptions& options = {});

struct Series {
  std::string name;
  std::vector<Point2> points;  // (x, y) in data units
  std::string colour;          // "" = palette by index
  bool dashed = false;
};

std::string plot_line_chart(const std::string& title, const std::string& x_label,
                            const std::string& y_label, std::span<const Series> series,
                            double width_px = 900, double height_px = 360);

struct IndexRow {
  std::string name;
  bool ok = true;                                             // row highlight
  std::vector<std::pair<std::string, std::string>> links;    // (label, href)
  std::vector<std::pair<std::string, std::string>> metrics;  // (column, formatted value)
};

// A self-contained HTML page: title, summary lines, a table (one row per scene,
// metric columns in the first row's order, links to per-scene SVGs).
std::string index_html(const std::string& title, std::span<const std::string> summary_lines,
                       std::span<const IndexRow> rows);

bool write_text_file(const std::string& path, const std::string& text);

}  // namespace hil::sim::svg
