// CommonRoad XML -> plain structs (formats/commonroad.hpp), with pugixml.
// Every problem becomes the first error, "line N: element id: what"; nothing
// here throws past read_commonroad().
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "formats/commonroad.hpp"

namespace hil::formats::commonroad {
namespace {

using pugi::xml_node;

std::string_view trimmed(const char* text) {
  std::string_view s(text);
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

std::optional<double> to_double(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc{} || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// Integers (ids, time steps); "3.0" is accepted as 3, "3.5" is not.
std::optional<long> to_long(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  long v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (!s.empty() && ec == std::errc{} && end == s.data() + s.size()) return v;
  const std::optional<double> d = to_double(s);
  if (d && std::fabs(*d) < 1e15 && *d == std::floor(*d)) return static_cast<long>(*d);
  return std::nullopt;
}

class Reader {
 public:
  Reader(std::string_view text, const ReadOptions& options) : options_(options) {
    for (std::size_t i = 0; i < text.size(); ++i) {
      if (text[i] == '\n') newlines_.push_back(static_cast<std::ptrdiff_t>(i));
    }
  }

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }

  int line_of(xml_node n) const {
    const std::ptrdiff_t at = n.offset_debug();
    if (at < 0) return 0;
    return static_cast<int>(std::lower_bound(newlines_.begin(), newlines_.end(), at) - newlines_.begin()) + 1;
  }

  // Records the first error; `where` names the element ("lanelet 5: leftBound").
  bool fail(xml_node at, const std::string& where, const std::string& what) {
    if (error_.empty()) {
      const int line = line_of(at);
      error_ = line > 0 ? fmt::format("line {}: {}: {}", line, where, what) : fmt::format("{}: {}", where, what);
    }
    return false;
  }

  bool number(xml_node parent, const char* child, const std::string& where, double& out) {
    const xml_node n = parent.child(child);
    if (!n) return fail(parent, where, fmt::format("<{}> missing", child));
    const std::string_view text = trimmed(n.child_value());
    const std::optional<double> v = to_double(text);
    if (!v) return fail(n, where, fmt::format("<{}>: '{}' is not a finite number", child, text));
    out = *v;
    return true;
  }

  bool id_attribute(xml_node n, const char* attr, const std::string& where, long& out) {
    const pugi::xml_attribute a = n.attribute(attr);
    if (!a) return fail(n, where, fmt::format("attribute {} missing", attr));
    const std::optional<long> v = to_long(trimmed(a.value()));
    if (!v) return fail(n, where, fmt::format("attribute {}='{}' is not an integer", attr, a.value()));
    out = *v;
    return true;
  }

  // One coordinate of a point, within limits::kMaxCoordinate.
  bool coordinate(xml_node n, const char* axis, const std::string& where, double& out) {
    if (!number(n, axis, where, out)) return false;
    if (std::fabs(out) > limits::kMaxCoordinate) {
      return fail(n.child(axis), where,
                  fmt::format("<{}> {} m lies beyond the importer's coordinate limit |{}| <= {:g} m", axis, out, axis,
                              limits::kMaxCoordinate));
    }
    return true;
  }

  bool point(xml_node n, const std::string& where, Vec2& p) {
    return coordinate(n, "x", where, p.x) && coordinate(n, "y", where, p.y);
  }

  // A lanelet bound: >= 2 points, at most limits::kMaxBoundLength long.
  bool bound(xml_node n, const std::string& where, std::vector<Vec2>& out) {
    if (!points(n, where, 2, out)) return false;
    double length = 0.0;
    for (std::size_t i = 0; i + 1 < out.size(); ++i) length += std::hypot(out[i + 1].x - out[i].x, out[i + 1].y - out[i].y);
    if (length > limits::kMaxBoundLength) {
      return fail(n, where,
                  fmt::format("{:.1f} m long; the importer's limit for a lanelet bound is {:g} m", length,
                              limits::kMaxBoundLength));
    }
    return true;
  }

  bool points(xml_node parent, const std::string& where, std::size_t at_least, std::vector<Vec2>& out) {
    int k = 0;
    for (xml_node p : parent.children("point")) {
      Vec2 v;
      if (!point(p, fmt::format("{}: point {}", where, k), v)) return false;
      out.push_back(v);
      ++k;
    }
    if (out.size() < at_least) {
      return fail(parent, where, fmt::format("{} points, at least {} needed", out.size(), at_least));
    }
    return true;
  }

  // <exact> or <intervalStart>/<intervalEnd> (read as the midpoint).
  bool exact_or_interval(xml_node n, const std::string& where, double& out, bool& interval) {
    if (n.child("exact")) return number(n, "exact", where, out);
    double lo = 0, hi = 0;
    if (!n.child("intervalStart") && !n.child("intervalEnd")) {
      return fail(n, where, "neither <exact> nor <intervalStart>/<intervalEnd>");
    }
    if (!number(n, "intervalStart", where, lo) || !number(n, "intervalEnd", where, hi)) return false;
    if (hi < lo) return fail(n, where, fmt::format("interval [{}, {}] is empty", lo, hi));
    out = 0.5 * (lo + hi);
    interval = true;
    return true;
  }

  bool shape_part(xml_node n, const std::string& where, ShapePart& part) {
    const std::string name = n.name();
    const std::string at = where + ": " + name;
    if (name == "rectangle") {
      part.kind = ShapePart::Kind::kRectangle;
      if (!number(n, "length", at, part.length) || !number(n, "width", at, part.width)) return false;
      if (part.length <= 0 || part.width <= 0) return fail(n, at, "length and width must be positive");
      if (n.child("orientation") && !number(n, "orientation", at, part.orientation)) return false;
      if (n.child("center") && !point(n.child("center"), at + ": center", part.center)) return false;
      return true;
    }
    if (name == "circle") {
      part.kind = ShapePart::Kind::kCircle;
      if (!number(n, "radius", at, part.radius)) return false;
      if (part.radius <= 0) return fail(n, at, "radius must be positive");
      if (n.child("center") && !point(n.child("center"), at + ": center", part.center)) return false;
      return true;
    }
    if (name == "polygon") {
      part.kind = ShapePart::Kind::kPolygon;
      return points(n, at, 3, part.points);
    }
    return fail(n, where, fmt::format("unknown shape <{}>", name));
  }

  bool shape(xml_node parent, const std::string& where, Shape& out) {
    const xml_node s = parent.child("shape");
    if (!s) return fail(parent, where, "<shape> missing");
    for (xml_node part = s.first_child(); part; part = part.next_sibling()) {
      if (part.type() != pugi::node_element) continue;
      ShapePart p;
      if (!shape_part(part, where + ": shape", p)) return false;
      out.push_back(std::move(p));
    }
    if (out.empty()) return fail(s, where, "<shape> is empty");
    return true;
  }

  // The centre of a position region (uncertain position).
  static Vec2 region_centre(const ShapePart& p) {
    if (p.kind != ShapePart::Kind::kPolygon) return p.center;
    // Area centroid; the vertex mean for a degenerate polygon.
    double a = 0, cx = 0, cy = 0;
    for (std::size_t i = 0; i < p.points.size(); ++i) {
      const Vec2& u = p.points[i];
      const Vec2& v = p.points[(i + 1) % p.points.size()];
      const double c = u.x * v.y - v.x * u.y;
      a += c;
      cx += (u.x + v.x) * c;
      cy += (u.y + v.y) * c;
    }
    if (std::fabs(a) > 1e-12) return {cx / (3 * a), cy / (3 * a)};
    Vec2 m;
    for (const Vec2& q : p.points) {
      m.x += q.x / static_cast<double>(p.points.size());
      m.y += q.y / static_cast<double>(p.points.size());
    }
    return m;
  }

  // <position>: a point, or regions (rectangles, circles, polygons: their
  // centres' mean, marked uncertain). Lanelet references only where allowed.
  bool position(xml_node state, const std::string& where, Vec2& out, bool& uncertain,
                std::vector<long>* lanelets = nullptr, std::vector<Vec2>* centres = nullptr) {
    const xml_node pos = state.child("position");
    if (!pos) return fail(state, where, "<position> missing");
    const std::string at = where + ": position";
    if (pos.child("point")) return point(pos.child("point"), at, out);
    int regions = 0;
    Vec2 sum;
    for (xml_node c = pos.first_child(); c; c = c.next_sibling()) {
      if (c.type() != pugi::node_element) continue;
      const std::string name = c.name();
      if (name == "lanelet") {
        if (!lanelets) return fail(c, at, "a position given as lanelet references is not supported here");
        long ref = 0;
        if (!id_attribute(c, "ref", at + ": lanelet", ref)) return false;
        lanelets->push_back(ref);
        continue;
      }
      ShapePart p;
      if (!shape_part(c, at, p)) return false;
      const Vec2 m = region_centre(p);
      if (centres) centres->push_back(m);
      sum.x += m.x;
      sum.y += m.y;
      ++regions;
    }
    if (regions == 0 && (!lanelets || lanelets->empty())) return fail(pos, at, "<position> is empty");
    if (regions > 0) {
      out = {sum.x / regions, sum.y / regions};
      uncertain = true;
    }
    return true;
  }

  bool time_step(xml_node state, const std::string& where, long& out) {
    const xml_node t = state.child("time");
    if (!t) return fail(state, where, "<time> missing");
    if (!t.child("exact")) {
      return fail(t, where, "a time interval (set-based state) is not supported; an exact time step is needed");
    }
    const std::string_view text = trimmed(t.child("exact").child_value());
    const std::optional<long> v = to_long(text);
    if (!v) return fail(t, where, fmt::format("<time><exact>: '{}' is not an integer time step", text));
    out = *v;
    return true;
  }

  bool optional_value(xml_node state, const char* name, const std::string& where, std::optional<double>& out,
                      bool& uncertain) {
    const xml_node n = state.child(name);
    if (!n) return true;
    double v = 0;
    if (!exact_or_interval(n, where + ": " + name, v, uncertain)) return false;
    out = v;
    return true;
  }

  bool state(xml_node n, const std::string& where, State& s) {
    if (!position(n, where, s.position, s.uncertain)) return false;
    const xml_node o = n.child("orientation");
    if (!o) return fail(n, where, "<orientation> missing");
    if (!exact_or_interval(o, where + ": orientation", s.orientation, s.uncertain)) return false;
    if (!time_step(n, where, s.time_step)) return false;
    return optional_value(n, "velocity", where, s.velocity, s.uncertain) &&
           optional_value(n, "acceleration", where, s.acceleration, s.uncertain) &&
           optional_value(n, "yawRate", where, s.yaw_rate, s.uncertain);
  }

  bool lanelet(xml_node n, Scenario& sc) {
    Lanelet l;
    l.line = line_of(n);
    if (!id_attribute(n, "id", "lanelet", l.id)) return false;
    const std::string where = fmt::format("lanelet {}", l.id);
    const xml_node left = n.child("leftBound");
    const xml_node right = n.child("rightBound");
    if (!left) return fail(n, where, "<leftBound> missing");
    if (!right) return fail(n, where, "<rightBound> missing");
    if (!bound(left, where + ": leftBound", l.left_bound) || !bound(right, where + ": rightBound", l.right_bound)) {
      return false;
    }
    for (const char* kind : {"predecessor", "successor"}) {
      for (xml_node r : n.children(kind)) {
        long ref = 0;
        if (!id_attribute(r, "ref", where + ": " + kind, ref)) return false;
        (std::strcmp(kind, "predecessor") == 0 ? l.predecessors : l.successors).push_back(ref);
      }
    }
    for (const char* side : {"adjacentLeft", "adjacentRight"}) {
      const xml_node a = n.child(side);
      if (!a) continue;
      Neighbour nb;
      if (!id_attribute(a, "ref", where + ": " + side, nb.id)) return false;
      const std::string dir = a.attribute("drivingDir").value();
      if (dir == "same") {
        nb.direction = DrivingDirection::kSame;
      } else if (dir == "opposite") {
        nb.direction = DrivingDirection::kOpposite;
      } else {
        return fail(a, where + ": " + side, fmt::format("drivingDir '{}' is neither 'same' nor 'opposite'", dir));
      }
      (std::strcmp(side, "adjacentLeft") == 0 ? l.left : l.right) = nb;
    }
    for (xml_node t : n.children("laneletType")) l.types.emplace_back(trimmed(t.child_value()));
    for (xml_node r : n.children("trafficSignRef")) {
      long ref = 0;
      if (!id_attribute(r, "ref", where + ": trafficSignRef", ref)) return false;
      l.traffic_signs.push_back(ref);
    }
    auto add_light = [&](long ref) {
      if (std::find(l.traffic_lights.begin(), l.traffic_lights.end(), ref) == l.traffic_lights.end()) {
        l.traffic_lights.push_back(ref);
      }
    };
    for (xml_node r : n.children("trafficLightRef")) {
      long ref = 0;
      if (!id_attribute(r, "ref", where + ": trafficLightRef", ref)) return false;
      add_light(ref);
    }
    if (const xml_node stop = n.child("stopLine")) {
      if (stop.child("point") && !points(stop, where + ": stopLine", 2, l.stop_line)) return false;
      for (xml_node r : stop.children("trafficLightRef")) {
        long ref = 0;
        if (!id_attribute(r, "ref", where + ": stopLine: trafficLightRef", ref)) return false;
        add_light(ref);
      }
    }
    if (n.child("speedLimit")) {
      double v = 0;
      if (!number(n, "speedLimit", where, v)) return false;
      l.speed_limit = v;
    }
    sc.lanelets.push_back(std::move(l));
    return true;
  }

  bool traffic_sign(xml_node n, Scenario& sc) {
    TrafficSign s;
    s.line = line_of(n);
    if (!id_attribute(n, "id", "trafficSign", s.id)) return false;
    const std::string where = fmt::format("trafficSign {}", s.id);
    for (xml_node e : n.children("trafficSignElement")) {
      TrafficSignElement el;
      el.sign_id = std::string(trimmed(e.child("trafficSignID").child_value()));
      if (el.sign_id.empty()) return fail(e, where, "<trafficSignElement> without <trafficSignID>");
      for (xml_node v : e.children("additionalValue")) el.values.emplace_back(trimmed(v.child_value()));
      s.elements.push_back(std::move(el));
    }
    if (n.child("position")) {
      Vec2 p;
      bool uncertain = false;
      if (!position(n, where, p, uncertain)) return false;
      s.position = p;
    }
    s.is_virtual = trimmed(n.child("virtual").child_value()) == "true";
    sc.traffic_signs.push_back(std::move(s));
    return true;
  }

  // <trafficLight>: <cycle> of <cycleElement> (<duration> in time steps,
  // <color>) and an optional <timeOffset>; <direction>, <active>.
  bool traffic_light(xml_node n, Scenario& sc) {
    TrafficLight t;
    t.line = line_of(n);
    if (!id_attribute(n, "id", "trafficLight", t.id)) return false;
    const std::string where = fmt::format("trafficLight {}", t.id);
    const xml_node cycle = n.child("cycle");
    if (!cycle) return fail(n, where, "<cycle> missing");
    int k = 0;
    for (xml_node e : cycle.children("cycleElement")) {
      const std::string at = fmt::format("{}: cycleElement {}", where, k++);
      TrafficLightPhase ph;
      double d = 0;
      if (!number(e, "duration", at, d)) return false;
      if (!(d > 0) || d != std::floor(d) || d > 1e9) {
        return fail(e, at, fmt::format("<duration> {} is not a positive whole number of time steps", d));
      }
      ph.duration = static_cast<long>(d);
      ph.color = std::string(trimmed(e.child("color").child_value()));
      if (ph.color != "red" && ph.color != "yellow" && ph.color != "redYellow" && ph.color != "green" &&
          ph.color != "inactive") {
        return fail(e, at, fmt::format("<color> '{}' is none of red, yellow, redYellow, green, inactive", ph.color));
      }
      t.cycle.push_back(std::move(ph));
    }
    if (t.cycle.empty()) return fail(cycle, where, "<cycle> without a <cycleElement>");
    if (cycle.child("timeOffset")) {
      double off = 0;
      if (!number(cycle, "timeOffset", where, off)) return false;
      if (off != std::floor(off) || std::fabs(off) > 1e9) {
        return fail(cycle, where, fmt::format("<timeOffset> {} is not a whole number of time steps", off));
      }
      t.time_offset = static_cast<long>(off);
    }
    if (const xml_node d = n.child("direction")) t.direction = std::string(trimmed(d.child_value()));
    if (const xml_node a = n.child("active")) t.active = trimmed(a.child_value()) != "false";
    sc.traffic_lights.push_back(std::move(t));
    return true;
  }

  bool obstacle(xml_node n, bool dynamic, Scenario& sc) {
    Obstacle o;
    o.line = line_of(n);
    o.dynamic = dynamic;
    const std::string element = n.name();
    if (!id_attribute(n, "id", element, o.id)) return false;
    const std::string where = fmt::format("{} {}", element, o.id);
    o.type = std::string(trimmed(n.child("type").child_value()));
    if (n.child("occupancySet")) {
      if (!options_.drop_set_based) {
        return fail(n.child("occupancySet"), where,
                    "<occupancySet> (set-based prediction) is not supported: the simulator needs a trajectory "
                    "(hil_sim import --drop-set-based leaves such obstacles out)");
      }
      sc.ignored.push_back(fmt::format("line {}: {}: set-based prediction (occupancySet), left out", o.line, where));
      return true;
    }
    if (!shape(n, where, o.shape)) return false;
    const xml_node init = n.child("initialState");
    if (!init) return fail(n, where, "<initialState> missing");
    if (!state(init, where + ": initialState", o.initial)) return false;
    if (const xml_node tr = n.child("trajectory")) {
      if (!dynamic) return fail(tr, where, "a static obstacle with a <trajectory>");
      long previous = o.initial.time_step;
      int k = 0;
      for (xml_node st : tr.children("state")) {
        State s;
        if (!state(st, fmt::format("{}: trajectory state {}", where, k), s)) return false;
        if (s.time_step <= previous) {
          return fail(st, fmt::format("{}: trajectory state {}", where, k),
                      fmt::format("time step {} does not follow {} (time steps must ascend)", s.time_step, previous));
        }
        previous = s.time_step;
        o.trajectory.push_back(s);
        ++k;
      }
    }
    sc.obstacles.push_back(std::move(o));
    return true;
  }

  bool planning_problem(xml_node n, Scenario& sc) {
    PlanningProblem p;
    p.line = line_of(n);
    if (!id_attribute(n, "id", "planningProblem", p.id)) return false;
    const std::string where = fmt::format("planningProblem {}", p.id);
    const xml_node init = n.child("initialState");
    if (!init) return fail(n, where, "<initialState> missing");
    if (!state(init, where + ": initialState", p.initial)) return false;
    int k = 0;
    for (xml_node g : n.children("goalState")) {
      GoalState goal;
      const std::string at = fmt::format("{}: goalState {}", where, k++);
      if (const xml_node t = g.child("time")) {
        double lo = 0, hi = 0;
        if (t.child("exact")) {
          if (!number(t, "exact", at + ": time", lo)) return false;
          hi = lo;
        } else if (!number(t, "intervalStart", at + ": time", lo) || !number(t, "intervalEnd", at + ": time", hi)) {
          return false;
        }
        goal.time_start = std::lround(lo);
        goal.time_end = std::lround(hi);
      }
      if (g.child("position")) {
        Vec2 unused;
        bool uncertain = false;
        if (!position(g, at, unused, uncertain, &goal.lanelets, &goal.area_centres)) return false;
      }
      p.goals.push_back(std::move(goal));
    }
    sc.planning_problems.push_back(std::move(p));
    return true;
  }

  bool document(xml_node root, Scenario& sc) {
    sc.benchmark_id = root.attribute("benchmarkID").value();
    sc.version = root.attribute("commonRoadVersion").value();
    const pugi::xml_attribute dt = root.attribute("timeStepSize");
    if (!dt) return fail(root, "commonRoad", "attribute timeStepSize missing");
    const std::optional<double> step = to_double(trimmed(dt.value()));
    if (!step || *step <= 0.0) {
      return fail(root, "commonRoad", fmt::format("timeStepSize='{}' is not a positive number", dt.value()));
    }
    sc.time_step = *step;
    if (sc.version != "2020a" && sc.version != "2018b") {
      sc.ignored.push_back(fmt::format("commonRoadVersion '{}': read as 2020a", sc.version));
    }
    std::map<std::string, int> skipped;
    for (xml_node n = root.first_child(); n; n = n.next_sibling()) {
      if (n.type() != pugi::node_element) continue;
      const std::string name = n.name();
      bool ok = true;
      if (name == "lanelet") {
        ok = lanelet(n, sc);
      } else if (name == "trafficSign") {
        ok = traffic_sign(n, sc);
      } else if (name == "trafficLight") {
        ok = traffic_light(n, sc);
      } else if (name == "staticObstacle" || name == "dynamicObstacle") {
        ok = obstacle(n, name == "dynamicObstacle", sc);
      } else if (name == "obstacle") {  // 2018b: one element, <role> static / dynamic
        const std::string_view role = trimmed(n.child("role").child_value());
        if (role != "static" && role != "dynamic") {
          return fail(n, "obstacle", fmt::format("<role> '{}' is neither 'static' nor 'dynamic'", role));
        }
        ok = obstacle(n, role == "dynamic", sc);
      } else if (name == "phantomObstacle") {
        long id = 0;
        id_attribute(n, "id", name, id);
        if (!options_.drop_set_based) {
          return fail(n, fmt::format("phantomObstacle {}", id),
                      "phantom obstacles (set-based occupancy) are not supported "
                      "(hil_sim import --drop-set-based leaves them out)");
        }
        sc.ignored.push_back(fmt::format("line {}: phantomObstacle {}: set-based occupancy, left out", line_of(n), id));
      } else if (name == "planningProblem") {
        ok = planning_problem(n, sc);
      } else if (name != "location" && name != "scenarioTags") {
        ++skipped[name];  // intersection, environmentObstacle, ...
      }
      if (!ok) return false;
    }
    for (const auto& [name, count] : skipped) sc.ignored.push_back(fmt::format("{} x <{}>: not mapped", count, name));
    // Ids must be unique per kind for references to mean anything.
    std::set<long> ids;
    for (const Lanelet& l : sc.lanelets) {
      if (!ids.insert(l.id).second) {
        error_ = fmt::format("line {}: lanelet {}: the id is used twice", l.line, l.id);
        return false;
      }
    }
    return true;
  }

 private:
  const ReadOptions& options_;
  std::vector<std::ptrdiff_t> newlines_;
  std::string error_;
};

}  // namespace

ReadResult read_commonroad(std::string_view xml, const ReadOptions& options) {
  ReadResult result;
  try {
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed =
        doc.load_buffer(xml.data(), xml.size(), pugi::parse_default, pugi::encoding_auto);
    Reader reader(xml, options);
    if (!parsed) {
      const auto at = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, parsed.offset));
      const auto line = 1 + std::count(xml.begin(), xml.begin() + static_cast<std::ptrdiff_t>(std::min(at, xml.size())), '\n');
      result.error = fmt::format("line {}: not well-formed XML: {}", line, parsed.description());
      return result;
    }
    const xml_node root = doc.child("commonRoad");
    if (!root) {
      result.error = "no <commonRoad> root element: not a CommonRoad scenario";
      return result;
    }
    Scenario sc;
    if (!reader.document(root, sc)) {
      result.error = reader.error();
      return result;
    }
    result.scenario = std::move(sc);
  } catch (const std::exception& e) {  // std::bad_alloc on absurd input; nothing else throws
    result.scenario.reset();
    result.error = fmt::format("cannot read the file: {}", e.what());
  }
  return result;
}

}  // namespace hil::formats::commonroad
