// The divergence guard (guard.hpp).
#include "cbps/step/guard.hpp"

#include <cmath>
#include <sstream>

#include "cbps/base/error.hpp"

namespace cbps {

namespace {

/// The body of a row: the first movable body its j_c acts on, −1 if none.
int body_of_row(const System& sys, int k) {
  for (SpMatRow::InnerIterator it(sys.J, k); it; ++it)
    return sys.body_of_block[static_cast<std::size_t>(it.col() / 6)];
  return -1;
}

/// The row whose impulse on column block `blk` is largest, |lambda_k| ‖j_k restricted to the
/// block‖, −1 if no row acts on it: the row a diverging body is most likely driven by.
int strongest_row_on(const System& sys, const VecX& lambda, int blk) {
  int best = -1;
  double largest = -1.0;
  for (int k = 0; k < sys.rows(); ++k) {
    double norm2 = 0.0;
    for (SpMatRow::InnerIterator it(sys.J, k); it; ++it)
      if (it.col() / 6 == blk) norm2 += it.value() * it.value();
    if (norm2 == 0.0) continue;
    const double impulse = std::abs(lambda(k)) * std::sqrt(norm2);
    if (!(impulse <= largest)) {  // NaN wins: it is the row to name
      largest = impulse;
      best = k;
    }
  }
  return best;
}

}  // namespace

void check_divergence(const System& sys,
                      const std::vector<Body>& bodies,
                      const World& world,
                      const VecX& lambda,
                      const VecX& v2,
                      long step,
                      const char* system) {
  const auto row_text = [&](int k) {
    std::ostringstream text;
    text << "row " << k << " (" << sys.labels[static_cast<std::size_t>(k)]
         << "), lambda = " << lambda(k) << " N";
    return text.str();
  };
  const auto body_text = [&](int body) {
    std::ostringstream text;
    text << "body " << body << " (" << bodies[static_cast<std::size_t>(body)].name << ")";
    return text.str();
  };
  const double t = static_cast<double>(step) * world.dt;
  for (int k = 0; k < sys.rows(); ++k) {
    if (std::isfinite(lambda(k))) continue;
    const int body = body_of_row(sys, k);
    std::ostringstream msg;
    msg << "step " << step << " (t = " << t << " s), " << system << ": " << row_text(k)
        << " is not finite";
    if (body >= 0) msg << "; it acts on " << body_text(body);
    throw DivergenceError(msg.str(), step, body, k);
  }
  for (int blk = 0; blk < sys.blocks(); ++blk) {
    const double speed = v2.segment<3>(6 * blk).norm();
    const double spin = v2.segment<3>(6 * blk + 3).norm();
    const bool finite = std::isfinite(speed) && std::isfinite(spin);
    if (finite && speed <= world.divergence_speed && spin <= world.divergence_spin) continue;
    const int body = sys.body_of_block[static_cast<std::size_t>(blk)];
    const int row = strongest_row_on(sys, lambda, blk);
    std::ostringstream msg;
    msg << "step " << step << " (t = " << t << " s), " << system << ": " << body_text(body);
    if (!finite) {
      msg << " has a velocity that is not finite";
    } else if (speed > world.divergence_speed) {
      msg << " moves at " << speed << " m/s, beyond divergence_speed " << world.divergence_speed
          << " m/s";
    } else {
      msg << " spins at " << spin << " rad/s, beyond divergence_spin " << world.divergence_spin
          << " rad/s";
    }
    if (row >= 0) {
      msg << "; the largest constraint impulse on it is " << row_text(row);
    } else {
      msg << "; no constraint row acts on it";
    }
    throw DivergenceError(msg.str(), step, body, row);
  }
}

}  // namespace cbps
