// libFuzzer target for the Matrix Market readers (src/io/matrix_market.cpp): every input is read
// both as a sparse matrix (parse_matrix_market_sparse) and as a vector
// (parse_matrix_market_vector). Each either returns or throws cbps::InputError; any other
// exception, a crash, a sanitizer report, or a NaN in what was read is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "cbps/error.hpp"
#include "cbps/io/matrix_market.hpp"

namespace {

void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_matrix_market: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    std::istringstream in(text);
    const cbps::SpMat M = cbps::parse_matrix_market_sparse(in, "fuzz.mtx");
    for (cbps::SpMat::Index k = 0; k < M.nonZeros(); ++k)
      require(!std::isnan(M.valuePtr()[k]), "a NaN in the sparse matrix read");
  } catch (const cbps::InputError&) {
  }
  try {
    std::istringstream in(text);
    const cbps::VecX v = cbps::parse_matrix_market_vector(in, "fuzz.mtx");
    require(!v.hasNaN(), "a NaN in the vector read");
  } catch (const cbps::InputError&) {
  }
  return 0;
}
