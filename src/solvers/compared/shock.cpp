// Shock propagation order: the layers of the contact graph from J's pattern, and 7.1.1 over the
// rows level by level from the ground up. The method and its sources are described in shock.hpp.
#include "cbps/solvers/compared/shock.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "../sweep.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"

namespace cbps {

namespace {

constexpr Eigen::Index kBlock = 6;  ///< columns of one body in J: [v_i; ω_i] (6.1.1)

/// The bodies row k of J acts on (a nonzero entry in their 6-column block), in column order.
void bodies_of_row(const SpMatRow& J, Eigen::Index k, std::vector<int>& out) {
  out.clear();
  for (SpMatRow::InnerIterator it(J, k); it; ++it) {
    if (it.value() == 0.0) continue;
    const int body = static_cast<int>(it.col() / kBlock);
    if (out.empty() || out.back() != body) out.push_back(body);
  }
}

}  // namespace

ContactLayers contact_layers(const SpMatRow& J) {
  if (J.cols() % kBlock != 0)
    throw std::invalid_argument("contact_layers: J's columns are not 6-column body blocks");
  const auto c = static_cast<std::size_t>(J.rows());
  const auto n = static_cast<std::size_t>(J.cols() / kBlock);
  ContactLayers g;
  g.layer.assign(n, -1);

  // The bodies of each row, and for each body the rows touching it.
  std::vector<std::vector<int>> bodies(c);
  std::vector<std::vector<int>> rows_of(n);
  for (std::size_t k = 0; k < c; ++k) {
    bodies_of_row(J, Eigen::Index(k), bodies[k]);
    for (const int body : bodies[k]) rows_of[std::size_t(body)].push_back(int(k));
  }

  // Breadth-first search over the rows from the bodies in `queue` (layers already set):
  // a body reached through a row from a body of layer L is in layer L + 1.
  std::vector<int> queue;
  auto spread = [&](std::size_t head) {
    for (; head < queue.size(); ++head) {
      const int body = queue[head];
      for (const int k : rows_of[std::size_t(body)]) {
        for (const int other : bodies[std::size_t(k)]) {
          if (g.layer[std::size_t(other)] >= 0) continue;
          g.layer[std::size_t(other)] = g.layer[std::size_t(body)] + 1;
          queue.push_back(other);
        }
      }
    }
  };
  int next_layer = 0;  // one past the highest layer used so far
  auto highest = [&](std::size_t head) {
    for (std::size_t m = head; m < queue.size(); ++m) {
      const int body = queue[m];
      next_layer = std::max(next_layer, g.layer[std::size_t(body)] + 1);
    }
  };

  // Layer 0: the bodies a row rests on the world (a row with one body).
  for (std::size_t k = 0; k < c; ++k) {
    if (bodies[k].size() != 1) continue;
    const int body = bodies[k].front();
    if (g.layer[std::size_t(body)] >= 0) continue;
    g.layer[std::size_t(body)] = 0;
    queue.push_back(body);
  }
  spread(0);
  highest(0);
  g.grounded = next_layer;

  // Groups touching the world nowhere: layered after, each from its lowest body.
  for (std::size_t body = 0; body < n; ++body) {
    if (g.layer[body] >= 0 || rows_of[body].empty()) continue;
    g.layer[body] = next_layer;
    const std::size_t head = queue.size();
    queue.push_back(int(body));
    spread(head);
    highest(head);
  }

  // Each row's level: the higher layer of its bodies (0 for a row acting on no body).
  g.level.assign(c, 0);
  for (std::size_t k = 0; k < c; ++k)
    for (const int body : bodies[k]) g.level[k] = std::max(g.level[k], g.layer[std::size_t(body)]);
  g.levels = c == 0 ? 0 : *std::max_element(g.level.begin(), g.level.end()) + 1;

  // The rows grouped by level, natural order within a level (a counting sort).
  g.start.assign(static_cast<std::size_t>(g.levels) + 1, 0);
  for (const int level : g.level) ++g.start[std::size_t(level) + 1];
  for (std::size_t l = 1; l < g.start.size(); ++l) g.start[l] += g.start[l - 1];
  g.order.resize(c);
  std::vector<int> next(g.start.begin(), g.start.end() - 1);
  for (std::size_t k = 0; k < c; ++k)
    g.order[std::size_t(next[std::size_t(g.level[k])]++)] = int(k);
  return g;
}

SolverSummary solve_shock(const BoxedProblem& problem,
                          VecX& lambda,
                          const SolverOptions& options,
                          const ShockSettings& settings) {
  if (problem.J == nullptr)
    throw std::invalid_argument(
        "solver 'shock' takes its layers from J's bodies: the problem has no J");
  if (settings.level_sweeps < 1)
    throw std::invalid_argument("solver 'shock': level_sweeps must be at least 1");
  const ContactLayers g = contact_layers(*problem.J);
  // Each level's rows, in the order the levels are visited: 0, 1, … (bottom-up) or the reverse.
  std::vector<std::vector<int>> level_rows;
  for (int l = 0; l < g.levels; ++l)
    level_rows.emplace_back(g.order.begin() + g.start[std::size_t(l)],
                            g.order.begin() + g.start[std::size_t(l) + 1]);
  if (settings.top_down) std::reverse(level_rows.begin(), level_rows.end());
  std::vector<int> order;  // one sweep's rows, level by level
  for (const std::vector<int>& rows : level_rows)
    order.insert(order.end(), rows.begin(), rows.end());
  SolverSummary s = detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) {
    if (settings.level_sweeps == 1)
      return pgs_sweep(problem, l, options.relaxation, order);  // 7.1.1, level by level
    double delta = 0.0;
    for (const std::vector<int>& rows : level_rows)
      for (int sweep = 0; sweep < settings.level_sweeps; ++sweep)
        max_keep_nan(delta, pgs_sweep(problem, l, options.relaxation, rows));
    return delta;
  });
  if (options.describe) {
    std::ostringstream msg;
    msg << ", " << g.levels << " levels (" << g.grounded << " layers on the ground)"
        << (settings.top_down ? ", top down" : "");
    if (settings.level_sweeps > 1) msg << ", " << settings.level_sweeps << " sweeps a level";
    s.message += msg.str();
  }
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

namespace {

SolverSummary shock_method(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_shock(p, lambda, o, o.methods.shock);
}

}  // namespace

/// shock's own keys (`--solver NAME:key=value`, /solver/parameters), over its settings
/// (method_settings.hpp).
constexpr MethodKey kShockKeys[] = {
    {"level_sweeps",
     "a whole number >= 1",
     [](const std::string& v, MethodSettings& s) { return key_count(v, s.shock.level_sweeps); },
     [](const MethodSettings& s) -> std::string { return std::to_string(s.shock.level_sweeps); }},
    {"direction",
     "up or down",
     [](const std::string& v, MethodSettings& s) {
       if (v != "up" && v != "down") return false;
       s.shock.top_down = v == "down";
       return true;
     },
     [](const MethodSettings& s) -> std::string { return s.shock.top_down ? "down" : "up"; }},
};

extern const MethodEntry kShockEntry;
constexpr MethodEntry kShockEntry{
    .method = Method::Shock,
    .name = "shock",
    .omega = true,
    .needs_jacobian = true,
    .sweeps_alone = true,
    .solve = shock_method,
    .what =
        "PGS level by level from the ground up (Guendelman, Bridson & Fedkiw 2003); "
        "level_sweeps=, direction=up|down",
    .keys = kShockKeys,
};

}  // namespace cbps
