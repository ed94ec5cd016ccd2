#include "sim/svg.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <fmt/format.h>

namespace hil::sim::svg {

namespace {
constexpr const char* kFont = "font-family=\"Helvetica, Arial, sans-serif\"";

std::string style_attrs(const Style& st) {
  std::string s = fmt::format("stroke=\"{}\" fill=\"{}\" stroke-width=\"{:.2f}\"", st.stroke,
                              st.fill, st.stroke_width);
  if (st.opacity < 1.0) s += fmt::format(" opacity=\"{:.3f}\"", st.opacity);
  if (!st.dash.empty()) s += fmt::format(" stroke-dasharray=\"{}\"", st.dash);
  s += " stroke-linejoin=\"round\" stroke-linecap=\"round\"";
  return s;
}

std::string tick_label(double v, double step) {
  const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  if (std::abs(v) < 1e-12) v = 0.0;
  return fmt::format("{:.{}f}", v, std::clamp(decimals, 0, 6));
}
}  // namespace

std::string escape_xml(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> t;
  if (!(hi > lo) || target < 1) return t;
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) {
    t.push_back(v);
  }
  return t;
}

Canvas::Canvas(double width_px, double height_px) : w_(width_px), h_(height_px) {}

void Canvas::set_view(double x0, double x1, double y0, double y1, bool equal_aspect, double ml,
                      double mr, double mt, double mb) {
  ml_ = ml;
  mr_ = mr;
  mt_ = mt;
  mb_ = mb;
  if (!(x1 > x0)) x1 = x0 + 1.0;
  if (!(y1 > y0)) y1 = y0 + 1.0;
  const double pw = w_ - ml_ - mr_;
  const double ph = h_ - mt_ - mb_;
  if (equal_aspect) {
    const double s = std::min(pw / (x1 - x0), ph / (y1 - y0));
    const double cx = 0.5 * (x0 + x1);
    const double cy = 0.5 * (y0 + y1);
    x0 = cx - 0.5 * pw / s;
    x1 = cx + 0.5 * pw / s;
    y0 = cy - 0.5 * ph / s;
    y1 = cy + 0.5 * ph / s;
  }
  x0_ = x0;
  x1_ = x1;
  y0_ = y0;
  y1_ = y1;
  sx_ = pw / (x1 - x0);
  sy_ = ph / (y1 - y0);
}

double Canvas::px(double x) const { return ml_ + (x - x0_) * sx_; }
double Canvas::py(double y) const { return h_ - mb_ - (y - y0_) * sy_; }

void Canvas::title(const std::string& text) {
  text_px(0.5 * w_, 26, text, 17, "middle", colour::kText, "font-weight=\"600\"");
}

void Canvas::axes(const std::string& x_label, const std::string& y_label, bool grid) {
  const double left = ml_, right = w_ - mr_, top = mt_, bottom = h_ - mb_;
  const auto xt = nice_ticks(x0_, x1_, std::max(3, static_cast<int>((right - left) / 90)));
  const auto yt = nice_ticks(y0_, y1_, std::max(3, static_cast<int>((bottom - top) / 50)));
  const double xs = xt.size() > 1 ? xt[1] - xt[0] : 1.0;
  const double ys = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (double v : xt) {
    const double p = px(v);
    if (grid) {
      body_ += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" stroke=\"{3}\"/>\n",
                           p, top, bottom, colour::kGrid);
    }
    body_ += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" stroke=\"{3}\"/>\n",
                         p, bottom, bottom + 5, colour::kText);
    text_px(p, bottom + 18, tick_label(v, xs), 11, "middle");
  }
  for (double v : yt) {
    const double p = py(v);
    if (grid) {
      body_ += fmt::format("<line x1=\"{0:.1f}\" y1=\"{2:.1f}\" x2=\"{1:.1f}\" y2=\"{2:.1f}\" stroke=\"{3}\"/>\n",
                           left, right, p, colour::kGrid);
    }
    body_ += fmt::format("<line x1=\"{0:.1f}\" y1=\"{2:.1f}\" x2=\"{1:.1f}\" y2=\"{2:.1f}\" stroke=\"{3}\"/>\n",
                         left - 5, left, p, colour::kText);
    text_px(left - 8, p + 4, tick_label(v, ys), 11, "end");
  }
  body_ += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"none\" stroke=\"{}\"/>\n",
                       left, top, right - left, bottom - top, colour::kText);
  text_px(0.5 * (left + right), h_ - 12, x_label, 13, "middle");
  body_ += fmt::format("<text x=\"16\" y=\"{0:.1f}\" transform=\"rotate(-90 16 {0:.1f})\" font-size=\"13\" "
                       "text-anchor=\"middle\" fill=\"{1}\" {2}>{3}</text>\n",
                       0.5 * (top + bottom), colour::kText, kFont, escape_xml(y_label));
}

