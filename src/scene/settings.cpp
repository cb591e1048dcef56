// The world's settings, one entry each (settings.hpp).
#include "cbps/scene/settings.hpp"

#include <charconv>
#include <cmath>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"

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
     .set = [](World& w, double v) { w.scheme.substeps = static_cast<int>(v); }},
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
// clang-format on

std::string join_words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

}  // namespace

std::span<const WorldSetting> world_settings() { return kWorldSettings; }

std::string range_text(const WorldSetting& s) {
  if (s.type == SettingType::Word) return "one of " + join_words(s.words());
  const std::string min = number_text(s.min);
  if (std::isfinite(s.max) && s.type == SettingType::Real)
    return "in [" + min + ", " + number_text(s.max) + "]";
  return (s.above_min ? "> " : ">= ") + min;
}

std::string option_name(const WorldSetting& s) {
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

World scene_file_world() {
  World world;
  world.contact_margin = kSceneContactMargin;
  world.contact_persistence = kSceneContactPersistence;
  return world;
}

std::optional<double> setting_value(const WorldSetting& s,
                                    std::string_view text,
                                    std::string& why) {
  if (s.type == SettingType::Word) {
    const std::vector<std::string>& words = s.words();
    for (std::size_t k = 0; k < words.size(); ++k)
      if (words[k] == text) return static_cast<double>(k);
    why = "unknown " + std::string(s.noun) + " \"" + std::string(text) +
          "\" (valid: " + join_words(words) + ")";
    return std::nullopt;
  }
  double value = 0.0;
  if (!parse_number(std::string(text), value)) {
    why = s.type == SettingType::Whole ? "expected a whole number" : "expected a number";
    return std::nullopt;
  }
  return value;
}

std::string set_world_setting(World& world, const WorldSetting& s, double value) {
  if (!std::isfinite(value)) return "not a finite number";
  if (s.type == SettingType::Whole && std::trunc(value) != value) return "expected an integer";
  if (s.type != SettingType::Word) {
    const bool low = s.above_min ? !(value > s.min) : !(value >= s.min);
    if (low || value > s.max)
      return s.type == SettingType::Whole && value > s.max ? "too large"
                                                           : "must be " + range_text(s);
  } else if (value < 0.0 || value >= static_cast<double>(s.words().size())) {
    return "not " + range_text(s);
  }
  if (s.applies != nullptr && !s.applies(world))
    return "a setting of " + std::string(s.applies_text) + "; the world has " +
           (s.applies == under_cones
                ? "friction " + std::string(friction_name(world.friction))
                : "scheme " + scheme_names().at(static_cast<std::size_t>(world.scheme.kind)));
  if (s.key == "substeps" && world.scheme.kind == Scheme::Paper && value != 1.0)
    return "needs a scheme that substeps (tgs, soft-step, xpbd), not paper";
  s.set(world, value);
  return {};
}

std::string setting_text(const WorldSetting& s, const World& world) {
  const double value = s.get(world);
  if (s.type == SettingType::Word) return s.words().at(static_cast<std::size_t>(value));
  char digits[32];
  const auto end = std::to_chars(digits, digits + sizeof digits, value).ptr;  // shortest exact
  return std::string(digits, end);
}

std::string world_settings_markdown() {
  const World defaults = scene_file_world();
  std::string out;
  for (const WorldSetting& s : kWorldSettings) {
    std::string type = s.type == SettingType::Word    ? "string"
                       : s.type == SettingType::Whole ? "integer " + range_text(s)
                                                      : "number " + range_text(s);
    if (s.fraction) type += ", or a string `\"p/q\"`";
    const std::string value = setting_text(s, defaults);
    const std::string fallback = s.type == SettingType::Word ? "`\"" + value + "\"`" : value;
    std::string rule(s.rule);
    if (s.applies != nullptr) rule = "under " + std::string(s.applies_text) + ": " + rule;
    if (s.option) rule += "; `" + option_name(s) + "`";
    out += "| `/world/" + std::string(s.key) + "` | " + type + " | " + std::string(s.unit) + " | " +
           (s.default_text.empty() ? fallback : std::string(s.default_text)) + " | " + rule +
           " |\n";
  }
  return out;
}

}  // namespace cbps
