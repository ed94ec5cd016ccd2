#include "formats/qp_text.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <istream>
#include <limits>
#include <new>
#include <stdexcept>
#include <ostream>
#include <sstream>

namespace hil::formats {

namespace {

// Tokens of a qp-text stream; '#' starts a comment that runs to the line's end.
class Tokens {
 public:
  explicit Tokens(std::istream& in) : in_(in) {}
  bool next(std::string& tok) {
    for (;;) {
      while (!(line_ >> tok)) {
        std::string text;
        if (!std::getline(in_, text)) return false;
        const auto hash = text.find('#');
        if (hash != std::string::npos) text.resize(hash);
        line_.clear();
        line_.str(text);
      }
      return true;
    }
  }

 private:
  std::istream& in_;
  std::istringstream line_;
};

bool parse_number(const std::string& tok, double& v) {
  if (tok == "inf" || tok == "+inf" || tok == "Inf") {
    v = std::numeric_limits<double>::infinity();
    return true;
  }
  if (tok == "-inf" || tok == "-Inf") {
    v = -std::numeric_limits<double>::infinity();
    return true;
  }
  char* end = nullptr;
  v = std::strtod(tok.c_str(), &end);
  return end != nullptr && *end == '\0' && !tok.empty() && !std::isnan(v);
}

// Appends `count` numbers to `out`, which grows only with the numbers
// actually read: a header that claims more than the file holds costs no
// more memory than the file itself (issue 13, defect 5).
bool read_numbers(Tokens& t, const char* section, std::size_t count, std::vector<double>& out,
                  std::string& error) {
  out.clear();
  constexpr std::size_t kFirstChunk = 1024;
  out.reserve(count < kFirstChunk ? count : kFirstChunk);
  for (std::size_t i = 0; i < count; ++i) {
    std::string tok;
    if (!t.next(tok)) {
      error = fmt::format("section {}: expected {} numbers, file ended after {}", section, count, i);
      return false;
    }
    double v = 0.0;
    if (!parse_number(tok, v)) {
      error = fmt::format("section {}: '{}' is not a number", section, tok);
      return false;
    }
    out.push_back(v);
  }
  return true;
}

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.17g}", v);
}

void write_matrix(std::ostream& out, const char* name, const std::vector<double>& v,
                  std::size_t rows, std::size_t cols) {
  out << name << '\n';
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < cols; ++c) out << (c ? " " : "") << number(v[r * cols + c]);
    if (cols > 0) out << '\n';
  }
}

}  // namespace

namespace {

bool read_qp_text_unguarded(std::istream& in, QpText& qp, std::string& error) {
  Tokens t(in);
  std::string tok;
  if (!t.next(tok) || tok != "qp-text/1") {
    error = "not a qp-text/1 file (first token must be 'qp-text/1')";
    return false;
  }
  std::string kn, km;
  double dn = 0, dm = 0;
  std::string sn, sm;
  if (!t.next(kn) || kn != "n" || !t.next(sn) || !parse_number(sn, dn) || !t.next(km) ||
      km != "m" || !t.next(sm) || !parse_number(sm, dm) || dn < 1 || dm < 0 ||
      dn != std::floor(dn) || dm != std::floor(dm)) {
    error = "header: expected 'n <int >= 1> m <int >= 0>'";
    return false;
  }
  // Bounded before anything is allocated (the dense format holds n(n + m) + 2(n + m) numbers).
  if (dn > kMaxTextVariables || dm > kMaxTextRows || dn * (dn + dm) > static_cast<double>(kMaxTextEntries)) {
    error = fmt::format("header: n {} m {} beyond the reader's limits (n <= {}, m <= {}, n (n + m) <= {})", dn, dm,
                        kMaxTextVariables, kMaxTextRows, kMaxTextEntries);
    return false;
  }
  qp = QpText{};
  qp.n = static_cast<int>(dn);
  qp.m = static_cast<int>(dm);
  const auto n = static_cast<std::size_t>(qp.n), m = static_cast<std::size_t>(qp.m);
  struct Section {
    const char* name;
    std::vector<double>* data;
    std::size_t count;
  };
  const Section sections[] = {{"H", &qp.H, n * n},     {"g", &qp.g, n},     {"A", &qp.A, m * n},
                              {"lbA", &qp.lbA, m},     {"ubA", &qp.ubA, m}, {"lb", &qp.lb, n},
                              {"ub", &qp.ub, n}};
  for (const auto& s : sections) {
    if (!t.next(tok) || tok != s.name) {
      error = fmt::format("expected section '{}'", s.name);
      return false;
    }
    if (!read_numbers(t, s.name, s.count, *s.data, error)) return false;
  }
  for (double v : qp.H) {
    if (!std::isfinite(v)) {
      error = "section H: entries must be finite";
      return false;
    }
  }
  while (t.next(tok)) {
    if (tok == "x_ref") {
      std::vector<double> x;
      if (!read_numbers(t, "x_ref", n, x, error)) return false;
      qp.x_ref = std::move(x);
    } else if (tok == "obj_ref") {
      std::vector<double> o;
      if (!read_numbers(t, "obj_ref", 1, o, error)) return false;
      qp.obj_ref = o[0];
    } else {
      error = fmt::format("unknown trailing section '{}'", tok);
      return false;
    }
  }
  return true;
}

}  // namespace

bool read_qp_text(std::istream& in, QpText& qp, std::string& error) {
  // Errors are values: not even an exhausted heap escapes as an exception.
  try {
    return read_qp_text_unguarded(in, qp, error);
  } catch (const std::bad_alloc&) {
    error = "out of memory while reading";
  } catch (const std::length_error&) {
    error = "a section is too long";
  }
  qp = QpText{};
  return false;
}

bool read_qp_text_file(const std::string& path, QpText& qp, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "cannot open " + path;
    return false;
  }
  return read_qp_text(in, qp, error);
}

void write_qp_text(std::ostream& out, const QpText& qp) {
  const auto n = static_cast<std::size_t>(qp.n), m = static_cast<std::size_t>(qp.m);
  out << "qp-text/1\n" << "n " << qp.n << " m " << qp.m << '\n';
  write_matrix(out, "H", qp.H, n, n);
  write_matrix(out, "g", qp.g, 1, n);
  write_matrix(out, "A", qp.A, m, n);
  write_matrix(out, "lbA", qp.lbA, 1, m);
  write_matrix(out, "ubA", qp.ubA, 1, m);
  write_matrix(out, "lb", qp.lb, 1, n);
  write_matrix(out, "ub", qp.ub, 1, n);
  if (qp.x_ref) write_matrix(out, "x_ref", *qp.x_ref, 1, n);
  if (qp.obj_ref) out << "obj_ref\n" << number(*qp.obj_ref) << '\n';
}

bool write_qp_text_file(const std::string& path, const QpText& qp, std::string& error) {
  std::ofstream out(path);
  if (!out) {
    error = "cannot write " + path;
    return false;
  }
  write_qp_text(out, qp);
  return static_cast<bool>(out);
}

}  // namespace hil::formats
