// What the validation programs share: the command line (`--name VALUE` options, --help, exit
// status 2 on bad usage), the one step loop (cbps::run_steps, a divergence rethrown), result
// files written whole or not at all, and their JSON numbers and strings. README.md, "Rerunning",
// describes each program's options.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cbps/studies/run.hpp"

namespace validation {

/// A program's options, each `--name VALUE`; `--help` and `-h` print the help text and exit 0.
class CommandLine {
 public:
  CommandLine(std::string program, std::string help);
  /// `set` receives the value; it may call fail() for a bad one.
  void option(const std::string& name, std::function<void(const std::string& value)> set);
  /// Reads argv; an unknown option or a missing value ends the program with status 2.
  void parse(int argc, char** argv) const;
  /// "<program>: <why> (see --help)" on stderr, exit status 2.
  [[noreturn]] void fail(const std::string& why) const;

 private:
  std::string program_, help_;
  std::map<std::string, std::function<void(const std::string&)>> options_;
};

/// main's body: run(), and exit status 2 for an InputError (bad input), 1 for any other error,
/// each reported as "<program>: <what>" on stderr.
int run_main(const std::string& program, const std::function<int()>& run);

/// cbps::run_steps(sim, steps, observers), with a DivergenceError thrown on, not stored: a
/// validation run that diverged has no numbers to report.
cbps::RunTotals run_steps(cbps::Simulation& sim,
                          long steps,
                          const std::vector<cbps::StepObserver*>& observers);

/// Writes `contents` to `path` whole or not at all (cbps::write_file_atomically: a temporary
/// file beside it, then a rename), creating its folder. std::runtime_error if it cannot.
void write_result(const std::filesystem::path& path, const std::string& contents);

/// A finite number as "%.10g"; "inf", "-inf" and "nan" otherwise (for messages).
std::string number_text(double v);
/// A JSON number as "%.10g"; the strings "inf", "-inf" and "nan" otherwise (cbps::number_json).
std::string json_number(double v);
/// A JSON number as "%.10g", or null when not finite: validate_pendulum's validation.json, whose
/// readers (scripts/doc_tables_validation*.py, plot_validation.py) take null for "none".
std::string json_number_or_null(double v);
/// A JSON string: `s` in double quotes, `"` and `\` escaped.
std::string json_string(const std::string& s);
/// A JSON array of strings, `["a", "b"]`.
std::string json_strings(const std::vector<std::string>& list);

/// The closing lines of every program: each failure, then PASS or FAILED; the exit status.
int report_failures(const std::vector<std::string>& failures);

}  // namespace validation
