// cbps check PROBLEM --lambda FILE [--json]: a given lambda judged against a stored problem
// (studies/check.hpp); exit 0 solved, 1 not, 2 bad input.
#include "cbps/studies/check.hpp"

#include <cstdio>
#include <memory>

#include "cbps/io/matrix_market.hpp"
#include "common.hpp"

namespace cbps::cli {

struct CheckOptions {
  std::string problem, lambda, siconos = "auto", cone;
  bool json = false, quiet = false;
  CheckSettings settings;
};

void register_check(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "check", "judge a given lambda against a stored problem (docs/outputs.md, cbps check)");
  auto o = std::make_shared<CheckOptions>();
  cmd->add_option("PROBLEM", o->problem, "as `cbps lcp` reads it: a folder, .dat or FCLIB file")
      ->required();
  cmd->add_option("--lambda",
                  o->lambda,
                  "the answer to judge, N: a Matrix Market array or one number a line, one "
                  "entry per row of the problem")
      ->required();
  add_problem_options(cmd, o->siconos, o->cone);
  cmd->add_option("--worst", o->settings.worst, "name this many of the largest terms (default 10)")
      ->check(non_negative());
  cmd->add_flag("!--no-exact",
                o->settings.exact,
                "do not solve the problem by direct for the distance from its exact answer");
  cmd->add_option("--time-limit",
                  o->settings.time_limit,
                  "stop direct after this many seconds (default 0: no limit)")
      ->check(non_negative());
  add_json_flag(cmd, o->json, "the report");
  add_quiet_flag(cmd, o->quiet, "no progress line on stderr every 2 s of a long exact solve");
  cmd->callback([&run, o] {
    run = [o] {
      const StoredProblem p = read_problem(o->problem, o->siconos, o->cone);
      const VecX lambda = read_vector_file(o->lambda);
      const Heartbeat beat("cbps check: " + o->problem, o->settings.time_limit, o->quiet);
      const CheckReport r = check_lambda(p, lambda, o->settings);
      if (o->json)
        std::printf("%s\n", check_json(o->problem, r).dump(2).c_str());
      else
        std::printf("%s", check_text(o->problem, r).c_str());
      return r.solved ? 0 : 1;
    };
  });
}

}  // namespace cbps::cli