void Canvas::polyline(std::span<const Point2> pts, const Style& st) {
  if (pts.empty()) return;
  std::string d;
  for (const auto& p : pts) d += fmt::format("{:.2f},{:.2f} ", px(p.x), py(p.y));
  body_ += fmt::format("<polyline points=\"{}\" {}/>\n", d, style_attrs(st));
}

void Canvas::polygon(std::span<const Point2> pts, const Style& st) {
  if (pts.empty()) return;
  std::string d;
  for (const auto& p : pts) d += fmt::format("{:.2f},{:.2f} ", px(p.x), py(p.y));
  body_ += fmt::format("<polygon points=\"{}\" {}/>\n", d, style_attrs(st));
}

void Canvas::box(const OrientedBox& b, const Style& st) {
  const auto c = b.corners();
  polygon(c, st);
}

void Canvas::circle(double x, double y, double r, const Style& st) {
  body_ += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{:.2f}\" {}/>\n", px(x), py(y), r,
                       style_attrs(st));
}

void Canvas::text(double x, double y, const std::string& s, double size, const char* anchor,
                  const char* col) {
  text_px(px(x), py(y), s, size, anchor, col);
}

void Canvas::text_px(double x, double y, const std::string& s, double size, const char* anchor,
                     const char* col, const std::string& extra) {
  body_ += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"{:.0f}\" text-anchor=\"{}\" fill=\"{}\" {} {}>{}</text>\n",
                       x, y, size, anchor, col, kFont, extra, escape_xml(s));
}

void Canvas::legend(std::span<const LegendEntry> entries) {
  if (entries.empty()) return;
  std::size_t longest = 0;
  for (const auto& e : entries) longest = std::max(longest, e.label.size());
  const double bw = 44.0 + 6.8 * static_cast<double>(longest);
  const double bh = 8.0 + 18.0 * static_cast<double>(entries.size());
  const double x = w_ - mr_ - bw - 8;
  const double y = mt_ + 8;
  body_ += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" rx=\"4\" "
                       "fill=\"white\" fill-opacity=\"0.88\" stroke=\"#cccccc\"/>\n",
                       x, y, bw, bh);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const double yy = y + 15.0 + 18.0 * static_cast<double>(i);
    const auto& e = entries[i];
    if (e.swatch_box) {
      Style st = e.style;
      body_ += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"22\" height=\"10\" {}/>\n", x + 8,
                           yy - 8, style_attrs(st));
    } else {
      body_ += fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" {}/>\n", x + 8,
                           yy - 3, x + 30, yy - 3, style_attrs(e.style));
    }
    text_px(x + 36, yy + 1, e.label, 11);
  }
}

void Canvas::raw(const std::string& element) { body_ += element + "\n"; }

void Canvas::begin_clip() { body_ += "<g clip-path=\"url(#plot)\">\n"; }
void Canvas::end_clip() { body_ += "</g>\n"; }

std::string Canvas::str() const {
  return fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.0f}\" height=\"{1:.0f}\" "
      "viewBox=\"0 0 {0:.0f} {1:.0f}\">\n"
      "<defs><clipPath id=\"plot\"><rect x=\"{2:.1f}\" y=\"{3:.1f}\" width=\"{4:.1f}\" "
      "height=\"{5:.1f}\"/></clipPath></defs>\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n{6}</svg>\n",
      w_, h_, ml_, mt_, w_ - ml_ - mr_, h_ - mt_ - mb_, body_);
}

bool Canvas::save(const std::string& path) const { return write_text_file(path, str()); }

bool write_text_file(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  return static_cast<bool>(out);
}

namespace {
// Offset polyline at lateral l(s) using vertex normals (mean of adjacent segments).
std::vector<Point2> offset_line(std::span<const Point2> ref, const Boundary& b) {
  std::vector<Point2> out;
  const auto sv = polyline_arc_lengths(ref);
  const std::size_t n = ref.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Point2 a = ref[i == 0 ? 0 : i - 1];
    const Point2 c = ref[i + 1 < n ? i + 1 : n - 1];
    const double h = std::atan2(c.y - a.y, c.x - a.x);
    const double l = b.at(sv[i]);
    out.push_back({ref[i].x - l * std::sin(h), ref[i].y + l * std::cos(h)});
  }
  return out;
}
}  // namespace

