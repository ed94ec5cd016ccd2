#include "formats/qps.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <istream>
#include <limits>
#include <new>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace hil::formats {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

enum class Section { kNone, kName, kRows, kColumns, kRhs, kRanges, kBounds, kQuad, kQuadFull, kObjSense, kEnd };

struct Entry {
  int row;
  int col;
  double value;
};

struct Builder {
  std::unordered_map<std::string, int> row_index;  // constraint rows only
  std::vector<char> row_type;                       // 'E', 'L', 'G'
  std::vector<double> rhs;                          // per constraint row
  std::vector<double> range;                        // NaN: none
  std::string objective;                            // first N row
  std::unordered_map<std::string, char> free_rows;  // further N rows (dropped)
  std::unordered_map<std::string, int> col_index;
  std::vector<double> cost, lb, ub;
  std::vector<char> lb_given;
  std::vector<Entry> a_entries;                     // (row, col, value)
  std::vector<Entry> q_entries;                     // (i, j, value), as listed
  double objective_rhs = 0.0;
};

bool number(const std::string& tok, double& v) {
  char* end = nullptr;
  v = std::strtod(tok.c_str(), &end);
  return !tok.empty() && end != nullptr && *end == '\0' && !std::isnan(v);
}

Section header(const std::string& word) {
  if (word == "NAME") return Section::kName;
  if (word == "ROWS") return Section::kRows;
  if (word == "COLUMNS") return Section::kColumns;
  if (word == "RHS") return Section::kRhs;
  if (word == "RANGES") return Section::kRanges;
  if (word == "BOUNDS") return Section::kBounds;
  if (word == "QUADOBJ" || word == "QSECTION") return Section::kQuad;
  if (word == "QMATRIX") return Section::kQuadFull;
  if (word == "OBJSENSE") return Section::kObjSense;
  if (word == "ENDATA") return Section::kEnd;
  return Section::kNone;
}

class Parser {
 public:
  Parser(QpsProblem& out, std::string& error) : out_(out), error_(error) {}

  bool line(const std::string& text, int lineno) {
    lineno_ = lineno;
    if (text.empty() || text[0] == '*') return true;
    std::istringstream ss(text);
    std::vector<std::string> tok;
    for (std::string t; ss >> t;) tok.push_back(t);
    if (tok.empty()) return true;
    if (text[0] != ' ' && text[0] != '\t') {
      const Section s = header(tok[0]);
      if (s == Section::kNone) return fail(fmt::format("unknown section '{}'", tok[0]));
      section_ = s;
      if (s == Section::kName && tok.size() > 1) out_.name = tok[1];
      if (s == Section::kObjSense && tok.size() > 1) return sense(tok[1]);
      return true;
    }
    switch (section_) {
      case Section::kRows: return rows(tok);
      case Section::kColumns: return columns(tok);
      case Section::kRhs: return rhs(tok, false);
      case Section::kRanges: return rhs(tok, true);
      case Section::kBounds: return bounds(tok);
      case Section::kQuad: return quad(tok, true);
      case Section::kQuadFull: return quad(tok, false);
      case Section::kObjSense: return sense(tok[0]);
      case Section::kName: return true;
      default: return fail("data outside a section");
    }
  }

