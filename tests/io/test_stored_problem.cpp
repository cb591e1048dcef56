// Stored problems (io/stored_problem.hpp): the one writer and the one reader of a problem
// folder, and the row kinds and manifolds a folder's labels.json carries.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/stored_problem.hpp"
#include "fixture.hpp"

using namespace cbps;
using namespace cbps::test;
namespace fs = std::filesystem;

namespace {

/// write_problem into `dir`, every file straight to its place.
void write_folder(const StoredProblem& p, const fs::path& dir) {
  fs::create_directories(dir);
  write_problem(p,
                [&](const std::string& name, const auto& write) { write((dir / name).string()); });
}

}  // namespace

TEST_CASE("a problem folder written by write_problem reads back bit for bit", "[stored_problem]") {
  const auto dir = scratch_dir("stored_problem_round_trip");
  // A step's system of a contact scene (contacts and friction rows, so J, Minv, v1, fext, dt
  // and every kind of bound are real), with a cfm.
  const System sys = system_of("stack", {{"n", "3"}}, 30);
  REQUIRE(sys.rows() > 0);
  const StoredProblem written = stored_problem(sys, 1e-6);
  write_folder(written, dir / "step");
  const StoredProblem read = read_problem((dir / "step").string());
  CHECK((read.A - written.A).norm() == 0.0);
  CHECK(read.b == written.b);
  CHECK(read.cmin == written.cmin);
  CHECK(read.cmax == written.cmax);
  REQUIRE(read.has_bodies());
  CHECK((SpMat(read.J) - SpMat(written.J)).norm() == 0.0);
  CHECK((read.Minv - written.Minv).norm() == 0.0);
  CHECK(read.v1 == written.v1);
  CHECK(read.fext == written.fext);
  CHECK(read.dt == written.dt);
  CHECK(read.cfm == 1e-6);
  CHECK(read.kinds.empty());  // write_problem writes no labels.json
  CHECK(read.blocks == std::vector<int>(static_cast<std::size_t>(sys.rows()), -1));

  // Without bodies (dt = 0) and without cfm: the four files of the boxed problem alone.
  StoredProblem bare;
  bare.A = written.A;
  bare.b = written.b;
  bare.cmin = written.cmin;
  bare.cmax = written.cmax;
  write_folder(bare, dir / "bare");
  for (const char* name : {"J.mtx", "Minv.mtx", "v1.mtx", "fext.mtx", "dt.txt", "cfm.txt"})
    CHECK_FALSE(fs::exists(dir / "bare" / name));
  const StoredProblem read_bare = read_problem((dir / "bare").string());
  CHECK_FALSE(read_bare.has_jacobian());
  CHECK(read_bare.cfm == 0.0);
  fs::remove_all(dir);
}

