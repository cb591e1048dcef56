// The --solver grammar (parse_solver_spec, parse_solver_list): names, relaxation factors, orders,
// warm starts, and the errors that name what was wrong.
#include <catch2/catch.hpp>
#include <string>

#include "cbps/error.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/solver_spec.hpp"

using namespace cbps;

TEST_CASE("solver specs: names, relaxation factors, orders and warm starts", "[solver][cli]") {
  const SolverSpec psor = parse_solver_spec("psor:1.3");
  CHECK(psor.method == Method::Pgs);
  CHECK(psor.relaxation == 1.3);
  const SolverSpec random = parse_solver_spec("pgs:order=random:warm=off");
  CHECK(random.order == RowOrder::Random);
  CHECK_FALSE(random.warm_start);
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
