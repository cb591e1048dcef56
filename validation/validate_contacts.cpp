// validate_contacts: the built-in contact scenes against their analytic results (paper 4, 5.3,
// 5.4, 8, 12.2). Derivations and the numbers observed are in README.md, "Case 3". One file per
// case in contacts/, each with its reference:
//
//   1. v-corner (12.2, Figure 11): lambda of a sphere at rest in a V of two planes against the
//      force balance, direct solver and PGS (contacts/v_corner.cpp).
//   2. bounce (8.2.1): each rebound apex is ε² times the one before (contacts/bounce.cpp).
//   3. slide (5.4): a box sliding at v0 stops after v0²/(2 μ g) at t = v0/(μ g)
//      (contacts/slide.cpp).
//   4. overlap (8.1): the kinetic energy the push factor injects, original against improved,
//      and the box states of the push-factor figure (contacts/overlap.cpp).
//   5. The paper's friction bound (5.4) against Coulomb's on a column of n boxes on a tilted
//      plane (contacts/column.cpp).
//   6. The 10-box stack (8.1, 7.1.1) by solver and push, and the spectrum of its A
//      (contacts/stack.cpp).
//
// Output: a Markdown table per case on stdout, all numbers and the figure's box states as JSON
// (--out, default validation/results/contacts.json). Exit status: 0 all checks pass, 1 a check
// failed, 2 bad usage.
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>

#include "contacts/contacts.hpp"
#include "harness.hpp"

namespace {

constexpr const char* kHelp =
    "validate_contacts: v-corner, bounce, slide, overlap and a tilted column of\n"
    "boxes against their analytic results (README.md, Case 3)\n\n"
    "Options:\n"
    "  --out FILE   JSON results (default validation/results/contacts.json)\n"
    "  --help       this text\n"
    "Exit status: 0 all checks pass, 1 a check failed, 2 bad usage.\n";

struct Results {
  std::vector<contacts::VCorner> v_corner;
  std::vector<contacts::Bounce> bounce;
  std::vector<contacts::Slide> slide;
  contacts::Overlaps overlap;
  std::vector<contacts::Column> column;
  contacts::Stacks stack;
  std::vector<std::string> failures;
  double wall_time_s = 0.0;
};

/// Every case in order, progress on stderr.
Results run_cases() {
  const auto start = std::chrono::steady_clock::now();
  Results res;
  res.v_corner = contacts::run_v_corners();
  std::fprintf(stderr, "validate_contacts: v-corner done\n");
  res.bounce = contacts::run_bounces();
  std::fprintf(stderr, "validate_contacts: bounce done\n");
  res.slide = contacts::run_slides();
  std::fprintf(stderr, "validate_contacts: slide done\n");
  res.overlap = contacts::run_overlaps();
  std::fprintf(stderr, "validate_contacts: overlap done\n");
  res.column = contacts::run_columns();
  std::fprintf(stderr, "validate_contacts: column done\n");
  res.stack = contacts::run_stacks();
  std::fprintf(stderr, "validate_contacts: stack done\n");
  res.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

std::string results_json(const Results& res) {
  std::ostringstream j;
  j << "{\n";
  contacts::write_v_corners(j, res.v_corner);
  contacts::write_bounces(j, res.bounce);
  contacts::write_slides(j, res.slide);
  contacts::write_overlaps(j, res.overlap);
  contacts::write_columns(j, res.column);
  contacts::write_stacks(j, res.stack);
  j << "  \"wall_time_s\": " << validation::json_number(res.wall_time_s)
    << ",\n  \"passed\": " << (res.failures.empty() ? "true" : "false")
    << ",\n  \"failures\": " << validation::json_strings(res.failures) << "\n}\n";
  return j.str();
}

int run_validation(const std::string& out) {
  Results res = run_cases();
  contacts::check_v_corners(res.v_corner, res.failures);
  contacts::check_bounces(res.bounce, res.failures);
  contacts::check_slides(res.slide, res.failures);
  contacts::check_overlaps(res.overlap, res.failures);
  contacts::check_stacks(res.stack, res.failures);
  contacts::check_columns(res.column, res.failures);
  contacts::print_v_corners(res.v_corner);
  contacts::print_bounces(res.bounce);
  contacts::print_slides(res.slide);
  contacts::print_overlaps(res.overlap);
  contacts::print_columns(res.column);
  contacts::print_stacks(res.stack);
  validation::write_result(out, results_json(res));
  std::printf("\nwrote %s (%.1f s)\n", out.c_str(), res.wall_time_s);
  return validation::report_failures(res.failures);
}

}  // namespace

int main(int argc, char** argv) {
  std::string out = "validation/results/contacts.json";
  validation::CommandLine cli("validate_contacts", kHelp);
  cli.option("--out", [&out](const std::string& value) { out = value; });
  cli.parse(argc, argv);
  return validation::run_main("validate_contacts", [&out] { return run_validation(out); });
}
