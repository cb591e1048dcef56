// FCLIB files (Dubois, Acary, Jean et al., the frictional-contact problem library; HDF5): the
// global problem (read: read_fclib) and the local problem
//   u = W r + q (+ V l),  0 = Vᵀ r + R l + s,  each contact's (u, r) in Coulomb's law,
// rows per contact in the order normal, t1, t2 (spacedim 3), read and written by cbps itself
// through HDF5 (FCLIB's own reader ends the process on a malformed file; cbps names the dataset
// and what is wrong, exit 2). The layout is FCLIB 3's: /fclib_local/{spacedim, W, V, R,
// vectors/{q, mu, s}, info/{title, description, math_info}}, /solution/{u, r, l}; a matrix is a
// group {nzmax, m, n, nz, p, i, x} in CSparse's forms (nz ≥ 0 triplets with i the rows and p the
// columns, −1 compressed columns, −2 compressed rows).
//
// In cbps's convention (6.2) the problem is w = A lambda − b with A = [W V; Vᵀ R], b = −[q; s],
// lambda = [r; l]: the contacts' rows in cones (StoredProblem::cones), the rows of l free.
#pragma once

#include <string>

#include "cbps/io/stored_problem.hpp"

namespace cbps {

/// True when the file begins with HDF5's signature (\x89HDF\r\n\x1a\n).
bool is_hdf5_file(const std::string& path);

/// An FCLIB local problem as a stored problem whose contacts are in cones (law Coulomb, FCLIB's)
/// and whose equality rows (V, R, s) are free; with the file's solution, if it has one, in
/// `solution` (lambda = [r; l]). A global problem (/fclib_global: M v = H r + G l + f,
/// Gᵀ v + b = 0, u = Hᵀ v + w) with v eliminated: J = [Hᵀ; Gᵀ], A = J M⁻¹ Jᵀ,
/// b = −[Hᵀ M⁻¹ f + w; Gᵀ M⁻¹ f + b], J and M⁻¹ kept where M is block-diagonal in blocks of at
/// most 12 rows (docs/cones.md). Throws InputError naming the file, the dataset (e.g.
/// /fclib_local/W/p) and what is wrong.
StoredProblem read_fclib(const std::string& path, VecX* solution = nullptr);

/// What write_fclib puts in /fclib_local/info.
struct FclibInfo {
  std::string title;
  std::string description;
  std::string math_info;
};

/// Which of FCLIB's problems write_fclib writes.
enum class FclibForm { Local, Global };

/// Writes p as an FCLIB problem to `path` (whole or not at all: write_file_atomically), the
/// contacts' rows first in contact order (normal, t1, t2), then the free rows. Local: W = A in
/// compressed columns (the form FCLIB's merit function reads), the free rows as V, R and s;
/// with `lambda`, /solution holds r, u = W r + q (+ V l) and l. Global (needs p's J and a
/// block-diagonal Minv): M = Minv⁻¹, H and G the transposes of J's contact and free rows, f = 0,
/// w and b the negated b of those rows, so that u = Hᵀ v + w = A r − b at v = Minv Jᵀ lambda;
/// /solution holds v, u, r and l. Throws InputError if a row is neither in a cone nor free
/// (FCLIB has no other kind), naming it, or if a global problem cannot be formed.
void write_fclib(const std::string& path,
                 const StoredProblem& p,
                 const FclibInfo& info,
                 const VecX* lambda = nullptr,
                 FclibForm form = FclibForm::Local);

}  // namespace cbps
