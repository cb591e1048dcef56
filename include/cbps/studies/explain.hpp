// What `cbps explain` shows of one step: the system with its labels and units, and the report of
// its solution (teaching_system, the same the teaching page draws), as text or JSON.
//
// Everything needed to redo the step by hand is there: J, Minv, v1, fext, upsilon and dt give
// A = J Minv J^T and b = upsilon/dt − J (v1/dt + Minv fext) (6.2.9); lambda with cmin, cmax and
// w = A lambda − b shows which rows are free and which sit at a bound (6.2); v2 follows by
// 12.3.1.
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cbps/step/simulation.hpp"
#include "cbps/studies/teaching_page.hpp"

namespace cbps {

/// The most matrix entries explain prints (its dense J, Minv and A together; 8 bytes each, and
/// several copies as text and JSON).
inline constexpr double kMaxExplainEntries = 4e6;

/// What the bounds of Coulomb friction rows are, and what CFM is, in explain's words.
inline constexpr const char* kCoulombNote =
    "Coulomb friction rows: bounds -mu lambda_n, +mu lambda_n at the fixed point lambda "
    "satisfies (5.4)";
inline constexpr const char* kConeNote =
    "contacts in Coulomb's cone |lambda_t| <= mu lambda_n (docs/cones.md): their three rows "
    "(normal, t1, t2) share the contact's status, separated, sticking or sliding, met when "
    "|lambda - P_K(lambda - u^)| is within the tolerance; cmin and cmax of those rows are not used";
inline constexpr const char* kCfmNote =
    "constraint-force mixing, a solver setting: the solve used A + eps E; A is J Minv J^T";

/// The coordinate of a column label "<body>.vx" … "<body>.wz": true for wx, wy, wz.
bool angular_column(const std::string& label);

/// What `cbps explain` shows of one step, as text or JSON: the system and the report of its
/// solution (teaching_system, the same the teaching page draws).
struct Explained {
  std::string scene;
  long step = 0;
  double t = 0.0;
  std::string method;  ///< the scene's solver
  double cfm = 0.0;    ///< kg⁻¹
  System sys;
  std::vector<std::string> cols;  ///< J's column labels
  TeachingSystem shown;           ///< the system shown, solved as the step solves it
  /// The tolerance rows are judged within: the requested one, or w's rounding floor if larger.
  double tol = 0.0;
  bool all_satisfied = true;
  bool coulomb = false;   ///< Coulomb friction rows: their bounds are those of the fixed point
  bool improved = false;  ///< the improved push (8.1): the velocity system is shown
  Integrator integrator = Integrator::Paper;  ///< gyroscopic: v1 took Bullet's step (body.hpp)
  SchemeSettings scheme;                      ///< a substepping scheme: its first substep is shown
  std::string A_unit, system_shown;
  std::vector<std::string> v_units, f_units;  ///< of the columns (velocities, forces)
};

/// What a scheme's softness is, wherever it is shown.
inline constexpr const char* kSoftnessNote =
    "what the step scheme adds to A's diagonal (docs/schemes.md), kept apart from A: the system "
    "that carries the push solves (A + diag(softness)) lambda = b; 0 for a rigid row";

/// What the system shown is under a substepping scheme (its first substep).
std::string scheme_note(const SchemeSettings& scheme);

/// The explanation of step `at_step` of `scene` (a new Simulation stepped there, progress as
/// step_to's); InputError, naming the sizes, when its dense J, Minv and A would be more than
/// kMaxExplainEntries numbers.
Explained explain_step(const Scene& scene, long at_step);

/// The teaching page's step `at_step` of `scene` (a new Simulation stepped there, progress as
/// step_to's), labelled by the scene's bodies: teaching_step of that simulation. On friction
/// cones the shown systems are solved exactly (`direct`) where the scene's method sweeps, unless
/// `method_chosen` (the user named the method: the page shows what it does).
TeachingStep teaching_step(const Scene& scene, long at_step, bool method_chosen);

/// `cbps explain --json`: every block with its equation, unit and value.
nlohmann::json explain_json(const Explained& e);

/// `cbps explain`'s text: J, Minv, A (dense when narrow, else their nonzeros), v1, fext,
/// upsilon, b, lambda against its bounds with w and each row's status, v2 and the solver's
/// message, labelled, with units and equation numbers (explain_text.cpp).
void print_explain_text(std::FILE* out, const Explained& e);

}  // namespace cbps
