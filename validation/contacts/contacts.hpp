// validate_contacts' cases (README.md, "Case 3"), one file each: the v-corner (v_corner.cpp),
// bounce, slide, overlap (with the push-factor figure), the column of boxes on a tilted plane
// and the 10-box stack by solver with its spectrum (stack.cpp). Each file runs its case, checks
// it, prints its Markdown table and writes its part of contacts.json; validate_contacts.cpp runs
// them in order.
#pragma once

#include <cmath>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

namespace contacts {

using cbps::Vec3;
using Failures = std::vector<std::string>;

inline const double kNaN = std::nan("");

/// A built-in scene with overrides and the solver to use ("pgs": the scene's settings).
cbps::Scene builtin(const std::string& name,
                    const std::map<std::string, std::string>& values,
                    const std::string& method);
/// The scene's duration in steps, at least 1.
long step_count(const cbps::Scene& scene);
/// v as "%.17g": a scene parameter that round-trips exactly.
std::string text(double v);
/// v printed with `format`, "—" when not finite (the tables).
std::string fmt(const char* format, double v);
/// Σ ½ m v² + ½ ω·Iω over the moving bodies, J.
double kinetic_energy(const cbps::Simulation& sim);
/// `[a, b, …]` of JSON numbers.
std::string json_array(const std::vector<double>& v);
/// "\n" after the last element of a JSON list, ",\n" after the others.
const char* list_end(std::size_t i, std::size_t size);

// ---- 1. v-corner (12.2) -------------------------------------------------------------------

struct Settled {
  double lambda1 = kNaN;  ///< left plane's contact row, N
  double lambda2 = kNaN;  ///< right plane's, N
  int sweeps_last = 0;    ///< solver iterations in the last step
  int sweeps_max = 0;
  double speed = 0.0;     ///< |v| of the sphere at the end, m/s
  int missing_steps = 0;  ///< steps in which a plane's contact was not found
};

struct VCorner {
  double phi_l_deg = 0.0, phi_r_deg = 0.0;
  std::string margin;                           ///< contact margin (4), m
  double lambda1_ref = 0.0, lambda2_ref = 0.0;  ///< N
  Settled direct, pgs;
  double error_direct = 0.0, error_pgs = 0.0;  ///< max |λ − λ_ref| / (m g)
};

std::vector<VCorner> run_v_corners();
void check_v_corners(const std::vector<VCorner>& runs, Failures& f);
void print_v_corners(const std::vector<VCorner>& runs);
void write_v_corners(std::ostream& j, const std::vector<VCorner>& runs);

// ---- 2. bounce (8.2.1) --------------------------------------------------------------------

struct Bounce {
  double eps = 0.0;
  std::string dt_inv;
  double h0 = 0.0;             ///< drop height of the lowest point, m
  std::vector<double> apex;    ///< first three rebound apexes of the lowest point, m
  std::vector<double> ratio;   ///< apex_k / apex_{k−1} (apex_0 = h0)
  double max_ratio_error = 0;  ///< max |ratio − ε²| / ε²
  /// max |v₊/v₋ − ε| over the impacts: v₋ the approach speed at the start of the step that
  /// found the contact (j_c v1 of 8.2.1), v₊ the speed after it.
  double max_speed_ratio_error = 0.0;
  int impacts = 0;  ///< steps with an approach faster than the restitution threshold
  int sweeps_max = 0;
};

std::vector<Bounce> run_bounces();
void check_bounces(const std::vector<Bounce>& runs, Failures& f);
void print_bounces(const std::vector<Bounce>& runs);
void write_bounces(std::ostream& j, const std::vector<Bounce>& runs);

// ---- 3. slide (5.4) -----------------------------------------------------------------------

struct Slide {
  double mu = 0.0;
  std::string dt_inv, method;
  double v0 = 0.0;
  double d_ref = 0.0, t_ref = 0.0;  ///< v0²/(2 μ g), v0/(μ g)
  double d_euler = 0.0;             ///< v0²/(2 μ g) − v0 dt/2 (semi-implicit Euler)
  double d = kNaN, t_stop = kNaN;   ///< measured
  double creep = kNaN;              ///< distance moved after t_stop, m
  double decel = kNaN;              ///< (v(T/4) − v(3T/4)) / (T/2), m/s²
  int sweeps_max = 0;
};

std::vector<Slide> run_slides();
void check_slides(const std::vector<Slide>& runs, Failures& f);
void print_slides(const std::vector<Slide>& runs);
void write_slides(std::ostream& j, const std::vector<Slide>& runs);

// ---- 4. overlap, the push-factor figure (8.1) ---------------------------------------------

struct BoxState {
  Vec3 x = Vec3::Zero();
  cbps::Quat q = cbps::Quat::Identity();
  Vec3 h = Vec3::Zero();  ///< half extents, m
};

struct Overlap {
  std::string push, method;
  double initial_overlap = 0.0;  ///< m
  double t_resolved = kNaN;      ///< first time the deepest contact ≤ 1 % of it, s
  double ke_resolved = kNaN;     ///< kinetic energy then, J
  double ke_injected = 0.0;      ///< max kinetic energy until t_resolved: what the push put in, J
  double ke_max = 0.0;           ///< max over the whole run, J
  double top_start = 0.0;        ///< top box centre height at t = 0, m
  double top_rest = 0.0;         ///< the same with the boxes exactly touching, m
  double top_max = 0.0;          ///< highest the top box's centre reached, m
  double t_top_max = 0.0;        ///< when, s
  double dt = 0.0;               ///< s
  double beta = 0.0, mu = 0.0;   ///< the scene's push factor and friction coefficient
  int sweeps_max = 0;
  std::vector<std::vector<BoxState>> states;  ///< per step (0 = begin), the boxes
  std::vector<double> ke;                     ///< per step, J
};

/// The overlap runs and the push-factor figure: begin, and both pushes when the original's top
/// box peaks (scene defaults, PGS).
struct Overlaps {
  std::vector<Overlap> runs;
  std::size_t figure_original = 0, figure_improved = 0;  ///< indices into runs
  double figure_time = 0.0;                              ///< s
  long figure_step = 0;
};

Overlaps run_overlaps();
void check_overlaps(const Overlaps& o, Failures& f);
void print_overlaps(const Overlaps& o);
void write_overlaps(std::ostream& j, const Overlaps& o);

// ---- 5. a column of boxes on a tilted plane: the paper's friction bound against Coulomb (5.4)

struct Column {
  int n = 0;
  std::string friction;
  double mu = 0.0, theta = 0.0;  ///< rad
  double duration = 0.0, dt = 0.0;
  double slip_bottom = 0.0;  ///< bottom box's displacement down the slope, m
  double slip_top = 0.0;     ///< top box's, m
  double tilt_deg = 0.0;     ///< largest rotation of a box from its start, deg
  bool predicted_slide = false;
  double predicted_slip = 0.0;  ///< ½ a t², a = g (sin θ − μ cos θ / n), paper bound only; m
  double predicted_slip_euler = 0.0;  ///< ½ a t (t + dt): semi-implicit Euler's x after t/dt steps
  int sweeps_max = 0;                 ///< the direct path's outer iterations, max over the steps
  int not_converged = 0;              ///< steps whose solve stopped short of its tolerance
  double wall_time_s = 0.0;           ///< of the whole run
};

std::vector<Column> run_columns();
void check_columns(const std::vector<Column>& runs, Failures& f);
void print_columns(const std::vector<Column>& runs);
void write_columns(std::ostream& j, const std::vector<Column>& runs);

// ---- 6. the 10-box stack at 20 sweeps (8.1, 7.1.1) -----------------------------------------

struct Stack {
  std::string method, push;
  double drift = 0.0;            ///< top box, horizontal, after 10 s, m
  double drift_vertical = 0.0;   ///< top box, m
  double max_penetration = 0.0;  ///< m
  double residual_last = 0.0;    ///< velocity system's natural-map residual, last step, N
  double wall_time_s = 0.0;
};

/// Why row-by-row PGS struggles there: the spectrum of the stack's A at rest (dense, 120 rows)
/// and the spectral radius of the Gauss-Seidel iteration matrix G = −(D + L)⁻¹ U on its range.
struct StackSpectrum {
  double mu = 0.0;
  int rows = 0;
  double eig_min = 0.0;  ///< smallest eigenvalue above 1e-9 of the largest, 1/kg
  double eig_max = 0.0;
  double rho = 0.0;  ///< largest |eigenvalue| of G below 1 − 1e-9 (1 is A's null space)
  double sweeps_per_decade = 0.0;  ///< ln 0.1 / ln rho
};

struct Stacks {
  std::vector<Stack> runs;
  std::vector<StackSpectrum> spectrum;
};

Stacks run_stacks();
void check_stacks(const Stacks& s, Failures& f);
void print_stacks(const Stacks& s);
void write_stacks(std::ostream& j, const Stacks& s);

}  // namespace contacts
