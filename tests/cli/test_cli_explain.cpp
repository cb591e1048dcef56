// cbps explain: one step's system printed so that a student can redo it by hand.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/base/types.hpp"
#include "fixture.hpp"

using namespace cbps;
using namespace cbps::test;

namespace {

double number_of(const nlohmann::json& j) {
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "inf") return INFINITY;
    if (s == "-inf") return -INFINITY;
    return NAN;
  }
  return j.get<double>();
}

VecX vector_of(const nlohmann::json& j) {
  VecX v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t k = 0; k < j.size(); ++k) v(static_cast<Eigen::Index>(k)) = number_of(j[k]);
  return v;
}

MatX matrix_of(const nlohmann::json& j, Eigen::Index cols) {
  MatX M(static_cast<Eigen::Index>(j.size()), cols);
  for (std::size_t r = 0; r < j.size(); ++r) {
    REQUIRE(static_cast<Eigen::Index>(j[r].size()) == cols);
    for (std::size_t c = 0; c < j[r].size(); ++c)
      M(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = number_of(j[r][c]);
  }
  return M;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// Every whitespace-separated token of the text that reads as a negative zero.
std::vector<std::string> negative_zeros(const std::string& text) {
  static const std::regex minus_zero(R"(-0(\.0*)?(e[+-]?0*\d+)?)");
  std::vector<std::string> found;
  std::istringstream in(text);
  for (std::string token; in >> token;)
    if (std::regex_match(token, minus_zero)) found.push_back(token);
  return found;
}

/// Checks the printed JSON by an independent computation: b from upsilon, J, v1, Minv, fext and
/// dt (6.2.9), A = J Minv J^T, w = A lambda − b (6.2), each row's status against its bounds.
/// Returns the statuses.
std::vector<std::string> check_explained(const nlohmann::json& e, bool solved_exactly) {
  const auto rows = e["row_labels"].size();
  const auto cols = static_cast<Eigen::Index>(e["column_labels"].size());
  const MatX J = matrix_of(e["J"]["value"], cols);
  const MatX Minv = matrix_of(e["Minv"]["value"], cols);
  const MatX A = matrix_of(e["A"]["value"], static_cast<Eigen::Index>(rows));
  const VecX v1 = vector_of(e["v1"]["value"]), fext = vector_of(e["fext"]["value"]);
  const VecX upsilon = vector_of(e["upsilon"]["value"]), b = vector_of(e["b"]["value"]);
  const VecX lambda = vector_of(e["lambda"]["value"]), w = vector_of(e["w"]["value"]);
  const VecX cmin = vector_of(e["cmin"]["value"]), cmax = vector_of(e["cmax"]["value"]);
  const double dt = e["dt"].get<double>();
  REQUIRE(J.rows() == static_cast<Eigen::Index>(rows));
  REQUIRE(v1.size() == cols);
  REQUIRE(fext.size() == cols);
  REQUIRE(w.size() == b.size());

  // b = upsilon/dt − J (v1/dt + Minv fext) (6.2.9), to round-off.
  const VecX b_hand = upsilon / dt - J * (v1 / dt + Minv * fext);
  const double b_scale =
      std::max(1.0,
               (upsilon.cwiseAbs() / dt +
                J.cwiseAbs() * (v1.cwiseAbs() / dt + Minv.cwiseAbs() * fext.cwiseAbs()))
                   .maxCoeff());
  CHECK((b_hand - b).cwiseAbs().maxCoeff() <= 1e-12 * b_scale);
  // A = J Minv J^T.
  const MatX A_hand = J * Minv * J.transpose();
  CHECK((A_hand - A).cwiseAbs().maxCoeff() <= 1e-12 * std::max(1.0, A.cwiseAbs().maxCoeff()));
  // w = A lambda − b.
  const VecX w_hand = A * lambda - b;
  const double w_scale =
      std::max(1.0, (A.cwiseAbs() * lambda.cwiseAbs() + b.cwiseAbs()).maxCoeff());
  CHECK((w_hand - w).cwiseAbs().maxCoeff() <= 1e-12 * w_scale);

  // Statuses: where lambda sits against its bounds, and w's sign there (6.2).
  const auto& status = e["status"]["value"];
  REQUIRE(status.size() == rows);
  REQUIRE(e["status"]["satisfied"].size() == rows);
  const double tol = 1e-8 * w_scale;
  std::vector<std::string> out;
  for (std::size_t i = 0; i < rows; ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const std::string s = status[i].get<std::string>();
    CAPTURE(i, e["row_labels"][i].get<std::string>(), s, cmin(k), lambda(k), cmax(k), w(k));
    out.push_back(s);
    CHECK(cmin(k) <= lambda(k) + tol);
    CHECK(lambda(k) <= cmax(k) + tol);
    if (s == "at cmin") {
      CHECK(std::abs(lambda(k) - cmin(k)) <= tol * std::max(1.0, std::abs(cmin(k))));
      if (solved_exactly) CHECK(w(k) >= -tol);
    } else if (s == "at cmax") {
      CHECK(std::abs(lambda(k) - cmax(k)) <= tol * std::max(1.0, std::abs(cmax(k))));
      if (solved_exactly) CHECK(w(k) <= tol);
    } else if (s == "free") {
      CHECK(lambda(k) > cmin(k));
      CHECK(lambda(k) < cmax(k));
      if (solved_exactly) CHECK(std::abs(w(k)) <= tol);
    } else {
      CHECK(s == "at cmin = cmax");
      CHECK(cmin(k) == cmax(k));
    }
    if (solved_exactly) CHECK(e["status"]["satisfied"][i] == true);
  }
  return out;
}

}  // namespace

TEST_CASE("cbps explain prints labels whole: a stack's friction rows all distinct",
          "[cli][explain]") {
  // One box on the ground: 4 contact points, each a contact row and two friction rows; J (12 x
  // 6) and A (12 x 12) are narrow enough to print densely, with every label in full.
  const CliResult js = run_cli("explain stack --param n=1 --step 5 --json");
  REQUIRE(js.code == 0);
  const auto e = nlohmann::json::parse(js.out);
  std::vector<std::string> labels;
  for (const auto& l : e["row_labels"]) labels.push_back(l.get<std::string>());
  REQUIRE(labels.size() == 12);
  const std::set<std::string> distinct(labels.begin(), labels.end());
  CHECK(distinct.size() == labels.size());
  int friction = 0;
  for (const std::string& l : labels) friction += l.rfind("friction", 0) == 0 ? 1 : 0;
  CHECK(friction == 8);

  const CliResult r = run_cli("explain stack --param n=1 --step 5");
  REQUIRE(r.code == 0);
  const std::vector<std::string> lines = lines_of(r.out);
  // A's block: a header line with every row label as a column label, then one line per row
  // starting with its label.
  const auto a_title = std::find_if(lines.begin(), lines.end(), [](const std::string& l) {
    return l.rfind("A = J Minv J^T", 0) == 0;
  });
  REQUIRE(a_title != lines.end());
  REQUIRE(lines.end() - a_title > 13);
  const std::string& header = *(a_title + 1);
  std::size_t from = 0;
  for (const std::string& l : labels) {
    CAPTURE(l);
    const std::size_t at = header.find(l, from);
    CHECK(at != std::string::npos);  // in full and in order
    if (at != std::string::npos) from = at + l.size();
  }
  for (std::size_t k = 0; k < labels.size(); ++k) {
    const std::string& line = *(a_title + 2 + static_cast<long>(k));
    CAPTURE(line);
    CHECK(line.rfind("  " + labels[k] + "  ", 0) == 0);
  }
  // J's rows likewise.
  const auto j_title = std::find_if(
      lines.begin(), lines.end(), [](const std::string& l) { return l.rfind("J: ", 0) == 0; });
  REQUIRE(j_title != lines.end());
  for (std::size_t k = 0; k < labels.size(); ++k) {
    const std::string& line = *(j_title + 2 + static_cast<long>(k));
    CAPTURE(line);
    CHECK(line.rfind("  " + labels[k] + "  ", 0) == 0);
  }
}

TEST_CASE("cbps explain prints no -0, the same digits everywhere, v1, fext, units and w",
          "[cli][explain]") {
  for (const char* args : {"chain --param n=2 --step 10",
                           "chain --param n=3",
                           "stack --param n=1 --step 5",
                           "slide --step 5",
                           "v-corner --step 3 --push improved"}) {
    CAPTURE(args);
    const CliResult r = run_cli(std::string("explain ") + args);
    REQUIRE(r.code == 0);
    CHECK(negative_zeros(r.out).empty());
    for (const char* block : {"J: ",
                              "Minv = ",
                              "A = J Minv J^T",
                              "v1: ",
                              "fext: ",
                              "upsilon: ",
                              "b = upsilon/dt",
                              "w = A lambda - b",
                              "v2 = v1",
                              "System shown: "}) {
      CAPTURE(block);
      CHECK(r.out.find(block) != std::string::npos);
    }
    // Units on every block.
    for (const char* unit : {"unit 1 in the linear columns",
                             "m in the angular ones",
                             "kg^-1 (linear block), kg^-1 m^-2 (angular block)",
                             "m/s^2",
                             "rad/s",
                             "N m",
                             "cmin (N)",
                             "lambda (N)",
                             "cmax (N)",
                             "w (m/s^2)"}) {
      CAPTURE(unit);
      CHECK(r.out.find(unit) != std::string::npos);
    }
    // Six significant digits at most in every number, matrices and vectors alike.
    static const std::regex number(R"(-?(\d+)(\.(\d+))?(e[+-]\d+)?)");
    std::istringstream in(r.out);
    int longer = 0;
    for (std::string token; in >> token;) {
      std::smatch m;
      if (!std::regex_match(token, m, number)) continue;
      std::string digits = m[1].str() + m[3].str();
      digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size()));
      if (digits.size() > 6) ++longer;
    }
    CHECK(longer == 0);
  }
  const CliResult improved = run_cli("explain v-corner --step 3 --push improved");
  CHECK(improved.out.find("the velocity system of the improved push (8.1)") != std::string::npos);
  const CliResult original = run_cli("explain v-corner --step 3");
  CHECK(original.out.find("the one system of the original push") != std::string::npos);
}

