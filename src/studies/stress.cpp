// The stress catalogue: the cases, what "stable" means for each, and the runner.
#include "cbps/studies/stress.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/io/json_numbers.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/studies/euler_reference.hpp"
#include "cbps/studies/run.hpp"
#include "cbps/studies/solver_spec.hpp"

namespace cbps {

namespace {

std::string format(double x) {
  std::ostringstream s;
  s.precision(2);
  s << x;
  return s.str();
}

Scene builtin(const std::string& name, const std::map<std::string, std::string>& values) {
  return make_builtin_scene(name, values);
}

/// Moves a whole scene by `offset`: bodies and the world anchors of distance constraints.
Scene translated(Scene scene, const Vec3& offset) {
  for (Body& body : scene.bodies) body.x += offset;
  for (DistanceConstraint& dc : scene.distances) {
    if (dc.a < 0) dc.anchor_a += offset;
    if (dc.b < 0) dc.anchor_b += offset;
  }
  return scene;
}

// ---- Probes -------------------------------------------------------------------------------

/// A body that should stay where it is: max |x − x0| ≤ drift_limit and the deepest contact
/// ≤ penetration_limit.
class RestProbe : public StressProbe {
 public:
  RestProbe(int body, double drift_limit, double penetration_limit)
      : body_(body), drift_limit_(drift_limit), penetration_limit_(penetration_limit) {}
  void start(const Simulation& sim) override {
    x0_ = sim.scene().bodies[static_cast<std::size_t>(body_)].x;
  }
  void after_step(const Simulation& sim, const StepReport& r) override {
    drift_ = std::max(drift_, (sim.scene().bodies[static_cast<std::size_t>(body_)].x - x0_).norm());
    penetration_ = std::max(penetration_, r.max_penetration);
  }
  StressVerdict finish(const Simulation& sim) override {
    StressVerdict v;
    v.stable = drift_ <= drift_limit_ && penetration_ <= penetration_limit_;
    v.measure = sim.scene().bodies[static_cast<std::size_t>(body_)].name + " drift " +
                format(drift_) + " m (≤ " + format(drift_limit_) + "), penetration " +
                format(penetration_) + " m (≤ " + format(penetration_limit_) + ")";
    v.extra = {{"drift_m", drift_}, {"penetration_m", penetration_}};
    return v;
  }

 private:
  int body_;
  double drift_limit_, penetration_limit_;
  Vec3 x0_ = Vec3::Zero();
  double drift_ = 0.0, penetration_ = 0.0;
};

/// Distance constraints that should hold: max |c| ≤ fraction × length, and, when
/// energy_scale > 0, the energy may not rise by more than energy_fraction × energy_scale
/// (constraint forces do no work; the push factor and the integrator may only remove energy).
class ConstraintProbe : public StressProbe {
 public:
  ConstraintProbe(double length, double fraction, double energy_scale, double energy_fraction)
      : length_(length),
        fraction_(fraction),
        energy_scale_(energy_scale),
        energy_fraction_(energy_fraction) {}
  void start(const Simulation& sim) override {
    e0_ = sim.energy();
    error_ = sim.max_constraint_error();
  }
  void after_step(const Simulation& sim, const StepReport& r) override {
    error_ = std::max(error_, r.max_constraint_error);
    rise_ = std::max(rise_, sim.energy() - e0_);
  }
  StressVerdict finish(const Simulation&) override {
    StressVerdict v;
    const double relative = error_ / length_;
    v.stable = relative <= fraction_;
    v.measure = "max |c| " + format(relative) + " of the length (≤ " + format(fraction_) + ")";
    if (energy_scale_ > 0.0) {
      const double rise = rise_ / energy_scale_;
      v.stable = v.stable && rise <= energy_fraction_;
      v.measure +=
          ", energy rise " + format(rise) + " of the scale (≤ " + format(energy_fraction_) + ")";
      v.extra.emplace_back("energy_rise_relative", rise);
    }
    v.extra.emplace_back("constraint_error_relative", relative);
    return v;
  }

 private:
  double length_, fraction_, energy_scale_, energy_fraction_;
  double e0_ = 0.0, error_ = 0.0, rise_ = 0.0;
};

/// A ball shot at a thin static plate along −x: it must not get past the plate's back face
/// (x < −half_thickness − radius at some step means it went through: tunnelling).
class TunnelProbe : public StressProbe {
 public:
  TunnelProbe(int body, double half_thickness, double radius)
      : body_(body), back_(-half_thickness - radius) {}
  void after_step(const Simulation& sim, const StepReport&) override {
    min_x_ = std::min(min_x_, sim.scene().bodies[static_cast<std::size_t>(body_)].x.x());
  }
  StressVerdict finish(const Simulation&) override {
    StressVerdict v;
    v.stable = min_x_ >= back_;
    v.measure = "ball's least x " + format(min_x_) + " m (≥ " + format(back_) +
                " m: not through the plate)";
    v.extra = {{"min_x_m", min_x_}};
    return v;
  }

