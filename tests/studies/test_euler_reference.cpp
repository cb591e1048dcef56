// The Euler reference (GSL) for torque-free rotation: a symmetric top's precession, energy and
// |L| through Dzhanibekov flips.
#include <catch2/catch.hpp>
#include <cmath>

#include "cbps/studies/euler_reference.hpp"

using namespace cbps;

TEST_CASE("Euler reference: a symmetric top precesses at (I3 − I1)/I1 omega3", "[stress][euler]") {
  const Vec3 I(1.0, 1.0, 2.0);
  const Vec3 omega0(0.3, 0.0, 5.0);
  const double dt = 0.01;
  const auto w = euler_reference(I, omega0, dt, 501);
  const double Omega = (I.z() - I.x()) / I.x() * omega0.z();
  for (std::size_t k = 0; k < w.size(); k += 50) {
    const double t = static_cast<double>(k) * dt;
    CHECK(w[k].x() == Approx(0.3 * std::cos(Omega * t)).margin(1e-9));
    CHECK(w[k].y() == Approx(0.3 * std::sin(Omega * t)).margin(1e-9));
    CHECK(w[k].z() == Approx(5.0).margin(1e-12));
  }
}

TEST_CASE("Euler reference: energy and |L| kept through Dzhanibekov flips", "[stress][euler]") {
  const Vec3 I(0.0241667, 0.0866667, 0.104167);
  const Vec3 omega0(1e-2, 10.0, 1e-2);
  const auto w = euler_reference(I, omega0, 0.01, 1001);
  const auto energy = [&](const Vec3& x) { return 0.5 * x.dot(I.cwiseProduct(x)); };
  const auto L2 = [&](const Vec3& x) { return I.cwiseProduct(x).squaredNorm(); };
  int flips = 0;
  for (std::size_t k = 1; k < w.size(); ++k) {
    CHECK(energy(w[k]) == Approx(energy(omega0)).epsilon(1e-9));
    CHECK(L2(w[k]) == Approx(L2(omega0)).epsilon(1e-9));
    if ((w[k - 1].y() > 0) != (w[k].y() > 0)) ++flips;
  }
  CHECK(flips >= 3);  // 10 s: the intermediate axis turns over several times
}
