// Step schemes beside the paper's: what each changes in a substep (scheme.hpp).
#include "cbps/step/scheme.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cbps {

double substep_dt(const World& world) {
  return world.dt / static_cast<double>(std::max(1, world.scheme.substeps));
}

PushMode scheme_push(const World& world) {
  switch (world.scheme.kind) {
    case Scheme::SoftStep:
      return PushMode::Improved;  // soft push system, then the rigid relax (8.1's two systems)
    case Scheme::Xpbd:
      return PushMode::Original;  // one system; its v2 both moves and is kept
    case Scheme::Paper:
    case Scheme::Tgs:
      break;
  }
  return world.push;
}

RowSettings substep_row_settings(const World& world) {
  RowSettings settings = world.rows();
  settings.dt = substep_dt(world);
  const Scheme kind = world.scheme.kind;
  if (kind == Scheme::SoftStep || kind == Scheme::Xpbd) settings.beta = 1.0;  // the whole C / h
  return settings;
}

SoftRow soft_row(double hertz, double zeta, double h) {
  if (!(hertz > 0.0)) return {};                        // rigid: no push, no softness
  const double omega = 2.0 * std::numbers::pi * hertz;  // rad/s
  const double a = h * omega * (2.0 * zeta + h * omega);
  return {h * omega / (2.0 * zeta + h * omega), 1.0 / a};
}

double contact_hertz(const SchemeSettings& s, double h) {
  return std::min(s.contact_hertz, 0.25 / h);
}

namespace {

/// A row against the world or a static body (one block): Box2D v3's staticSoftness, twice the
/// contact hertz.
bool against_static(const Row& row) { return row.body_a < 0 || row.body_b < 0; }

SoftRow contact_soft_row(const SchemeSettings& s, const Row& row, double h) {
  const double hertz = contact_hertz(s, h) * (against_static(row) ? 2.0 : 1.0);
  return soft_row(hertz, s.contact_damping_ratio, h);
}

/// The soft step softens a contact at depth ≥ 0 and a distance row; gaps and friction stay rigid.
bool soft_step_softens(const Row& row) {
  return row.kind == RowKind::Distance || (row.kind == RowKind::Contact && row.depth >= 0.0);
}

}  // namespace

void scheme_rows(const World& world, std::vector<Row>& rows) {
  if (world.scheme.kind != Scheme::SoftStep) return;
  const SchemeSettings& s = world.scheme;
  const double h = substep_dt(world);
  const SoftRow joint = soft_row(s.joint_hertz, s.joint_damping_ratio, h);
  for (Row& row : rows) {
    if (!soft_step_softens(row)) continue;
    if (row.kind == RowKind::Distance) {
      row.upsilon_push *= joint.beta;  // −beta_j C / h (5.2.3 with the soft beta)
    } else {
      const double beta = contact_soft_row(s, row, h).beta;
      row.upsilon_push = std::min(beta * row.upsilon_push, s.max_push_speed);  // beta_c d / h
    }
  }
}

VecX scheme_softness(const World& world, const std::vector<Row>& rows, const System& sys) {
  const SchemeSettings& s = world.scheme;
  const double h = substep_dt(world);
  if (!scheme_softens(world)) return {};
  VecX gamma = VecX::Zero(sys.rows());
  const SoftRow joint = soft_row(s.joint_hertz, s.joint_damping_ratio, h);
  for (int k = 0; k < sys.rows(); ++k) {
    const Row& row = rows[static_cast<std::size_t>(k)];
    if (s.kind == Scheme::Xpbd) {
      if (row.kind != RowKind::Friction) gamma(k) = s.compliance / (h * h);  // alpha / h², kg⁻¹
      continue;
    }
    if (!soft_step_softens(row)) continue;
    const SoftRow soft = row.kind == RowKind::Distance ? joint : contact_soft_row(s, row, h);
    gamma(k) = soft.gamma_per_A_kk * sys.A.coeff(k, k);  // kg⁻¹
  }
  return gamma;
}

bool scheme_softens(const World& world) {
  const SchemeSettings& s = world.scheme;
  return s.kind == Scheme::SoftStep || (s.kind == Scheme::Xpbd && s.compliance > 0.0);
}

}  // namespace cbps
