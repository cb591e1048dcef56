// The teaching page's HTML (teaching_page.hpp): one document with its CSS and inline SVG
// pictures, no scripts, no network. Each block opens with its equation as the paper writes it;
// every table has row and column labels and units. Above TeachingLimits the tables give way to
// pictures and statistics, and the page says so.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/studies/teaching_page.hpp"

namespace cbps {

namespace {

/// Significant digits of every number shown (as `cbps explain`).
constexpr int kDigits = 6;

/// An entry at most this fraction of its row's largest magnitude is drawn as rounding in the
/// sparsity pictures (about 4500 ε: a few roundings of the row's products).
constexpr double kRoundingRatio = 1e-12;

/// The largest magnitude in each row of M.
VecX row_magnitudes(const SpMat& M) {
  VecX largest = VecX::Zero(M.rows());
  for (Eigen::Index c = 0; c < M.outerSize(); ++c)
    for (SpMat::InnerIterator it(M, c); it; ++it)
      largest(it.row()) = std::max(largest(it.row()), std::abs(it.value()));
  return largest;
}

/// A number with kDigits significant digits; -0 as 0, inf as ∞.
std::string num(double x) {
  if (x == 0.0) return "0";
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "∞" : "-∞";
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", kDigits, x);
  return text;
}

/// A coordinate in an SVG picture, to 0.01 px.
std::string px(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", x);
  return text;
}

/// Row colours by kind, the same in every picture and table.
const char* kind_colour(RowKind kind) {
  switch (kind) {
    case RowKind::Distance:
      return "#1f6fb4";
    case RowKind::Contact:
      return "#c62828";
    case RowKind::Friction:
      return "#2e8b2e";
  }
  return "#1f6fb4";
}

RowKind kind_of(const System& sys, Eigen::Index k) {
  const auto i = static_cast<std::size_t>(k);
  return i < sys.kind.size() ? sys.kind[i] : RowKind::Distance;
}

const char* const kCss = R"(
:root{color-scheme:light}
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;margin:0 auto;
 max-width:62rem;padding:.75rem;line-height:1.45;color:#111;background:#fff}
h1{font-size:1.45rem;margin:.3rem 0}h2{font-size:1.2rem;margin:1.6rem 0 .4rem;
 border-bottom:2px solid #ccc}h3{font-size:1.02rem;margin:1rem 0 .3rem}
.eq{font-family:"STIX Two Math","Latin Modern Math","Cambria Math","DejaVu Serif",serif;
 font-size:1.08rem;background:#f5f5ef;border-left:4px solid #8a8a70;padding:.35rem .7rem;
 margin:.4rem 0;overflow-x:auto}
.unit,.note{color:#444;font-size:.92rem;margin:.25rem 0}
.limit{background:#fff6d8;border:1px solid #e0c060;padding:.3rem .6rem;font-size:.92rem}
.scroll{overflow-x:auto;max-width:100%}
table{border-collapse:collapse;font-variant-numeric:tabular-nums;font-size:.82rem;margin:.3rem 0}
th,td{padding:.12rem .45rem;border-bottom:1px solid #e2e2e2;text-align:right;white-space:nowrap}
thead th{border-bottom:2px solid #999;font-weight:600;position:sticky;top:0;background:#fff}
th.row{text-align:left;font-weight:500;position:sticky;left:0;background:#fff}
thead th:first-child{left:0;z-index:1}
td.zero{color:#b8b8b8}
tr.distance th.row{border-left:5px solid #1f6fb4}tr.contact th.row{border-left:5px solid #c62828}
tr.friction th.row{border-left:5px solid #2e8b2e}
tr.at-bound td.lambda{background:#ffe9a8;font-weight:700}tr.miss td.status{color:#b00000}
.key span{display:inline-block;margin-right:1rem}.key i{display:inline-block;width:.9rem;
 height:.9rem;vertical-align:-.1rem;margin-right:.3rem;border-radius:2px}
svg{max-width:100%;height:auto;display:block;margin:.4rem 0;background:#fff}
svg text{font-family:system-ui,"DejaVu Sans",sans-serif}
nav ul{padding-left:1.2rem;margin:.2rem 0}nav li{display:inline;margin-right:.9rem}
dl.stats{display:grid;grid-template-columns:max-content auto;gap:.1rem .8rem;font-size:.9rem}
dl.stats dt{color:#444}dl.stats dd{margin:0;font-variant-numeric:tabular-nums}
@media (max-width:40rem){body{padding:.4rem}.eq{font-size:.98rem}}
@media print{body{max-width:none;padding:0}nav{display:none}.scroll{overflow:visible}
 section,figure,table{break-inside:avoid-page}thead th{position:static}}
)";

/// Builds the page into one stream.
/// A panel of the bounds picture: every row (nullopt) or one kind's.
using Panel = std::optional<RowKind>;

bool in_panel(const System& sys, const Panel& panel, Eigen::Index k) {
  return !panel || kind_of(sys, k) == *panel;
}

/// A panel's λ axis: 0, λ and the finite bounds of its rows, with its three labels.
struct BoundsAxis {
  double lo = 0.0, hi = 0.0;
  std::vector<std::string> labels;  // lo, 0, hi
};

BoundsAxis bounds_axis(const System& sys, const Panel& panel, const TeachingSystem& t) {
  BoundsAxis a;
  for (Eigen::Index k = 0; k < t.lambda.size(); ++k)
    if (in_panel(sys, panel, k))
      for (double v : {t.lambda(k), t.cmin(k), t.cmax(k)})
        if (std::isfinite(v)) {
          a.lo = std::min(a.lo, v);
          a.hi = std::max(a.hi, v);
        }
  if (a.hi - a.lo <= 0.0) a.hi = a.lo + 1.0;
  for (double v : {a.lo, 0.0, a.hi}) a.labels.push_back(num(v) + " N");
  return a;
}

/// How the names above a sparsity picture's column bands are set: slanted in 11 px where a band
/// is wide enough (18 px), else upright in a font that fits the band (8 to 11 px), one name in
/// `every` where even 8 px does not fit (a band under 9 px: the base-6 pyramid's 21 bodies in
/// J's 126 columns beside 432 rows); `top`, px, the room they take above the picture.
struct GroupNames {
  double band = 0.0;  ///< px, one band's width (0: no bands)
  bool slanted = true;
  double font = 11.0;  ///< px
  long every = 1;
  double top = 10.0;  ///< px
};

GroupNames group_names_layout(double band, const std::vector<std::string>& names) {
  GroupNames g;
  g.band = band;
  if (band <= 0.0) return g;
  g.slanted = band >= 18.0;
  g.font = g.slanted ? 11.0 : std::clamp(band * 0.9, 8.0, 11.0);
  g.every = g.slanted || band >= 9.0 ? 1 : static_cast<long>(std::ceil(9.0 / band));
  std::size_t longest = 0;
  for (const std::string& name : names) longest = std::max(longest, name.size());
  // About 0.62 em a character (6.2 px at 11 px, as the row labels take).
  g.top = g.slanted ? 70.0 : 0.62 * g.font * static_cast<double>(longest) + 10.0;
  return g;
}

class Page {
 public:
  Page(const TeachingStep& step, const TeachingLimits& limits)
      : s_(step), sys_(step.sys), l_(limits) {}
  std::string render();

 private:
  void header();
  void jacobian();
  void mass();
  void system_matrix();
  void spectrum();
  void velocities();
  void one_system(const TeachingSystem& t, const std::string& id);
  /// λ against its bounds, w and the residual per sweep of one system.
  void solution(const TeachingSystem& t, const std::string& id);
  /// How many rows are free, at a bound, missing their condition; the tolerance and residual.
  void solution_stats(const TeachingSystem& t, const std::string& id);
  /// cmin, λ, cmax, w and the status of every row (small systems).
  void solution_table(const TeachingSystem& t, const std::string& id);
  /// The residual after each sweep from the step's guess.
  void residual_per_sweep(const TeachingSystem& t, const std::string& id);
  void footer();

  void equation(const std::string& html) { o_ << "<p class=\"eq\">" << html << "</p>\n"; }
  void unit(const std::string& html) { o_ << "<p class=\"unit\">Unit: " << html << "</p>\n"; }
  void note(const std::string& html) { o_ << "<p class=\"note\">" << html << "</p>\n"; }
  void limit(const std::string& html) { o_ << "<p class=\"limit\">" << html << "</p>\n"; }
  void stat(const std::string& name, const std::string& value) {
    o_ << "<dt>" << name << "</dt><dd>" << value << "</dd>";
  }
  void number_cell(double x, const char* cls = nullptr) {
    o_ << "<td";
    if (x == 0.0)
      o_ << " class=\"zero\"";
    else if (cls != nullptr)
      o_ << " class=\"" << cls << "\"";
    o_ << ">" << num(x) << "</td>";
  }
  void row_head(Eigen::Index k) {
    o_ << "<tr class=\"" << to_string(kind_of(sys_, k)) << "\"><th class=\"row\">"
       << html_escape(sys_.labels[static_cast<std::size_t>(k)]) << "</th>";
  }
  /// A dense matrix as a table, row and column labels escaped.
  void matrix_table(const std::string& id,
                    const MatX& M,
                    bool rows_are_constraints,
                    const std::vector<std::string>& col_labels);
  /// One band's name above a sparsity picture, its band starting at x px.
  void group_name(const GroupNames& names, double x, const std::string& name);
  /// Where each nonzero of M lies, rows coloured by kind, columns banded by `group` columns
  /// (6: one band per body) with `group_names` above them.
  void sparsity(const std::string& id,
                const std::string& title,
                const SpMat& M,
                int group,
                const std::vector<std::string>& group_names);
  /// Values on a logarithmic axis: a line (line = true) or points, one per index.
  void log_plot(const std::string& id,
                const std::string& title,
                const std::vector<double>& values,
                const std::string& x_name,
                const std::string& y_name,
                bool line,
                double floor_value,
                double mark_value,
                const std::string& mark_name);
  /// λ of every row against its bounds: one bar per row, or binned in one panel per row kind.
  void bounds_picture(const std::string& id, const TeachingSystem& t);
  /// Where bounds_picture draws: bars of `bin` rows each, `w` px wide between `left` and
  /// `right`; each panel a title line, a plot `plot` px high, `panel_height` in all.
  struct BoundsLayout {
    Eigen::Index bin = 1, bars = 1;
    double font = 11.0, left = 60.0, right = 560.0, w = 1.0;
    double title = 0.0, plot = 188.0, panel_height = 200.0;
  };
  /// One panel's axis lines and bars; counts the rows at a bound by kind into at_bound.
  void bounds_panel(const BoundsLayout& l,
                    const std::optional<RowKind>& panel,
                    const BoundsAxis& a,
                    double top,
                    const TeachingSystem& t,
                    std::array<long, 3>& at_bound);
  void body_table(const std::string& id,
                  const std::vector<const VecX*>& vectors,
                  const std::vector<std::string>& names,
                  const std::vector<std::string>& units);

  const TeachingStep& s_;
  const System& sys_;
  TeachingLimits l_;
  std::ostringstream o_;
};

void Page::matrix_table(const std::string& id,
                        const MatX& M,
                        bool rows_are_constraints,
                        const std::vector<std::string>& col_labels) {
  o_ << "<div class=\"scroll\"><table id=\"" << id << "\"><thead><tr><th></th>";
  for (const std::string& c : col_labels) o_ << "<th>" << html_escape(c) << "</th>";
  o_ << "</tr></thead><tbody>\n";
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    if (rows_are_constraints) row_head(r);
    for (Eigen::Index c = 0; c < M.cols(); ++c) number_cell(M(r, c));
    o_ << "</tr>\n";
  }
  o_ << "</tbody></table></div>\n";
}

void Page::group_name(const GroupNames& names, double x, const std::string& name) {
  // Slanted text starts at the band's middle; upright text is centred on it.
  const double at = x + names.band / 2 + (names.slanted ? 0.0 : names.font / 3);
  o_ << "<text class=\"group-name\" x=\"" << px(at) << "\" y=\"" << px(names.top - 4)
     << "\" font-size=\"" << px(names.font) << "\" transform=\"rotate("
     << (names.slanted ? -40 : -90) << " " << px(at) << " " << px(names.top - 4) << ")\">"
     << html_escape(name) << "</text>";
}

void Page::sparsity(const std::string& id,
                    const std::string& title,
                    const SpMat& M,
                    int group,
                    const std::vector<std::string>& group_names) {
  const auto rows = static_cast<double>(M.rows()), cols = static_cast<double>(M.cols());
  if (M.rows() == 0 || M.cols() == 0) return;
  // Large matrices are binned: one square per bin of `bin` × `bin` entries.
  const double cells = std::max(rows, cols);
  const int bin = static_cast<int>(std::ceil(cells / 300.0));
  const double cell = std::clamp(560.0 / (cells / bin), 2.0, 28.0);
  const bool labels = M.rows() <= l_.dense_rows;
  // Room for the row labels at the left (about 6.2 px a character at 11 px) and for the body
  // names, slanted, above and to the right.
  std::size_t longest = 0;
  if (labels)
    for (const std::string& label : sys_.labels) longest = std::max(longest, label.size());
  const double left = labels ? std::min(320.0, 6.2 * static_cast<double>(longest) + 10.0) : 40.0;
  const GroupNames names =
      group_names_layout(group > 0 ? cell * static_cast<double>(group) / bin : 0.0, group_names);
  const double top = names.top;
  const double width = left + cell * std::ceil(cols / bin) + (group > 0 ? 70.0 : 10.0);
  const double height = top + cell * std::ceil(rows / bin) + 10.0;
  o_ << "<figure><svg id=\"" << id << "\" role=\"img\" viewBox=\"0 0 " << px(width) << " "
     << px(height) << "\" width=\"" << px(width) << "\" height=\"" << px(height)
     << "\" xmlns=\"http://www.w3.org/2000/svg\"><title>" << html_escape(title) << "</title>\n";
  // Column bands: one per body (J) or none (A).
  if (group > 0) {
    for (Eigen::Index g = 0; g * group < M.cols(); ++g) {
      const double x = left + cell * static_cast<double>(g * group) / bin;
      o_ << "<rect x=\"" << px(x) << "\" y=\"" << px(top) << "\" width=\"" << px(names.band)
         << "\" height=\"" << px(height - top - 10.0) << "\" fill=\""
         << (g % 2 == 0 ? "#eef1f6" : "#fafafa") << "\"/>";
      if (static_cast<std::size_t>(g) < group_names.size() && g % names.every == 0)
        group_name(names, x, group_names[static_cast<std::size_t>(g)]);
    }
  } else {
    o_ << "<rect x=\"" << px(left) << "\" y=\"" << px(top) << "\" width=\""
       << px(cell * std::ceil(cols / bin)) << "\" height=\"" << px(height - top - 10.0)
       << "\" fill=\"#f4f4f4\"/>";
  }
  o_ << "\n";
  // Nonzeros per bin and row kind; a bin takes the colour of the kind with the most. Entries
  // within kRoundingRatio of their row's largest (a sum that cancels in exact arithmetic, such
  // as -6.9e-18 where r x n has no z part) are stored nonzeros but not structure: a bin holding
  // only those is drawn hollow, and the caption counts them.
  const VecX row_max = row_magnitudes(M);
  std::map<std::pair<Eigen::Index, Eigen::Index>, std::array<int, 3>> kinds;
  std::map<std::pair<Eigen::Index, Eigen::Index>, int> rounding_only;
  long rounding = 0;
  for (Eigen::Index c = 0; c < M.outerSize(); ++c)
    for (SpMat::InnerIterator it(M, c); it; ++it) {
      if (it.value() == 0.0) continue;
      const std::pair<Eigen::Index, Eigen::Index> at{it.row() / bin, c / bin};
      if (std::abs(it.value()) <= kRoundingRatio * row_max(it.row())) {
        ++rounding;
        ++rounding_only[at];
      } else {
        ++kinds[at][static_cast<int>(kind_of(sys_, it.row()))];
      }
    }
  for (const auto& [at, count] : kinds) {
    const auto most = std::max_element(count.begin(), count.end()) - count.begin();
    o_ << "<rect x=\"" << px(left + cell * static_cast<double>(at.second)) << "\" y=\""
       << px(top + cell * static_cast<double>(at.first)) << "\" width=\"" << px(cell * 0.92)
       << "\" height=\"" << px(cell * 0.92) << "\" fill=\""
       << kind_colour(static_cast<RowKind>(most)) << "\"/>";
  }
  for (const auto& entry : rounding_only) {
    const auto& at = entry.first;
    if (kinds.count(at) != 0) continue;
    o_ << "<rect class=\"rounding\" x=\"" << px(left + cell * static_cast<double>(at.second) + 0.5)
       << "\" y=\"" << px(top + cell * static_cast<double>(at.first) + 0.5) << "\" width=\""
       << px(cell * 0.92 - 1.0) << "\" height=\"" << px(cell * 0.92 - 1.0)
       << "\" fill=\"none\" stroke=\"#999\"/>";
  }
  o_ << "\n";
  if (labels)
    for (Eigen::Index r = 0; r < M.rows(); ++r)
      o_ << "<text x=\"" << px(left - 4) << "\" y=\""
         << px(top + cell * (static_cast<double>(r) + 0.75)) << "\" font-size=\""
         << px(std::min(11.0, cell * 0.9)) << "\" text-anchor=\"end\" fill=\""
         << kind_colour(kind_of(sys_, r)) << "\">"
         << html_escape(sys_.labels[static_cast<std::size_t>(r)]) << "</text>";
  o_ << "</svg><figcaption class=\"note\">" << html_escape(title);
  if (names.every > 1)
    o_ << " (one band in " << names.every << " named: the bands are " << px(names.band)
       << " px wide)";
  if (bin > 1)
    o_ << " (one square per " << bin << " × " << bin
       << " entries, coloured by the kind with the most nonzeros in it)";
  if (rounding > 0)
    o_ << ". " << rounding << (rounding == 1 ? " stored entry is" : " stored entries are")
       << " rounding: at most " << num(kRoundingRatio)
       << " of its row's largest (zero in exact arithmetic, e.g. a cross product's cancelled "
          "part); the tables show its value, the picture draws it hollow and grey";
  o_ << "</figcaption></figure>\n";
}

void Page::log_plot(const std::string& id,
                    const std::string& title,
                    const std::vector<double>& values,
                    const std::string& x_name,
                    const std::string& y_name,
                    bool line,
                    double floor_value,
                    double mark_value,
                    const std::string& mark_name) {
  // The decades spanned by the values above floor_value (and the mark), at least one.
  double lo = INFINITY, hi = 0.0;
  for (double v : values)
    if (std::isfinite(v) && v > floor_value) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (mark_value > 0.0) {
    lo = std::min(lo, mark_value);
    hi = std::max(hi, mark_value);
  }
  if (!(hi > 0.0)) {
    note("(nothing to plot: every value is " + num(floor_value) + " or less)");
    return;
  }
  const double d_lo = std::floor(std::log10(lo)),
               d_hi = std::max(d_lo + 1, std::ceil(std::log10(hi)));
  const double left = 60, right = 560, top = 12, bottom = 200, below = 238;
  const double n = std::max<double>(1.0, static_cast<double>(values.size()) - 1.0);
  auto x_of = [&](std::size_t i) {
    return left + 8.0 + (right - left - 16.0) * static_cast<double>(i) / n;
  };
  auto y_of = [&](double v) {
    if (!(v > floor_value)) return bottom + 9.0;  // just below the axis: "zero"
    return bottom - (bottom - top) * (std::log10(v) - d_lo) / (d_hi - d_lo);
  };
  o_ << "<figure><svg id=\"" << id << "\" role=\"img\" viewBox=\"0 0 580 " << below + 12
     << "\" width=\"580\" height=\"" << below + 12
     << "\" xmlns=\"http://www.w3.org/2000/svg\"><title>" << html_escape(title) << "</title>\n";
  const int step = std::max(1, static_cast<int>(std::ceil((d_hi - d_lo) / 8.0)));
  for (double d = d_lo; d <= d_hi; d += step) {
    const double y = bottom - (bottom - top) * (d - d_lo) / (d_hi - d_lo);
    o_ << "<line x1=\"" << left << "\" x2=\"" << right << "\" y1=\"" << px(y) << "\" y2=\"" << px(y)
       << "\" stroke=\"#ddd\"/><text x=\"" << left - 4 << "\" y=\"" << px(y + 4)
       << "\" font-size=\"11\" text-anchor=\"end\">1e" << static_cast<int>(d) << "</text>";
  }
  o_ << "<line x1=\"" << left << "\" x2=\"" << left << "\" y1=\"" << top << "\" y2=\"" << bottom
     << "\" stroke=\"#333\"/><line x1=\"" << left << "\" x2=\"" << right << "\" y1=\"" << bottom
     << "\" y2=\"" << bottom << "\" stroke=\"#333\"/>";
  o_ << "<text x=\"" << left << "\" y=\"" << bottom + 30 << "\" font-size=\"11\">0</text>"
     << "<text x=\"" << right << "\" y=\"" << bottom + 30 << "\" font-size=\"11\" "
     << "text-anchor=\"end\">" << values.size() - 1 << "</text><text x=\"" << (left + right) / 2
     << "\" y=\"" << bottom + 30 << "\" font-size=\"12\" text-anchor=\"middle\">"
     << html_escape(x_name) << "</text><text x=\"12\" y=\"" << (top + bottom) / 2
     << "\" font-size=\"12\" text-anchor=\"middle\" transform=\"rotate(-90 12 "
     << (top + bottom) / 2 << ")\">" << html_escape(y_name) << "</text>\n";
  if (mark_value > 0.0)
    o_ << "<line x1=\"" << left << "\" x2=\"" << right << "\" y1=\"" << px(y_of(mark_value))
       << "\" y2=\"" << px(y_of(mark_value)) << "\" stroke=\"#b00\" stroke-dasharray=\"5 4\"/>"
       << "<text x=\"" << right << "\" y=\"" << px(y_of(mark_value) - 4) << "\" font-size=\"11\" "
       << "text-anchor=\"end\" fill=\"#b00\">" << html_escape(mark_name) << "</text>";
  if (line) {
    o_ << "<polyline fill=\"none\" stroke=\"#1f4f9f\" stroke-width=\"2\" points=\"";
    for (std::size_t i = 0; i < values.size(); ++i)
      o_ << px(x_of(i)) << "," << px(y_of(values[i])) << " ";
    o_ << "\"/>";
  } else {
    for (std::size_t i = 0; i < values.size(); ++i)
      o_ << "<circle cx=\"" << px(x_of(i)) << "\" cy=\"" << px(y_of(values[i])) << "\" r=\"3\" "
         << (values[i] > floor_value ? "fill=\"#1f4f9f\"" : "fill=\"none\" stroke=\"#b00\"")
         << "/>";
  }
  o_ << "</svg><figcaption class=\"note\">" << html_escape(title) << "</figcaption></figure>\n";
}

void Page::bounds_picture(const std::string& id, const TeachingSystem& t) {
  const Eigen::Index c = t.lambda.size();
  if (c == 0) return;
  // Above l_.bar_rows rows one bar stands for `bin` consecutive rows: the range of their λ, the
  // lowest finite cmin and highest finite cmax among them, a dot if any is at a bound. The page
  // stays small at any size. Binned, the picture has one panel per row kind (same bins, each on
  // its own λ scale): a bin mixes kinds (a contact's normal row beside its two friction rows),
  // and one colour per bin would hide the kinds with fewer rows.
  BoundsLayout l;
  const Eigen::Index bars_max = std::max(1, l_.bar_rows);
  l.bin = (c + bars_max - 1) / bars_max;
  l.bars = (c + l.bin - 1) / l.bin;
  std::array<long, 3> rows_of_kind{};
  for (Eigen::Index k = 0; k < c; ++k) ++rows_of_kind[static_cast<std::size_t>(kind_of(sys_, k))];
  // The panels: every kind together (one bar per row), or one per kind present (binned).
  std::vector<Panel> panels;
  if (l.bin == 1) {
    panels.push_back(std::nullopt);
  } else {
    for (RowKind kind : {RowKind::Distance, RowKind::Contact, RowKind::Friction})
      if (rows_of_kind[static_cast<std::size_t>(kind)] > 0) panels.push_back(kind);
  }
  std::vector<BoundsAxis> axes;
  std::size_t longest = 0;
  for (const Panel& panel : panels) {
    axes.push_back(bounds_axis(sys_, panel, t));
    for (const std::string& label : axes.back().labels) longest = std::max(longest, label.size());
  }
  // Room at the left for the longest label, a minus sign included: 0.65 em a character is wider
  // than the digits of the usual sans-serif fonts (DejaVu Sans 0.64 em, Roboto 0.56 em).
  l.left = std::max(60.0, std::ceil(0.65 * l.font * static_cast<double>(longest)) + 8.0);
  l.right = l.left + 500.0;
  const double width = l.right + 20.0;
  l.title = l.bin == 1 ? 0.0 : 18.0;    // a panel's title line
  l.plot = l.bin == 1 ? 188.0 : 130.0;  // a panel's λ axis, px
  l.panel_height = l.title + l.plot + (l.bin == 1 ? 12.0 : 20.0);
  const double height = 12.0 + l.panel_height * static_cast<double>(panels.size()) + 18.0;
  l.w = (l.right - l.left) / static_cast<double>(l.bars);
  o_ << "<figure><svg id=\"" << id << "\" role=\"img\" viewBox=\"0 0 " << px(width) << " "
     << px(height) << "\" width=\"" << px(width) << "\" height=\"" << px(height)
     << "\" xmlns=\"http://www.w3.org/2000/svg\"><title>lambda per row within its bounds"
     << (l.bin == 1 ? "" : ", one panel per row kind") << "</title>\n";
  std::array<long, 3> at_bound{};
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const double top = 12.0 + l.panel_height * static_cast<double>(p) + l.title;
    if (panels[p]) {
      const auto n = rows_of_kind[static_cast<std::size_t>(*panels[p])];
      o_ << "<text class=\"panel\" x=\"" << px(l.left) << "\" y=\"" << px(top - 6.0)
         << "\" font-size=\"12\" font-weight=\"600\" fill=\"" << kind_colour(*panels[p]) << "\">"
         << to_string(*panels[p]) << " rows: " << n << " of " << c << "</text>";
    }
    bounds_panel(l, panels[p], axes[p], top, t, at_bound);
  }
  o_ << "<text x=\"" << px((l.left + l.right) / 2) << "\" y=\"" << px(height - 8.0)
     << "\" font-size=\"12\" text-anchor=\"middle\">row k (0 … " << c - 1
     << ")</text></svg><figcaption class=\"note\">";
  if (l.bin == 1) {
    o_ << "Bars: λ per row, coloured by kind; black dashes: finite bounds cmin, cmax; yellow "
       << "dots: rows at a bound.";
  } else {
    o_ << "One bar per " << l.bin << " consecutive rows (" << l.bars << " bars), in one panel per "
       << "row kind, each on its own scale: the range of λ and 0 over the bin's rows of that "
       << "kind; black dashes: the lowest finite cmin and highest finite cmax among them; yellow "
       << "dots: bins with a row of that kind at a bound (";
    bool first = true;
    for (const Panel& panel : panels) {
      o_ << (first ? "" : ", ") << at_bound[static_cast<std::size_t>(*panel)] << " "
         << to_string(*panel);
      first = false;
    }
    o_ << " rows in all).";
  }
  o_ << "</figcaption></figure>\n";
}

void Page::bounds_panel(const BoundsLayout& l,
                        const std::optional<RowKind>& panel,
                        const BoundsAxis& a,
                        double top,
                        const TeachingSystem& t,
                        std::array<long, 3>& at_bound) {
  const Eigen::Index c = t.lambda.size();
  const double bottom = top + l.plot;
  auto y_of = [&](double v) { return bottom - (bottom - top) * (v - a.lo) / (a.hi - a.lo); };
  const std::array<double, 3> ticks{a.lo, 0.0, a.hi};
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    if (i > 0 && ticks[i] == ticks[i - 1]) continue;  // 0 at an end of the axis: once
    o_ << "<line x1=\"" << px(l.left) << "\" x2=\"" << px(l.right) << "\" y1=\""
       << px(y_of(ticks[i])) << "\" y2=\"" << px(y_of(ticks[i])) << "\" stroke=\""
       << (ticks[i] == 0.0 ? "#333" : "#ddd") << "\"/><text x=\"" << px(l.left - 4) << "\" y=\""
       << px(y_of(ticks[i]) + 4) << "\" font-size=\"" << l.font << "\" text-anchor=\"end\">"
       << a.labels[i] << "</text>";
  }
  const Eigen::Index bin = l.bin;
  const double w = l.w;
  for (Eigen::Index j = 0; j < l.bars; ++j) {
    const Eigen::Index first = j * bin, last = std::min(c, first + bin);
    double l_lo = 0.0, l_hi = 0.0, b_lo = INFINITY, b_hi = -INFINITY;
    bool any = false, bound = false;
    for (Eigen::Index k = first; k < last; ++k) {
      if (!in_panel(sys_, panel, k)) continue;
      any = true;
      l_lo = std::min(l_lo, t.lambda(k));
      l_hi = std::max(l_hi, t.lambda(k));
      if (std::isfinite(t.cmin(k))) b_lo = std::min(b_lo, t.cmin(k));
      if (std::isfinite(t.cmax(k))) b_hi = std::max(b_hi, t.cmax(k));
      if (t.status[static_cast<std::size_t>(k)].at_bound()) {
        bound = true;
        ++at_bound[static_cast<std::size_t>(kind_of(sys_, k))];
      }
    }
    if (!any) continue;  // no row of this panel's kind in the bin
    const RowKind kind = panel ? *panel : kind_of(sys_, first);
    // One row: its bar runs from 0 to λ; a bin: over the range of its λ and 0.
    const double x = l.left + w * static_cast<double>(j);
    const double y_top = y_of(bin == 1 ? std::max(0.0, t.lambda(first)) : l_hi);
    const double y_bottom = y_of(bin == 1 ? std::min(0.0, t.lambda(first)) : l_lo);
    o_ << "<rect x=\"" << px(x + 0.1 * w) << "\" y=\"" << px(y_top) << "\" width=\"" << px(0.8 * w)
       << "\" height=\"" << px(std::max(0.5, y_bottom - y_top)) << "\" fill=\"" << kind_colour(kind)
       << "\"/>";
    for (double b : {b_lo, b_hi})
      if (std::isfinite(b))
        o_ << "<line x1=\"" << px(x) << "\" x2=\"" << px(x + w) << "\" y1=\"" << px(y_of(b))
           << "\" y2=\"" << px(y_of(b)) << "\" stroke=\"#000\" stroke-width=\"1.5\"/>";
    if (bound)
      o_ << "<circle cx=\"" << px(x + w / 2) << "\" cy=\""
         << px(bin == 1 ? y_of(t.lambda(first)) : y_top) << "\" r=\""
         << px(std::clamp(w / 3, 1.5, 5.0)) << "\" fill=\"#ffd23f\" stroke=\"#000\"/>";
  }
  o_ << "\n";
}

void Page::body_table(const std::string& id,
                      const std::vector<const VecX*>& vectors,
                      const std::vector<std::string>& names,
                      const std::vector<std::string>& units) {
  static const char* const coords[6] = {"x", "y", "z", "x", "y", "z"};
  o_ << "<div class=\"scroll\"><table id=\"" << id << "\"><thead><tr><th>body</th>";
  for (std::size_t v = 0; v < vectors.size(); ++v)
    for (int j = 0; j < 6; ++j)
      o_ << "<th>" << names[2 * v + (j < 3 ? 0 : 1)] << "<sub>" << coords[j] << "</sub> ("
         << units[2 * v + (j < 3 ? 0 : 1)] << ")</th>";
  o_ << "</tr></thead><tbody>\n";
  for (int blk = 0; blk < sys_.blocks(); ++blk) {
    o_ << "<tr><th class=\"row\">" << html_escape(s_.bodies[static_cast<std::size_t>(blk)])
       << "</th>";
    for (const VecX* v : vectors)
      for (int j = 0; j < 6; ++j) number_cell((*v)(6 * blk + j));
    o_ << "</tr>\n";
  }
  o_ << "</tbody></table></div>\n";
}

void Page::header() {
  const std::string title = html_escape(s_.scene) + ", step " + std::to_string(s_.step);
  o_ << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
     << "<meta name=\"generator\" content=\"" << kTeachingPageGenerator << "\">\n"
     << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
     << "<title>cbps explain: " << title << "</title>\n<style>" << kCss << "</style></head>\n"
     << "<body>\n<header><h1>" << title << ": the system of one step</h1>\n";
  int count[3] = {0, 0, 0};
  for (Eigen::Index k = 0; k < sys_.rows(); ++k) ++count[static_cast<int>(kind_of(sys_, k))];
  o_ << "<p>t = " << num(s_.t) << " s, Δt = " << num(sys_.dt)
     << " s; c = " << count_text(sys_.rows(), "row") << " (" << count[0] << " distance, "
     << count[1] << " contact, " << count[2]
     << " friction), n = " << count_text(sys_.blocks(), "movable body", "movable bodies")
     << " (6n = " << 6 * sys_.blocks() << " columns); solver " << html_escape(s_.method)
     << ". Push: "
     << (sys_.push == PushMode::Improved ? "improved, two systems with the same J, M⁻¹, A (8.1)"
                                         : "original, one system (5.2.3, 5.3)")
     << ". Numbers to " << kDigits << " significant digits.</p>\n"
     << "<p class=\"key\">Rows by kind: ";
  for (RowKind k : {RowKind::Distance, RowKind::Contact, RowKind::Friction})
    o_ << "<span><i style=\"background:" << kind_colour(k) << "\"></i>" << to_string(k)
       << "</span>";
  o_ << "</p>\n<nav><ul><li><a href=\"#J\">J</a></li><li><a href=\"#Minv\">M⁻¹</a></li>"
     << "<li><a href=\"#A\">A</a></li><li><a href=\"#spectrum\">eigenvalues</a></li>"
     << "<li><a href=\"#v1\">v₁, f<sub>ext</sub></a></li>";
  for (std::size_t i = 0; i < s_.systems.size(); ++i)
    o_ << "<li><a href=\"#system-" << i + 1 << "\">" << html_escape(s_.systems[i].name)
       << "</a></li>";
  o_ << "</ul></nav></header>\n";
}

void Page::jacobian() {
  o_ << "<section id=\"J\"><h2>J: the constraint Jacobian</h2>\n";
  equation(
      "J ∈ ℝ<sup>c×6n</sup>; row k is j<sub>c</sub> = [−nᵀ, −(r<sub>a</sub>×n)ᵀ, nᵀ, "
      "(r<sub>b</sub>×n)ᵀ] in the columns of its two bodies (5.1.3, 5.2.1, 6.1)");
  unit(
      "1 in the linear columns (v<sub>x</sub>, v<sub>y</sub>, v<sub>z</sub>), m in the "
      "angular ones (ω<sub>x</sub>, ω<sub>y</sub>, ω<sub>z</sub>). Static bodies have no "
      "columns (5.3).");
  o_ << "<dl class=\"stats\">";
  stat("size", std::to_string(sys_.rows()) + " × " + std::to_string(6 * sys_.blocks()));
  stat("nonzeros", std::to_string(sys_.J.nonZeros()));
  o_ << "</dl>\n";
  sparsity("svg-J",
           "Sparsity of J: a square per nonzero, rows coloured by kind, columns banded by body",
           SpMat(sys_.J),
           6,
           s_.bodies);
  // A wide J scrolls sideways, its row labels kept in view (th.row is sticky).
  if (sys_.rows() <= l_.dense_rows && sys_.blocks() <= l_.dense_bodies)
    matrix_table("table-J", MatX(sys_.J), true, s_.columns);
  else
    limit("J is " + std::to_string(sys_.rows()) + " × " + std::to_string(6 * sys_.blocks()) +
          ": its table is shown up to " + std::to_string(l_.dense_rows) + " rows and " +
          std::to_string(6 * l_.dense_bodies) + " columns (" + std::to_string(l_.dense_bodies) +
          " bodies); above that, the picture and counts. <code>cbps matrices</code> writes it "
          "whole.");
  o_ << "</section>\n";
}

void Page::mass() {
  o_ << "<section id=\"Minv\"><h2>M⁻¹: the inverse mass matrix</h2>\n";
  equation(
      "M⁻¹ = blockdiag(m<sub>i</sub>⁻¹ E<sub>3</sub>, I<sub>i</sub>⁻¹) (6.1.2), 6n × 6n, "
      "I<sub>i</sub>⁻¹ = R I<sub>body</sub>⁻¹ Rᵀ (3.1)");
  unit("m⁻¹ in kg⁻¹, I⁻¹ in kg⁻¹ m⁻². One row per movable body: its two diagonal blocks.");
  const int max_bodies = l_.dense_bodies;
  if (sys_.blocks() <= max_bodies) {
    const MatX Minv(sys_.Minv);
    static const int ij[6][2] = {{3, 3}, {4, 4}, {5, 5}, {3, 4}, {3, 5}, {4, 5}};
    static const char* const names[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
    o_ << "<div class=\"scroll\"><table id=\"table-Minv\"><thead><tr><th>body</th>"
       << "<th>m⁻¹ (kg⁻¹)</th>";
    for (const char* n : names) o_ << "<th>(I⁻¹)<sub>" << n << "</sub> (kg⁻¹ m⁻²)</th>";
    o_ << "</tr></thead><tbody>\n";
    for (int blk = 0; blk < sys_.blocks(); ++blk) {
      o_ << "<tr><th class=\"row\">" << html_escape(s_.bodies[static_cast<std::size_t>(blk)])
         << "</th>";
      number_cell(Minv(6 * blk, 6 * blk));
      for (const auto& e : ij) number_cell(Minv(6 * blk + e[0], 6 * blk + e[1]));
      o_ << "</tr>\n";
    }
    o_ << "</tbody></table></div>\n";
  } else {
    limit("The table of M⁻¹ is shown up to " + std::to_string(max_bodies) +
          " bodies; this "
          "step has " +
          std::to_string(sys_.blocks()) + ".");
  }
  o_ << "</section>\n";
}

void Page::system_matrix() {
  o_ << "<section id=\"A\"><h2>A: the system matrix</h2>\n";
  equation("A = J M⁻¹ Jᵀ (6.2.9), c × c, symmetric positive semidefinite");
  // Every row of this project is a force row (a unit vector in its linear part), so A is kg⁻¹
  // throughout; a row with only angular entries would be a torque row and mix the units.
  bool torque_rows = false;
  const SpMat Jt = SpMat(sys_.J.transpose());
  for (Eigen::Index k = 0; k < Jt.outerSize(); ++k) {
    bool linear = false, any = false;
    for (SpMat::InnerIterator it(Jt, k); it; ++it) {
      if (it.value() == 0.0) continue;
      any = true;
      if (it.row() % 6 < 3) linear = true;
    }
    torque_rows = torque_rows || (any && !linear);
  }
  unit(torque_rows ? "mixed: kg⁻¹ between force rows, kg⁻¹ m⁻¹ between a force and a torque "
                     "row, kg⁻¹ m⁻² between torque rows"
                   : "kg⁻¹ (every row is a force row, λ in N)");
  o_ << "<dl class=\"stats\">";
  stat("size", std::to_string(sys_.rows()) + " × " + std::to_string(sys_.rows()));
  stat("nonzeros", std::to_string(sys_.A.nonZeros()));
  if (sys_.rows() > 0) {
    const VecX d = VecX(sys_.A.diagonal());
    stat("diagonal A<sub>kk</sub>", num(d.minCoeff()) + " … " + num(d.maxCoeff()) + " kg⁻¹");
  }
  if (s_.cfm > 0.0)
    stat("cfm ε", num(s_.cfm) + " kg⁻¹: a solver setting; the solve used A + εE, A is shown");
  o_ << "</dl>\n";
  sparsity("svg-A",
           "Sparsity of A: rows k and l share a body where A_kl ≠ 0; coloured by row kind",
           sys_.A,
           0,
           {});
  if (sys_.rows() <= l_.dense_rows)
    matrix_table("table-A", MatX(sys_.A), true, sys_.labels);
  else
    limit("A is " + std::to_string(sys_.rows()) + " × " + std::to_string(sys_.rows()) +
          ": its table is shown up to " + std::to_string(l_.dense_rows) + " rows.");
  o_ << "</section>\n";
}

void Page::spectrum() {
  o_ << "<section id=\"spectrum\"><h2>Eigenvalues of A</h2>\n";
  equation(
      "A u<sub>i</sub> = σ<sub>i</sub> u<sub>i</sub>, 0 ≤ σ<sub>1</sub> ≤ … ≤ "
      "σ<sub>c</sub>; A u = 0 ⇔ Jᵀu = 0 (M⁻¹ is positive definite)");
  unit("kg⁻¹");
  if (sys_.rows() == 0) {
    note("No rows: A is empty.");
  } else if (sys_.rows() > l_.eigen_rows) {
    limit("The eigenvalues are computed up to " + std::to_string(l_.eigen_rows) +
          " rows (a dense eigen-solve costs c³); this step has " + std::to_string(sys_.rows()) +
          ".");
  } else {
    const Spectrum sp = spectrum_of(sys_.A);
    double smallest = INFINITY;
    for (Eigen::Index k = 0; k < sp.values.size(); ++k)
      if (sp.values(k) > sp.tolerance) smallest = std::min(smallest, sp.values(k));
    const double largest = sp.values.maxCoeff();
    o_ << "<dl class=\"stats\" id=\"spectrum-stats\">";
    stat("largest σ<sub>c</sub>", num(largest) + " kg⁻¹");
    stat("smallest nonzero σ", std::isfinite(smallest) ? num(smallest) + " kg⁻¹" : "none");
    if (std::isfinite(smallest))
      stat("ratio σ<sub>c</sub> / σ<sub>min&gt;0</sub>", num(largest / smallest));
    stat("null space dimension", std::to_string(sp.null_dimension));
    stat("zero tolerance",
         num(sp.tolerance) +
             " kg⁻¹ = c · ε · σ<sub>c</sub> (ε = 2<sup>−52</sup>): "
             "eigenvalues at or below it count as zero");
    o_ << "</dl>\n";
    std::vector<double> values(sp.values.data(), sp.values.data() + sp.values.size());
    log_plot("svg-spectrum",
             "Eigenvalues of A, ascending (hollow red circles at the bottom: zero within the "
             "tolerance)",
             values,
             "index i",
             "σ_i (kg⁻¹)",
             false,
             sp.tolerance,
             0.0,
             "");
    note(
        "Why this matters: projected Gauss-Seidel (7.1.1) removes the error along eigenvectors "
        "of large σ in a few sweeps and along those of small σ slowly, so the ratio "
        "σ<sub>c</sub>/σ<sub>min&gt;0</sub> sets how many sweeps it needs; in a stack it grows "
        "with the height, as each box's rows couple to those of the boxes above it. Directions "
        "u with σ = 0 (redundant rows, such as four contact points of a box on the ground) "
        "change λ without changing Jᵀλ: λ is not unique there, w and v₂ are.");
  }
  o_ << "</section>\n";
}

void Page::velocities() {
  o_ << "<section id=\"v1\"><h2>v₁ and f<sub>ext</sub>: the start of the step</h2>\n";
  equation(
      "v₁ = [v<sub>i</sub>; ω<sub>i</sub>] stacked over the movable bodies (6.1.1); "
      "f<sub>ext</sub> = [f<sub>i</sub> + m<sub>i</sub> g; τ<sub>i</sub>] (6.1.3)");
  unit("v in m/s, ω in rad/s, f in N, τ in N m");
  if (sys_.blocks() <= l_.dense_bodies)
    body_table(
        "table-v1", {&sys_.v1, &sys_.fext}, {"v₁", "ω₁", "f", "τ"}, {"m/s", "rad/s", "N", "N m"});
  else
    limit("The table is shown up to " + std::to_string(l_.dense_bodies) + " bodies.");
  o_ << "</section>\n";
}

void Page::one_system(const TeachingSystem& t, const std::string& id) {
  const Eigen::Index c = t.lambda.size();
  const bool dense = c <= l_.dense_rows;
  o_ << "<section id=\"system-" << id << "\"><h2>" << html_escape(t.name) << "</h2>\n";
  note(html_escape(t.note) + ".");

  o_ << "<h3>υ and b</h3>\n";
  equation("b = υ/Δt − J (v₁/Δt + M⁻¹ f<sub>ext</sub>) (6.2.9)");
  unit("υ in m/s (5.1.2, 6.1.4), b in m/s²");
  if (dense) {
    o_ << "<div class=\"scroll\"><table id=\"table-b-" << id << "\"><thead><tr><th>row</th>"
       << "<th>kind</th><th>υ (m/s)</th><th>b (m/s²)</th></tr></thead><tbody>\n";
    for (Eigen::Index k = 0; k < c; ++k) {
      row_head(k);
      o_ << "<td>" << to_string(kind_of(sys_, k)) << "</td>";
      number_cell(t.upsilon(k));
      number_cell(t.b(k));
      o_ << "</tr>\n";
    }
    o_ << "</tbody></table></div>\n";
  } else if (c > 0) {
    o_ << "<dl class=\"stats\">";
    stat("υ", num(t.upsilon.minCoeff()) + " … " + num(t.upsilon.maxCoeff()) + " m/s");
    stat("b", num(t.b.minCoeff()) + " … " + num(t.b.maxCoeff()) + " m/s²");
    o_ << "</dl>\n";
  }

  if (c == 0) {
    note("No rows: nothing to solve; v₂ = v₁ + Δt M⁻¹ f<sub>ext</sub> (12.3.1 with λ empty).");
  } else {
    solution(t, id);
  }

  o_ << "<h3>v₂: the velocities after the step</h3>\n";
  equation("v₂ = v₁ + Δt M⁻¹ (Jᵀλ + f<sub>ext</sub>) (12.3.1)");
  unit("v in m/s, ω in rad/s");
  if (sys_.blocks() <= l_.dense_bodies)
    body_table("table-v2-" + id, {&t.v2}, {"v₂", "ω₂"}, {"m/s", "rad/s"});
  else
    limit("The table is shown up to " + std::to_string(l_.dense_bodies) + " bodies.");
  o_ << "</section>\n";
}

void Page::solution(const TeachingSystem& t, const std::string& id) {
  o_ << "<h3>λ within its bounds, and w = Aλ − b</h3>\n";
  equation(
      "cmin ≤ λ ≤ cmax (5.1); w = Aλ − b (6.2): λ<sub>k</sub> = cmin<sub>k</sub> ⇒ "
      "w<sub>k</sub> ≥ 0, λ<sub>k</sub> = cmax<sub>k</sub> ⇒ w<sub>k</sub> ≤ 0, "
      "cmin<sub>k</sub> &lt; λ<sub>k</sub> &lt; cmax<sub>k</sub> ⇒ w<sub>k</sub> = 0");
  unit("λ, cmin, cmax in N; w in m/s²");
  solution_stats(t, id);
  bounds_picture("svg-lambda-" + id, t);
  solution_table(t, id);
  if (sys_.coulomb().any())
    note(
        "Coulomb friction rows: their bounds are ∓μ λ<sub>n</sub> at the fixed point λ "
        "satisfies (5.4).");
  if (sys_.cones() != nullptr)
    note(
        "Coulomb's cone (docs/cones.md): each contact's rows (normal, t1, t2) live in "
        "K<sub>μ</sub> = {‖λ<sub>t</sub>‖ ≤ μ λ<sub>n</sub>}, not in boxes, under the " +
        std::string(sys_.contacts.law == FrictionLaw::CoulombCone
                        ? "Coulomb law (De Saxcé's û = u + μ "
                          "‖u<sub>t</sub>‖ e<sub>n</sub>)"
                        : "convex relaxation (CCP)") +
        ": cmin and cmax of those rows are not used; a contact is separated (λ = 0), sticking "
        "(λ inside the cone, û = 0) or sliding (λ on its surface, opposing u<sub>t</sub>), "
        "and meets its law when ‖λ − P<sub>K</sub>(λ − û)‖ is within the tolerance.");

  residual_per_sweep(t, id);
}

void Page::solution_stats(const TeachingSystem& t, const std::string& id) {
  int at_min = 0, at_max = 0, fixed = 0, free = 0, missed = 0;
  for (const RowStatus& s : t.status) {
    if (s.where == "at cmin") ++at_min;
    if (s.where == "at cmax") ++at_max;
    if (s.where == "at cmin = cmax") ++fixed;
    if (s.where == "free") ++free;
    if (!s.satisfied) ++missed;
  }
  o_ << "<dl class=\"stats\" id=\"status-" << id << "\">";
  stat("free", std::to_string(free));
  stat("at cmin", std::to_string(at_min));
  stat("at cmax", std::to_string(at_max));
  if (fixed > 0) stat("at cmin = cmax", std::to_string(fixed));
  if (sys_.cones() != nullptr) {
    for (const char* state : {"separated", "sticking", "sliding"}) {
      long contacts = 0;
      for (long i = 0; i < sys_.contacts.contacts(); ++i)
        if (t.status[static_cast<std::size_t>(sys_.contacts.normal[static_cast<std::size_t>(i)])]
                .where == std::string("cone: ") + state)
          ++contacts;
      stat(std::string("contacts ") + state + " (cone)", std::to_string(contacts));
    }
  }
  stat("rows missing their condition", std::to_string(missed));
  {
    // The rows are judged against the tolerance the scene asks for, not the residual the solve
    // reached (teaching_page.cpp).
    std::string judged = num(t.tolerance) + " N, the residual the scene asks for";
    if (t.rounding_floor > t.tolerance)
      judged += ", raised to " + num(t.rounding_floor) +
                " N, the rounding floor of w = Aλ − b (64 u (max<sub>i</sub> Σ<sub>k</sub> "
                "|A<sub>ik</sub>| ‖λ‖<sub>∞</sub> + ‖b‖<sub>∞</sub>))";
    if (s_.cfm > 0.0) judged += ", plus ε |λ<sub>k</sub>| per row (the solve met (A + εE) λ = b)";
    stat("tolerance", judged);
  }
  stat("residual",
       num(t.summary.residual) + " N, the solve's" +
           (t.summary.residual > std::max(t.tolerance, t.rounding_floor)
                ? std::string(": above the tolerance, so rows can miss their condition")
                : std::string()));
  stat("solver", html_escape(s_.method) + ": " + html_escape(t.summary.message));
  o_ << "</dl>\n";
}

void Page::solution_table(const TeachingSystem& t, const std::string& id) {
  const Eigen::Index c = t.lambda.size();
  const bool dense = c <= l_.dense_rows;
  if (dense) {
    o_ << "<div class=\"scroll\"><table id=\"table-lambda-" << id << "\"><thead><tr>"
       << "<th>row</th><th>cmin (N)</th><th>λ (N)</th><th>cmax (N)</th><th>w (m/s²)</th>"
       << "<th>status</th></tr></thead><tbody>\n";
    for (Eigen::Index k = 0; k < c; ++k) {
      const RowStatus& s = t.status[static_cast<std::size_t>(k)];
      o_ << "<tr class=\"" << to_string(kind_of(sys_, k)) << (s.at_bound() ? " at-bound" : "")
         << (s.satisfied ? "" : " miss") << "\"><th class=\"row\">"
         << html_escape(sys_.labels[static_cast<std::size_t>(k)]) << "</th>";
      number_cell(t.cmin(k));
      number_cell(t.lambda(k), "lambda");
      number_cell(t.cmax(k));
      number_cell(t.w(k));
      o_ << "<td class=\"status\">" << (s.at_bound() ? "● " : "") << s.where
         << (s.satisfied ? "" : " (w violates it)") << "</td></tr>\n";
    }
    o_ << "</tbody></table></div>\n";
  } else {
    limit("The table of λ, bounds and w is shown up to " + std::to_string(l_.dense_rows) +
          " rows; this system has " + std::to_string(c) + ": the picture and counts above.");
  }
}

void Page::residual_per_sweep(const TeachingSystem& t, const std::string& id) {
  o_ << "<h3>Residual per sweep</h3>\n";
  equation(
      "r = ‖λ − clamp(λ − w, cmin, cmax)‖<sub>∞</sub> (the natural-map residual, zero "
      "exactly at a solution of 6.2)");
  unit("N, as the solver reports it");
  if (t.sweep_residuals.size() <= 1) {
    // The guess already meets the tolerance: the solver stops before its first sweep and there
    // is no curve to draw.
    note("<span id=\"no-sweeps-" + id + "\">No sweep: the step's guess (sweep 0; the warm " +
         "start of 7 where the scene has one) already meets the tolerance, its residual " +
         (t.sweep_residuals.empty() ? std::string("—") : num(t.sweep_residuals.front())) + " N ≤ " +
         num(s_.solver_tolerance) + " N, so " + html_escape(t.sweep_method) +
         " stops before its first sweep: λ is the guess, and there is no curve to draw.</span>");
    return;
  }
  log_plot("svg-residual-" + id,
           "Residual after each sweep of " + t.sweep_method + " from the step's guess (sweep 0)",
           t.sweep_residuals,
           "sweep",
           "r (N)",
           true,
           0.0,
           s_.solver_tolerance,
           "tolerance");
  note(html_escape(t.sweep_method) +
       " run again on the whole system (islands not split) from "
       "the step's own guess, " +
       count_text(static_cast<long>(t.sweep_residuals.size()) - 1, "sweep") +
       (t.sweep_method != s_.method
            ? std::string(": the system above is solved by ") + html_escape(s_.method) +
                  ", which does not sweep, so " + html_escape(t.sweep_method) +
                  (t.sweep_method == to_string(kPaperMethod) ? std::string(" (7.1.1)")
                                                             : std::string()) +
                  " is shown beside it"
            : std::string()) +
       ". The residual of the answer shown is the one in the statistics above.");
}

void Page::footer() {
  const std::string command = !s_.command.empty() ? s_.command
                                                  : "cbps explain " + s_.scene + " --step " +
                                                        std::to_string(s_.step) + " --html FILE";
  o_ << "<footer><p class=\"note\">Written by <code>" << html_escape(command)
     << "</code>, which writes it again. Tables give way to pictures and counts above "
     << l_.dense_rows << " rows (the tables of J, M⁻¹ and v also above " << l_.dense_bodies
     << " bodies); eigenvalues are computed up to " << l_.eigen_rows
     << " rows. Equation numbers are those of Tamis &amp; Maggiore (2015).</p></footer>\n"
     << "</body></html>\n";
}

std::string Page::render() {
  header();
  jacobian();
  mass();
  system_matrix();
  spectrum();
  velocities();
  for (std::size_t i = 0; i < s_.systems.size(); ++i)
    one_system(s_.systems[i], std::to_string(i + 1));
  footer();
  return o_.str();
}

}  // namespace

std::string teaching_page_html(const TeachingStep& step, const TeachingLimits& limits) {
  Page page(step, limits);
  return page.render();
}

}  // namespace cbps