  bool finish() {
    if (section_ != Section::kEnd) return fail("missing ENDATA");
    const std::size_t n = b_.cost.size(), m = b_.rhs.size();
    if (n < 1) return fail("no columns");
    QpText& qp = out_.qp;
    qp = QpText{};
    qp.n = static_cast<int>(n);
    qp.m = static_cast<int>(m);
    qp.H.assign(n * n, 0.0);
    qp.A.assign(m * n, 0.0);
    const double sign = out_.maximise ? -1.0 : 1.0;
    for (const Entry& e : b_.q_entries) {
      const auto i = static_cast<std::size_t>(e.row), j = static_cast<std::size_t>(e.col);
      qp.H[i * n + j] += sign * e.value;
      if (quad_triangle_ && i != j) qp.H[j * n + i] += sign * e.value;
    }
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < i; ++j) {
        if (qp.H[i * n + j] != qp.H[j * n + i]) {
          return fail(fmt::format("the quadratic part is not symmetric at ({}, {})", i, j));
        }
      }
    }
    for (const Entry& e : b_.a_entries) {
      qp.A[static_cast<std::size_t>(e.row) * n + static_cast<std::size_t>(e.col)] += e.value;
    }
    for (std::size_t j = 0; j < n; ++j) qp.g.push_back(sign * b_.cost[j]);
    qp.lb = b_.lb;
    qp.ub = b_.ub;
    for (std::size_t r = 0; r < m; ++r) {
      double lo = b_.rhs[r], hi = b_.rhs[r];
      const double rg = b_.range[r];
      switch (b_.row_type[r]) {
        case 'L': lo = std::isnan(rg) ? -kInf : b_.rhs[r] - std::abs(rg); break;
        case 'G': hi = std::isnan(rg) ? kInf : b_.rhs[r] + std::abs(rg); break;
        default:
          if (!std::isnan(rg)) (rg > 0 ? hi : lo) = b_.rhs[r] + rg;
          break;
      }
      qp.lbA.push_back(lo);
      qp.ubA.push_back(hi);
    }
    for (std::size_t j = 0; j < n; ++j) {
      if (qp.lb[j] > qp.ub[j]) return fail(fmt::format("column {}: lower bound above upper bound", j));
    }
    out_.constant = -sign * b_.objective_rhs;
    return true;
  }

 private:
  bool fail(const std::string& what) {
    error_ = fmt::format("line {}: {}", lineno_, what);
    return false;
  }

  bool sense(const std::string& word) {
    if (word == "MAX" || word == "MAXIMIZE") {
      out_.maximise = true;
    } else if (word != "MIN" && word != "MINIMIZE") {
      return fail(fmt::format("OBJSENSE '{}'", word));
    }
    return true;
  }

  bool rows(const std::vector<std::string>& tok) {
    if (tok.size() != 2) return fail("ROWS: expected 'type name'");
    const std::string& type = tok[0];
    const std::string& name = tok[1];
    if (type == "N") {
      if (b_.objective.empty()) {
        b_.objective = name;
      } else {
        b_.free_rows[name] = 'N';
      }
      return true;
    }
    if (type != "E" && type != "L" && type != "G") return fail(fmt::format("ROWS: type '{}'", type));
    if (b_.row_index.count(name) != 0 || name == b_.objective) return fail(fmt::format("row '{}' twice", name));
    if (static_cast<int>(b_.rhs.size()) >= kMaxTextRows) return fail("more rows than the reader's limit");
    b_.row_index[name] = static_cast<int>(b_.rhs.size());
    b_.row_type.push_back(type[0]);
    b_.rhs.push_back(0.0);
    b_.range.push_back(std::numeric_limits<double>::quiet_NaN());
    return true;
  }

  int column(const std::string& name, bool create) {
    const auto it = b_.col_index.find(name);
    if (it != b_.col_index.end()) return it->second;
    if (!create) return -1;
    if (static_cast<int>(b_.cost.size()) >= kMaxTextVariables) return -2;
    const int j = static_cast<int>(b_.cost.size());
    b_.col_index[name] = j;
    b_.cost.push_back(0.0);
    b_.lb.push_back(0.0);
    b_.ub.push_back(kInf);
    b_.lb_given.push_back(0);
    return j;
  }

  bool columns(const std::vector<std::string>& tok) {
    if (tok.size() >= 2 && (tok[1] == "'MARKER'" || tok[1] == "MARKER")) {
      return fail("integer markers are not supported (continuous QPs only)");
    }
    if (tok.size() != 3 && tok.size() != 5) return fail("COLUMNS: expected 'column row value [row value]'");
    const int j = column(tok[0], true);
    if (j == -2) return fail("more columns than the reader's limit");
    for (std::size_t k = 1; k + 1 < tok.size(); k += 2) {
      double v = 0.0;
      if (!number(tok[k + 1], v) || !std::isfinite(v)) return fail(fmt::format("COLUMNS: '{}' is not a finite number", tok[k + 1]));
      if (tok[k] == b_.objective) {
        b_.cost[static_cast<std::size_t>(j)] += v;
        continue;
      }
      if (b_.free_rows.count(tok[k]) != 0) continue;
      const auto it = b_.row_index.find(tok[k]);
      if (it == b_.row_index.end()) return fail(fmt::format("COLUMNS: unknown row '{}'", tok[k]));
      b_.a_entries.push_back({it->second, j, v});
    }
    const double cells = static_cast<double>(b_.cost.size()) * static_cast<double>(b_.cost.size() + b_.rhs.size());
    if (cells > static_cast<double>(kMaxTextEntries)) return fail("n (n + m) beyond the reader's limit");
    return true;
  }

  // RHS and RANGES lines: [set] row value [row value].
  bool rhs(const std::vector<std::string>& tok, bool ranges) {
    const std::size_t first = tok.size() % 2 == 1 ? 1 : 0;
    if (tok.size() < 2 || tok.size() > 5) return fail(ranges ? "RANGES: bad line" : "RHS: bad line");
    for (std::size_t k = first; k + 1 < tok.size(); k += 2) {
      double v = 0.0;
      if (!number(tok[k + 1], v) || !std::isfinite(v)) return fail(fmt::format("'{}' is not a finite number", tok[k + 1]));
      if (!ranges && tok[k] == b_.objective) {
        b_.objective_rhs = v;
        continue;
      }
      if (b_.free_rows.count(tok[k]) != 0) continue;
      const auto it = b_.row_index.find(tok[k]);
      if (it == b_.row_index.end()) return fail(fmt::format("unknown row '{}'", tok[k]));
      (ranges ? b_.range : b_.rhs)[static_cast<std::size_t>(it->second)] = v;
    }
    return true;
  }

  bool bounds(const std::vector<std::string>& tok) {
    const std::string& type = tok[0];
    const bool valued = type == "UP" || type == "LO" || type == "FX" || type == "LI" || type == "UI";
    const bool flag = type == "FR" || type == "MI" || type == "PL" || type == "BV";
    if (!valued && !flag) return fail(fmt::format("BOUNDS: type '{}' not supported", type));
    // with or without the bound set's name
    const std::size_t want = valued ? 4 : 3;
    if (tok.size() != want && tok.size() != want - 1) return fail("BOUNDS: bad line");
    const std::string& name = tok.size() == want ? tok[2] : tok[1];
    const int j = column(name, false);
    if (j < 0) return fail(fmt::format("BOUNDS: unknown column '{}'", name));
    const auto u = static_cast<std::size_t>(j);
    double v = 0.0;
    if (valued && (!number(tok.back(), v))) return fail(fmt::format("BOUNDS: '{}' is not a number", tok.back()));
    if (type == "UP" || type == "UI") {
      b_.ub[u] = v;
      if (v < 0.0 && !b_.lb_given[u] && b_.lb[u] == 0.0) b_.lb[u] = -kInf;
    } else if (type == "LO" || type == "LI") {
      b_.lb[u] = v;
      b_.lb_given[u] = 1;
    } else if (type == "FX") {
      b_.lb[u] = b_.ub[u] = v;
      b_.lb_given[u] = 1;
    } else if (type == "FR") {
      b_.lb[u] = -kInf;
      b_.ub[u] = kInf;
      b_.lb_given[u] = 1;
    } else if (type == "MI") {
      b_.lb[u] = -kInf;
      b_.lb_given[u] = 1;
    } else if (type == "PL") {
      b_.ub[u] = kInf;
    } else {  // BV: the continuous relaxation would be a different problem
      return fail("BOUNDS: binary variables are not supported");
    }
    if (std::isnan(b_.lb[u]) || std::isnan(b_.ub[u]) || b_.lb[u] == kInf || b_.ub[u] == -kInf) {
      return fail("BOUNDS: bad bound value");
    }
    return true;
  }

  bool quad(const std::vector<std::string>& tok, bool triangle) {
    if (tok.size() != 3) return fail("quadratic section: expected 'column column value'");
    const int i = column(tok[0], false), j = column(tok[1], false);
    if (i < 0 || j < 0) return fail("quadratic section: unknown column");
    double v = 0.0;
    if (!number(tok[2], v) || !std::isfinite(v)) return fail(fmt::format("'{}' is not a finite number", tok[2]));
    quad_triangle_ = triangle;
    b_.q_entries.push_back({i, j, v});
    return true;
  }

  QpsProblem& out_;
  std::string& error_;
  Builder b_;
  Section section_ = Section::kNone;
  int lineno_ = 0;
  bool quad_triangle_ = true;
};

}  // namespace

bool read_qps(std::istream& in, QpsProblem& out, std::string& error) {
  try {
    out = QpsProblem{};
    Parser parser(out, error);
    std::string text;
    int lineno = 0;
    while (std::getline(in, text)) {
      ++lineno;
      if (!text.empty() && text.back() == '\r') text.pop_back();
      if (!parser.line(text, lineno)) return false;
    }
    return parser.finish();
  } catch (const std::bad_alloc&) {
    error = "out of memory while reading";
  } catch (const std::length_error&) {
    error = "a section is too long";
  }
  return false;
}

bool read_qps_file(const std::string& path, QpsProblem& out, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "cannot open " + path;
    return false;
  }
  return read_qps(in, out, error);
}

bool looks_like_qps(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  while (std::getline(in, text)) {
    if (text.empty() || text[0] == '*') continue;
    std::istringstream ss(text);
    std::string word;
    if (!(ss >> word)) continue;
    return word == "NAME" || word == "ROWS";
  }
  return false;
}

}  // namespace hil::formats
