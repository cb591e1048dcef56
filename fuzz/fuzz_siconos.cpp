// libFuzzer target for the Siconos .dat readers (src/io/siconos.cpp, src/io/siconos_fc3d.cpp):
// every input is read as an LCP (relay = false), as a relay problem (relay = true) and as a
// frictional-contact dump. Each either returns a problem whose matrices and vectors have the
// right sizes and no NaN (M, q finite; lb ≤ ub; a friction-contact problem's A and b finite, three
// rows per contact, each mu ≥ 0), or throws cbps::InputError; any other exception, a crash or a
// sanitizer report is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/io/siconos_fc3d.hpp"

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

void check(const cbps::StoredProblem& p) {
  const auto c = p.b.size();
  require(p.A.rows() == c && p.A.cols() == c && p.cmin.size() == c && p.cmax.size() == c,
          "sizes do not agree");
  require(p.cones.contacts() * 3 == c, "not three rows per contact");
  bool finite = p.b.allFinite();
  for (int j = 0; j < p.A.outerSize(); ++j)
    for (cbps::SpMat::InnerIterator it(p.A, j); it; ++it)
      finite = finite && std::isfinite(it.value());
  require(finite, "A or b is not finite");
  require((p.cones.mu.array() >= 0.0).all(), "a negative mu");
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
  try {
    std::istringstream in(text);
    check(cbps::parse_siconos_fc3d(in, "fuzz.dat"));
  } catch (const cbps::InputError&) {
  }
  return 0;
}
