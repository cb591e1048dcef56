// Warm starting (7): each row starts from its warm-start factor times its lambda of the last
// step, matched by row id (SolverSettings::warm, warm_friction); the default is the paper's.
#include <catch2/catch.hpp>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>

#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::contact_scene;

namespace {

using LambdaById = std::unordered_map<std::uint64_t, double>;

/// Records every step's lambda by row id (the answer the step kept, before integration).
void record_lambda(Simulation& sim, LambdaById& last) {
  sim.set_observer([&last](const System& sys, const VecX& lambda, const VecX&) {
    last.clear();
    for (int k = 0; k < sys.rows(); ++k) last[sys.ids[static_cast<std::size_t>(k)]] = lambda(k);
  });
}

/// A row is a friction row when rows/friction.cpp labelled it so (independent of Row::kind).
bool is_friction_label(const std::string& label) { return label.rfind("friction ", 0) == 0; }

/// The solver's lambda of the next step of `sim`, solved from `guess(sys)` on a copy of it.
template <class Guess>
VecX solve_from(const Simulation& sim, Guess guess) {
  Simulation copy = sim;
  const System& sys = copy.assemble();
  VecX lambda = guess(copy, sys);
  copy.solve_system(sys, lambda);
  return lambda;
}

}  // namespace

TEST_CASE("the warm start is F times last step's lambda, G on friction rows, exactly (7)",
          "[simulation][warm]") {
  // Unconverged solves (5 sweeps), so a different start gives a different lambda.
  using Named = std::pair<std::string, std::map<std::string, std::string>>;
  const Named named =
      GENERATE(values<Named>({{"stack", {{"n", "3"}, {"mu", "0.5"}}}, {"chain", {{"n", "6"}}}}));
  const std::string& name = named.first;
  CAPTURE(name);
  Scene scene = contact_scene(name, named.second);
  scene.solver.max_iterations = 5;
  scene.solver.warm = 0.85;
  scene.solver.warm_friction = 0.25;
  Simulation sim(scene);
  LambdaById last;
  record_lambda(sim, last);
  for (int s = 0; s < 30; ++s) sim.step();

  Simulation copy = sim;
  const System& sys = copy.assemble();
  const VecX guess = copy.initial_lambda(sys);
  int matched = 0, friction = 0;
  for (int k = 0; k < sys.rows(); ++k) {
    const auto row = static_cast<std::size_t>(k);
    INFO("row " << k << " " << sys.labels[row]);
    const bool is_friction = is_friction_label(sys.labels[row]);
    CHECK((sys.kind[row] == RowKind::Friction) == is_friction);
    const auto it = last.find(sys.ids[row]);
    if (it == last.end()) {
      CHECK(guess(k) == 0.0);
      continue;
    }
    ++matched;
    friction += is_friction && it->second != 0.0;
    CHECK(guess(k) == (is_friction ? 0.25 : 0.85) * it->second);  // one product, exact
  }
  INFO(matched << " of " << sys.rows() << " rows warm started, " << friction << " friction");
  CHECK(matched > 0);
  if (name == "chain") CHECK(matched == sys.rows());  // distance rows never change
  if (name == "stack") CHECK(friction > 0);

  // The step hands exactly this guess to the solver: its lambda is the one solved from it,
  // bit for bit, and not the one solved from the unscaled lambda.
  const VecX from_guess =
      solve_from(sim, [](const Simulation& s, const System& y) { return s.initial_lambda(y); });
  const VecX from_last =
      solve_from(sim, [](const Simulation& s, const System& y) { return s.last_lambda(y); });
  sim.step();
  VecX stepped(sys.rows());
  for (int k = 0; k < sys.rows(); ++k) stepped(k) = last.at(sys.ids[static_cast<std::size_t>(k)]);
  CHECK(stepped == from_guess);
  CHECK(stepped != from_last);
}

TEST_CASE("the default warm start is the paper's, bit for bit: last step's lambda by row id (7)",
          "[simulation][warm]") {
  // The previous code's guess, written here on its own: lambda_k = last lambda of row id_k,
  // else 0. Every step of a default run (and of warm = 1 given explicitly) must solve from it;
  // warm = 0 from lambda = 0. Unconverged solves (10 sweeps) make any other start show.
  struct Case {
    std::string spec;
    bool cold;
  };
  const Case c = GENERATE(values<Case>({{"", false},
                                        {"pgs:warm=on", false},
                                        {"pgs:warm=1:warm_friction=1", false},
                                        {"pgs:order=random", false},
                                        {"pgs:warm=off", true}}));
  CAPTURE(c.spec);
  Scene scene = contact_scene("stack", {{"n", "4"}, {"mu", "0.5"}});
  scene.solver.max_iterations = 10;
  if (!c.spec.empty()) apply_solver_spec(parse_solver_spec(c.spec), scene.solver);
  Simulation sim(scene);
  LambdaById last;
  VecX stepped;
  sim.set_observer([&](const System& sys, const VecX& lambda, const VecX&) {
    last.clear();
    for (int k = 0; k < sys.rows(); ++k) last[sys.ids[static_cast<std::size_t>(k)]] = lambda(k);
    stepped = lambda;
  });
  int differing = 0;
  long warm_rows = 0;
  for (int s = 0; s < 100; ++s) {
    const VecX expected = solve_from(sim, [&](const Simulation&, const System& sys) {
      VecX guess = VecX::Zero(sys.rows());
      for (int k = 0; k < sys.rows(); ++k) {
        const auto it = last.find(sys.ids[static_cast<std::size_t>(k)]);
        if (it == last.end()) continue;
        ++warm_rows;
        if (!c.cold) guess(k) = it->second;
      }
      return guess;
    });
    sim.step();
    differing += !(stepped.size() == expected.size() && stepped == expected);
  }
  INFO(warm_rows << " rows found last step's lambda over 100 steps");
  CHECK(differing == 0);
  CHECK(warm_rows > 0);
}
