// Scenes with Coulomb's cone (friction=cone, docs/cones.md) through the commands: the problem
// `cbps matrices` writes (cones.json beside the folder's matrices, an FCLIB file with --fclib),
// what `cbps lcp` solves of it, what `cbps explain` shows, and a run verified every step. The
// expected forces come from statics and Coulomb's law on a box on an incline, not from cbps.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cbps/io/fclib_file.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/stored_problem.hpp"
#include "fixture.hpp"

namespace fs = std::filesystem;
using namespace cbps;
using namespace cbps::test;

namespace {

constexpr double kGravity = 9.81;  // m/s²
constexpr double kMu = 0.5;

/// The incline (incline_scene_json: a 1 kg cube on a plane inclined by `degrees`, mu = 0.5) in
/// Coulomb's cone under `law`, stepped by the direct path: four contact points, each a normal
/// row and two friction rows.
std::string cone_incline(const fs::path& dir, double degrees, const std::string& law) {
  nlohmann::json scene = incline_scene_json(degrees, "cone");
  scene["world"]["cone"] = law;
  scene["solver"] = {{"method", "direct"}};
  const fs::path path = dir / ("incline-" + law + ".json");
  write_file(path, scene.dump(2));
  return path.string();
}

/// The sums over the contacts of lambda's normal rows and of the friction force J_tᵀ lambda_t
/// along the slope (x), N·s/s = N per the step's 1 kg (forces, 6.2).
struct Sums {
  double normal = 0.0;
  double friction_x = 0.0;
};
Sums sums_of(const StoredProblem& p, const VecX& lambda) {
  Sums s;
  VecX friction = VecX::Zero(lambda.size());
  for (const int n : p.cones.normal) {
    s.normal += lambda(n);
    friction.segment<2>(n + 1) = lambda.segment<2>(n + 1);
  }
  s.friction_x = (SpMat(p.J.transpose()) * friction)(0);
  return s;
}

}  // namespace

TEST_CASE("matrices writes a cone step's problem (cones.json, --fclib) and lcp solves it",
          "[cli][cones]") {
  const fs::path dir = scratch_dir("cli_cones");
  const double g = kGravity;
  // 20°: tan 20° = 0.36 < mu, the box sticks: the contacts carry m g cos a and m g sin a.
  // 30°: tan 30° = 0.58 > mu, it slides: Coulomb's law gives friction mu m g cos a (u_n = 0).
  for (const double degrees : {20.0, 30.0}) {
    CAPTURE(degrees);
    const double a = degrees * kPi / 180.0;
    const std::string name = std::to_string(int(degrees)) + "deg";
    const fs::path m = dir / name;
    const fs::path h5 = dir / (name + ".hdf5");
    const CliResult made = run_cli("matrices " + cone_incline(dir, degrees, "coulomb") + " --out " +
                                   m.string() + " --fclib " + h5.string());
    INFO(made.out << made.err);
    REQUIRE(made.code == 0);
    const StoredProblem p = read_problem(m.string());
    REQUIRE(p.cones.contacts() == 4);
    CHECK(p.cones.law == FrictionLaw::CoulombCone);
    CHECK(p.cones.mu.isConstant(kMu));
    const VecX lambda = read_matrix_market_vector((m / "lambda.mtx").string());
    const Sums s = sums_of(p, lambda);
    CHECK(s.normal == Approx(g * std::cos(a)).epsilon(1e-8));
    const double friction = degrees < 25.0 ? g * std::sin(a) : kMu * g * std::cos(a);
    CHECK(s.friction_x == Approx(-friction).epsilon(1e-8));

    // The FCLIB file holds the same problem (rows already in contact order) and its solution.
    VecX r;
    const StoredProblem f = read_fclib(h5.string(), &r);
    CHECK((MatX(f.A) - MatX(p.A)).cwiseAbs().maxCoeff() == 0.0);
    CHECK((f.b - p.b).cwiseAbs().maxCoeff() == 0.0);
    CHECK(f.cones.mu.isConstant(kMu));
    CHECK((r - lambda).cwiseAbs().maxCoeff() == 0.0);
    // An existing file is never replaced (cbps cannot tell its own FCLIB files from a user's).
    const auto before = fs::last_write_time(h5);
    const CliResult again =
        run_cli("matrices " + cone_incline(dir, degrees, "coulomb") + " --out " +
                (dir / (name + "-again")).string() + " --fclib " + h5.string());
    CHECK(again.code == 2);
    CHECK(again.err.find("--fclib " + h5.string()) != std::string::npos);
    CHECK(fs::last_write_time(h5) == before);
    CHECK(!fs::exists(dir / (name + "-again")));

    // `cbps lcp` on the folder solves the cone problem (its cones.json), by both methods.
    for (const char* solver : {"direct", "nsgs"}) {
      const CliResult solved =
          run_cli("lcp " + m.string() + " --solver " + solver + " --iterations 100000 --json");
      INFO(solved.out << solved.err);
      REQUIRE(solved.code == 0);
      const auto j = nlohmann::json::parse(solved.out);
      CHECK(j["status"] == "solved");
      VecX l(lambda.size());
      for (Eigen::Index k = 0; k < l.size(); ++k) l(k) = j["lambda"][std::size_t(k)];
      const Sums t = sums_of(p, l);
      CHECK(t.normal == Approx(g * std::cos(a)).epsilon(1e-6));
      CHECK(t.friction_x == Approx(-friction).epsilon(1e-6));
    }

    // `cbps explain --json` shows the contacts in their cone, each meeting Coulomb's law.
    const CliResult explained =
        run_cli("explain " + cone_incline(dir, degrees, "coulomb") + " --json");
    INFO(explained.err);
    REQUIRE(explained.code == 0);
    const auto e = nlohmann::json::parse(explained.out);
    REQUIRE(e["cones"]["contacts"].size() == 4);
    CHECK(e["cones"]["law"] == "coulomb");
    for (const auto& contact : e["cones"]["contacts"]) {
      CHECK(contact["mu"] == kMu);
      const std::string status = contact["status"];
      // Sliding: each contact's friction is on the cone's surface (or the contact is unloaded).
      if (degrees > 25.0) CHECK((status == "cone: sliding" || status == "cone: separated"));
    }
    for (const auto& ok : e["status"]["satisfied"]) CHECK(ok == true);
  }
}

