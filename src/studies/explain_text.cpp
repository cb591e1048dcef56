// The text `cbps explain` prints (explain.hpp): every block of the step's system with its labels,
// units and equation numbers, to kDigits significant digits.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/step/push.hpp"
#include "cbps/studies/explain.hpp"

namespace cbps {

namespace {

/// Significant digits of every number in the text output.
constexpr int kDigits = 6;

/// A number with kDigits significant digits; -0 is printed as 0.
std::string num(double x) {
  if (x == 0.0) return "0";
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", kDigits, x);
  return text;
}

std::size_t longest(const std::vector<std::string>& labels, std::size_t at_least = 0) {
  std::size_t w = at_least;
  for (const std::string& s : labels) w = std::max(w, s.size());
  return w;
}

int width(std::size_t w) { return static_cast<int>(w); }

/// Prints a matrix densely when it is narrow, else its nonzeros with their labels. Labels are
/// never cut: column widths come from the longest label and the widest number.
void print_matrix(std::FILE* out,
                  const std::string& title,
                  const MatX& M,
                  const std::vector<std::string>& row_labels,
                  const std::vector<std::string>& col_labels) {
  std::fprintf(out,
               "%s  (%ld x %ld)\n",
               title.c_str(),
               static_cast<long>(M.rows()),
               static_cast<long>(M.cols()));
  if (M.rows() == 0 || M.cols() == 0) {
    std::fprintf(out, "  (empty)\n");
    return;
  }
  const int row_w = width(longest(row_labels));
  if (M.cols() <= 12) {
    std::vector<int> col_w;
    for (Eigen::Index c = 0; c < M.cols(); ++c) {
      std::size_t w = col_labels[static_cast<std::size_t>(c)].size();
      for (Eigen::Index r = 0; r < M.rows(); ++r) w = std::max(w, num(M(r, c)).size());
      col_w.push_back(width(w));
    }
    std::fprintf(out, "  %-*s", row_w, "");
    for (Eigen::Index c = 0; c < M.cols(); ++c)
      std::fprintf(out,
                   "  %*s",
                   col_w[static_cast<std::size_t>(c)],
                   col_labels[static_cast<std::size_t>(c)].c_str());
    std::fprintf(out, "\n");
    for (Eigen::Index r = 0; r < M.rows(); ++r) {
      std::fprintf(out, "  %-*s", row_w, row_labels[static_cast<std::size_t>(r)].c_str());
      for (Eigen::Index c = 0; c < M.cols(); ++c)
        std::fprintf(out, "  %*s", col_w[static_cast<std::size_t>(c)], num(M(r, c)).c_str());
      std::fprintf(out, "\n");
    }
    return;
  }
  std::fprintf(
      out, "  (%ld columns: nonzero entries only, row by row)\n", static_cast<long>(M.cols()));
  const int col_w = width(longest(col_labels));
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    for (Eigen::Index c = 0; c < M.cols(); ++c) {
      if (M(r, c) == 0.0) continue;
      std::fprintf(out,
                   "  %-*s  %-*s  %s\n",
                   row_w,
                   row_labels[static_cast<std::size_t>(r)].c_str(),
                   col_w,
                   col_labels[static_cast<std::size_t>(c)].c_str(),
                   num(M(r, c)).c_str());
    }
  }
}

/// Prints a vector, one labelled entry a line, with each entry's unit.
void print_vector(std::FILE* out,
                  const std::string& title,
                  const VecX& v,
                  const std::vector<std::string>& labels,
                  const std::vector<std::string>& units) {
  std::fprintf(out, "%s  (%ld)\n", title.c_str(), static_cast<long>(v.size()));
  const int label_w = width(longest(labels));
  std::vector<std::string> values;
  for (Eigen::Index k = 0; k < v.size(); ++k) values.push_back(num(v(k)));
  const int value_w = width(longest(values));
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    std::fprintf(out,
                 "  %-*s  %*s  %s\n",
                 label_w,
                 labels[i].c_str(),
                 value_w,
                 values[i].c_str(),
                 units[i].c_str());
  }
}

