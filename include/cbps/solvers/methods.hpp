// The one table of methods: each method's entry (its name, what it is, what it takes, the
// function that solves with it), every name the command line, scene files and the Python module
// accept (`--solver NAME[:OMEGA][:key=value]...`, a scene's "method" and "parameters"), and each
// method's own parameters with their checks (MethodSettings, method_settings.hpp). solve()
// dispatches through it; solver.hpp's to_string, method_from_string and the trait questions
// (is_iterative, needs_symmetric, takes_cones, ...) read it.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// Whose code a method runs: cbps's own, or a peer library's (peers/peers.hpp).
enum class Library { Cbps, Siconos, Bullet };

/// The cone laws a method takes (base/friction_law.hpp), as bits of MethodEntry::laws.
inline constexpr unsigned kRelaxationLaw = 1;  ///< the convex relaxation (FrictionLaw::Relaxation)
inline constexpr unsigned kCoulombLaw = 2;     ///< Coulomb's law (FrictionLaw::CoulombCone)
inline constexpr unsigned kEitherLaw = kRelaxationLaw | kCoulombLaw;

/// A method's own key=value: the key, what it accepts (for messages) and its setter (false for a
/// value out of range), over the method's settings (method_settings.hpp). Each method's keys
/// are written beside its code, in its entry.
struct MethodKey {
  std::string_view key;
  std::string_view accepts;
  bool (*set)(const std::string& value, MethodSettings& settings);
  std::string (*get)(const MethodSettings& settings);  ///< as the grammar writes it
};
/// The pieces keys are made of: x as the grammar reads it back (the shortest text that does),
/// and a whole number ≥ 1 (a count of sweeps or iterations) read into out.
std::string key_number(double x);
bool key_count(const std::string& value, int& out);

/// One method: its own name, its traits, its solve function and its own keys. The traits'
/// meanings are the questions of solver.hpp that read them.
struct MethodEntry {
  Method method;
  std::string_view name;        ///< its own name (to_string); aliases are apart (method_table)
  bool omega = false;           ///< takes :OMEGA (relaxation_in_range)
  bool damping = false;         ///< its OMEGA damps, in (0, 1] (else SOR's range, (0, 2))
  bool order = false;           ///< takes order=
  bool contacts_first = false;  ///< takes contacts_first= (SweepOrder, pgs.hpp)
  bool iterative = true;        ///< runs to a sweep limit (is_iterative)
  Library library = Library::Cbps;
  bool needs_jacobian = false;  ///< reads J and Minv (needs_jacobian)
  /// Sweeps J Minv Jᵀ itself, never A: CFM goes on its own diagonal, and solve() checks that
  /// J Minv Jᵀ is A.
  bool sweeps_factors = false;
  /// Its sweep depends on nothing but lambda and the problem (no momentum, dual or loop of its
  /// own): the Coulomb box may move the bounds between two sweeps (paper/coulomb.hpp).
  bool sweeps_alone = false;
  bool reads_A = true;              ///< reads A's entries on the boxed problem (reads_A)
  bool reads_A_on_cones = true;     ///< ... on friction cones
  bool symmetric = false;           ///< needs a symmetric A on the boxed problem (needs_symmetric)
  bool symmetric_on_cones = false;  ///< ... on friction cones
  unsigned laws = 0;                ///< the cone laws it takes (takes_cones, takes_cone_law)
  long max_rows = 0;                ///< the most rows it takes (a dense copy of A), 0: any
  std::string_view rows_why{};      ///< why max_rows holds, for the refusal's message
  bool pivots = false;              ///< its iterations are pivots (counts_pivots)
  /// The method on a whole problem as it is (no CFM, no islands: solve() does those).
  SolverSummary (*solve)(const BoxedProblem& problem,
                         VecX& lambda,
                         const SolverOptions& options) = nullptr;
  /// Why it cannot take this problem beyond the traits above, or "" where it can (a peer's own
  /// limits: siconos:avi takes no free row, bullet:dantzig needs cmin <= 0 <= cmax); null: none.
  std::string (*refuse)(const BoxedProblem& problem) = nullptr;
  std::string_view what;              ///< one line for --help
  std::span<const MethodKey> keys{};  ///< its own key=value, written beside it; none: {}
};

/// Every method's entry, in the order --help lists them. Each is written beside its code (the
/// file that solves with it defines `const MethodEntry k<Method>Entry`); methods.cpp gathers
/// them: a new method is its file pair with its entry, its enumerator (solver.hpp), its two
/// lines in that list and a test.
std::span<const MethodEntry* const> method_entries();
/// Every method, in that order.
std::vector<Method> all_methods();
/// The entry of a method.
const MethodEntry& method_entry(Method method);

/// A name the grammar accepts: the method it selects, what it takes, and one line for --help.
/// A method's first name is its own (to_string); a later one is an alias (psor).
struct MethodName {
  std::string_view name;
  Method method;
  bool omega;  ///< takes :OMEGA (relaxation_in_range of the method)
  bool order;  ///< takes order=
  std::string_view what;
};

/// Every name, in the order --help lists them: each method's own, an alias after its method.
std::span<const MethodName> method_table();
/// The entry of a name, or null.
const MethodName* find_method_name(std::string_view name);

/// The key of a method, or null.
const MethodKey* find_method_key(Method method, std::string_view key);

/// A method's own parameters as key and value text, the way the grammar writes them
/// (`apgd`: grow 2, shrink 0.9, restart on); none for the methods without.
std::vector<std::pair<std::string, std::string>> method_parameters(Method method,
                                                                   const MethodSettings& settings);

/// "on" or "off" as a bool; false for anything else.
bool on_off(const std::string& value, bool& out);
/// A warm-start factor: on (1), off (0) or a number in [0, 1]; false for anything else.
bool warm_factor(const std::string& value, double& out);

}  // namespace cbps
