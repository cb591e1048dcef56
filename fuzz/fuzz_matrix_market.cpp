// libFuzzer target for the Matrix Market readers (src/io/matrix_market.cpp): every input is read
// both as a sparse matrix (parse_matrix_market_sparse) and as a vector
// (parse_matrix_market_vector), and what reads whole is read again by rows in two halves
// (parse_matrix_market_*_rows), which must give the whole's rows. Each either returns or throws
// cbps::InputError; any other exception, a crash, a sanitizer report, a NaN in what was read or
// a half that differs is a finding. Each input is also read as a lambda file
// (parse_vector_text), which must give finite entries or throw InputError.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/matrix_market.hpp"

namespace {

void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_matrix_market: %s\n", what);
  std::abort();
}

/// a and b hold the same entries in the same places, bit for bit (inf == inf; no arithmetic).
bool same(const cbps::SpMat& a, const cbps::SpMat& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros()) return false;
  for (cbps::SpMat::Index c = 0; c < a.outerSize(); ++c) {
    cbps::SpMat::InnerIterator x(a, c);
    cbps::SpMat::InnerIterator y(b, c);
    for (; x && y; ++x, ++y)
      if (x.row() != y.row() || !(x.value() == y.value())) return false;
    if (x || y) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  cbps::SpMat M;
  bool read = false;
  try {
    std::istringstream in(text);
    M = cbps::parse_matrix_market_sparse(in, "fuzz.mtx");
    read = true;
    for (cbps::SpMat::Index k = 0; k < M.nonZeros(); ++k)
      require(!std::isnan(M.valuePtr()[k]), "a NaN in the sparse matrix read");
  } catch (const cbps::InputError&) {
  }
  if (read) {
    // Read by rows (two ranks' halves, docs/distributed.md): what reads whole reads by rows
    // without error (an exception here is a finding), and the halves are the whole's rows.
    const long half = static_cast<long>(M.rows()) / 2;
    for (const cbps::RowRange keep : {cbps::RowRange{0, half}, cbps::RowRange{half, M.rows()}}) {
      std::istringstream again(text);
      const cbps::SpMat part = cbps::parse_matrix_market_sparse_rows(again, "fuzz.mtx", keep);
      require(same(part, cbps::SpMat(M.middleRows(keep.first, keep.last - keep.first))),
              "a half read by rows differs from the whole's rows");
    }
  }
  cbps::VecX v;
  read = false;
  try {
    std::istringstream in(text);
    v = cbps::parse_matrix_market_vector(in, "fuzz.mtx");
    read = true;
    require(!v.hasNaN(), "a NaN in the vector read");
  } catch (const cbps::InputError&) {
  }
  if (read) {
    const long half = static_cast<long>(v.size()) / 2;
    for (const cbps::RowRange keep : {cbps::RowRange{0, half}, cbps::RowRange{half, v.size()}}) {
      std::istringstream again(text);
      const cbps::VecX part = cbps::parse_matrix_market_vector_rows(again, "fuzz.mtx", keep);
      require(part.size() == keep.last - keep.first &&
                  (part.array() == v.segment(keep.first, part.size()).array()).all(),
              "a half read by rows differs from the whole's entries");
    }
  }
  // The same text as a given lambda (`cbps check --lambda`): Matrix Market or one number a line,
  // every entry finite.
  try {
    std::istringstream in(text);
    require(cbps::parse_vector_text(in, "fuzz.txt").allFinite(),
            "an entry of a lambda file read that is not finite");
  } catch (const cbps::InputError&) {
  }
  return 0;
}
