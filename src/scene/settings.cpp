// The world's and the solver's settings, one entry each (settings.hpp).
#include "cbps/scene/settings.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/methods.hpp"

namespace cbps {

namespace {

const std::vector<std::string>& push_names() {
  static const std::vector<std::string> names{"original", "improved"};  // PushMode order
  return names;
}
const std::vector<std::string>& friction_names() {
  static const std::vector<std::string> names{"paper", "coulomb", "cone"};  // friction_name
  return names;
}
const std::vector<std::string>& cone_law_names() {
  static const std::vector<std::string> names{"coulomb", "ccp"};  // cone_law_name
  return names;
}

bool under_soft_step(const World& w) { return w.scheme.kind == Scheme::SoftStep; }
bool under_xpbd(const World& w) { return w.scheme.kind == Scheme::Xpbd; }
bool under_substeps(const World& w) { return w.scheme.kind != Scheme::Paper; }
bool under_cones(const World& w) { return is_cone(w.friction); }

template <typename E>
E word(double index) {
  return static_cast<E>(static_cast<int>(index));
}

void set_scheme(World& w, double index) {
  const auto kind = word<Scheme>(index);
  if (kind != w.scheme.kind) w.scheme.substeps = kind == Scheme::Paper ? 1 : kSchemeSubsteps;
  w.scheme.kind = kind;
}

// clang-format off
const WorldSetting kWorldSettings[] = {
    {.key = "dt", .unit = "s", .above_min = true, .fraction = true, .option = true, .default_text = "`1/240`",
     .rule = "time step; a fraction \"p/q\" such as \"1/240\" is p / q",
     .get = [](const World& w) { return w.dt; },
     .set = [](World& w, double v) { w.dt = v; }},
    {.key = "beta", .max = 1.0, .option = true,
     .rule = "Baumgarte push factor (5.2.3, 5.3)",
     .get = [](const World& w) { return w.beta; },
     .set = [](World& w, double v) { w.beta = v; }},
    {.key = "push", .type = SettingType::Word, .words = push_names, .noun = "push mode",
     .option = true,
     .rule = "the push factor's form: `original` (Baumgarte in the one system, 5.2.3, 5.3) or "
             "`improved` (8.1: a velocity system, then a position system that only moves the "
             "bodies)",
     .get = [](const World& w) { return double(w.push); },
     .set = [](World& w, double v) { w.push = word<PushMode>(v); }},
    {.key = "integrator", .type = SettingType::Word, .words = integrator_names,
     .noun = "integrator", .option = true,
     .rule = "how a step turns the bodies: `paper` (3.2, explicit turn), `gyroscopic` (Bullet's "
             "implicit gyroscopic step) or `midpoint` (implicit midpoint, keeps energy and L); "
             "docs/integrators.md",
     .get = [](const World& w) { return double(w.integrator); },
     .set = [](World& w, double v) { w.integrator = word<Integrator>(v); }},
    {.key = "scheme", .type = SettingType::Word, .words = scheme_names, .noun = "scheme",
     .option = true,
     .rule = "how a step advances time: `paper` (one solve a step), `tgs` (temporal "
             "Gauss-Seidel: substeps), `soft-step` (Box2D v3's soft step) or `xpbd` (linear "
             "XPBD); docs/schemes.md. Naming another scheme sets substeps to its default",
     .get = [](const World& w) { return double(w.scheme.kind); },
     .set = set_scheme},
    {.key = "substeps", .type = SettingType::Whole, .min = 1.0,
     .max = double(std::numeric_limits<int>::max()), .option = true,
     .default_text = "1 under `paper`, 4 otherwise",
     .rule = "substeps N a step under `tgs`, `soft-step`, `xpbd`, each solving the paper's "
             "system with dt/N; more than 1 needs one of those schemes",
     .get = [](const World& w) { return double(w.scheme.substeps); },
     .set = [](World& w, double v) { w.scheme.substeps = static_cast<int>(v); },
     .check = [](const World& w, double v) -> std::string {
       if (w.scheme.kind == Scheme::Paper && v != 1.0)
         return "needs a scheme that substeps (tgs, soft-step, xpbd), not paper";
       return {};
     }},
    {.key = "contact_hertz", .unit = "Hz", .applies = under_soft_step, .applies_text = "scheme soft-step", .option = true,
     .rule = "contact stiffness, at most a quarter of the substep rate; twice this against a "
             "static body",
     .get = [](const World& w) { return w.scheme.contact_hertz; },
     .set = [](World& w, double v) { w.scheme.contact_hertz = v; }},
    {.key = "contact_damping_ratio", .applies = under_soft_step, .applies_text = "scheme soft-step", .option = true,
     .rule = "contact damping ratio",
     .get = [](const World& w) { return w.scheme.contact_damping_ratio; },
     .set = [](World& w, double v) { w.scheme.contact_damping_ratio = v; }},
    {.key = "joint_hertz", .unit = "Hz", .applies = under_soft_step, .applies_text = "scheme soft-step", .option = true,
     .rule = "distance rows' stiffness (0: rigid rows with no push)",
     .get = [](const World& w) { return w.scheme.joint_hertz; },
     .set = [](World& w, double v) { w.scheme.joint_hertz = v; }},
    {.key = "joint_damping_ratio", .applies = under_soft_step, .applies_text = "scheme soft-step", .option = true,
     .rule = "distance rows' damping ratio",
     .get = [](const World& w) { return w.scheme.joint_damping_ratio; },
     .set = [](World& w, double v) { w.scheme.joint_damping_ratio = v; }},
    {.key = "max_push_speed", .unit = "m/s", .applies = under_soft_step, .applies_text = "scheme soft-step",
     .rule = "the most a contact's push asks",
     .get = [](const World& w) { return w.scheme.max_push_speed; },
     .set = [](World& w, double v) { w.scheme.max_push_speed = v; }},
    {.key = "compliance", .unit = "m/N", .applies = under_xpbd, .applies_text = "scheme xpbd",
     .option = true,
     .rule = "every row's compliance alpha, alpha/h^2 added to A's diagonal (friction rows stay "
             "rigid); 0: rigid",
     .get = [](const World& w) { return w.scheme.compliance; },
     .set = [](World& w, double v) { w.scheme.compliance = v; }},
    {.key = "speculative_distance", .unit = "m", .applies = under_substeps,
     .applies_text = "a scheme that substeps (tgs, soft-step, xpbd)",
     .rule = "contacts are found once a step, and pairs up to this far apart are kept (Box2D "
             "v3's speculative distance; the contact margin when larger)",
     .get = [](const World& w) { return w.scheme.speculative_distance; },
     .set = [](World& w, double v) { w.scheme.speculative_distance = v; }},
    {.key = "mu",
     .rule = "friction coefficient (5.4); 0: no friction rows",
     .get = [](const World& w) { return w.mu; },
     .set = [](World& w, double v) { w.mu = v; }},
    {.key = "friction", .type = SettingType::Word, .words = friction_names,
     .noun = "friction model",
     .rule = "`paper` (5.4: bounds +-mu m g_n, m the pair's movable mass shared over its "
             "contact points, g_n gravity along the normal), `coulomb` (bounds +-mu lambda_n "
             "of the same point) or `cone` (Coulomb's cone, norm(lambda_t) <= mu lambda_n per "
             "contact point, no box on the friction rows; solved by `nsgs` and `direct`, "
             "docs/cones.md)",
     // The law's box or cone: `cone` keeps a cone's law (the `cone` key's), else Coulomb's.
     .get = [](const World& w) { return is_cone(w.friction) ? 2.0 : double(w.friction); },
     .set =
         [](World& w, double v) {
           if (v < 2.0 || !is_cone(w.friction))
             w.friction = v < 2.0 ? word<FrictionLaw>(v) : FrictionLaw::CoulombCone;
         }},
    {.key = "cone", .type = SettingType::Word, .words = cone_law_names, .noun = "cone law",
     .applies = under_cones, .applies_text = "friction cone",
     .rule = "the cone's law: `coulomb` (Coulomb's law with De Saxce's term, FCLIB's) or `ccp` "
             "(the convex relaxation)",
     .get = [](const World& w) { return w.friction == FrictionLaw::Relaxation ? 1.0 : 0.0; },
     .set =
         [](World& w, double v) {
           w.friction = v == 1.0 ? FrictionLaw::Relaxation : FrictionLaw::CoulombCone;
         }},
    {.key = "restitution", .max = 1.0,
     .rule = "epsilon (8.2.1)",
     .get = [](const World& w) { return w.restitution; },
     .set = [](World& w, double v) { w.restitution = v; }},
    {.key = "restitution_threshold", .unit = "m/s",
     .rule = "approach speed below which a contact does not bounce (8.2)",
     .get = [](const World& w) { return w.restitution_threshold; },
     .set = [](World& w, double v) { w.restitution_threshold = v; }},
    {.key = "contact_margin", .unit = "m",
     .rule = "contacts are kept up to this separation (4); the built-in scenes' `margin` has the "
             "same default",
     .get = [](const World& w) { return w.contact_margin; },
     .set = [](World& w, double v) { w.contact_margin = v; }},
    {.key = "contact_persistence", .unit = "m",
     .rule = "a contact point found within this distance of where a point of the same pair sat "
             "on both bodies last step continues it, keeping its rows' ids and so their warm "
             "start (7; docs/contacts.md); 0: points are known again only by their clipping "
             "feature id; the built-in scenes' `persistence` has the same default",
     .get = [](const World& w) { return w.contact_persistence; },
     .set = [](World& w, double v) { w.contact_persistence = v; }},
    {.key = "divergence_speed", .unit = "m/s", .above_min = true,
     .rule = "a body faster than this stops the run as diverged (the step, body and row are "
             "named; exit 1, outputs up to that step kept)",
     .get = [](const World& w) { return w.divergence_speed; },
     .set = [](World& w, double v) { w.divergence_speed = v; }},
    {.key = "divergence_spin", .unit = "rad/s", .above_min = true,
     .rule = "the same for angular speed",
     .get = [](const World& w) { return w.divergence_spin; },
     .set = [](World& w, double v) { w.divergence_spin = v; }},
};

// The methods as words in the one table's order (all_methods(), methods.hpp), the order
// method_names() lists them in; a method's index there is its value as a setting.
const std::vector<std::string>& method_words() {
  static const std::vector<std::string> words = [] {
    std::vector<std::string> w;
    for (const Method m : all_methods()) w.emplace_back(to_string(m));
    return w;
  }();
  return words;
}
Method method_at(double index) { return all_methods().at(static_cast<std::size_t>(index)); }
double method_index(Method method) {
  const std::vector<Method> methods = all_methods();
  return double(std::find(methods.begin(), methods.end(), method) - methods.begin());
}
const std::vector<std::string>& row_order_words() {
  static const std::vector<std::string> words{"natural", "reverse", "random"};  // RowOrder order
  return words;
}

/// Why `method` cannot take contacts_first, or "".
std::string contacts_first_fits(Method method, bool contacts_first) {
  if (!contacts_first || method_entry(method).contacts_first) return {};
  return "applies to the methods pgs and matrix-free (method is \"" +
         std::string(to_string(method)) + "\")";
}

const SolverSetting kSolverSettings[] = {
    {.key = "method", .type = SettingType::Word, .words = method_words, .noun = "method",
     .default_text = "`\"pgs\"`; `\"nsgs\"` with `\"friction\": \"cone\"`",
     .rule = "the method: the names of `--solver`, one table for both "
             "(`include/cbps/solvers/methods.hpp`; `cbps run --help` lists them): `pgs` (7.1.1), "
             "its variants and accelerations (docs/convergence.md; their own parameters in "
             "`/solver/parameters`), the exact paths `direct`, `active-set`, `lemke`, `nsgs` "
             "(7.1.1 with each contact projected onto its friction cone, [cones.md](cones.md)), "
             "or a peer's solver (`siconos:...`, `bullet:...`, in a build with them, "
             "[peers.md](peers.md))",
     .get = [](const SolverSettings& v) { return method_index(v.method); },
     .set = [](SolverSettings& v, double x) { v.method = method_at(x); },
     .check = [](const SolverSettings& v, double x) -> std::string {
       const Method method = method_at(x);  // the settings given before it must fit it
       if (!relaxation_in_range(method, v.relaxation))
         return "takes a relaxation in " + std::string(relaxation_range(method)) + ", not " +
                number_text(v.relaxation);
       if (!contacts_first_fits(method, v.contacts_first).empty())
         return "takes no contacts_first (on here; pgs and matrix-free do)";
       return {};
     }},
    {.key = "iterations", .type = SettingType::Whole, .min = 1.0,
     .max = double(std::numeric_limits<int>::max()), .option = true,
     .rule = "max sweeps per step (the iterative methods)",
     .get = [](const SolverSettings& v) { return double(v.max_iterations); },
     .set = [](SolverSettings& v, double x) { v.max_iterations = static_cast<int>(x); }},
    {.key = "tolerance", .unit = "N", .option = true,
     .rule = "natural-map residual to stop at, for every method (0: all sweeps, and the direct "
             "path to its rounding floor; below that floor the direct path stops there once its "
             "steps no longer reduce the residual)",
     .get = [](const SolverSettings& v) { return v.tolerance; },
     .set = [](SolverSettings& v, double x) { v.tolerance = x; }},
    {.key = "delta_tolerance", .unit = "N",
     .rule = "max abs(delta lambda) in a sweep to stop at (0: off)",
     .get = [](const SolverSettings& v) { return v.delta_tolerance; },
     .set = [](SolverSettings& v, double x) { v.delta_tolerance = x; }},
    {.key = "relaxation", .above_min = true,
     .rule = "omega: in (0, 1] for `jacobi` (damping), in (0, 2) for the others (SOR), the same "
             "rule as `--solver NAME:OMEGA`",
     .get = [](const SolverSettings& v) { return v.relaxation; },
     .set = [](SolverSettings& v, double x) { v.relaxation = x; },
     .check = [](const SolverSettings& v, double x) {
       return relaxation_in_range(v.method, x)
                  ? std::string()
                  : "must be in " + std::string(relaxation_range(v.method));
     }},
    {.key = "order", .type = SettingType::Word, .words = row_order_words, .noun = "row order",
     .rule = "the row order of a Gauss-Seidel sweep (`pgs`, `matrix-free`): `natural`, "
             "`reverse` or `random` (a new permutation every sweep and step)",
     .get = [](const SolverSettings& v) { return double(v.order); },
     .set = [](SolverSettings& v, double x) { v.order = static_cast<RowOrder>(int(x)); }},
    {.key = "seed", .type = SettingType::Whole, .max = 9007199254740992.0, .option = true,
     .rule = "the seed of the random row order (`order` random)",
     .get = [](const SolverSettings& v) { return double(v.seed); },
     .set = [](SolverSettings& v, double x) { v.seed = static_cast<std::uint64_t>(x); }},
    {.key = "warm", .max = 1.0,
     .rule = "the warm-start factor F (7): each row starts the step from F times its lambda of "
             "the last step (matched by row id; a new row from 0). 1 is the paper's warm start, "
             "0 a cold start from lambda = 0",
     .get = [](const SolverSettings& v) { return v.warm; },
     .set = [](SolverSettings& v, double x) { v.warm = x; }},
    {.key = "warm_friction", .max = 1.0, .default_text = "`warm`",
     .rule = "the factor G of the friction rows (5.4) instead of F, e.g. `\"warm\": 0.85, "
             "\"warm_friction\": 0` as Bullet's solver",
     .get = [](const SolverSettings& v) { return v.warm_friction.value_or(v.warm); },
     .set = [](SolverSettings& v, double x) { v.warm_friction = x; },
     .given = [](const SolverSettings& v) { return v.warm_friction.has_value(); }},
    {.key = "contacts_first", .type = SettingType::Flag,
     .rule = "`pgs` and `matrix-free` only: every sweep visits the distance rows, then all "
             "contact normal rows, then all friction rows, each group in `order` (Bullet's "
             "order); `false`: each contact's friction rows right after its normal row",
     .get = [](const SolverSettings& v) { return v.contacts_first ? 1.0 : 0.0; },
     .set = [](SolverSettings& v, double x) { v.contacts_first = x != 0.0; },
     .check = [](const SolverSettings& v,
                 double x) { return contacts_first_fits(v.method, x != 0.0); }},
    {.key = "split_islands", .type = SettingType::Flag,
     .rule = "solve independent islands of A apart (the iterative methods)",
     .get = [](const SolverSettings& v) { return v.split_islands ? 1.0 : 0.0; },
     .set = [](SolverSettings& v, double x) { v.split_islands = x != 0.0; }},
    {.key = "cfm", .unit = "kg⁻¹", .option = true,
     .rule = "constraint-force mixing eps: every solver works on `A + eps E`, so redundant or "
             "near-parallel rows get a unique lambda; the answer then misses `A lambda = b` by "
             "`eps lambda`, which `cbps run` reports as `regularization` in summary.json",
     .get = [](const SolverSettings& v) { return v.cfm; },
     .set = [](SolverSettings& v, double x) { v.cfm = x; }},
};
// clang-format on

std::string join_words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

}  // namespace

std::span<const WorldSetting> world_settings() { return kWorldSettings; }
std::span<const SolverSetting> solver_settings() { return kSolverSettings; }

template <typename T>
std::string range_text(const Setting<T>& s) {
  if (s.type == SettingType::Word) return "one of " + join_words(s.words());
  if (s.type == SettingType::Flag) return "true or false";
  const std::string min = number_text(s.min);
  if (std::isfinite(s.max) && s.type == SettingType::Real)
    return "in [" + min + ", " + number_text(s.max) + "]";
  return (s.above_min ? "> " : ">= ") + min;
}

template <typename T>
std::string option_name(const Setting<T>& s) {
  std::string name = "--" + std::string(s.key);
  for (char& c : name)
    if (c == '_') c = '-';
  return name;
}

const WorldSetting* find_world_setting(std::string_view key) {
  for (const WorldSetting& s : kWorldSettings)
    if (s.key == key) return &s;
  return nullptr;
}

const SolverSetting* find_solver_setting(std::string_view key) {
  for (const SolverSetting& s : kSolverSettings)
    if (s.key == key) return &s;
  return nullptr;
}

World scene_file_world() {
  World world;
  world.contact_margin = kSceneContactMargin;
  world.contact_persistence = kSceneContactPersistence;
  return world;
}

template <typename T>
std::optional<double> setting_value(const Setting<T>& s, std::string_view text, std::string& why) {
  if (s.type == SettingType::Word) {
    const std::vector<std::string>& words = s.words();
    for (std::size_t k = 0; k < words.size(); ++k)
      if (words[k] == text) return static_cast<double>(k);
    why = "unknown " + std::string(s.noun) + " \"" + std::string(text) +
          "\" (valid: " + join_words(words) + ")";
    return std::nullopt;
  }
  if (s.type == SettingType::Flag) {
    if (text == "true" || text == "on") return 1.0;
    if (text == "false" || text == "off") return 0.0;
    why = "expected true or false";
    return std::nullopt;
  }
  double value = 0.0;
  if (!parse_number(std::string(text), value)) {
    why = s.type == SettingType::Whole ? "expected a whole number" : "expected a number";
    return std::nullopt;
  }
  return value;
}

namespace {

/// What the target has that a setting does not apply under, for messages.
std::string what_it_has(const World& world, const WorldSetting& s) {
  return "the world has " +
         (s.applies == under_cones
              ? "friction " + std::string(friction_name(world.friction))
              : "scheme " + scheme_names().at(static_cast<std::size_t>(world.scheme.kind)));
}
std::string what_it_has(const SolverSettings& solver, const SolverSetting&) {
  return "the method is " + std::string(to_string(solver.method));
}

}  // namespace

template <typename T>
std::string set_setting(T& target, const Setting<T>& s, double value) {
  if (!std::isfinite(value)) return "not a finite number";
  if (s.type == SettingType::Whole && std::trunc(value) != value) return "expected an integer";
  if (s.type == SettingType::Word) {
    if (value < 0.0 || value >= static_cast<double>(s.words().size()))
      return "not " + range_text(s);
  } else if (s.type == SettingType::Flag) {
    if (value != 0.0 && value != 1.0) return "expected true or false";
  } else {
    const bool low = s.above_min ? !(value > s.min) : !(value >= s.min);
    if (low || value > s.max)
      return s.type == SettingType::Whole && value > s.max ? "too large"
                                                           : "must be " + range_text(s);
  }
  if (s.applies != nullptr && !s.applies(target))
    return "a setting of " + std::string(s.applies_text) + "; " + what_it_has(target, s);
  if (s.check != nullptr)
    if (std::string why = s.check(target, value); !why.empty()) return why;
  s.set(target, value);
  return {};
}

template <typename T>
std::string set_setting_text(T& target, const Setting<T>& s, std::string_view text) {
  std::string why;
  const std::optional<double> value = setting_value(s, text, why);
  return value ? set_setting(target, s, *value) : why;
}

template <typename T>
std::string setting_text(const Setting<T>& s, const T& target) {
  const double value = s.get(target);
  if (s.type == SettingType::Word) return s.words().at(static_cast<std::size_t>(value));
  if (s.type == SettingType::Flag) return value != 0.0 ? "true" : "false";
  char digits[32];
  const auto end = std::to_chars(digits, digits + sizeof digits, value).ptr;  // shortest exact
  return std::string(digits, end);
}

namespace {

std::string quoted_words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "`" : ", `") + w + "`";
  return out;
}

