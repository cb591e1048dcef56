// The one table of methods (methods.hpp): every enumerator has one entry with a solve function
// and a name of its own, and the questions solver.hpp asks of a method answer what the docs say
// of it (solver.hpp's comments, docs/cones.md, docs/peers.md), written out here by hand.
#include <catch2/catch.hpp>
#include <set>
#include <string>

#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/solvers/solver.hpp"

using namespace cbps;

namespace {

/// The names of the methods for which `question` is true, in the table's order.
template <class Question>
std::set<std::string> named(Question question) {
  std::set<std::string> names;
  for (const Method m : all_methods())
    if (question(m)) names.insert(std::string(to_string(m)));
  return names;
}

}  // namespace

TEST_CASE("every method has one entry, a name of its own and a solve function",
          "[solver][methods]") {
  // The enumerators run from Pgs to BulletPgs (solver.hpp): each has exactly one entry.
  const int last = static_cast<int>(Method::BulletPgs);
  CHECK(all_methods().size() == static_cast<std::size_t>(last + 1));
  std::set<int> seen;
  std::set<std::string_view> names;
  for (const MethodEntry* entry : method_entries()) {
    const MethodEntry& e = *entry;
    INFO(e.name);
    CHECK(seen.insert(static_cast<int>(e.method)).second);
    CHECK(names.insert(e.name).second);
    CHECK(e.solve != nullptr);
    CHECK(!e.what.empty());
    CHECK(&method_entry(e.method) == &e);
    CHECK(to_string(e.method) == e.name);
    CHECK(method_of(e.name) == e.method);
    // A peer works on a dense copy of A: it has a row limit.
    CHECK((e.library == Library::Cbps || e.max_rows > 0));
  }
  // An alias selects its method and is not its name: psor is pgs with a relaxation.
  const MethodName* psor = find_method_name("psor");
  REQUIRE(psor != nullptr);
  CHECK(psor->method == Method::Pgs);
  CHECK(psor->omega);
  Method m = Method::Direct;
  CHECK_FALSE(method_from_string("psor", m));
  // Every name --help lists once; each method's own before its aliases.
  CHECK(method_table().size() == method_entries().size() + 1);
}

TEST_CASE("the questions of solver.hpp answer what the docs say of each method",
          "[solver][methods]") {
  using S = std::set<std::string>;
  // Not iterative: the exact paths and the pivoting methods, cbps's and the peers'.
  CHECK(named([](Method m) { return !is_iterative(m); }) == S{"direct",
                                                              "active-set",
                                                              "lemke",
                                                              "siconos:lemke",
                                                              "siconos:enum",
                                                              "siconos:avi",
                                                              "bullet:dantzig",
                                                              "bullet:lemke"});
  CHECK(named([](Method m) { return needs_jacobian(m); }) == S{"matrix-free", "shock"});
  CHECK(named([](Method m) { return !reads_A(m, false); }) == S{"matrix-free", "direct"});
  CHECK(named([](Method m) { return !reads_A(m, true); }) == S{"matrix-free"});
  // The QP of 6.2's minimisers need A = Aᵀ; direct on cones takes any A.
  const S qp{"direct", "active-set", "apgd", "nncg", "pgs-sm", "admm"};
  CHECK(named([](Method m) { return needs_symmetric(m, false); }) == qp);
  S qp_on_cones = qp;
  qp_on_cones.erase("direct");
  CHECK(named([](Method m) { return needs_symmetric(m, true); }) == qp_on_cones);
  // docs/cones.md: nsgs and direct under either law, Siconos' fc3d solvers Coulomb's only,
  // apgd, admm and pgs-nesterov the relaxation only.
  const S fc3d{
      "siconos:fc3d-nsgs", "siconos:fc3d-nsn-ac", "siconos:fc3d-prox", "siconos:fc3d-admm"};
  CHECK(named([](Method m) { return is_siconos_fc3d(m); }) == fc3d);
  S coulomb = fc3d;
  coulomb.insert({"nsgs", "direct"});
  CHECK(named([](Method m) { return takes_cone_law(m, FrictionLaw::CoulombCone); }) == coulomb);
  CHECK(named([](Method m) { return takes_cone_law(m, FrictionLaw::Relaxation); }) ==
        S{"nsgs", "direct", "apgd", "admm", "pgs-nesterov"});
  CHECK(named([](Method m) { return takes_cones(m); }).size() == 9);
  CHECK(named([](Method m) { return is_peer(m); }).size() == 11);
  // Jacobi's omega damps: (0, 1]; SOR's range for the rest.
  CHECK(relaxation_in_range(Method::Jacobi, 1.0));
  CHECK_FALSE(relaxation_in_range(Method::Jacobi, 1.5));
  CHECK(relaxation_in_range(Method::Sgs, 1.5));
  CHECK_FALSE(relaxation_in_range(Method::Pgs, 2.0));
  // docs/peers.md: the peers' row limits.
  CHECK(peer_max_rows(Method::SiconosEnum) == 20);
  CHECK(peer_max_rows(Method::BulletLemke) == 1000);
  CHECK(peer_max_rows(Method::SiconosFc3dProx) == 6000);
  CHECK(peer_max_rows(Method::SiconosLemke) == 3000);
}
