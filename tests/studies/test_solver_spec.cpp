// The --solver grammar (parse_solver_spec, parse_solver_list): names, relaxation factors, orders,
// warm starts, and the errors that name what was wrong.
#include <catch2/catch.hpp>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/solver_spec.hpp"

using namespace cbps;

TEST_CASE("solver specs: names, relaxation factors, orders and warm starts", "[solver][cli]") {
  const SolverSpec psor = parse_solver_spec("psor:1.3");
  CHECK(psor.method == Method::Pgs);
  CHECK(psor.relaxation == 1.3);
  const SolverSpec random = parse_solver_spec("pgs:order=random:warm=off");
  CHECK(random.order == RowOrder::Random);
  CHECK(random.warm == 0.0);
  CHECK_FALSE(random.warm_friction.has_value());
  CHECK(parse_solver_spec("jacobi:1").relaxation == 1.0);
  CHECK(parse_solver_spec("matrix-free:order=reverse").order == RowOrder::Reverse);
  const auto list = parse_solver_list("pgs,psor:1.3,direct");
  REQUIRE(list.size() == 3);
  CHECK(list[2].method == Method::Direct);
  CHECK(parse_solver_spec("active-set").method == Method::ActiveSet);  // the previous exact path
  const auto error_of = [](const std::string& text) {
    try {
      parse_solver_spec(text, "--solver");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error_of("cg").find("--solver 'cg': unknown solver") != std::string::npos);
  CHECK(error_of("psor").find("psor needs its factor") != std::string::npos);
  CHECK(error_of("psor:2").find("in (0, 2)") != std::string::npos);
  CHECK(error_of("jacobi:1.5").find("in (0, 1]") != std::string::npos);
  CHECK(error_of("pgs:1.3").find("takes no relaxation factor") != std::string::npos);
  CHECK(error_of("sgs:order=random").find("order= applies to") != std::string::npos);
  CHECK(error_of("pgs:order=spiral").find("valid: natural, reverse, random") != std::string::npos);
  CHECK(error_of("pgs:warm=maybe").find("valid: on, off") != std::string::npos);
  CHECK(error_of("pgs:colour=red").find("unknown option 'colour'") != std::string::npos);
  CHECK_THROWS_AS(parse_solver_list("pgs,,direct"), InputError);
}

TEST_CASE("solver specs: warm-start factors and contacts first", "[solver][cli][warm]") {
  // The paper's warm start (7) by default: every row from its last lambda, F = 1.
  const SolverSpec plain = parse_solver_spec("pgs");
  CHECK(plain.warm == 1.0);
  CHECK_FALSE(plain.warm_friction.has_value());
  CHECK_FALSE(plain.contacts_first);
  CHECK(parse_solver_spec("pgs:warm=on").warm == 1.0);
  // Bullet's choice: 0.85 of the contact impulses, none of the friction ones.
  const SolverSpec bullet = parse_solver_spec("pgs:order=random:warm=0.85:warm_friction=0");
  CHECK(bullet.order == RowOrder::Random);
  CHECK(bullet.warm == 0.85);
  REQUIRE(bullet.warm_friction.has_value());
  CHECK(*bullet.warm_friction == 0.0);
  CHECK(*parse_solver_spec("sgs:warm_friction=on").warm_friction == 1.0);
  CHECK(parse_solver_spec("direct:warm=0").warm == 0.0);
  // Into the settings: friction rows take G, the others F; unset G is F.
  SolverSettings settings;
  apply_solver_spec(bullet, settings);
  CHECK(settings.warm_factor(RowKind::Distance) == 0.85);
  CHECK(settings.warm_factor(RowKind::Contact) == 0.85);
  CHECK(settings.warm_factor(RowKind::Friction) == 0.0);
  apply_solver_spec(parse_solver_spec("pgs:warm=0.5"), settings);
  CHECK(settings.warm_factor(RowKind::Friction) == 0.5);
  CHECK_FALSE(settings.contacts_first);
  apply_solver_spec(parse_solver_spec("matrix-free:contacts_first=on:order=random"), settings);
  CHECK(settings.contacts_first);
  CHECK(settings.options().contacts_first);
  CHECK(parse_solver_spec("psor:1.2:contacts_first=on").contacts_first);
  const auto error_of = [](const std::string& text) {
    try {
      parse_solver_spec(text, "--solver");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error_of("pgs:warm=1.5") ==
        "--solver 'pgs:warm=1.5': warm '1.5' (valid: on, off or a number in [0, 1])");
  CHECK(error_of("pgs:warm_friction=-0.1") ==
        "--solver 'pgs:warm_friction=-0.1': warm_friction '-0.1' (valid: on, off or a number in "
        "[0, 1])");
  CHECK(error_of("pgs:warm=nan").find("valid: on, off or a number") != std::string::npos);
  CHECK(error_of("pgs:warm=1:warm=0").find("'warm=' given twice") != std::string::npos);
  CHECK(error_of("jacobi:contacts_first=on") ==
        "--solver 'jacobi:contacts_first=on': contacts_first= applies to pgs, psor and "
        "matrix-free");
  CHECK(error_of("pgs:contacts_first=yes").find("(valid: on, off)") != std::string::npos);
  CHECK(error_of("apgd:colour=red").find("valid: warm, warm_friction, restart, grow") !=
        std::string::npos);
  CHECK(error_of("pgs:colour=red").find("valid: order, contacts_first, warm, warm_friction)") !=
        std::string::npos);
}

TEST_CASE("solver specs: each method's own parameters, their ranges, and read back as written",
          "[solver][cli]") {
  const SolverSpec apgd = parse_solver_spec("apgd:grow=3:shrink=0.5:restart=off");
  CHECK(apgd.method == Method::Apgd);
  CHECK(apgd.methods.apgd.grow == 3.0);
  CHECK(apgd.methods.apgd.shrink == 0.5);
  CHECK_FALSE(apgd.methods.apgd.restart);
  const SolverSpec nesterov = parse_solver_spec("pgs-nesterov:1.2:order=random:restart=off");
  CHECK(nesterov.relaxation == 1.2);
  CHECK(nesterov.order == RowOrder::Random);
  CHECK_FALSE(nesterov.methods.pgs_nesterov.restart);
  const SolverSpec sm = parse_solver_spec("pgs-sm:sweeps=3:cg=50:cg_tolerance=1e-8");
  CHECK(sm.methods.pgs_sm.pgs_sweeps == 3);
  CHECK(sm.methods.pgs_sm.cg_iterations == 50);
  CHECK(sm.methods.pgs_sm.cg_tolerance == 1e-8);
  const SolverSpec admm = parse_solver_spec("admm:rho=0.1:alpha=1:adapt=off:rho_min=1e-6");
  CHECK(admm.methods.admm.rho == 0.1);
  CHECK(admm.methods.admm.alpha == 1.0);
  CHECK_FALSE(admm.methods.admm.adapt_rho);
  CHECK(admm.methods.admm.rho_min == 1e-6);
  CHECK(parse_solver_spec("nncg:restart_beta=0").methods.nncg.restart_beta == 0.0);
  CHECK(parse_solver_spec("rbgs:1.5").relaxation == 1.5);
  const SolverSpec shock = parse_solver_spec("shock:1.2:level_sweeps=3");
  CHECK(shock.method == Method::Shock);
  CHECK(shock.relaxation == 1.2);
  CHECK(shock.methods.shock.level_sweeps == 3);
  CHECK(parse_solver_spec("shock:direction=down").methods.shock.top_down);
  CHECK_FALSE(parse_solver_spec("shock:direction=up").methods.shock.top_down);
  CHECK(parse_solver_spec("shock").methods.shock.level_sweeps == ShockSettings{}.level_sweeps);
  // The defaults are the sources' (method_settings.hpp), untouched by a bare name.
  CHECK(parse_solver_spec("admm").methods.admm.alpha == AdmmSettings{}.alpha);

  const auto error_of = [](const std::string& text) {
    try {
      parse_solver_spec(text, "--solver");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error_of("apgd:grow=1").find("grow '1' must be a number > 1") != std::string::npos);
  CHECK(error_of("apgd:shrink=0").find("in (0, 1]") != std::string::npos);
  CHECK(error_of("pgs-sm:sweeps=2.5").find("a whole number >= 1") != std::string::npos);
  CHECK(error_of("admm:alpha=2").find("in (0, 2)") != std::string::npos);
  CHECK(error_of("shock:level_sweeps=0").find("a whole number >= 1") != std::string::npos);
  CHECK(error_of("shock:direction=left").find("must be up or down") != std::string::npos);
  CHECK(
      error_of("admm:restart=on").find("valid: warm, warm_friction, rho, alpha, adapt, rho_min") !=
      std::string::npos);
  CHECK(error_of("apgd:1.3").find("takes no relaxation factor") != std::string::npos);
  CHECK(error_of("pgs:grow=2").find("unknown option 'grow'") != std::string::npos);

  // Read back: every parameter of every method, written as the grammar writes it, parses to
  // the same settings.
  for (const char* text : {"apgd:grow=3:shrink=0.5:restart=off",
                           "pgs-sm:sweeps=3:cg=50:cg_tolerance=1e-8",
                           "admm:rho=0.1:alpha=1:adapt=off:rho_min=1e-6",
                           "nncg:restart_beta=0.25",
                           "pgs-nesterov:restart=off"}) {
    const SolverSpec spec = parse_solver_spec(text);
    std::string again = std::string(to_string(spec.method));
    for (const auto& [key, value] : method_parameters(spec.method, spec.methods))
      again += ":" + key + "=" + value;
    INFO(text << " read back as " << again);
    const SolverSpec reread = parse_solver_spec(again);
    CHECK(method_parameters(reread.method, reread.methods) ==
          method_parameters(spec.method, spec.methods));
  }
  CHECK(method_parameters(Method::Pgs, MethodSettings{}).empty());
  CHECK(solver_spec_help().find("  admm") != std::string::npos);
}
