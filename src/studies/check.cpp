// A given lambda judged against a stored problem (studies/check.hpp).
#include "cbps/studies/check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/base/friction_law.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/lcp.hpp"
#include "cbps/studies/solver_spec.hpp"

namespace cbps {

namespace {

/// The row's label from labels.json, else "row k" (or "contact i" for contact i's normal row).
std::string label_of(const StoredProblem& p, long row, long contact = -1) {
  if (p.labels.size() == static_cast<std::size_t>(p.rows())) return p.labels[std::size_t(row)];
  return contact >= 0 ? "contact " + std::to_string(contact) : "row " + std::to_string(row);
}

/// A row's status: where lambda_k is in [cmin_k, cmax_k], to within delta (N).
std::string row_status(double lambda, double cmin, double cmax, double delta) {
  if (lambda < cmin - delta || lambda > cmax + delta) return "outside bounds";
  if (cmin == -kInf && cmax == kInf) return "free";
  if (std::abs(lambda - cmin) <= delta) return "at cmin";
  if (std::abs(lambda - cmax) <= delta) return "at cmax";
  return "between";
}

/// A contact's status: where r is in Coulomb's cone K_mu, to within delta (N).
std::string contact_status(const Vec3& r, double mu, double delta) {
  const double tangential = r.tail<2>().norm();
  if (r.norm() <= delta) return "separated";
  if (std::max(tangential - mu * r(0), -r(0)) > delta) return "outside cone";
  return tangential < mu * r(0) - delta ? "sticking" : "sliding";
}

/// lambda* by direct, and the distances of lambda from it (check.hpp).
ExactDistance exact_distance(const StoredProblem& p,
                             const VecX& lambda,
                             const UnitFreeTerms& terms,
                             const CheckSettings& s) {
  ExactDistance d;
  const SolverSpec spec = parse_solver_spec(std::string(to_string(kExactMethod)));
  try {
    check_applicable(spec, p, "the problem");
  } catch (const InputError& e) {
    d.why = e.what();
    return d;
  }
  const auto start = std::chrono::steady_clock::now();
  LcpOutcome r;
  try {
    r = solve_stored(spec, p, s.iterations, s.tolerance, s.time_limit);
  } catch (const InputError& e) {  // the given lambda is still judged
    d.why = e.what();
    return d;
  } catch (const ComputationError& e) {
    d.why = e.what();
    return d;
  }
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const UnitFreeResidual u = unit_free_residual(p.problem(), r.lambda, p.cfm);
  d.relative = u.relative;
  if (!is_solved(u, r.lambda)) {
    d.status = "failed";
    d.why = std::string(to_string(kExactMethod)) + " did not solve it: unit-free residual " +
            number_text(u.relative) + " (" + r.message + ")";
    return d;
  }
  d.available = true;
  d.status = "solved";
  const UnitFreeTerms exact = unit_free_terms(p.problem(), r.lambda, p.cfm);
  const VecX dw = terms.w - exact.w;
  d.w_distance = dw.lpNorm<Eigen::Infinity>();
  if (dw.size() > 0)
    d.w_distance_relative =
        unit_free_of((terms.rho.array() * dw.array().abs()).maxCoeff(), terms.scale).relative;
  const VecX dl = lambda - r.lambda;
  d.lambda_distance = dl.lpNorm<Eigen::Infinity>();
  if (p.has_jacobian()) d.force_distance = VecX(p.J.transpose() * dl).lpNorm<Eigen::Infinity>();
  return d;
}

}  // namespace

CheckReport check_lambda(const StoredProblem& p, const VecX& lambda, const CheckSettings& s) {
  if (lambda.size() != p.rows())
    throw InputError("lambda has " + std::to_string(lambda.size()) + " entries; the problem has " +
                     std::to_string(p.rows()) + " rows");
  for (Eigen::Index k = 0; k < lambda.size(); ++k)
    if (!std::isfinite(lambda(k)))
      throw InputError("lambda entry " + std::to_string(k + 1) + " is not finite");
  CheckReport r;
  r.rows = p.rows();
  r.contacts = p.cones.contacts();
  r.law = p.cones.law;
  const BoxedProblem problem = p.problem();
  const UnitFreeTerms terms = unit_free_terms(problem, lambda, p.cfm);
  r.unit_free = unit_free_residual(problem, lambda, p.cfm);
  r.solved = is_solved(r.unit_free, lambda);
  r.natural_map = natural_map_residual(terms.w, lambda, p.cmin, p.cmax, p.cones);
  if (!p.cones.empty()) r.cone = cone_measures(p.cones, lambda, terms.w, p.b);

  // Each row no contact owns, and each contact, with its status; then the largest terms.
  const double delta = kSolvedTolerance * terms.scale;  // "at a bound" to within the verdict's
  std::vector<CheckedTerm> all;
  std::vector<char> in_cone(std::size_t(p.rows()), 0);
  for (long i = 0; i < p.cones.contacts(); ++i) {
    const int n = p.cones.normal[std::size_t(i)];
    CheckedTerm t{
        n, i, label_of(p, n, i), "", terms.term(n), lambda.segment<3>(n), terms.w.segment<3>(n)};
    t.status = contact_status(lambda.segment<3>(n), p.cones.mu(i), delta);
    all.push_back(t);
    in_cone[std::size_t(n)] = in_cone[std::size_t(n + 1)] = in_cone[std::size_t(n + 2)] = 1;
  }
  for (long k = 0; k < p.rows(); ++k) {
    if (in_cone[std::size_t(k)]) continue;
    all.push_back({k,
                   -1,
                   label_of(p, k),
                   row_status(lambda(k), p.cmin(k), p.cmax(k), delta),
                   terms.term(k),
                   lambda.segment<1>(k),
                   terms.w.segment<1>(k)});
  }
  for (const CheckedTerm& t : all) ++r.statuses[t.status];
  const std::size_t worst = std::min(all.size(), std::size_t(std::max(0, s.worst)));
  std::partial_sort(all.begin(),
                    all.begin() + long(worst),
                    all.end(),
                    [](const CheckedTerm& a, const CheckedTerm& b) {
                      return a.residual > b.residual || (a.residual == b.residual && a.row < b.row);
                    });
  r.worst.assign(all.begin(), all.begin() + long(worst));
  if (s.exact) r.exact = exact_distance(p, lambda, terms, s);
  return r;
}

nlohmann::json check_json(const std::string& problem, const CheckReport& r) {
  const auto vec = [](const VecX& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  nlohmann::json j;
  j["problem"] = problem;
  j["rows"] = r.rows;
  j["contacts"] = r.contacts;
  j["law"] = r.contacts > 0 ? nlohmann::json(cone_law_name(r.law)) : nlohmann::json(nullptr);
  j["solved"] = r.solved;
  j["tolerance"] = kSolvedTolerance;
  j["unit_free"] = {{"relative", r.unit_free.relative},
                    {"residual", r.unit_free.residual},
                    {"scale", r.unit_free.scale}};
  j["natural_map"] = r.natural_map;
  j["cone"] = nullptr;
  if (r.cone)
    j["cone"] = {{"natural_map", r.cone->natural_map},
                 {"signorini", r.cone->signorini},
                 {"violation", r.cone->violation},
                 {"dissipation", r.cone->dissipation},
                 {"fclib_merit", r.cone->fclib_merit},
                 {"siconos_error", r.cone->siconos_error}};
  j["statuses"] = r.statuses;
  j["worst"] = nlohmann::json::array();
  for (const CheckedTerm& t : r.worst)
    j["worst"].push_back(
        {{"row", t.row},
         {"contact", t.contact < 0 ? nlohmann::json(nullptr) : nlohmann::json(t.contact)},
         {"label", t.label},
         {"status", t.status},
         {"residual", t.residual},
         {"relative", unit_free_of(t.residual, r.unit_free.scale).relative},
         {"lambda", vec(t.lambda)},
         {"w", vec(t.w)}});
  j["exact"] = nullptr;
  if (r.exact) {
    const ExactDistance& e = *r.exact;
    nlohmann::json x = {{"method", std::string(to_string(kExactMethod))},
                        {"available", e.available},
                        {"status", e.status},
                        {"relative", e.relative},
                        {"seconds", e.seconds}};
    if (e.available) {
      x["w_distance"] = e.w_distance;
      x["w_distance_relative"] = e.w_distance_relative;
      x["lambda_distance"] = e.lambda_distance;
      x["force_distance"] = e.force_distance ? nlohmann::json(*e.force_distance) : nullptr;
    } else {
      x["why"] = e.why;
    }
    j["exact"] = x;
  }
  return j;
}

std::string check_text(const std::string& problem, const CheckReport& r) {
  std::ostringstream out;
  out << problem << ": " << r.rows << " rows";
  if (r.contacts > 0)
    out << ", " << r.contacts << " contacts in cones (" << cone_law_name(r.law) << ")";
  out << "\n"
      << (r.solved ? "solved" : "not solved") << ": " << unit_free_text(r.unit_free) << "\n"
      << "natural map " << number_text(r.natural_map) << " N (unit step, infinity norm)\n";
  if (r.cone) out << cone_measures_text(r.law, r.contacts, *r.cone) << "\n";
  out << "statuses:";
  for (const auto& [status, count] : r.statuses) out << " " << count << " " << status << ";";
  out << "\n";
  if (!r.worst.empty()) out << "largest terms (N, relative, status, label: lambda | w):\n";
  for (const CheckedTerm& t : r.worst) {
    out << "  " << number_text(t.residual) << "  "
        << number_text(unit_free_of(t.residual, r.unit_free.scale).relative) << "  " << t.status
        << "  " << t.label << ":";
    for (Eigen::Index k = 0; k < t.lambda.size(); ++k) out << " " << number_text(t.lambda(k));
    out << " |";
    for (Eigen::Index k = 0; k < t.w.size(); ++k) out << " " << number_text(t.w(k));
    out << "\n";
  }
  if (r.exact) {
    const ExactDistance& e = *r.exact;
    if (!e.available) {
      out << "distance from the exact answer: not measured; " << e.why << "\n";
    } else {
      out << "distance from the exact answer (" << to_string(kExactMethod)
          << ", unit-free residual " << number_text(e.relative) << ", " << number_text(e.seconds)
          << " s): |w - w*| = " << number_text(e.w_distance) << " ("
          << number_text(e.w_distance_relative)
          << " unit-free), |lambda - lambda*| = " << number_text(e.lambda_distance) << " N";
      if (e.force_distance)
        out << ", |J^T (lambda - lambda*)| = " << number_text(*e.force_distance);
      out << "\n";
    }
  }
  return out.str();
}

}  // namespace cbps