/// lambda with its bounds, w and each row's status, one row a line (6.2, 7.1.1).
void print_solution_table(std::FILE* out, const Explained& e) {
  const TeachingSystem& x = e.shown;
  const std::vector<std::string>& rows = e.sys.labels;
  std::fprintf(out,
               "lambda (7.1.1) within [cmin, cmax] (5.1), and w = A lambda - b (6.2)  (%d)\n",
               e.sys.rows());
  std::vector<std::vector<std::string>> table;
  table.push_back({"row", "cmin (N)", "lambda (N)", "cmax (N)", "w (m/s^2)", "status"});
  for (Eigen::Index k = 0; k < x.w.size(); ++k) {
    const RowStatus& s = x.status[static_cast<std::size_t>(k)];
    table.push_back({rows[static_cast<std::size_t>(k)],
                     num(x.cmin(k)),
                     num(x.lambda(k)),
                     num(x.cmax(k)),
                     num(x.w(k)),
                     s.where + (s.satisfied ? "" : " (w violates it)")});
  }
  std::vector<int> col_w(6, 0);
  for (const auto& line : table)
    for (std::size_t c = 0; c < line.size(); ++c)
      col_w[c] = std::max(col_w[c], width(line[c].size()));
  for (const auto& line : table) {
    std::fprintf(out, "  %-*s", col_w[0], line[0].c_str());
    for (std::size_t c = 1; c < 5; ++c) std::fprintf(out, "  %*s", col_w[c], line[c].c_str());
    std::fprintf(out, "  %s\n", line[5].c_str());
  }
  std::fprintf(out,
               "  (free: cmin < lambda < cmax and w = 0; at cmin: w >= 0; at cmax: w <= 0; within "
               "%s N, the requested solver tolerance or the rounding floor of w if larger)\n",
               num(e.tol).c_str());
  if (!e.all_satisfied)
    std::fprintf(out,
                 "  (some rows miss their condition: the solver stopped at residual %s N, before "
                 "it met them)\n",
                 num(x.summary.residual).c_str());
  if (e.coulomb) std::fprintf(out, "  (%s)\n", kCoulombNote);
  if (e.sys.cones() != nullptr)
    std::fprintf(
        out, "  (%s; law %s)\n", kConeNote, std::string(cone_law_name(e.sys.contacts.law)).c_str());
}

}  // namespace

void print_explain_text(std::FILE* out, const Explained& e) {
  const System& sys = e.sys;
  const std::vector<std::string>& rows = sys.labels;
  std::fprintf(out,
               "%s, step %ld (t = %s s, dt = %s s): %s, %s\n",
               e.scene.c_str(),
               e.step,
               num(e.t).c_str(),
               num(sys.dt).c_str(),
               count_text(sys.rows(), "row").c_str(),
               count_text(sys.blocks(), "movable body", "movable bodies").c_str());
  std::fprintf(out, "System shown: %s.\n", e.system_shown.c_str());
  std::fprintf(out, "Numbers to %d significant digits.\n\n", kDigits);
  print_matrix(out,
               "J: constraint Jacobian, rows j_c (5.1.3, 5.2.1), 6.1; unit 1 in the linear "
               "columns (vx, vy, vz), m in the angular ones (wx, wy, wz)",
               MatX(sys.J),
               rows,
               e.cols);
  std::fprintf(out, "\n");
  print_matrix(out,
               "Minv = blockdiag(m^-1 E3, I^-1) (6.1.2); kg^-1 (linear block), kg^-1 m^-2 "
               "(angular block)",
               MatX(sys.Minv),
               e.cols,
               e.cols);
  std::fprintf(out, "\n");
  print_matrix(out, "A = J Minv J^T (6.2.9); " + e.A_unit, MatX(sys.A), rows, rows);
  std::fprintf(out, "\n");
  if (sys.softness.size() > 0) {
    const std::vector<std::string> per_kg(rows.size(), "kg^-1");
    print_vector(out, std::string("softness: ") + kSoftnessNote, sys.softness, rows, per_kg);
    std::fprintf(out, "\n");
  }
  print_vector(out, "v1: velocities at the start of the step (6.1.1)", sys.v1, e.cols, e.v_units);
  std::fprintf(out, "\n");
  print_vector(out,
               "fext: external forces and torques, gravity included (6.1.3)",
               sys.fext,
               e.cols,
               e.f_units);
  std::fprintf(out, "\n");
  const std::vector<std::string> ms(rows.size(), "m/s"), ms2(rows.size(), "m/s^2");
  print_vector(out, "upsilon: velocity bias (5.1.2, 5.2.3, 8.2)", sys.upsilon, rows, ms);
  if (e.improved) {
    std::fprintf(out, "\n");
    print_vector(out,
                 "upsilon_position: the position system's bias (8.1), not the system shown",
                 position_bias(sys),
                 rows,
                 ms);
  }
  std::fprintf(out, "\n");
  print_vector(out, "b = upsilon/dt - J (v1/dt + Minv fext) (6.2.9)", sys.b, rows, ms2);
  std::fprintf(out, "\n");
  print_solution_table(out, e);
  std::fprintf(out, "\n");
  print_vector(
      out, "v2 = v1 + dt Minv (J^T lambda + fext) (12.3.1)", e.shown.v2, e.cols, e.v_units);
  if (e.cfm > 0.0)
    std::fprintf(out,
                 "\neps = %s kg^-1: %s; w of A is eps lambda off on free rows\n",
                 num(e.cfm).c_str(),
                 kCfmNote);
  std::fprintf(out, "\nsolver %s: %s\n", e.method.c_str(), e.shown.summary.message.c_str());
}

}  // namespace cbps