TEST_CASE("cbps explain --json: b, A and w recomputed by hand, statuses agree with the bounds",
          "[cli][explain]") {
  SECTION("a chain swinging: every row free (distance rows are unbounded)") {
    const CliResult r = run_cli("explain chain --param n=2 --step 10 --solver direct --json");
    REQUIRE(r.code == 0);
    const auto e = nlohmann::json::parse(r.out);
    CHECK(e["system"]["shown"] == "one");
    const auto status = check_explained(e, true);
    CHECK(std::count(status.begin(), status.end(), "free") == 2);
    // Not the uninstructive rest state: b and lambda are not zero.
    CHECK(vector_of(e["b"]["value"]).cwiseAbs().maxCoeff() > 1.0);
    CHECK(vector_of(e["lambda"]["value"]).cwiseAbs().maxCoeff() > 0.1);
  }
  SECTION("a box sliding along x: its x-friction rows at a bound, the contacts pushing") {
    // Sliding along x (v0 = 2 m/s, paper friction, 5.4): kinetic friction holds each of the 4
    // points' x rows at a bound, the z rows (no sideways motion) are free, and the 4 contact
    // rows push, lambda > 0, free.
    const CliResult r = run_cli("explain slide --step 5 --solver direct --json");
    REQUIRE(r.code == 0);
    const auto e = nlohmann::json::parse(r.out);
    const auto status = check_explained(e, true);
    int contacts_free = 0, friction_at_bound = 0;
    for (std::size_t i = 0; i < status.size(); ++i) {
      const std::string label = e["row_labels"][i].get<std::string>();
      if (label.rfind("contact", 0) == 0 && status[i] == "free") ++contacts_free;
      if (label.rfind("friction", 0) == 0 && status[i].rfind("at cm", 0) == 0) ++friction_at_bound;
    }
    CHECK(contacts_free == 4);
    CHECK(friction_at_bound == 4);
  }
  SECTION("the default solver's answer: statuses still consistent with the bounds") {
    const CliResult r = run_cli("explain stack --param n=2 --step 20 --json");
    REQUIRE(r.code == 0);
    check_explained(nlohmann::json::parse(r.out), false);
  }
  SECTION("a solve stopped short of the tolerance leaves rows missing their condition") {
    // PGS's default 100 sweeps leave the chain at step 30 far from 1e-10 N: a natural-map
    // residual above the tolerance means some row is more than the tolerance from its
    // condition (6.2), so some row must be shown unsatisfied (before, each row was judged
    // against the larger of the tolerance and the residual, and none could fail).
    const CliResult r = run_cli("explain chain --step 30 --json");
    REQUIRE(r.code == 0);
    const auto e = nlohmann::json::parse(r.out);
    const double residual = e["solver"]["residual"].get<double>();
    REQUIRE(residual > 1e-6);
    CHECK(e["status"]["tolerance"].get<double>() < 1e-9);
    const auto& satisfied = e["status"]["satisfied"];
    CHECK(std::count(satisfied.begin(), satisfied.end(), false) >= 1);
    const CliResult text = run_cli("explain chain --step 30");
    CHECK(text.out.find("some rows miss their condition") != std::string::npos);
  }
  SECTION("the improved push shows the velocity system and says so") {
    const CliResult r = run_cli("explain v-corner --step 3 --push improved --json");
    REQUIRE(r.code == 0);
    const auto e = nlohmann::json::parse(r.out);
    CHECK(e["system"]["shown"] == "velocity");
    CHECK(e.contains("upsilon_position"));
    check_explained(e, false);
  }
}