TEST_CASE("a `cbps matrices` folder gives back the step's row kinds and contact manifolds",
          "[stored_problem]") {
  // The kinds and manifolds the step's System made (rows/, System::manifold) against those
  // read_problem finds in the folder's labels.json.
  const auto dir = scratch_dir("stored_problem_labels");
  const std::string out = (dir / "m").string();
  const auto r =
      run_cli("matrices stack --param n=3 --param columns=2 --step 30 --quiet --out " + out);
  INFO(r.err);
  REQUIRE(r.code == 0);
  const System sys = system_of("stack", {{"n", "3"}, {"columns", "2"}}, 30);
  const StoredProblem p = read_problem(out);
  REQUIRE(p.rows() == sys.rows());
  CHECK(p.kinds == sys.kind);
  // The same partition of the rows into manifolds (the numbering may differ).
  REQUIRE(p.blocks.size() == sys.manifold.size());
  for (std::size_t i = 0; i < p.blocks.size(); ++i) {
    CHECK((p.blocks[i] < 0) == (sys.manifold[i] < 0));
    for (std::size_t j = 0; j < i; ++j)
      CHECK((p.blocks[i] >= 0 && p.blocks[i] == p.blocks[j]) ==
            (sys.manifold[i] >= 0 && sys.manifold[i] == sys.manifold[j]));
  }
  const BoxedProblem boxed = p.problem();
  CHECK(boxed.kinds == &p.kinds);
  CHECK(boxed.blocks == &p.blocks);

  // A labels.json that does not label every row is refused, naming the file.
  write_file(fs::path(out) / "labels.json", R"({"rows": ["contact a-b #1"]})");
  CHECK_THROWS_WITH(read_problem(out),
                    Catch::Contains("labels.json") && Catch::Contains("one label per row"));
  write_file(fs::path(out) / "labels.json", "{\"rows\": [" + std::string("1,") + "]");
  CHECK_THROWS_AS(read_problem(out), InputError);
  // Without labels.json: no kinds, every row alone.
  fs::remove(fs::path(out) / "labels.json");
  const StoredProblem unlabelled = read_problem(out);
  CHECK(unlabelled.kinds.empty());
  CHECK(unlabelled.problem().kinds == nullptr);
  fs::remove_all(dir);
}

TEST_CASE("a folder's cones.json gives back the contacts in cones, and a bad one is named",
          "[stored_problem][cones]") {
  const auto dir = scratch_dir("stored_problem_cones");
  const System sys = system_of("stack", {{"n", "2"}, {"friction", "cone"}, {"cone", "ccp"}}, 0);
  REQUIRE(sys.contacts.contacts() > 0);
  write_folder(stored_problem(sys, 0.0), dir / "step");
  const StoredProblem read = read_problem((dir / "step").string());
  CHECK(read.cones.normal == sys.contacts.normal);
  CHECK(read.cones.mu == sys.contacts.mu);
  CHECK(read.cones.law == FrictionLaw::Relaxation);
  CHECK(read.problem().cones != nullptr);

  // Each wrong cones.json is an InputError naming the file, the JSON path and what is wrong.
  const long c = sys.rows();
  const std::string file = (dir / "step" / "cones.json").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[1, 2]", "/law: not \"coulomb\" or \"ccp\""},
      {R"({"law": "cone", "contacts": []})", "/law: not \"coulomb\" or \"ccp\""},
      {R"({"law": "ccp"})", "/contacts: not an array"},
      {R"({"law": "ccp", "contacts": [{"normal_row": 0}]})", "/contacts/0: not {"},
      {R"({"law": "ccp", "contacts": [{"normal_row": 0.5, "mu": 1}]})", "/contacts/0: not {"},
      {R"({"law": "ccp", "contacts": [{"normal_row": -3, "mu": 1}]})",
       "/contacts/0/normal_row: -3 is not a row of A"},
      {R"({"law": "ccp", "contacts": [{"normal_row": 0, "mu": 1}, {"normal_row": 2, "mu": 1}]})",
       "/contacts: contact 1: normal row 2 is not after the rows of contact 0 (0 to 2)"},
      {R"({"law": "ccp", "contacts": [{"normal_row": )" + std::to_string(c - 2) + R"(, "mu": 1}]})",
       "/contacts: contact 0: normal row " + std::to_string(c - 2) +
           " has not two rows after it for t1, t2 (the problem has " + std::to_string(c) +
           " rows)"},
      {R"({"law": "ccp", "contacts": [{"normal_row": 0, "mu": -0.5}]})",
       "/contacts: contact 0: mu -0.5 is not a finite number >= 0"},
      {"{", "not JSON"}};
  for (const auto& [text, message] : cases) {
    CAPTURE(text);
    write_file(file, text);
    try {
      read_problem((dir / "step").string());
      FAIL("no InputError");
    } catch (const InputError& e) {
      const std::string what = e.what();
      CAPTURE(what);
      CHECK(what.rfind(file + ": ", 0) == 0);
      CHECK(what.find(message) != std::string::npos);
    }
  }
  fs::remove_all(dir);
}