TEST_CASE("matrices --fclib --cone poses a boxed step's A and b on Coulomb's cone",
          "[cli][cones]") {
  const fs::path dir = scratch_dir("cli_cones_posed");
  const double g = kGravity;
  // The incline under the paper's box (±mu m g cos a per row). 20°: the cube rests, so its
  // contacts carry m g cos a and m g sin a under the cone as under the box. 30°: it slides down
  // the slope (x) under the box; posed on the cone, Coulomb's law gives mu m g cos a against it.
  for (const double degrees : {20.0, 30.0}) {
    CAPTURE(degrees);
    const double a = degrees * kPi / 180.0;
    const std::string name = std::to_string(int(degrees)) + "deg";
    nlohmann::json scene = incline_scene_json(degrees, "paper");
    const fs::path path = dir / (name + ".json");
    write_file(path, scene.dump(2));
    const fs::path m = dir / name;
    const fs::path h5 = dir / (name + ".hdf5");
    const CliResult made = run_cli("matrices " + path.string() + " --step 20 --out " + m.string() +
                                   " --fclib " + h5.string() + " --cone coulomb");
    INFO(made.out << made.err);
    REQUIRE(made.code == 0);
    const StoredProblem p = read_problem(m.string());
    CHECK(p.cones.empty());  // the folder is the box the step solved
    VecX r;
    const StoredProblem f = read_fclib(h5.string(), &r);
    REQUIRE(f.cones.contacts() == 4);
    CHECK(f.cones.mu.isConstant(kMu));
    CHECK((MatX(f.A) - MatX(p.A)).cwiseAbs().maxCoeff() == 0.0);
    CHECK((f.b - p.b).cwiseAbs().maxCoeff() == 0.0);
    REQUIRE(r.size() == p.rows());
    StoredProblem posed = p;
    posed.cones = f.cones;
    const Sums s = sums_of(posed, r);
    CHECK(s.normal == Approx(g * std::cos(a)).epsilon(1e-8));
    const double friction = degrees < 25.0 ? g * std::sin(a) : kMu * g * std::cos(a);
    CHECK(s.friction_x == Approx(-friction).epsilon(1e-8));
  }
  // A box scene without --cone: nothing is written; --cone names a law.
  const std::string base = "matrices stack --param n=2 --out " + (dir / "m").string();
  const CliResult boxed = run_cli(base + " --fclib " + (dir / "boxed.hdf5").string());
  CHECK(boxed.code == 2);
  CHECK(boxed.err.find("--cone coulomb|ccp") != std::string::npos);
  const CliResult unknown =
      run_cli(base + " --fclib " + (dir / "boxed.hdf5").string() + " --cone elliptic");
  CHECK(unknown.code == 2);
  CHECK(unknown.err.find("--cone elliptic: unknown") != std::string::npos);
  const CliResult no_file = run_cli(base + " --cone ccp");
  CHECK(no_file.code == 2);
  CHECK(no_file.err.find("--fclib") != std::string::npos);
  // On a cone scene the law is the scene's.
  const CliResult other = run_cli(
      "matrices stack --param n=2 --param friction=cone --param cone=ccp --solver direct --out " +
      (dir / "c").string() + " --fclib " + (dir / "c.hdf5").string() + " --cone coulomb");
  CHECK(other.code == 2);
  CHECK(other.err.find("--param cone=LAW") != std::string::npos);
  CHECK(!fs::exists(dir / "m"));
  CHECK(!fs::exists(dir / "c"));
  CHECK(!fs::exists(dir / "boxed.hdf5"));
  CHECK(!fs::exists(dir / "c.hdf5"));
}

