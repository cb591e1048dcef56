// The row stage of a step (paper 5.2–5.4): distance constraints and contact manifolds → rows.
#pragma once

#include <vector>

#include "cbps/collision/collision.hpp"
#include "cbps/rows/distance.hpp"
#include "cbps/rows/friction.hpp"

namespace cbps {

/// What the rows of a step are built with (from the scene's World).
struct RowSettings {
  double beta = 0.2;        ///< push factor (5.2.3, 5.3), in [0, 1]
  double dt = 1.0 / 240.0;  ///< time step, s
  double mu = 0.0;          ///< friction coefficient (5.4); 0: no friction rows
  FrictionLaw friction = FrictionLaw::PaperBox;  ///< how friction rows are bounded
  Vec3 gravity{0.0, -9.81, 0.0};                 ///< g, m/s² (the paper's friction bound)
  double restitution = 0.0;                      ///< epsilon of 8.2.1
  double restitution_threshold = 0.1;            ///< approach speed below which no bounce, m/s
};

/// The rows of the current state, into `rows` (storage reused): the distance rows (5.2) in
/// constraint order (row k has id k), then for each contact manifold (4) and point its contact
/// row (5.3) and, when mu > 0, its two friction rows (5.4) along tangent_basis(n). Each row
/// carries its velocity bias (upsilon) and its push term (upsilon_push) apart; which system the
/// push enters is decided at assembly (PushMode). A contact row with friction rows carries its
/// contact's mu and law, each friction row its contact row (normal_row); the friction rows'
/// bounds are the paper's (5.4), 0 under Coulomb's box until the solve sets them, (−∞, ∞) in a
/// cone.
void build_rows(const std::vector<Body>& bodies,
                const std::vector<DistanceConstraint>& distances,
                const std::vector<Manifold>& manifolds,
                const RowSettings& settings,
                std::vector<Row>& rows);

}  // namespace cbps
