// Performance profiles (Dolan & Moré, Math. Program. 91, 2002) on tables worked out by hand.
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "cbps/studies/performance_profile.hpp"
#include "cbps/studies/profile.hpp"

using namespace cbps;

TEST_CASE("performance ratios and rho(tau) match a table worked by hand (Dolan & More eq. 1)",
          "[profile]") {
  // Four problems, three solvers; inf: the solver failed. By hand:
  //   p0: best 1  -> r = (1, 2, inf)
  //   p1: best 5  -> r = (2, 1, 4)
  //   p2: best 3  -> r = (inf, 1, 1)
  //   p3: every solver failed -> r = (inf, inf, inf)
  const CostTable cost = {
      {1.0, 2.0, kInf}, {10.0, 5.0, 20.0}, {kInf, 3.0, 3.0}, {kInf, kInf, kInf}};
  const CostTable r = performance_ratios(cost);
  const CostTable expected = {
      {1.0, 2.0, kInf}, {2.0, 1.0, 4.0}, {kInf, 1.0, 1.0}, {kInf, kInf, kInf}};
  REQUIRE(r.size() == expected.size());
  for (std::size_t p = 0; p < r.size(); ++p)
    for (std::size_t s = 0; s < 3; ++s) {
      CAPTURE(p, s);
      CHECK(r[p][s] == expected[p][s]);
    }
  // rho_s(tau) = |{p : r_ps <= tau}| / 4.
  CHECK(performance_fraction(r, 0, 1.0) == 0.25);  // best on p0
  CHECK(performance_fraction(r, 0, 2.0) == 0.5);   // p0, p1
  CHECK(performance_fraction(r, 0, 10.0) == 0.5);
  CHECK(performance_fraction(r, 1, 1.0) == 0.5);  // best on p1 and p2 (a tie on p2)
  CHECK(performance_fraction(r, 1, 2.0) == 0.75);
  CHECK(performance_fraction(r, 2, 1.0) == 0.25);  // the tie on p2
  CHECK(performance_fraction(r, 2, 3.99) == 0.25);
  CHECK(performance_fraction(r, 2, 4.0) == 0.5);  // p1 enters at tau = 4
  // rho_s(inf): the fraction solved; p3 counts for nobody.
  CHECK(performance_fraction(r, 0, kInf) == 0.5);
  CHECK(performance_fraction(r, 1, kInf) == 0.75);
  CHECK(performance_fraction(r, 2, kInf) == 0.5);
}

TEST_CASE("a solver that never converges has rho = 0 at every tau", "[profile]") {
  // Solver 1 fails everywhere (inf, and NaN as a failure too); solver 0 is then best everywhere.
  const CostTable cost = {{4.0, kInf}, {0.5, std::nan("")}, {7.0, kInf}};
  const CostTable r = performance_ratios(cost);
  for (const double tau : {1.0, 2.0, 10.0, 1e300, kInf}) {
    CAPTURE(tau);
    CHECK(performance_fraction(r, 1, tau) == 0.0);
    CHECK(performance_fraction(r, 0, tau) == 1.0);
  }
}

TEST_CASE("a best cost of 0 gives ratio 1 to the solvers at 0 and infinity to the rest",
          "[profile]") {
  // The guess already meets the tolerance: sweeps 0 for two solvers, 3 for the third.
  const CostTable r = performance_ratios({{0.0, 0.0, 3.0}, {2.0, 1.0, 1.0}});
  CHECK(r[0][0] == 1.0);
  CHECK(r[0][1] == 1.0);
  CHECK(r[0][2] == kInf);
  CHECK(r[1][0] == 2.0);
  CHECK(performance_fraction(r, 2, 1e6) == 0.5);
}

TEST_CASE("performance ratios refuse negative costs and ragged tables", "[profile]") {
  CHECK_THROWS_AS(performance_ratios({{1.0, -1.0}}), std::invalid_argument);
  CHECK_THROWS_AS(performance_ratios({{1.0, 2.0}, {1.0}}), std::invalid_argument);
  CHECK(performance_fraction({}, 0, 2.0) == 0.0);
}

TEST_CASE("where lambda = 0 already meets a tolerance, every solver that reached it has ratio 1",
          "[profile]") {
  // nsgs checks lambda = 0 before its first sweep (cost 0); direct's one answer comes after a
  // solve of 5 ms, pgs never reaches the tolerance. On the second problem nobody starts solved.
  const std::vector<SolverSpec> specs = {
      parse_solver_spec("nsgs"), parse_solver_spec("direct"), parse_solver_spec("pgs")};
  std::vector<std::vector<ProfileMeasurement>> runs(2, std::vector<ProfileMeasurement>(3));
  runs[0][0].reached[0] = {0, 0.0};
  runs[0][1].reached[0] = {1, 0.005};
  runs[1][0].reached[0] = {40, 0.002};
  runs[1][1].reached[0] = {1, 0.004};
  runs[1][2].reached[0] = {80, 0.008};
  const Profile time = make_profile(kProfileTolerances[0], 0, false, specs, runs);
  REQUIRE(time.ratios.size() == 2);
  CHECK(time.ratios[0][0] == 1.0);
  CHECK(time.ratios[0][1] == 1.0);
  CHECK(time.ratios[0][2] == kInf);
  CHECK(time.ratios[1][0] == 1.0);
  CHECK(time.ratios[1][1] == 2.0);
  CHECK(time.ratios[1][2] == 4.0);
}

TEST_CASE("a short measurement is taken again and keeps its least times, a long one is taken once",
          "[profile]") {
  // Runs of 3, 2, 4, 1, 5 and 6 ms (the sweeps alike): after five runs, 15 ms in all, below
  // kRepeatSpan, a sixth; then 21 ms, and no more. The best of the runs is 1 ms, and the
  // tolerance reached at a different sweep in one run (a run that differs) keeps its own time.
  static_assert(kRepeats == 5 && kRepeatSpan > 0.015 && kRepeatSpan <= 0.021);
  const double times[] = {0.003, 0.002, 0.004, 0.001, 0.005, 0.006};
  int calls = 0;
  const ProfileMeasurement m = best_of_runs([&] {
    ProfileMeasurement r;
    r.status = calls == 0 ? "solved" : "other";
    r.time_s = times[calls];
    r.reached[0] = {10, times[calls] / 2};
    r.reached[1] = {calls == 3 ? 21 : 20, times[calls]};
    ++calls;
    return r;
  });
  CHECK(calls == 6);
  CHECK(m.status == "solved");
  CHECK(m.time_s == 0.001);
  CHECK(m.reached[0].time_s == 0.0005);
  CHECK(m.reached[1].iterations == 20);
  CHECK(m.reached[1].time_s == 0.002);
  CHECK(m.reached[2].iterations == -1);
  // Runs of 0.1 ms: kMostRepeats of them, 2 ms in all, short of kRepeatSpan.
  calls = 0;
  const ProfileMeasurement quick = best_of_runs([&] {
    ProfileMeasurement r;
    r.time_s = calls == 7 ? 5e-5 : 1e-4;
    ++calls;
    return r;
  });
  CHECK(calls == kMostRepeats);
  CHECK(quick.time_s == 5e-5);
  // A measurement of kRepeatBelow or more: once.
  calls = 0;
  const ProfileMeasurement once = best_of_runs([&] {
    ProfileMeasurement r;
    r.time_s = kRepeatBelow;
    ++calls;
    return r;
  });
  CHECK(calls == 1);
  CHECK(once.time_s == kRepeatBelow);
}