template <typename T>
std::string settings_markdown(std::span<const Setting<T>> settings,
                              const T& defaults,
                              const std::string& prefix) {
  std::string out;
  for (const Setting<T>& s : settings) {
    std::string type = s.type == SettingType::Word    ? "string, one of " + quoted_words(s.words())
                       : s.type == SettingType::Flag  ? "boolean"
                       : s.type == SettingType::Whole ? "integer " + range_text(s)
                                                      : "number " + range_text(s);
    if (s.fraction) type += ", or a string `\"p/q\"`";
    const std::string value = setting_text(s, defaults);
    const std::string fallback = s.type == SettingType::Word   ? "`\"" + value + "\"`"
                                 : s.type == SettingType::Flag ? "`" + value + "`"
                                                               : value;
    std::string rule(s.rule);
    if (s.applies != nullptr) rule = "under " + std::string(s.applies_text) + ": " + rule;
    if (s.option) rule += "; `" + option_name(s) + "`";
    out += "| `" + prefix + std::string(s.key) + "` | " + type + " | " + std::string(s.unit) +
           " | " + (s.default_text.empty() ? fallback : std::string(s.default_text)) + " | " +
           rule + " |\n";
  }
  return out;
}

}  // namespace

std::string world_settings_markdown() {
  return settings_markdown(world_settings(), scene_file_world(), "/world/");
}

std::string solver_settings_markdown() {
  return settings_markdown(solver_settings(), SolverSettings{}, "/solver/");
}

template std::string range_text(const WorldSetting&);
template std::string range_text(const SolverSetting&);
template std::string option_name(const WorldSetting&);
template std::string option_name(const SolverSetting&);
template std::optional<double> setting_value(const WorldSetting&, std::string_view, std::string&);
template std::optional<double> setting_value(const SolverSetting&, std::string_view, std::string&);
template std::string set_setting(World&, const WorldSetting&, double);
template std::string set_setting(SolverSettings&, const SolverSetting&, double);
template std::string set_setting_text(World&, const WorldSetting&, std::string_view);
template std::string set_setting_text(SolverSettings&, const SolverSetting&, std::string_view);
template std::string setting_text(const WorldSetting&, const World&);
template std::string setting_text(const SolverSetting&, const SolverSettings&);

}  // namespace cbps