 private:
  int body_;
  double back_;
  double min_x_ = kInf;
};

/// A fast ball onto the ground plane: at the end it must rest on the plane (centre height
/// within 1 cm of its radius, speed below 0.1 m/s).
class LandingProbe : public StressProbe {
 public:
  LandingProbe(int body, double radius) : body_(body), radius_(radius) {}
  StressVerdict finish(const Simulation& sim) override {
    const Body& ball = sim.scene().bodies[static_cast<std::size_t>(body_)];
    const double height = ball.x.y() - radius_;
    const double speed = ball.v().norm();
    StressVerdict v;
    v.stable = std::abs(height) <= 0.01 && speed <= 0.1;
    v.measure =
        "final gap " + format(height) + " m (|·| ≤ 0.01), speed " + format(speed) + " m/s (≤ 0.1)";
    v.extra = {{"final_gap_m", height}, {"final_speed_m_s", speed}};
    return v;
  }

 private:
  int body_;
  double radius_;
};

/// A plate dropped on the ground: at the end it must lie on the ground (its centre within 1 mm
/// of half its thickness above the plane: not sunk, not stuck inside) and be at rest.
class PlateProbe : public StressProbe {
 public:
  PlateProbe(int body, double thickness) : body_(body), thickness_(thickness) {}
  void after_step(const Simulation&, const StepReport& r) override {
    penetration_ = std::max(penetration_, r.max_penetration);
  }
  StressVerdict finish(const Simulation& sim) override {
    const Body& plate = sim.scene().bodies[static_cast<std::size_t>(body_)];
    const double gap = plate.x.y() - 0.5 * thickness_;
    const double speed = plate.v().norm();
    const double spin = plate.omega().norm();
    StressVerdict v;
    v.stable = std::abs(gap) <= 1e-3 && speed <= 0.01 && spin <= 0.1;
    v.measure = "final gap " + format(gap) + " m (|·| ≤ 0.001), speed " + format(speed) +
                " m/s (≤ 0.01), spin " + format(spin) + " rad/s (≤ 0.1)";
    v.extra = {{"final_gap_m", gap},
               {"penetration_m", penetration_},
               {"final_speed_m_s", speed},
               {"final_spin_rad_s", spin}};
    return v;
  }

 private:
  int body_;
  double thickness_;
  double penetration_ = 0.0;
};

/// Contacts that must neither explode nor sink: deepest contact ≤ 1 cm, energy rise ≤ 1 % of
/// m g h (h the moving box's size).
class ContactSanityProbe : public StressProbe {
 public:
  explicit ContactSanityProbe(double energy_scale) : energy_scale_(energy_scale) {}
  void start(const Simulation& sim) override { e0_ = sim.energy(); }
  void after_step(const Simulation& sim, const StepReport& r) override {
    penetration_ = std::max(penetration_, r.max_penetration);
    rise_ = std::max(rise_, sim.energy() - e0_);
  }
  StressVerdict finish(const Simulation&) override {
    StressVerdict v;
    const double rise = rise_ / energy_scale_;
    v.stable = penetration_ <= 0.01 && rise <= 0.01;
    v.measure = "penetration " + format(penetration_) + " m (≤ 0.01), energy rise " + format(rise) +
                " of m g h (≤ 0.01)";
    v.extra = {{"penetration_m", penetration_}, {"energy_rise_relative", rise}};
    return v;
  }

 private:
  double energy_scale_;
  double e0_ = 0.0, penetration_ = 0.0, rise_ = 0.0;
};

/// The Dzhanibekov effect: a free body spun about its intermediate axis flips over and back
/// with a period set by the spin and the perturbation. Compared against Euler's equations
/// integrated by GSL (euler_reference): the mean time between flips (sign changes of the
/// intermediate-axis spin) within 5 %, the world angular momentum L kept to 1e-9 relative and
/// the kinetic energy to 1 %.
class DzhanibekovProbe : public StressProbe {
 public:
  DzhanibekovProbe(const Scene& scene, long steps) {
    const Body& body = scene.bodies.front();
    const Vec3 I = body.I_body.diagonal();
    const Vec3 omega0 = body.R().transpose() * body.omega();
    reference_ = euler_reference(I, omega0, scene.world.dt, steps + 1);
    dt_ = scene.world.dt;
  }
  void start(const Simulation& sim) override {
    const Body& body = sim.scene().bodies.front();
    L0_ = body.l;
    E0_ = body.kinetic_energy();
    record(body, 0);
  }
  void after_step(const Simulation& sim, const StepReport&) override {
    const Body& body = sim.scene().bodies.front();
    L_drift_ = std::max(L_drift_, (body.l - L0_).norm() / L0_.norm());
    E_drift_ = std::max(E_drift_, std::abs(body.kinetic_energy() - E0_) / E0_);
    record(body, sim.steps_done());
  }
  StressVerdict finish(const Simulation&) override {
    std::vector<double> ref_flips;
    for (std::size_t k = 1; k < reference_.size(); ++k) {
      if ((reference_[k - 1].y() > 0.0) != (reference_[k].y() > 0.0))
        ref_flips.push_back(static_cast<double>(k) * dt_);
    }
    const double period = mean_gap(flips_);
    const double ref_period = mean_gap(ref_flips);
    const double error = std::abs(period - ref_period) / ref_period;
    StressVerdict v;
    v.stable = flips_.size() >= 2 && ref_flips.size() >= 2 && error <= 0.05 && L_drift_ <= 1e-9 &&
               E_drift_ <= 0.01;
    v.measure = "flip interval " + format(period) + " s vs GSL " + format(ref_period) +
                " s (error " + format(error) + " ≤ 0.05), |ΔL|/|L| " + format(L_drift_) +
                " (≤ 1e-9), |ΔE|/E " + format(E_drift_) + " (≤ 0.01)";
    v.extra = {{"flips", static_cast<double>(flips_.size())},
               {"reference_flips", static_cast<double>(ref_flips.size())},
               {"flip_interval_s", period},
               {"reference_flip_interval_s", ref_period},
               {"max_omega_error_rad_s", omega_error_},
               {"angular_momentum_drift_relative", L_drift_},
               {"energy_drift_relative", E_drift_}};
    return v;
  }