std::string plot_scene_xy(const World& w, std::span<const EgoTraceSample> trace,
                          const XyPlotOptions& opt) {
  const std::span<const Point2> ref(w.reference_line);
  const auto left = offset_line(ref, w.road.left_boundary);
  const auto right = offset_line(ref, w.road.right_boundary);
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  auto grow = [&](double x, double y) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  };
  for (const auto& p : left) grow(p.x, p.y);
  for (const auto& p : right) grow(p.x, p.y);
  for (const auto& e : trace) grow(e.pose.x, e.pose.y);
  x0 -= 5;
  x1 += 5;
  y0 -= 5;
  y1 += 5;
  // Height follows the data's aspect within [260, 900] px.
  const double pw = opt.width_px - 90;
  const double want_h = (y1 - y0) * pw / (x1 - x0);
  const double height = std::clamp(want_h, 200.0, 820.0) + 96;
  Canvas cv(opt.width_px, height);
  cv.set_view(x0, x1, y0, y1, true);
  std::string title = opt.title;
  if (title.empty()) {
    title = w.name;
    if (!w.tags.empty()) {
      title += " —";
      for (const auto& t : w.tags) title += " " + t;
    }
  }
  cv.title(title);
  cv.axes("x [m]", "y [m]");
  cv.begin_clip();

  // Drivable area, lane lines, edges, reference line.
  std::vector<Point2> area(left.begin(), left.end());
  area.insert(area.end(), right.rbegin(), right.rend());
  cv.polygon(area, Style{"none", colour::kRoadFill, 0.0});
  const double lw = w.road.lane_width;
  for (int k = -6; k <= 6; ++k) {
    const double l = 0.5 * lw + k * lw;
    const Boundary lb = Boundary::constant_at(l);
    const bool inside = l > w.road.right_boundary.at(0.0) + 0.1 && l < w.road.left_boundary.at(0.0) - 0.1;
    if (inside) cv.polyline(offset_line(ref, lb), Style{colour::kLaneLine, "none", 1.2, 1.0, "8 8"});
  }
  cv.polyline(left, Style{colour::kRoadEdge, "none", 2.0});
  cv.polyline(right, Style{colour::kRoadEdge, "none", 2.0});
  cv.polyline(ref, Style{colour::kReference, "none", 1.2, 0.9, "2 4"});

  // Obstacles.
  for (const auto& o : w.static_obstacles) {
    cv.box(obstacle_box(o), Style{"#333333", colour::kStatic, 1.0, 0.85});
    cv.text(o.x, o.y + 0.5 * o.width + 0.8, fmt::format("{}", o.id), 10, "middle", colour::kStatic);
  }
  const double t_end = opt.t_end > 0 ? opt.t_end : w.duration.value_or(12.0);
  for (const auto& d : w.dynamic_obstacles) {
    const bool ped = d.kind == "pedestrian";
    const char* col = ped ? colour::kPedestrian : colour::kDynamic;
    const double step = std::max(0.1, opt.dynamic_footprint_dt);
    bool labelled = false;
    std::vector<Point2> path;
    for (double t = 0.0; t <= t_end + 1e-9; t += step) {
      const auto p = pose_at(d, t);
      if (!p) continue;
      const double fade = 0.75 - 0.6 * t / std::max(t_end, 1e-6);
      cv.box(obstacle_box(d, *p), Style{col, col, 0.8, std::max(0.1, fade)});
      path.push_back({p->x, p->y});
      if (!labelled) {
        cv.text(p->x, p->y + 0.5 * d.width + 0.8, fmt::format("{}", d.id), 10, "middle", col);
        labelled = true;
      }
    }
    cv.polyline(path, Style{col, "none", 1.0, 0.6, "3 3"});
  }

  // Ego.
  if (trace.empty()) {
    cv.box(ego_box(w.ego), Style{colour::kEgo, colour::kEgo, 1.2, 0.8});
  } else {
    std::vector<Point2> path;
    for (const auto& e : trace) path.push_back({e.pose.x, e.pose.y});
    cv.polyline(path, Style{colour::kEgoTrace, "none", 1.5});
    double next = trace.front().t;
    for (const auto& e : trace) {
      if (e.t + 1e-9 < next) continue;
      next += opt.ego_footprint_dt;
      cv.box(ego_box(e.pose, w.ego.length, w.ego.width, w.ego.wheelbase),
             Style{colour::kEgo, colour::kEgo, 0.8, 0.25});
    }
    cv.box(ego_box(trace.front().pose, w.ego.length, w.ego.width, w.ego.wheelbase),
           Style{colour::kEgo, colour::kEgo, 1.2, 0.8});
  }
  cv.end_clip();

  const LegendEntry legend[] = {
      {"ego (footprints every " + fmt::format("{:g}", opt.ego_footprint_dt) + " s)",
       Style{colour::kEgo, colour::kEgo, 1.0, 0.5}, true},
      {"static obstacle", Style{"#333333", colour::kStatic, 1.0, 0.85}, true},
      {"dynamic obstacle (fades with t)", Style{colour::kDynamic, colour::kDynamic, 1.0, 0.6}, true},
      {"pedestrian", Style{colour::kPedestrian, colour::kPedestrian, 1.0, 0.6}, true},
      {"reference line", Style{colour::kReference, "none", 1.5, 1.0, "2 4"}, false},
      {"road edge", Style{colour::kRoadEdge, "none", 2.0}, false}};
  cv.legend(legend);
  return cv.str();
}

