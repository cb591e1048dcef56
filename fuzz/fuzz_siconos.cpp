// libFuzzer target for the Siconos .dat reader (src/io/siconos.cpp): every input is read both as an
// LCP (relay = false) and as a relay problem (relay = true). Each either returns a problem whose
// M, q, lb and ub have the right sizes and no NaN (M, q finite; lb ≤ ub), or throws
// cbps::InputError; any other exception, a crash or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/siconos.hpp"

namespace {

void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_siconos: %s\n", what);
  std::abort();
}

void check(const cbps::StoredLcp& p, bool relay) {
  const auto n = p.q.size();
  require(n >= 1 && n <= cbps::kMaxSiconosSize, "n out of range");
  require(p.M.rows() == n && p.M.cols() == n && p.lb.size() == n && p.ub.size() == n,
          "sizes do not agree");
  require(p.M.allFinite() && p.q.allFinite(), "M or q is not finite");
  require(!p.lb.hasNaN() && !p.ub.hasNaN() && (p.lb.array() <= p.ub.array()).all(),
          "lb or ub is NaN, or lb > ub");
  require(p.boxed == relay, "boxed is not the relay flag");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const bool relay : {false, true}) {
    try {
      std::istringstream in(text);
      check(cbps::parse_siconos(in, "fuzz.dat", relay), relay);
    } catch (const cbps::InputError&) {
    }
  }
  return 0;
}