TEST_CASE("cbps explain --html writes the teaching page atomically, labels as --json has them",
          "[cli][explain][html]") {
  const auto dir = scratch_dir("explain_html");
  const auto page = dir / "page.html";
  const CliResult r = run_cli("explain v-corner --step 10 --html " + page.string());
  REQUIRE(r.code == 0);
  CHECK(r.out.find(page.string()) != std::string::npos);
  const std::string html = slurp(page);
  CHECK(html.rfind("<!DOCTYPE html>", 0) == 0);
  CHECK(html.find("</html>") != std::string::npos);
  // The same rows and columns as --json, and the page's λ table lists the same solution.
  const CliResult js = run_cli("explain v-corner --step 10 --json");
  REQUIRE(js.code == 0);
  const auto e = nlohmann::json::parse(js.out);
  for (const auto& label : e["row_labels"]) {
    CAPTURE(label.get<std::string>());
    CHECK(html.find("<th class=\"row\">" + label.get<std::string>() + "</th>") !=
          std::string::npos);
  }
  for (const auto& label : e["column_labels"])
    CHECK(html.find(label.get<std::string>()) != std::string::npos);
  // Only the page in the folder: no temporary left behind.
  int files = 0;
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    CAPTURE(f.path().string());
    ++files;
  }
  CHECK(files == 1);
}

