// Performance profiles (Dolan & Moré 2002): ratios to the best solver and their distribution.
#include "cbps/studies/performance_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cbps {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// A cost that counts as solved: finite (a failure is +inf or NaN).
bool solved(double cost) { return std::isfinite(cost); }

}  // namespace

CostTable performance_ratios(const CostTable& cost) {
  CostTable ratios;
  ratios.reserve(cost.size());
  for (const std::vector<double>& row : cost) {
    if (row.size() != cost.front().size())
      throw std::invalid_argument("performance_ratios: problems with different solver counts");
    double best = kInfinity;  // min_s t_{p,s} over the solvers that solved p
    for (const double t : row) {
      if (t < 0.0) throw std::invalid_argument("performance_ratios: a negative cost");
      if (solved(t)) best = std::min(best, t);
    }
    std::vector<double> r(row.size(), kInfinity);
    for (std::size_t s = 0; s < row.size(); ++s) {
      if (!solved(row[s]) || !solved(best)) continue;
      // r_{p,s} = t_{p,s} / min_s' t_{p,s'} (section 2); 0/0 is a tie at the best, 1.
      r[s] = best > 0.0 ? row[s] / best : (row[s] == 0.0 ? 1.0 : kInfinity);
    }
    ratios.push_back(std::move(r));
  }
  return ratios;
}

double performance_fraction(const CostTable& ratios, std::size_t solver, double tau) {
  if (ratios.empty()) return 0.0;
  std::size_t within = 0;  // |{p : r_{p,s} <= tau}|, a failure (r_M) never within
  for (const std::vector<double>& r : ratios)
    if (std::isfinite(r.at(solver)) && r.at(solver) <= tau) ++within;
  return static_cast<double>(within) / static_cast<double>(ratios.size());
}

}  // namespace cbps
