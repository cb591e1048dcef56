// Stored problems for `cbps lcp` and `cbps converge`: a folder written by `cbps matrices`, a
// Siconos .dat file (LCP or relay) or an FCLIB file (io/fclib_file.hpp), held in the paper's
// convention (6.2).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cbps/io/siconos.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"

namespace cbps {

/// The boxed problem of 6.2 as stored: w = A lambda − b, cmin ≤ lambda ≤ cmax. Siconos'
/// w = M z + q, lb ≤ z ≤ ub is M = A, q = −b, lb = cmin, ub = cmax. A `cbps matrices` folder
/// also gives the system's J and Minv (6.1), with which the direct path factors in body space
/// and the matrix-free and shock sweeps can run (has_jacobian()), and its v1, fext and dt, with
/// which v2 (12.3.1) can be formed (has_bodies()).
struct StoredProblem {
  SpMat A;    ///< c×c
  VecX b;     ///< c
  VecX cmin;  ///< c, −∞ allowed
  VecX cmax;  ///< c, +∞ allowed
  bool folder = false;
  SpMatRow J;     ///< c×6n, from J.mtx when the folder has J.mtx and Minv.mtx
  SpMat Minv;     ///< 6n×6n, from Minv.mtx likewise
  VecX v1, fext;  ///< 6n, from v1.mtx and fext.mtx when these, dt.txt, J and Minv are all there
  double dt = 0.0;
  /// Why J and Minv are not here ("no J.mtx in the folder", "a Siconos file carries no J and
  /// Minv"); empty when they are.
  std::string without_jacobian;
  /// Constraint-force mixing eps, kg⁻¹, from the folder's cfm.txt (0 without one): the step
  /// solved the boxed problem of A + eps E (with_cfm), and so do `cbps lcp` and `converge`.
  double cfm = 0.0;
  /// Each row's kind from the folder's labels.json (row labels "contact A-B #F", "friction A-B
  /// #F t1", anything else a distance row; docs/outputs.md); empty without labels.json (a
  /// Siconos file, a folder written without one): then no sweep can put contacts first.
  std::vector<RowKind> kinds;
  /// Each row's label from labels.json ("contact A-B #F", ...); empty without one.
  std::vector<std::string> labels;
  /// Each row's contact manifold for block PGS: the contact and friction rows of one body pair
  /// A-B in a run of rows form one, as System::manifold groups a step's rows; −1 for a row
  /// alone (every row without labels.json).
  std::vector<int> blocks;
  /// The contacts whose rows live in Coulomb's cone (an FCLIB file, a step with friction=cone);
  /// empty for the paper's boxed problem.
  FrictionContacts cones;
  bool fclib = false;  ///< read from an FCLIB file (io/fclib_file.hpp)
  /// What the reader did to the file's data beyond reading it, one sentence each (a global
  /// problem's M stored as one triangle, read as the symmetric M it is half of); `cbps lcp`
  /// prints them (`read_notes` in its JSON).
  std::vector<std::string> notes;
  long rows() const { return static_cast<long>(b.size()); }
  /// J and Minv are here (A = J Minv Jᵀ, 6.2.9): body space for the direct path.
  bool has_jacobian() const { return J.rows() == rows() && J.rows() > 0; }
  /// J, Minv, v1, fext and dt are all here: v2 can be formed (12.3.1).
  bool has_bodies() const { return has_jacobian() && dt > 0.0; }
  /// The boxed problem, with J and Minv when the folder has them and its rows' kinds and
  /// manifolds when its labels.json gives them. A view: keep this alive.
  BoxedProblem problem() const {
    BoxedProblem p =
        has_jacobian() ? BoxedProblem{A, b, cmin, cmax, &J, &Minv} : BoxedProblem{A, b, cmin, cmax};
    if (blocks.size() == static_cast<std::size_t>(rows())) p.blocks = &blocks;
    if (!kinds.empty()) p.kinds = &kinds;
    if (!cones.empty()) p.cones = &cones;
    return p;
  }
};

/// A step's system as the problem a folder stores (copies): A, b, cmin, cmax, J, Minv, v1,
/// fext, dt, the rows' kinds and manifolds, and the solver's constraint-force mixing `cfm`.
StoredProblem stored_problem(const System& sys, double cfm);

/// A folder (by its A.mtx, b.mtx, cmin.mtx, cmax.mtx, cfm.txt if there is one; J.mtx and
/// Minv.mtx when both are there, A.mtx then checked to be J Minv Jᵀ (check_factors_agree), and then
/// v1.mtx, fext.mtx and dt.txt when all three are; labels.json's row labels when it is there), an
/// FCLIB file (an HDF5 file: read_fclib) or a Siconos file. Throws InputError naming the file and
/// line. `kind` says what a .dat file holds (SiconosKind::Auto: from its contents).
StoredProblem read_problem(const std::string& path, SiconosKind kind = SiconosKind::Auto);

/// read_problem as the commands that read a stored problem take it (`cbps lcp`, `cbps check`):
/// `siconos` the word of their --siconos (auto, lcp, relay, fc3d; a kind other than auto on a
/// folder or an FCLIB file is refused), `cone` that of their --cone (set_cone_law). InputError
/// naming the option.
StoredProblem read_problem(const std::string& path,
                           const std::string& siconos,
                           const std::string& cone);
/// --cone's law on p's contacts (nothing when cone is empty): "coulomb" or "ccp"; InputError
/// naming `path` when p has no contacts in cones or the word is another.
void set_cone_law(StoredProblem& p, const std::string& cone, const std::string& path);

/// Where write_problem puts each file: called with the file's name in the folder ("A.mtx") and
/// a function that writes the content to a path it is given; the sink chooses that path (a
/// `--out` folder's temporary place, a temporary name renamed into place, ...).
using FileSink = std::function<void(const std::string& name,
                                    const std::function<void(const std::string& path)>& write)>;

/// What the writer of a problem folder adds to the files' comment lines.
struct ProblemNotes {
  std::string A;       ///< after A's comment, e.g. how its rows were made
  std::string bounds;  ///< after cmin's and cmax's, e.g. the Coulomb fixed point of their rows
};

/// The one writer of a problem folder, the files read_problem reads: A.mtx, b.mtx, cmin.mtx,
/// cmax.mtx; J.mtx, Minv.mtx, v1.mtx, fext.mtx and dt.txt when p.dt > 0 (a step's system, whose
/// bodies are all known; J.mtx and Minv.mtx alone when only p.has_jacobian()); cfm.txt when
/// p.cfm > 0. Numbers are written to read back as the same
/// doubles. `cbps matrices`, `cbps lcp --generate --write-system` and the Python module's
/// write_problem write through it; each adds its own files (labels.json, lambda.mtx) beside.
void write_problem(const StoredProblem& p, const FileSink& sink, const ProblemNotes& notes = {});

/// The bounds and right-hand side of a problem's rows (all of them, or one rank's rows from
/// `first_row`, which the messages number from): cmin ≤ cmax, neither NaN, cmin < +inf and
/// cmax > −inf (a bound no lambda can meet), b finite. Throws InputError naming the file, the
/// vector and its row.
void check_bounds(const VecX& b,
                  const VecX& cmin,
                  const VecX& cmax,
                  const std::string& cmin_file,
                  const std::string& cmax_file,
                  const std::string& b_file,
                  long first_row = 0);

/// A folder's constraint-force mixing eps from its cfm.txt, kg⁻¹; 0 without one. Throws
/// InputError for a text that is not a number >= 0.
double read_cfm(const std::string& dir);

/// InputError naming the folder's A.mtx, J.mtx and Minv.mtx and the gap unless `gap` (of A.mtx
/// against J Minv Jᵀ, factors_gap) is within kFactorsTolerance: a folder whose A is not its J
/// Minv Jᵀ is bad input on every path (read_problem; the exact path and TAO under MPI, each rank
/// measuring its rows).
void check_factors_agree(const std::string& dir, const FactorsGap& gap);

/// The number of contacts in the friction cones of the folder `dir` (its cones.json's
/// /contacts), 0 without cones.json; InputError naming the file when it is not such JSON. For
/// the paths that read a folder by rows and solve only the boxed problem of 6.2 (under MPI),
/// which must refuse a problem on cones.
long folder_cone_contacts(const std::string& dir);

/// InputError naming `what` and max |A − Aᵀ| unless A is symmetric to kSymmetryTolerance
/// (system/boxed_problem.hpp; solve() makes the same test on every solve):
/// the direct path solves the QP of 6.2, which needs it. A problem on friction cones passes
/// whatever its A: direct solves the law itself there (needs_symmetric).
void require_symmetric(const StoredProblem& p, const std::string& what);

}  // namespace cbps