TEST_CASE("the teaching page of a cone scene shows the exact answer, the scene's sweeps beside",
          "[cli][explain][html][cones]") {
  // Issue 50, item 13: on `stack --param friction=cone` the page showed the answer of the
  // scene's 100 nsgs sweeps, its rows red (missing their condition). Without --solver the shown
  // system is solved by direct, and nsgs's residual per sweep is drawn beside it; --solver nsgs
  // shows nsgs's own answer.
  const auto dir = scratch_dir("explain_cones");
  const std::string scene =
      "explain stack --param n=4 --param friction=cone --param mu=0.5 --step 20";
  const auto exact = dir / "exact.html";
  const CliResult r = run_cli(scene + " --html " + exact.string());
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string html = slurp(exact);
  CHECK(html.find("<dt>solver</dt><dd>direct: ") != std::string::npos);
  CHECK(html.find(" miss\"") == std::string::npos);  // no row misses its condition
  CHECK(html.find("which does not sweep, so nsgs is shown beside it") != std::string::npos);
  CHECK(html.find("id=\"svg-residual-") != std::string::npos);
  const auto swept = dir / "nsgs.html";
  const CliResult n = run_cli(scene + " --solver nsgs --iterations 3 --html " + swept.string());
  REQUIRE(n.code == 0);
  const std::string nsgs = slurp(swept);
  CHECK(nsgs.find("<dt>solver</dt><dd>nsgs: ") != std::string::npos);
  CHECK(nsgs.find(" miss\"") != std::string::npos);  // 3 sweeps stop short: rows miss
}