std::string plot_line_chart(const std::string& title, const std::string& x_label,
                            const std::string& y_label, std::span<const Series> series,
                            double width_px, double height_px) {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : series) {
    for (const auto& p : s.points) {
      x0 = std::min(x0, p.x);
      x1 = std::max(x1, p.x);
      y0 = std::min(y0, p.y);
      y1 = std::max(y1, p.y);
    }
  }
  if (!std::isfinite(x0)) {
    x0 = 0;
    x1 = 1;
    y0 = 0;
    y1 = 1;
  }
  if (y1 - y0 < 1e-9 + 1e-3 * std::max(std::abs(y0), std::abs(y1))) {  // flat data
    const double half = std::max(1.0, 0.1 * std::abs(y0));
    y0 -= half;
    y1 += half;
  }
  const double pad = 0.06 * (y1 - y0);
  Canvas cv(width_px, height_px);
  cv.set_view(x0, x1, y0 - pad, y1 + pad, false);
  cv.title(title);
  cv.axes(x_label, y_label);
  cv.begin_clip();
  std::vector<LegendEntry> legend;
  std::size_t i = 0;
  for (const auto& s : series) {
    const std::string col = s.colour.empty() ? colour::kSeries[i % std::size(colour::kSeries)] : s.colour;
    const Style st{col, "none", 2.0, 1.0, s.dashed ? "6 4" : ""};
    cv.polyline(s.points, st);
    legend.push_back({s.name, st, false});
    ++i;
  }
  cv.end_clip();
  cv.legend(legend);
  return cv.str();
}

std::string index_html(const std::string& title, std::span<const std::string> summary,
                       std::span<const IndexRow> rows) {
  std::string h = fmt::format(
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{0}</title>\n<style>\n"
      "body{{font-family:Helvetica,Arial,sans-serif;margin:24px;color:#222}}\n"
      "table{{border-collapse:collapse;font-size:13px}}\n"
      "th,td{{border:1px solid #ddd;padding:4px 8px;text-align:right}}\n"
      "th{{background:#f3f3f3;position:sticky;top:0}}\n"
      "td.name{{text-align:left;font-family:monospace}}\n"
      "tr.bad td{{background:#fde8e4}}\n tr:hover td{{background:#eef5fb}}\n"
      "a{{color:#0072B2}}\n</style></head><body>\n<h1>{0}</h1>\n",
      escape_xml(title));
  if (!summary.empty()) {
    h += "<ul>\n";
    for (const auto& line : summary) h += fmt::format("<li>{}</li>\n", escape_xml(line));
    h += "</ul>\n";
  }
  h += "<table>\n<tr><th>scene</th>";
  if (!rows.empty()) {
    for (const auto& [k, v] : rows.front().metrics) h += fmt::format("<th>{}</th>", escape_xml(k));
  }
  h += "<th>plots</th></tr>\n";
  for (const auto& r : rows) {
    h += fmt::format("<tr{}><td class=\"name\">{}</td>", r.ok ? "" : " class=\"bad\"", escape_xml(r.name));
    for (const auto& [k, v] : r.metrics) h += fmt::format("<td>{}</td>", escape_xml(v));
    h += "<td>";
    for (const auto& [label, href] : r.links) {
      h += fmt::format("<a href=\"{}\">{}</a> ", escape_xml(href), escape_xml(label));
    }
    h += "</td></tr>\n";
  }
  h += "</table>\n</body></html>\n";
  return h;
}

}  // namespace hil::sim::svg
