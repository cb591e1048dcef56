// Siconos .dat reader: a tokeniser that remembers each token's line, then the fields in order.
#include "cbps/io/siconos.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <istream>
#include <sstream>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/io/input_file.hpp"
#include "token_reader.hpp"

namespace cbps {

namespace {

/// The free text after the data must not start with a number (see siconos.hpp).
void expect_end_of_data(const TokenReader& reader, const std::string& after) {
  const Token* t = reader.peek();
  double value = 0;
  if (t != nullptr && parse_token(t->text, value))
    reader.fail(t->line,
                "a number ('" + t->text + "') after " + after + ": wrong n or wrong problem type");
}

/// n numbers into v, named e.g. "q[3]".
void read_vector(TokenReader& reader, const std::string& name, VecX& v) {
  for (Eigen::Index k = 0; k < v.size(); ++k)
    v(k) = reader.next_number([&] { return name + "[" + std::to_string(k) + "]"; });
}

}  // namespace

StoredLcp parse_siconos(std::istream& in, const std::string& source, bool relay) {
  return parse_siconos(in, source, relay ? SiconosKind::Relay : SiconosKind::Lcp);
}

StoredLcp parse_siconos(std::istream& in, const std::string& source, SiconosKind kind) {
  TokenReader reader(in, source);
  if (kind == SiconosKind::FrictionContact)
    reader.fail(1, "a frictional-contact problem is not an LCP (read_problem reads it)");

  // Header: n, storage type, rows cols, rows cols.
  const long n = reader.next_integer("n (size of the problem)");
  if (n <= 0 || n > kMaxSiconosSize)
    reader.fail(reader.line(),
                "n = " + std::to_string(n) + " is outside 1 … " + std::to_string(kMaxSiconosSize));
  const long storage = reader.next_integer("storage type");
  if (storage == 1)
    reader.fail(reader.line(), "storage type 1 (sparse-block) is not read; only 0 (dense)");
  if (storage != 0) reader.fail(reader.line(), "unknown storage type " + std::to_string(storage));
  for (const char* what :
       {"rows of M", "columns of M", "rows of M (again)", "columns of M (again)"}) {
    const long size = reader.next_integer(what);
    if (size != n)
      reader.fail(
          reader.line(),
          std::string(what) + " = " + std::to_string(size) + ", not n = " + std::to_string(n));
  }
  if (kind == SiconosKind::Auto) {
    const std::size_t numbers = reader.leading_numbers();
    const std::size_t nn = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    const std::size_t un = static_cast<std::size_t>(n);
    // Short of a whole LCP or relay problem: read as the smaller one that does not fit, so the
    // reader names the token or the end of file where the data stop.
    if (numbers <= nn + un) {
      kind = SiconosKind::Lcp;
    } else if (numbers <= nn + 3 * un) {
      kind = SiconosKind::Relay;
    } else {
      reader.fail(reader.line(),
                  std::to_string(numbers) + " numbers after the header; n = " + std::to_string(n) +
                      " needs " + std::to_string(nn + un) + " for an LCP (M, q) or " +
                      std::to_string(nn + 3 * un) + " for a relay problem (M, q, lb, ub)");
    }
  }
  const bool relay = kind == SiconosKind::Relay;

  // M is read into a buffer that grows with the numbers actually there, and only then into an
  // n×n matrix: a header may claim n = kMaxSiconosSize (200 MB) over a file of a few bytes.
  // Column-major, as Siconos reads it (see siconos.hpp): the k-th number is M(k mod n, k / n).
  const std::size_t count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  std::vector<double> m_values;
  m_values.reserve(std::min(count, reader.remaining()));
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < n; ++i)
      m_values.push_back(reader.next_number(
          [&] { return "M(" + std::to_string(i) + ", " + std::to_string(j) + ")"; }));

  StoredLcp p;
  p.source = source;
  p.boxed = relay;
  p.M = Eigen::Map<const MatX>(m_values.data(), n, n);
  p.q.resize(n);
  read_vector(reader, "q", p.q);
  if (relay) {
    p.lb.resize(n);
    p.ub.resize(n);
    read_vector(reader, "lb", p.lb);
    read_vector(reader, "ub", p.ub);
    for (Eigen::Index k = 0; k < n; ++k)
      if (p.lb(k) > p.ub(k))
        reader.fail(reader.line(), "lb[" + std::to_string(k) + "] > ub[" + std::to_string(k) + "]");
  } else {
    p.lb = VecX::Zero(n);
    p.ub = VecX::Constant(n, kInf);
  }
  expect_end_of_data(reader, relay ? "ub" : "q");
  return p;
}

StoredLcp read_siconos(const std::string& path, bool relay) {
  return read_siconos(path, relay ? SiconosKind::Relay : SiconosKind::Lcp);
}

StoredLcp read_siconos(const std::string& path, SiconosKind kind) {
  std::ifstream in = open_text_file(path, "a Siconos .dat text file (or a cbps matrices folder)");
  return parse_siconos(in, path, kind);
}

SiconosKind parse_siconos_kind(const std::string& text, const std::string& what) {
  if (text == "auto") return SiconosKind::Auto;
  if (text == "lcp") return SiconosKind::Lcp;
  if (text == "relay") return SiconosKind::Relay;
  if (text == "fc3d") return SiconosKind::FrictionContact;
  throw InputError(what + " '" + text + "': expected auto, lcp, relay or fc3d");
}

}  // namespace cbps