TEST_CASE("the teaching page names the command that writes it again, every option included",
          "[cli][explain][html]") {
  // Issue 50, item 13: `explain chain --param n=2 --html` printed a command without n=2, and a
  // scene file was named as its scene's name.
  const auto dir = scratch_dir("explain_html_command");
  const auto page = dir / "a page.html";
  const CliResult r = run_cli("explain chain --param n=2 --param mass_ratio=10 --step 3 --html '" +
                              page.string() + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(slurp(page).find("<code>cbps explain chain --param n=2 --param mass_ratio=10 --step 3 "
                         "--html &#39;" +
                         page.string() + "&#39;</code>") != std::string::npos);
  const std::filesystem::path scene =
      std::filesystem::path(CBPS_SOURCE_DIR) / "scenes" / "two-link-chain.json";
  const auto from_file = dir / "file.html";
  REQUIRE(run_cli("explain " + scene.string() + " --html " + from_file.string()).code == 0);
  CHECK(slurp(from_file).find("<code>cbps explain " + scene.string() + " --html " +
                              from_file.string() + "</code>") != std::string::npos);
}

TEST_CASE("cbps explain --html: bad input exits 2 naming it and leaves the old file",
          "[cli][explain][html]") {
  const auto dir = scratch_dir("explain_html_bad");
  const auto page = dir / "page.html";
  write_file(page, "old");
  SECTION("a folder that does not exist") {
    const CliResult r = run_cli("explain v-corner --html " + (dir / "none" / "p.html").string());
    CHECK(r.code == 2);
    CHECK(r.err.find("--html") != std::string::npos);
    CHECK(r.err.find("does not exist") != std::string::npos);
  }
  SECTION("a folder instead of a file") {
    const CliResult r = run_cli("explain v-corner --html " + dir.string());
    CHECK(r.code == 2);
    CHECK(r.err.find("is a folder") != std::string::npos);
  }
  SECTION("an unknown scene: the existing page stays as it was") {
    const CliResult r = run_cli("explain no-such-scene --html " + page.string());
    CHECK(r.code == 2);
    CHECK(r.err.find("no-such-scene") != std::string::npos);
  }
  SECTION("--html with --json") {
    const CliResult r = run_cli("explain v-corner --json --html " + page.string());
    CHECK(r.code == 2);
  }
  CHECK(slurp(page) == "old");
}

TEST_CASE("cbps explain --html replaces a page it wrote, a user's file only with --force",
          "[cli][explain][html]") {
  const auto dir = scratch_dir("explain_html_replace");
  const auto page = dir / "page.html";
  // A page cbps wrote is replaced by the next one (another step, so the content changes).
  REQUIRE(run_cli("explain v-corner --html " + page.string()).code == 0);
  const std::string first = slurp(page);
  REQUIRE(run_cli("explain v-corner --step 3 --html " + page.string()).code == 0);
  CHECK(slurp(page) != first);
  CHECK(slurp(page).find("step 3") != std::string::npos);
  // A file cbps did not write (here an HTML file of the user's) is kept, and said why.
  const auto mine = dir / "notes.html";
  write_file(mine, "<!DOCTYPE html><p>my notes</p>");
  const CliResult refused = run_cli("explain v-corner --html " + mine.string());
  CHECK(refused.code == 2);
  CHECK(refused.err.find("--html " + mine.string() + ": exists") != std::string::npos);
  CHECK(refused.err.find("--force") != std::string::npos);
  CHECK(slurp(mine) == "<!DOCTYPE html><p>my notes</p>");
  // --force replaces it; --force without --html is refused.
  CHECK(run_cli("explain v-corner --html " + mine.string() + " --force").code == 0);
  CHECK(slurp(mine).find("<meta name=\"generator\" content=\"cbps explain --html\">") !=
        std::string::npos);
  CHECK(run_cli("explain v-corner --force").code == 2);
}

TEST_CASE("cbps explain --html of a step without rows says so and still gives v1 and v2",
          "[cli][explain][html]") {
  const auto page = scratch_dir("explain_html_empty") / "page.html";
  const CliResult r = run_cli("explain " + std::string(CBPS_SOURCE_DIR) +
                              "/scenes/spinning-box.json --html " + page.string());
  REQUIRE(r.code == 0);
  const std::string html = slurp(page);
  CHECK(html.find("No rows: nothing to solve") != std::string::npos);
  CHECK(html.find("No rows: A is empty.") != std::string::npos);
  CHECK(html.find("id=\"table-lambda-1\"") == std::string::npos);
  CHECK(html.find("id=\"table-v1\"") != std::string::npos);
  CHECK(html.find("id=\"table-v2-1\"") != std::string::npos);
}

TEST_CASE("cbps explain --integrator gyroscopic shows the v1 the step solved from, and says so",
          "[cli][explain][integrator]") {
  // The spinning box's first step (no rows): under the paper's integrator v1 is the body's
  // spin, (0.01, 5, 0.01) rad/s; under Bullet's gyroscopic step its angular part has taken one
  // Newton step, whose change is about dt |ω × I ω| / I: small, but not zero.
  const std::string box = std::string(CBPS_SOURCE_DIR) + "/scenes/spinning-box.json";
  const CliResult paper = run_cli("explain " + box + " --json");
  const CliResult gyroscopic = run_cli("explain " + box + " --integrator gyroscopic --json");
  REQUIRE(paper.code == 0);
  REQUIRE(gyroscopic.code == 0);
  const nlohmann::json p = nlohmann::json::parse(paper.out);
  const nlohmann::json g = nlohmann::json::parse(gyroscopic.out);
  CHECK(p.at("integrator") == "paper");
  CHECK(g.at("integrator") == "gyroscopic");
  CHECK_FALSE(p.at("v1").contains("note"));
  CHECK(g.at("v1").at("note").get<std::string>().find("gyroscopic") != std::string::npos);
  const VecX v1_paper = vector_of(p.at("v1").at("value"));
  const VecX v1_gyroscopic = vector_of(g.at("v1").at("value"));
  REQUIRE(v1_paper.size() == 6);
  REQUIRE(v1_gyroscopic.size() == 6);
  CHECK(std::abs(v1_paper(4) - 5.0) <= 1e-12);
  const double change = (v1_gyroscopic - v1_paper).norm();
  CAPTURE(change);
  CHECK(change > 1e-7);
  CHECK(change < 1e-2);
  CHECK(v1_gyroscopic.head<3>().isZero(0.0));  // the linear part is the paper's
}

TEST_CASE("cbps explain and matrices under a scheme show its first substep and its softness apart",
          "[cli][explain][scheme]") {
  // One box on the ground under the soft step, 4 substeps of 1/240 s: the contact rows take
  // Catto's softness gamma = A_kk / (h omega (2 zeta + h omega)), omega = 2 pi 60 Hz (twice the
  // 30 Hz contact stiffness against a static body), zeta = 10; friction rows none. A stays
  // J Minv Jᵀ, and dt is the substep.
  const CliResult r = run_cli("explain stack --param n=1 --scheme soft-step --json");
  REQUIRE(r.code == 0);
  const nlohmann::json e = nlohmann::json::parse(r.out);
  const double h = 1.0 / 240.0;
  CHECK(e.at("dt").get<double>() == Approx(h).epsilon(1e-15));
  CHECK(e.at("scheme").at("name") == "soft-step");
  CHECK(e.at("scheme").at("substeps") == 4);
  const auto& labels = e.at("row_labels");
  const auto& A = e.at("A").at("value");
  const VecX softness = vector_of(e.at("scheme").at("softness").at("value"));
  const double omega = 2.0 * std::numbers::pi * 60.0, zeta = 10.0;
  int soft_rows = 0;
  for (std::size_t k = 0; k < labels.size(); ++k) {
    CAPTURE(labels[k]);
    const bool contact = labels[k].get<std::string>().rfind("contact", 0) == 0;
    const double A_kk = A[k][k].get<double>();
    const double want = contact ? A_kk / (h * omega * (2.0 * zeta + h * omega)) : 0.0;
    CHECK(softness(static_cast<Eigen::Index>(k)) == Approx(want).epsilon(1e-12));
    soft_rows += contact ? 1 : 0;
  }
  CHECK(soft_rows == 4);
  // matrices writes the same softness beside A, and says which substep it wrote.
  const auto dir = scratch_dir("matrices_scheme");
  REQUIRE(
      run_cli("matrices stack --param n=1 --scheme soft-step --out " + (dir / "m").string()).code ==
      0);
  CHECK(std::filesystem::exists(dir / "m" / "softness.mtx"));
  const auto labels_json = nlohmann::json::parse(slurp(dir / "m" / "labels.json"));
  CHECK(labels_json.at("scheme").at("softness") == "softness.mtx");
  CHECK(labels_json.at("scheme").at("h").get<double>() == Approx(h).epsilon(1e-15));
  // The paper's scheme has no softness to show.
  const nlohmann::json paper =
      nlohmann::json::parse(run_cli("explain stack --param n=1 --json").out);
  CHECK_FALSE(paper.at("scheme").contains("softness"));
}