 private:
  void record(const Body& body, long k) {
    const Vec3 omega = body.R().transpose() * body.omega();  // body axes
    if (k > 0 && (last_.y() > 0.0) != (omega.y() > 0.0))
      flips_.push_back(static_cast<double>(k) * dt_);
    last_ = omega;
    if (static_cast<std::size_t>(k) < reference_.size())
      omega_error_ =
          std::max(omega_error_, (omega - reference_[static_cast<std::size_t>(k)]).norm());
  }
  static double mean_gap(const std::vector<double>& t) {
    if (t.size() < 2) return kInf;
    return (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  }
  std::vector<Vec3> reference_;
  double dt_ = 0.0;
  Vec3 L0_ = Vec3::Zero();
  double E0_ = 0.0;
  Vec3 last_ = Vec3::Zero();
  std::vector<double> flips_;
  double L_drift_ = 0.0, E_drift_ = 0.0, omega_error_ = 0.0;
};

// ---- Cases --------------------------------------------------------------------------------

const std::vector<std::string> kDistanceSolvers = {std::string(to_string(kPaperMethod)),
                                                   std::string(to_string(kExactMethod))};
const std::vector<std::string> kContactSolvers = {std::string(to_string(kPaperMethod)),
                                                  std::string(to_string(kBlockMethod)),
                                                  std::string(to_string(kExactMethod))};

std::function<std::unique_ptr<StressProbe>(const Scene&)> rest_of_last(double drift,
                                                                       double penetration) {
  return [drift, penetration](const Scene& s) -> std::unique_ptr<StressProbe> {
    return std::make_unique<RestProbe>(static_cast<int>(s.bodies.size()) - 1, drift, penetration);
  };
}

std::function<std::unique_ptr<StressProbe>(const Scene&)> constraints_hold(
    double length, double fraction, double energy_scale = 0.0, double energy_fraction = 0.0) {
  return [=](const Scene&) -> std::unique_ptr<StressProbe> {
    return std::make_unique<ConstraintProbe>(length, fraction, energy_scale, energy_fraction);
  };
}

const char* kRestMeans =
    "the top box stays put: drift ≤ 1 cm over the run and no contact deeper than 1 cm (the "
    "stack test of the contact issue); a solver that leaves residual force lets boxes sink or "
    "slide";
const char* kChainMeans =
    "every distance constraint holds to 1 % of the link length: beyond that the chain has "
    "visibly stretched, the solver is not solving";

void add_mass_ratio_cases(std::vector<StressCase>& cases) {
  for (const double ratio : {1e3, 1e6}) {
    const std::string tag = ratio == 1e3 ? "1e3" : "1e6";
    cases.push_back({"mass-ratio-box-" + tag,
                     "mass ratio",
                     "a box of " + tag +
                         " kg resting on a box of 1 kg on the ground; dt 1/60, mu 0.5, "
                         "improved push",
                     kRestMeans,
                     [ratio] {
                       Scene s = builtin("stack", {{"n", "2"}});
                       set_mass(s.bodies[2], ratio);
                       return s;
                     },
                     120,
                     kContactSolvers,
                     {},
                     rest_of_last(0.01, 0.01)});
    cases.push_back(
        {"mass-ratio-chain-" + tag,
         "mass ratio",
         "10 links of 0.1 kg, the last one " + tag +
             " times heavier, released horizontally; "
             "1 s at dt 1/2400 (at 1/240 even the direct path stretches the chain by 15 % with "
             "equal "
             "masses: that is the time step, not the solver)",
         kChainMeans,
         [tag] {
           return builtin("chain", {{"n", "10"}, {"mass_ratio", tag}, {"dt", "1/2400"}});
         },
         2400,
         kDistanceSolvers,
         {},
         constraints_hold(0.1, 0.01)});
  }
}

void add_size_cases(std::vector<StressCase>& cases) {
  cases.push_back({"chain-1000",
                   "size",
                   "1000 links of 0.1 m released horizontally (a 100 m chain); dt 1/240",
                   kChainMeans,
                   [] {
                     return builtin("chain", {{"n", "1000"}});
                   },
                   240,
                   kDistanceSolvers,
                   {},
                   constraints_hold(0.1, 0.01)});
  cases.push_back(
      {"chain-10000",
       "size",
       "10000 links of 0.01 m released horizontally (a 100 m chain); 120 steps of "
       "dt 1/2400 (short links need the shorter step)",
       kChainMeans,
       [] {
         return builtin(
             "chain",
             {{"n", "10000"}, {"link_length", "0.01"}, {"radius", "0.002"}, {"dt", "1/2400"}});
       },
       120,
       kDistanceSolvers,
       {},
       constraints_hold(0.01, 0.01)});
  for (const int n : {20, 50}) {
    cases.push_back(
        {"stack-" + std::to_string(n),
         "size",
         std::to_string(n) + " boxes of 1 kg in a column; dt 1/60, mu 0.5, improved push",
         kRestMeans,
         [n] {
           return builtin("stack", {{"n", std::to_string(n)}});
         },
         120,
         kContactSolvers,
         {},
         rest_of_last(0.01, 0.01)});
  }
  cases.push_back(
      {"pyramid-30",
       "size",
       "a 2-D pyramid of 465 boxes (base 30); 10 steps of dt 1/60, mu 0.5, improved push",
       "the top box stays put: drift ≤ 1 cm and no contact deeper than 1 cm",
       [] {
         return builtin("pyramid", {{"base", "30"}});
       },
       10,
       kContactSolvers,
       {},
       rest_of_last(0.01, 0.01)});
}

void add_time_step_cases(std::vector<StressCase>& cases) {
  // A 1 m pendulum of 0.1 kg released horizontally: m g L = 0.981 J.
  for (const char* dt : {"1e-5", "1e-3", "1e-2", "1e-1"}) {
    double h = 0.0;
    parse_number(dt, h);
    cases.push_back(
        {std::string("pendulum-dt-") + dt,
         "time step",
         std::string("a 1 m pendulum released horizontally, 1 s at dt ") + dt + " s",
         "the string holds to 1 % of its length and the energy never rises by more than 5 % of "
         "m g L (a constraint does no work; Baumgarte may only remove energy)",
         [dt] {
           return builtin("chain",
                          {{"n", "1"}, {"link_length", "1"}, {"dt", dt}, {"duration", "1"}});
         },
         static_cast<long>(std::llround(1.0 / h)),
         kDistanceSolvers,
         {},
         constraints_hold(1.0, 0.01, 0.1 * 9.81 * 1.0, 0.05)});
  }
  for (const char* dt : {"1e-5", "1e-1"}) {
    const long steps = std::string(dt) == "1e-5" ? 2000 : 10;
    cases.push_back({std::string("box-dt-") + dt,
                     "time step",
                     std::string("one box resting on the ground, ") + std::to_string(steps) +
                         " steps of dt " + dt + " s",
                     "the box stays put: drift ≤ 1 cm, no contact deeper than 1 cm",
                     [dt] {
                       return builtin("stack", {{"n", "1"}, {"dt", dt}});
                     },
                     steps,
                     kContactSolvers,
                     {},
                     rest_of_last(0.01, 0.01)});
  }
}

void add_impact_cases(std::vector<StressCase>& cases) {
  cases.push_back({"impact-plane",
                   "fast impact",
                   "a 0.1 m ball at 100 m/s straight down onto the ground plane from 1 m "
                   "(1.7 m per step); dt 1/60, restitution 0",
                   "the ball ends resting on the plane (gap within 1 cm, speed ≤ 0.1 m/s): a "
                   "half-space cannot be tunnelled through, only sunk into",
                   [] {
                     Scene s = builtin("bounce", {{"restitution", "0"}, {"dt", "1/60"}});
                     s.bodies[1].set_velocity(Vec3(0.0, -100.0, 0.0), Vec3::Zero());
                     return s;
                   },
                   60,
                   kDistanceSolvers,
                   {},
                   [](const Scene& s) -> std::unique_ptr<StressProbe> {
                     return std::make_unique<LandingProbe>(1, s.bodies[1].shape.radius);
                   }});
  cases.push_back(
      {"impact-plate",
       "fast impact",
       "a 5 cm ball at 300 m/s at a static plate 10 cm thick (1.25 m per step); dt 1/240, no "
       "gravity",
       "the ball never gets past the plate's back face; discrete collision detection sees no "
       "overlap when a step jumps the plate, so every solver tunnels: the lesson of the case",
       [] {
         Scene s;
         s.name = "impact-plate";
         s.world.gravity = Vec3::Zero();
         s.world.dt = 1.0 / 240.0;
         Body plate = box_body("plate", Vec3(0.05, 1.0, 1.0), 1.0, Vec3::Zero());
         plate.is_static = true;
         s.bodies.push_back(plate);
         Body ball = sphere_body("ball", 0.05, 0.1, Vec3(1.0, 0.0, 0.0));
         ball.set_velocity(Vec3(-300.0, 0.0, 0.0), Vec3::Zero());
         s.bodies.push_back(ball);
         return s;
       },
       60,
       kDistanceSolvers,
       {},
       [](const Scene&) -> std::unique_ptr<StressProbe> {
         return std::make_unique<TunnelProbe>(1, 0.05, 0.05);
       }});
}

/// Four 1 kg balls on a 0.5 m square in the x-y plane, joined by the four sides and both
/// diagonals (one bar more than a plane frame needs: a self-stress, A singular), hung by one
/// corner from a fixed point 0.5 m above it, released.
Scene braced_square(double cfm) {
  Scene s;
  s.name = "braced-square";
  s.world.dt = 1.0 / 240.0;
  s.solver.cfm = cfm;
  const double a = 0.5;
  const std::vector<Vec3> corners = {
      Vec3(0.0, 0.0, 0.0), Vec3(a, 0.0, 0.0), Vec3(a, -a, 0.0), Vec3(0.0, -a, 0.0)};
  for (std::size_t k = 0; k < corners.size(); ++k) {
    Body ball = sphere_body("ball" + std::to_string(k), 0.05, 1.0, corners[k]);
    ball.collides = false;
    s.bodies.push_back(ball);
  }
  const auto bar = [&](int i, int j) {
    DistanceConstraint dc;
    dc.name = "bar" + std::to_string(i) + std::to_string(j);
    dc.a = i;
    dc.b = j;
    dc.length =
        (corners[static_cast<std::size_t>(i)] - corners[static_cast<std::size_t>(j)]).norm();
    s.distances.push_back(dc);
  };
  bar(0, 1);
  bar(1, 2);
  bar(2, 3);
  bar(3, 0);
  bar(0, 2);
  bar(1, 3);
  DistanceConstraint pin;
  pin.name = "pin";
  pin.a = -1;
  pin.anchor_a = Vec3(-0.3, 0.4, 0.0);  // 0.5 m from ball0, off the vertical: it swings
  pin.b = 0;
  pin.length = 0.5;
  s.distances.push_back(pin);
  return s;
}

/// A 1 m pendulum of 0.1 kg released horizontally whose distance constraint is given twice.
Scene row_twice(double cfm) {
  Scene s = builtin("chain", {{"n", "1"}, {"link_length", "1"}});
  s.name = "row-twice";
  s.solver.cfm = cfm;
  DistanceConstraint twin = s.distances.front();
  twin.name = "joint0-again";
  s.distances.push_back(twin);
  return s;
}

void add_redundant_cases(std::vector<StressCase>& cases) {
  const char* means =
      "the bars hold to 1 % of their length: a redundant row makes A singular, so lambda is "
      "not unique, but v2 is, and the motion must not suffer";
  for (const double cfm : {0.0, 1e-6}) {
    const std::string tag = cfm > 0.0 ? "+cfm" : "";
    cases.push_back({"closed-loop" + tag,
                     "redundant",
                     "four balls on a square joined by its sides and both diagonals (a closed "
                     "loop with one bar too many), hung by a corner; dt 1/240" +
                         std::string(cfm > 0.0 ? ", cfm 1e-6 kg^-1" : ""),
                     means,
                     [cfm] { return braced_square(cfm); },
                     480,
                     kDistanceSolvers,
                     {},
                     constraints_hold(0.5, 0.01)});
    cases.push_back({"row-twice" + tag,
                     "redundant",
                     "a 1 m pendulum whose distance constraint is given twice (the same row "
                     "twice in J); dt 1/240" +
                         std::string(cfm > 0.0 ? ", cfm 1e-6 kg^-1" : ""),
                     means,
                     [cfm] { return row_twice(cfm); },
                     480,
                     kDistanceSolvers,
                     {},
                     constraints_hold(1.0, 0.01)});
  }
}

void add_degenerate_cases(std::vector<StressCase>& cases) {
  for (const double cfm : {0.0, 1e-6}) {
    cases.push_back(
        {std::string("near-coincident-anchors") + (cfm > 0.0 ? "+cfm" : ""),
         "near-degenerate",
         "a 0.1 kg ball hung from two fixed points 1e-7 m apart, 1 m strings to the same point "
         "of the ball (two rows that differ by 1e-7), released at 60°; dt 1/240" +
             std::string(cfm > 0.0 ? ", cfm 1e-6 kg^-1" : ""),
         "the strings hold to 1 % of their length and the energy never rises by more than 5 % "
         "of m g L: A's two rows are almost parallel (condition ~1e15), the split of lambda "
         "between them is arbitrary but v2 is not",
         [cfm] {
           Scene s = builtin("chain", {{"n", "1"}, {"link_length", "1"}});
           s.name = "near-coincident-anchors";
           s.solver.cfm = cfm;
           const double theta = std::acos(-1.0) / 3.0;
           s.bodies[0].x = Vec3(std::sin(theta), -std::cos(theta), 0.0);
           DistanceConstraint twin = s.distances.front();
           twin.name = "joint0-near";
           twin.anchor_a = Vec3(1e-7, 0.0, 0.0);
           twin.length = (s.bodies[0].x - twin.anchor_a).norm();
           s.distances.push_back(twin);
           return s;
         },
         480,
         kDistanceSolvers,
         {},
         constraints_hold(1.0, 0.01, 0.1 * 9.81 * 1.0, 0.05)});
  }
  cases.push_back(
      {"edge-edge-parallel",
       "near-degenerate",
       "a box balanced edge-down on the top edge of a fixed box turned 45°, the two edges "
       "1e-6 rad from parallel; it slides off the ridge (no ground); 1 s at dt 1/60, mu 0.5",
       "no explosion and no sinking: deepest contact ≤ 1 cm, energy never above the start by "
       "more than 1 % of m g h; the separating axis of two almost parallel edges is the cross "
       "product of nearly equal vectors, the classic source of wild normals",
       [] {
         Scene s = builtin("stack", {{"n", "1"}});
         s.name = "edge-edge-parallel";
         s.bodies.erase(s.bodies.begin());  // no ground: only the edge contacts are judged
         const Quat ridge_q(Eigen::AngleAxisd(std::acos(-1.0) / 4.0, Vec3::UnitZ()));
         Body ridge = box_body("ridge", Vec3(0.5, 0.5, 1.0), 1.0, Vec3::Zero());
         ridge.is_static = true;
         ridge.q = ridge_q;
         const double top = 0.5 * std::sqrt(2.0);
         Body& top_box = s.bodies[0];
         top_box.shape.half_extents = Vec3(0.5, 0.5, 1.0);
         set_mass(top_box, 1.0);
         top_box.q = Quat(Eigen::AngleAxisd(1e-6, Vec3::UnitY())) * ridge_q;
         top_box.x = Vec3(0.0, 2.0 * top, 0.0);
         s.bodies.insert(s.bodies.begin(), ridge);
         return s;
       },
       60,
       kContactSolvers,
       {},
       [](const Scene&) -> std::unique_ptr<StressProbe> {
         return std::make_unique<ContactSanityProbe>(9.81 * 1.0 * 1.0);
       }});
}

void add_far_cases(std::vector<StressCase>& cases) {
  const Vec3 far(1e6, 1e6, 1e6);
  cases.push_back({"far-stack",
                   "far from origin",
                   "5 boxes in a column with everything moved by 1e6 m along x, y and z "
                   "(position ulp 1.2e-10 m); dt 1/60, mu 0.5",
                   kRestMeans,
                   [far] {
                     return translated(builtin("stack", {{"n", "5"}}), far);
                   },
                   120,
                   kContactSolvers,
                   {},
                   rest_of_last(0.01, 0.01)});
  cases.push_back({"far-chain",
                   "far from origin",
                   "10 links released horizontally, everything moved by 1e6 m along x, y, z; "
                   "1 s at dt 1/2400",
                   kChainMeans,
                   [far] {
                     return translated(builtin("chain", {{"n", "10"}, {"dt", "1/2400"}}), far);
                   },
                   2400,
                   kDistanceSolvers,
                   {},
                   constraints_hold(0.1, 0.01)});
}

void add_inertia_cases(std::vector<StressCase>& cases) {
  cases.push_back(
      {"thin-rod",
       "extreme inertia",
       "a 1 m rod 1 mm thick (inertia ratio 2e5) hung by a 0.1 m string from one end, spinning "
       "at 100 rad/s about its axis, released horizontally; dt 1/240",
       "the string holds to 1 % of its length and the energy never rises by more than 5 % of "
       "m g L (L = 0.6 m, the drop of the rod's centre)",
       [] {
         Scene s;
         s.name = "thin-rod";
         s.world.dt = 1.0 / 240.0;
         Body rod = box_body("rod", Vec3(0.5, 5e-4, 5e-4), 1.0, Vec3(0.6, 0.0, 0.0));
         rod.collides = false;
         rod.set_velocity(Vec3::Zero(), Vec3(100.0, 0.0, 0.0));
         s.bodies.push_back(rod);
         DistanceConstraint string;
         string.name = "string";
         string.a = -1;
         string.b = 0;
         string.anchor_b = Vec3(-0.5, 0.0, 0.0);
         string.length = 0.1;
         s.distances.push_back(string);
         return s;
       },
       480,
       kDistanceSolvers,
       {},
       constraints_hold(0.1, 0.01, 9.81 * 0.6, 0.05)});
  cases.push_back({"flat-plate",
                   "extreme inertia",
                   "a 1 m × 1 m plate 1 mm thick (inertia ratio 2:1:1 over a 1e-6 thin axis) "
                   "dropped from 0.1 m tilted 5°; dt 1/60, mu 0.5",
                   "it lands and comes to rest on the ground: at the end (2 s) its centre "
                   "within 1 mm of half its thickness, speed ≤ 1 cm/s, spin ≤ 0.1 rad/s (the "
                   "landing itself sinks it by about the speed times dt, as any impact)",
                   [] {
                     Scene s = builtin("stack", {{"n", "1"}});
                     s.name = "flat-plate";
                     Body& plate = s.bodies[1];
                     plate.shape.half_extents = Vec3(0.5, 5e-4, 0.5);
                     set_mass(plate, 1.0);
                     plate.q =
                         Quat(Eigen::AngleAxisd(5.0 * std::acos(-1.0) / 180.0, Vec3::UnitX()));
                     plate.x = Vec3(0.0, 0.15, 0.0);
                     return s;
                   },
                   120,
                   kContactSolvers,
                   {},
                   [](const Scene&) -> std::unique_ptr<StressProbe> {
                     return std::make_unique<PlateProbe>(1, 1e-3);
                   }});
  for (const char* dt : {"1/240", "1e-4"}) {
    double h = 0.0;
    parse_number(dt, h);
    const long steps = std::llround(10.0 / h);
    cases.push_back(
        {std::string("dzhanibekov-dt-") + (h > 1e-3 ? "1/240" : dt),
         "extreme inertia",
         std::string("a free box 1 × 0.5 × 0.2 m spun at 10 rad/s about its intermediate axis "
                     "with a 1e-3 perturbation, no gravity, 10 s at dt ") +
             dt + " s (no rows: the integrator of 3.2 alone)",
         "the flips of the intermediate axis come at GSL's reference interval within 5 %, the "
         "angular momentum is kept to 1e-9 and the kinetic energy to 1 %",
         [h] {
           Scene s;
           s.name = "dzhanibekov";
           s.world.gravity = Vec3::Zero();
           s.world.dt = h;
           Body body = box_body("tee", Vec3(0.5, 0.25, 0.1), 1.0, Vec3::Zero());
           body.collides = false;
           body.set_velocity(Vec3::Zero(), Vec3(1e-2, 10.0, 1e-2));
           s.bodies.push_back(body);
           return s;
         },
         steps,
         {"-"},
         {},
         [steps](const Scene& s) -> std::unique_ptr<StressProbe> {
           return std::make_unique<DzhanibekovProbe>(s, steps);
         }});
  }
}

}  // namespace

std::vector<StressCase> stress_catalogue() {
  std::vector<StressCase> cases;
  add_mass_ratio_cases(cases);
  add_size_cases(cases);
  add_time_step_cases(cases);
  add_impact_cases(cases);
  add_redundant_cases(cases);
  add_degenerate_cases(cases);
  add_far_cases(cases);
  add_inertia_cases(cases);
  return cases;
}

StressResult run_stress(const StressCase& c,
                        const std::string& solver,
                        double budget_s,
                        const std::function<void(long, long)>& progress,
                        Integrator integrator) {
  StressResult r;
  r.case_name = c.name;
  r.solver = solver;
  r.integrator = integrator;
  r.steps = c.steps;
  Scene scene = c.build();
  scene.world.integrator = integrator;
  if (solver != "-")
    apply_solver_spec(parse_solver_spec(solver, "stress case " + c.name), scene.solver);
  r.cfm = scene.solver.cfm;
  const std::unique_ptr<StressProbe> probe = c.probe(scene);
  Simulation sim(std::move(scene));
  probe->start(sim);
  /// The probe after each step, progress, and the wall-time budget.
  class Watch : public StepObserver {
   public:
    Watch(StressProbe& probe,
          const std::function<void(long, long)>& progress,
          long steps,
          double budget_s)
        : probe_(probe), progress_(progress), steps_(steps), budget_s_(budget_s) {}
    bool after_step(const Simulation& sim, const StepReport& report, long done) override {
      probe_.after_step(sim, report);
      if (progress_) progress_(done, steps_);
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() <=
             budget_s_;
    }

   private:
    StressProbe& probe_;
    const std::function<void(long, long)>& progress_;
    long steps_;
    double budget_s_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  } watch(*probe, progress, c.steps, budget_s);
  const RunTotals t = run_steps(sim, c.steps, {&watch});
  r.steps_done = t.steps_done;
  r.max_rows = t.max_rows;
  r.max_constraint_error = t.max_constraint_error;
  r.max_penetration = t.max_penetration;
  r.final_residual = t.final_residual;
  r.max_residual = t.max_residual;
  r.cfm_acceleration_error = t.cfm_acceleration_error;
  r.energy_initial = t.energy_initial;
  r.wall_time_s = t.wall_time_s;
  if (t.diverged) {
    r.status = "diverged";
    r.note = t.diverged->what();
  } else if (t.stopped) {
    r.status = "budget";
    r.note = "stopped after " + std::to_string(t.steps_done) + " of " + std::to_string(c.steps) +
             " steps: the wall-time budget of " + format(budget_s) + " s was spent";
  }
  r.energy_final = sim.energy();
  // of the matrix the solvers work on: A + eps E with constraint-force mixing
  r.condition = estimate_condition(with_cfm(sim.build_system().A, scene.solver.cfm));
  r.verdict = probe->finish(sim);
  if (r.status.empty()) r.status = r.verdict.stable ? "stable" : "unstable";
  return r;
}

namespace {

std::string sci(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", x);
  return buf;
}

/// A divergence message without its "step N (t = …), system:" head (the table shows the step).
std::string short_divergence(const std::string& message) {
  const auto colon = message.find("): ");
  return colon == std::string::npos ? message : "guard: " + message.substr(colon + 3);
}

}  // namespace

nlohmann::json stress_result_json(const StressResult& r) {
  nlohmann::json j;
  j["case"] = r.case_name;
  j["solver"] = r.solver;
  j["integrator"] = integrator_names().at(static_cast<std::size_t>(r.integrator));
  j["status"] = r.status;
  if (!r.note.empty()) j["note"] = r.note;
  if (r.status == "skipped") return j;
  j["steps"] = r.steps;
  j["steps_done"] = r.steps_done;
  j["max_rows"] = r.max_rows;
  j["max_constraint_error_m"] = number_json(r.max_constraint_error);
  j["max_penetration_m"] = number_json(r.max_penetration);
  j["energy_initial_J"] = number_json(r.energy_initial);
  j["energy_final_J"] = number_json(r.energy_final);
  j["energy_change_J"] = number_json(r.energy_final - r.energy_initial);
  j["final_residual_N"] = number_json(r.final_residual);
  j["max_residual_N"] = number_json(r.max_residual);
  j["condition"] = {{"value", number_json(r.condition.condition)},
                    {"lambda_max", number_json(r.condition.lambda_max)},
                    {"lambda_min", number_json(r.condition.lambda_min)},
                    {"range_condition", number_json(r.condition.range_condition)},
                    {"nullity", r.condition.nullity},
                    {"exact", r.condition.exact},
                    {"method", r.condition.method}};
  if (r.cfm > 0.0) {
    j["regularization"] = {{"cfm", r.cfm},
                           {"max_acceleration_error", number_json(r.cfm_acceleration_error)}};
  }
  j["wall_time_s"] = r.wall_time_s;
  j["stable"] = r.status == "stable";
  j["measure"] = r.verdict.measure;
  nlohmann::json extra = nlohmann::json::object();
  for (const auto& [name, value] : r.verdict.extra) extra[name] = number_json(value);
  j["measured"] = extra;
  return j;
}

std::string stress_table(const std::vector<StressResult>& results) {
  const std::vector<std::string> header = {"case",
                                           "solver",
                                           "stable",
                                           "max |c| m",
                                           "max pen. m",
                                           "ΔE J",
                                           "residual N",
                                           "cond(A)",
                                           "wall s",
                                           "judged on"};
  std::vector<std::vector<std::string>> rows;
  for (const StressResult& r : results) {
    if (r.status == "skipped") {
      rows.push_back({r.case_name, r.solver, "skipped", "", "", "", "", "", "", r.note});
      continue;
    }
    std::string stable = r.status == "stable" ? "yes" : r.status == "unstable" ? "NO" : r.status;
    if (r.status == "diverged" || r.status == "budget")
      stable += " @" + std::to_string(r.steps_done);
    std::string cond = sci(r.condition.condition);
    if (!r.condition.exact) cond += "~";
    if (r.condition.nullity > 0) cond += " (null " + std::to_string(r.condition.nullity) + ")";
    rows.push_back({r.case_name,
                    r.solver,
                    stable,
                    sci(r.max_constraint_error),
                    sci(r.max_penetration),
                    sci(r.energy_final - r.energy_initial),
                    sci(r.final_residual),
                    cond,
                    sci(r.wall_time_s),
                    r.status == "diverged" ? short_divergence(r.note) : r.verdict.measure});
  }
  std::ostringstream out;
  const auto line = [&](const std::vector<std::string>& cells) {
    out << "|";
    for (const std::string& cell : cells) {
      out << " ";
      for (const char ch : cell) {
        if (ch == '|') out << '\\';  // a Markdown table cell keeps its |c| and |ΔL|
        out << ch;
      }
      out << " |";
    }
    out << "\n";
  };
  line(header);
  out << "|";
  for (std::size_t k = 0; k < header.size(); ++k) out << (k >= 3 && k <= 8 ? "---:|" : "---|");
  out << "\n";
  for (const auto& row : rows) line(row);
  return out.str();
}

std::vector<StressResult> run_stress_catalogue(const std::vector<StressCase>& cases,
                                               const std::function<bool(const std::string&)>& kept,
                                               double budget_s,
                                               const StressProgress& progress,
                                               Integrator integrator) {
  std::size_t total = 0;
  for (const StressCase& c : cases)
    total += static_cast<std::size_t>(std::count_if(c.solvers.begin(), c.solvers.end(), kept));
  std::vector<StressResult> results;
  std::size_t done = 0;
  for (const StressCase& c : cases) {
    for (const std::string& solver : c.solvers) {
      if (!kept(solver)) continue;
      ++done;
      const auto step_progress = [&](long step, long steps) {
        if (progress) progress(done, total, c, solver, step, steps, nullptr);
      };
      results.push_back(run_stress(c, solver, budget_s, step_progress, integrator));
      if (progress) progress(done, total, c, solver, c.steps, c.steps, &results.back());
    }
    for (const auto& [solver, why] : c.skipped) {
      if (!kept(solver)) continue;
      StressResult r;
      r.case_name = c.name;
      r.solver = solver;
      r.integrator = integrator;
      r.status = "skipped";
      r.note = why;
      results.push_back(std::move(r));
    }
  }
  return results;
}

nlohmann::json stress_report_json(const std::vector<StressCase>& cases,
                                  const std::vector<StressResult>& results,
                                  double wall_time_s) {
  nlohmann::json report;
  report["cases"] = nlohmann::json::array();
  for (const StressCase& c : cases) {
    report["cases"].push_back({{"name", c.name},
                               {"group", c.group},
                               {"description", c.description},
                               {"stable_means", c.stable_means},
                               {"steps", c.steps}});
  }
  report["results"] = nlohmann::json::array();
  int stable = 0, unstable = 0, diverged = 0, other = 0;
  for (const StressResult& r : results) {
    report["results"].push_back(stress_result_json(r));
    if (r.status == "stable")
      ++stable;
    else if (r.status == "unstable")
      ++unstable;
    else if (r.status == "diverged")
      ++diverged;
    else
      ++other;
  }
  report["counts"] = {
      {"stable", stable}, {"unstable", unstable}, {"diverged", diverged}, {"other", other}};
  report["wall_time_s"] = wall_time_s;
  return report;
}

std::string stress_markdown(const std::vector<StressCase>& cases,
                            const std::vector<StressResult>& results) {
  std::ostringstream md;
  md << "# cbps stress\n\n" << stress_table(results) << "\n## What stable means\n\n";
  for (const StressCase& c : cases)
    md << "- **" << c.name << "** (" << c.description << "): " << c.stable_means << "\n";
  return md.str();
}

}  // namespace cbps