TEST_CASE("a cone scene runs verified, converge compares the cone methods", "[cli][cones]") {
  const fs::path dir = scratch_dir("cli_cones_run");
  for (const char* law : {"coulomb", "ccp"}) {
    const CliResult run =
        run_cli(std::string("run stack --param n=3 --param friction=cone --param cone=") + law +
                " --solver direct --steps 20 --check --out " + (dir / law).string());
    INFO(run.out << run.err);
    CHECK(run.code == 0);
    const auto summary = nlohmann::json::parse(slurp(dir / law / "summary.json"));
    CHECK(summary["contacts"]["friction"] == "cone");
    CHECK(summary["contacts"]["cone"] == law);
    CHECK(summary["max_residual"].get<double>() <= 1e-10);  // every step's law met (N)
  }
  // converge on a cone scene: the cone methods by default, the steps before by the exact path.
  const CliResult converged = run_cli(
      "converge stack --param n=2 --param friction=cone --param mu=0.5 --step 3 "
      "--iterations 2000 --quiet --no-plot --out " +
      (dir / "converge").string());
  INFO(converged.out << converged.err);
  REQUIRE(converged.code == 0);
  const auto summary = nlohmann::json::parse(slurp(dir / "converge" / "summary.json"));
  CHECK(summary["cone"]["law"] == "coulomb");
  std::vector<std::string> solvers;
  for (const auto& j : summary["solvers"]) solvers.push_back(j["solver"]);
  CHECK(solvers == std::vector<std::string>{"nsgs", "nsgs:local=3", "direct"});
  // profile over a library holding a cone step: the boxed methods are not applicable there.
  const fs::path lib = dir / "lib";
  REQUIRE(run_cli("matrices stack --param n=2 --param friction=cone --param mu=0.5 --solver "
                  "direct --step 10 --quiet --out " +
                  (lib / "cone").string())
              .code == 0);
  write_file(lib / "library.json",
             R"({"format": "cbps-problem-library/1", "problems": [{"name": "cone", "path": )"
             R"("cone", "exact": "cone/lambda.mtx", "definite": false, "quick": true}]})");
  const CliResult profiled =
      run_cli("profile " + lib.string() + " --solvers pgs,nsgs,direct --no-plot --quiet --out " +
              (dir / "profile").string());
  INFO(profiled.out << profiled.err);
  REQUIRE(profiled.code == 0);
  const auto profile = nlohmann::json::parse(slurp(dir / "profile" / "profile.json"));
  for (const auto& m : profile["measurements"]) {
    CAPTURE(m["solver"]);
    if (m["solver"] == "pgs")
      CHECK(m["status"].get<std::string>().find("not applicable: contacts in friction cones") == 0);
    else
      CHECK(m["status"] == "solved");
  }
  // The teaching page says what the contacts' rows live in.
  const fs::path page = dir / "page.html";
  const CliResult taught = run_cli(
      "explain stack --param n=2 --param friction=cone --solver direct --html " + page.string());
  INFO(taught.err);
  REQUIRE(taught.code == 0);
  const std::string html = slurp(page);
  CHECK(html.find("Coulomb's cone") != std::string::npos);
  CHECK(html.find("contacts sliding (cone)") != std::string::npos);
  // Without --solver a cone scene runs nsgs, the paper's PGS on cones, built in or from a file;
  // the methods of the boxed problem refuse it, naming the ones that solve it.
  const CliResult plain = run_cli("run stack --param friction=cone --steps 2 --quiet --out " +
                                  (dir / "plain").string());
  INFO(plain.err);
  REQUIRE(plain.code == 0);
  CHECK(nlohmann::json::parse(slurp(dir / "plain" / "summary.json"))["solver"]["method"] == "nsgs");
  nlohmann::json file = incline_scene_json(20.0, "cone");
  file["solver"] = {{"iterations", 50}};  // a solver without a method
  write_file(dir / "incline.json", file.dump(2));
  const CliResult from_file = run_cli("run " + (dir / "incline.json").string() +
                                      " --steps 2 --quiet --out " + (dir / "file").string());
  INFO(from_file.err);
  REQUIRE(from_file.code == 0);
  CHECK(nlohmann::json::parse(slurp(dir / "file" / "summary.json"))["solver"]["method"] == "nsgs");
  const CliResult pgs = run_cli("run stack --param friction=cone --solver pgs --steps 2 --out " +
                                (dir / "pgs").string());
  CHECK(pgs.code == 2);
  CHECK(pgs.err.find("nsgs and direct") != std::string::npos);
}
