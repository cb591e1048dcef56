#include "harness.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "cbps/base/error.hpp"
#include "cbps/io/json_numbers.hpp"
#include "cbps/io/output_file.hpp"

namespace validation {

CommandLine::CommandLine(std::string program, std::string help)
    : program_(std::move(program)), help_(std::move(help)) {}

void CommandLine::option(const std::string& name,
                         std::function<void(const std::string& value)> set) {
  options_[name] = std::move(set);
}

void CommandLine::parse(int argc, char** argv) const {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << help_;
      std::exit(0);
    }
    const auto option = options_.find(arg);
    if (option == options_.end()) fail(arg + ": unknown option");
    if (i + 1 >= argc) fail(arg + ": missing value");
    option->second(argv[++i]);
  }
}

void CommandLine::fail(const std::string& why) const {
  std::cerr << program_ << ": " << why << " (see --help)\n";
  std::exit(2);
}

int run_main(const std::string& program, const std::function<int()>& run) {
  try {
    return run();
  } catch (const cbps::InputError& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 1;
  }
}

cbps::RunTotals run_steps(cbps::Simulation& sim,
                          long steps,
                          const std::vector<cbps::StepObserver*>& observers) {
  cbps::RunTotals totals = cbps::run_steps(sim, steps, observers);
  if (totals.diverged) throw *totals.diverged;
  return totals;
}

void write_result(const std::filesystem::path& path, const std::string& contents) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  try {
    cbps::write_file_atomically(path.string(), path.string(), [&](const std::string& temporary) {
      std::ofstream out(temporary);
      out << contents;
      out.close();
      if (!out) throw std::runtime_error("write failed");
    });
  } catch (const cbps::InputError& e) {
    throw std::runtime_error(e.what());  // not a usage error: exit status 1
  }
}

std::string number_text(double v) {
  if (!std::isfinite(v)) return cbps::number_json(v).get<std::string>();
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string json_number(double v) {
  return std::isfinite(v) ? number_text(v) : json_string(number_text(v));
}

std::string json_number_or_null(double v) { return std::isfinite(v) ? number_text(v) : "null"; }

std::string json_string(const std::string& s) {
  std::string quoted = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

std::string json_strings(const std::vector<std::string>& list) {
  std::string out = "[";
  for (std::size_t i = 0; i < list.size(); ++i) out += (i ? ", " : "") + json_string(list[i]);
  return out + "]";
}

int report_failures(const std::vector<std::string>& failures) {
  for (const std::string& f : failures) std::printf("FAIL: %s\n", f.c_str());
  std::printf("%s\n", failures.empty() ? "PASS" : "FAILED");
  return failures.empty() ? 0 : 1;
}

}  // namespace validation
