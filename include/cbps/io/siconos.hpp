// Reader of the Siconos numerics test problems (.dat, dense storage only): the external data in
// tests/data/siconos, problems nobody on the team chose (see tests/data/README.md).
//
// File layout, whitespace separated (numbers may be spread over lines in any way):
//   n                       size of the problem, 1 ≤ n ≤ kMaxSiconosSize
//   storage                 0 = dense (the only one read); 1 = sparse-block storage (rejected)
//   rows cols               n n
//   rows cols               n n again
//   M                       n×n numbers in COLUMN-MAJOR order: each line of n numbers is a
//                           column of M (see below)
//   q                       n numbers
//   lb ub                   relay only: n numbers each
// The order of M. Siconos (numerics, NumericsMatrix newFromFile) reads the n² numbers in file
// order into its dense array matrix0, which is column-major (entry (i, j) at i + j n), so the
// file's lines are the columns of M, not its rows as a plain reading of the layout suggests. The
// data agree: read by rows, lcp_CPS_4 has the row w_4 = −z_1 − z_2 − z_3 − 6 < 0 and
// lcp_Pang_isolated_sol the row w_2 = −z_1 − 1 < 0 (no solution at all, against their sources);
// read by columns, both have solutions (CPS_4 is then the KKT system of a convex QP). Symmetric
// files are unaffected. Free text after the numbers (a remark on the source) is not data; it must
// not start with a number, so that a wrong n or a relay file read as an LCP is caught rather than
// half-read.
#pragma once

#include <istream>
#include <string>

#include "cbps/base/types.hpp"

namespace cbps {

/// The largest n read: a dense n×n M beyond this is more likely a corrupt header than a problem.
inline constexpr int kMaxSiconosSize = 5000;

/// An LCP `w = M z + q, w ≥ 0, z ≥ 0, wᵀz = 0` (Siconos sign convention) or, if boxed, a relay
/// problem `lb ≤ z ≤ ub` with z_i = lb_i ⇒ w_i ≥ 0, z_i = ub_i ⇒ w_i ≤ 0, between ⇒ w_i = 0.
/// The paper's boxed problem (6.2) is the same with M = A, q = −b, lb = cmin, ub = cmax.
struct StoredLcp {
  MatX M;              ///< n×n, any matrix (not necessarily symmetric or definite)
  VecX q;              ///< n
  VecX lb;             ///< n; 0 for an LCP
  VecX ub;             ///< n; +∞ for an LCP
  bool boxed = false;  ///< true for a relay file
  std::string source;  ///< the path read
};

/// Reads a dense Siconos .dat file; relay = true reads lb and ub after q. Throws InputError
/// "<path>: line L: <why>" on a missing file, a token that is not a number, too few or too many
/// numbers, storage type 1, a non-finite value, or n ≤ 0 or n > kMaxSiconosSize.
StoredLcp read_siconos(const std::string& path, bool relay);

/// read_siconos from a stream; `source` names it in errors ("<source>: line L: <why>") and in
/// StoredLcp::source.
StoredLcp parse_siconos(std::istream& in, const std::string& source, bool relay);

/// What a .dat file holds: found from its contents (Auto), or as the user says. FrictionContact
/// is a frictional-contact dump, local or global (io/siconos_fc3d.hpp), read by read_problem;
/// read_siconos reads the other two.
enum class SiconosKind { Auto, Lcp, Relay, FrictionContact };

/// Reads a dense Siconos .dat file of the given kind. Auto tells the two apart by the count of
/// numbers after the header: n² + n (M, q) is an LCP, n² + 3n (M, q, lb, ub) a relay problem;
/// as free text after the data may not start with a number, the count is never ambiguous. A
/// count between the two is read as a relay problem, a smaller one as an LCP, so the error
/// names where the data stop; a larger one is an InputError saying what each kind needs.
StoredLcp read_siconos(const std::string& path, SiconosKind kind);
StoredLcp parse_siconos(std::istream& in, const std::string& source, SiconosKind kind);

/// The kind named on the command line: "auto", "lcp", "relay" or "fc3d"; InputError otherwise.
SiconosKind parse_siconos_kind(const std::string& text, const std::string& what);

}  // namespace cbps
