// One full step of the pyramid scene (bases 10, 20, 40: 55, 210 and 820 boxes) split by stage:
// broad phase and narrow phase of collision detection (4), rows (5.3, 5.4), assembly (6.1,
// 6.2.9), solve (both systems of the improved push, 8.1; PGS, 100 sweeps at most, tolerance
// 1e-10 N) and integration (12.3.1, 3.2). Each pyramid is stepped `--settle` steps (default 30)
// first, then `--steps` steps (default 60) are timed; the table gives the mean per step.
// Usage: bench_contacts [--out FILE] [--steps N] [--settle N] [--solver NAME]
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "cbps/io/output_dir.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

int main(int argc, char** argv) {
  std::string out_path, solver = "pgs";
  long steps = 60, settle = 30;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--out" && has_value) {
      out_path = argv[++i];
    } else if (a == "--steps" && has_value) {
      steps = std::max(1L, std::atol(argv[++i]));
    } else if (a == "--settle" && has_value) {
      settle = std::max(0L, std::atol(argv[++i]));
    } else if (a == "--solver" && has_value) {
      solver = argv[++i];
    } else {
      std::cerr << "usage: bench_contacts [--out FILE] [--steps N] [--settle N] [--solver S]\n";
      return 2;
    }
  }
  std::printf(
      "| base (boxes) | rows | contacts | broad phase | narrow phase | rows | assembly | solve "
      "| integrate | step (ms) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  nlohmann::json result = nlohmann::json::array();
  for (const int base : {10, 20, 40}) {
    cbps::Scene scene = cbps::make_builtin_scene("pyramid", {{"base", std::to_string(base)}});
    scene.solver.method = cbps::method_of(solver);
    cbps::Simulation sim(scene);
    for (long s = 0; s < settle; ++s) sim.step();
    cbps::StageTimes sum;
    double total = 0.0;
    long rows = 0, contacts = 0;
    for (long s = 0; s < steps; ++s) {
      const cbps::StepReport r = sim.step();
      sum += r.times;
      total += r.wall_time_s;
      rows += r.rows;
      contacts += r.contacts;
    }
    const double n = static_cast<double>(steps);
    const auto ms = [&](double s) { return 1e3 * s / n; };
    const auto share = [&](double s) { return 100.0 * s / total; };
    std::printf("| %d (%zu) | %.0f | %.0f |",
                base,
                scene.bodies.size() - 1,
                static_cast<double>(rows) / n,
                static_cast<double>(contacts) / n);
    for (const double s :
         {sum.broad_phase, sum.narrow_phase, sum.rows, sum.assembly, sum.solve, sum.integrate}) {
      std::printf(" %.3g ms (%.0f%%) |", ms(s), share(s));
    }
    std::printf(" %.3g |\n", ms(total));
    std::fflush(stdout);
    result.push_back({{"base", base},
                      {"boxes", scene.bodies.size() - 1},
                      {"rows_mean", static_cast<double>(rows) / n},
                      {"contacts_mean", static_cast<double>(contacts) / n},
                      {"ms_per_step",
                       {{"broad_phase", ms(sum.broad_phase)},
                        {"narrow_phase", ms(sum.narrow_phase)},
                        {"rows", ms(sum.rows)},
                        {"assembly", ms(sum.assembly)},
                        {"solve", ms(sum.solve)},
                        {"integrate", ms(sum.integrate)},
                        {"step", ms(total)}}}});
  }
  if (!out_path.empty()) {
    // Whole or not at all (a temporary file beside it, renamed into place).
    try {
      cbps::write_output_file(out_path,
                              "--out " + out_path,
                              nlohmann::json{{"bench", "pyramid step by stage"},
                                             {"solver", solver},
                                             {"steps", steps},
                                             {"settle", settle},
                                             {"pyramids", result}}
                                      .dump(2) +
                                  "\n");
    } catch (const std::exception& e) {
      std::cerr << "bench_contacts: " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}
