// FCLIB local problems read and written through HDF5 (io/fclib_file.hpp).
#include "cbps/io/fclib_file.hpp"

#include <hdf5.h>
#include <hdf5_hl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <utility>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/output_file.hpp"
#include "cbps/system/system.hpp"
#include "global_problem.hpp"

namespace cbps {

namespace {

/// HDF5 prints its own error stack on every failed call; cbps's message is the one the user
/// reads, so printing is off while a file is read or written (restored after).
class QuietHdf5 {
 public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietHdf5(const QuietHdf5&) = delete;
  QuietHdf5& operator=(const QuietHdf5&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// An open HDF5 file, closed on every path out.
class File {
 public:
  explicit File(hid_t id) : id_(id) {}
  ~File() {
    if (id_ >= 0) H5Fclose(id_);
  }
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  hid_t id() const { return id_; }

 private:
  hid_t id_;
};

/// The datasets of one file, each read with its size and kind checked.
class Reader {
 public:
  Reader(std::string path, hid_t file) : path_(std::move(path)), file_(file) {}

  [[noreturn]] void fail(const std::string& name, const std::string& what) const {
    throw InputError(path_ + ": " + name + ": " + what);
  }

  /// Whether the object `name` (an absolute path) exists, every group on the way included.
  bool exists(const std::string& name) const {
    for (std::size_t slash = name.find('/', 1);; slash = name.find('/', slash + 1)) {
      const std::string prefix = name.substr(0, slash);
      if (H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
      if (slash == std::string::npos) return true;
    }
  }

  /// The dataset's number of entries (a scalar or a vector), checked to be of `cls`.
  hsize_t size(const std::string& name, H5T_class_t cls, const char* kind) const {
    if (!exists(name)) fail(name, "missing");
    int rank = 0;
    if (H5LTget_dataset_ndims(file_, name.c_str(), &rank) < 0) fail(name, "not a dataset");
    if (rank > 1) fail(name, "has " + std::to_string(rank) + " dimensions; a vector was expected");
    hsize_t dims[1] = {1};
    H5T_class_t got{};
    std::size_t bytes = 0;
    if (H5LTget_dataset_info(file_, name.c_str(), rank == 1 ? dims : nullptr, &got, &bytes) < 0)
      fail(name, "unreadable");
    if (got != cls) fail(name, std::string("not ") + kind);
    return rank == 1 ? dims[0] : 1;
  }

  std::vector<double> doubles(const std::string& name, long expected) const {
    const hsize_t n = size(name, H5T_FLOAT, "floating-point numbers");
    if (expected >= 0 && n != static_cast<hsize_t>(expected))
      fail(name, std::to_string(n) + " entries, " + std::to_string(expected) + " expected");
    std::vector<double> v(n);
    if (n > 0 && H5LTread_dataset_double(file_, name.c_str(), v.data()) < 0)
      fail(name, "unreadable");
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k]))
        fail(name, "entry " + std::to_string(k) + " is " + std::to_string(v[k]) + ", not finite");
    return v;
  }

  std::vector<int> ints(const std::string& name, long expected) const {
    const hsize_t n = size(name, H5T_INTEGER, "integers");
    if (expected >= 0 && n != static_cast<hsize_t>(expected))
      fail(name, std::to_string(n) + " entries, " + std::to_string(expected) + " expected");
    std::vector<int> v(n);
    if (n > 0 && H5LTread_dataset_int(file_, name.c_str(), v.data()) < 0) fail(name, "unreadable");
    return v;
  }

  int integer(const std::string& name) const { return ints(name, 1)[0]; }

  /// A matrix group {nzmax, m, n, nz, p, i, x}, every index checked.
  SpMat matrix(const std::string& group) const;

 private:
  std::string path_;
  hid_t file_;
};

SpMat Reader::matrix(const std::string& group) const {
  const int m = integer(group + "/m"), n = integer(group + "/n");
  const int nz = integer(group + "/nz"), nzmax = integer(group + "/nzmax");
  if (m < 0 || n < 0) fail(group, "size " + std::to_string(m) + " x " + std::to_string(n));
  std::vector<Triplet> entries;
  const auto check = [&](const std::string& what, int value, int bound, long k) {
    if (value < 0 || value >= bound)
      fail(group + "/" + what,
           "entry " + std::to_string(k) + " is " + std::to_string(value) + ", outside 0.." +
               std::to_string(bound - 1));
  };
  if (nz >= 0) {  // triplets: i the rows, p the columns (CSparse's cs, which FCLIB's merit reads)
    const std::vector<int> rows = ints(group + "/i", -1), cols = ints(group + "/p", -1);
    const std::vector<double> x = doubles(group + "/x", -1);
    if (static_cast<long>(rows.size()) < nz || static_cast<long>(cols.size()) < nz ||
        static_cast<long>(x.size()) < nz)
      fail(group, "fewer than nz = " + std::to_string(nz) + " entries in i, p or x");
    for (int k = 0; k < nz; ++k) {
      check("i", rows[k], m, k);
      check("p", cols[k], n, k);
      entries.emplace_back(rows[k], cols[k], x[k]);
    }
  } else if (nz == -1 || nz == -2) {  // compressed columns (−1) or rows (−2)
    const int outer = nz == -1 ? n : m, inner = nz == -1 ? m : n;
    const std::vector<int> p = ints(group + "/p", outer + 1);
    const std::vector<int> i = ints(group + "/i", -1);
    const std::vector<double> x = doubles(group + "/x", -1);
    if (p[0] != 0) fail(group + "/p", "starts at " + std::to_string(p[0]) + ", not 0");
    for (int j = 0; j < outer; ++j)
      if (p[j + 1] < p[j]) fail(group + "/p", "decreases at entry " + std::to_string(j + 1));
    const int count = p[outer];
    if (count > nzmax || static_cast<long>(i.size()) < count || static_cast<long>(x.size()) < count)
      fail(group, "p ends at " + std::to_string(count) + " but nzmax, i or x is shorter");
    for (int j = 0; j < outer; ++j) {
      for (int k = p[j]; k < p[j + 1]; ++k) {
        check("i", i[k], inner, k);
        entries.emplace_back(nz == -1 ? i[k] : j, nz == -1 ? j : i[k], x[k]);
      }
    }
  } else {
    fail(group + "/nz", std::to_string(nz) + " is no matrix form (>= 0 triplets, -1, -2)");
  }
  SpMat M(m, n);
  M.setFromTriplets(entries.begin(), entries.end());  // duplicates summed, as CSparse does
  return M;
}

/// The contacts' friction coefficients from dataset `name`, each checked to be ≥ 0.
std::vector<double> friction_coefficients(const Reader& in,
                                          const std::string& name,
                                          long contacts) {
  const std::vector<double> mu = in.doubles(name, contacts);
  for (std::size_t i = 0; i < mu.size(); ++i)
    if (mu[i] < 0.0)
      in.fail(name, "entry " + std::to_string(i) + " is " + std::to_string(mu[i]) + " < 0");
  return mu;
}

/// The stored problem of W, V, R, q, s and mu: A = [W V; Vᵀ R], b = −[q; s].
StoredProblem assemble(const SpMat& W,
                       const SpMat* V,
                       const SpMat* R,
                       const std::vector<double>& q,
                       const std::vector<double>& s,
                       const std::vector<double>& mu) {
  const long m = W.rows(), e = R != nullptr ? R->rows() : 0;
  StoredProblem p;
  std::vector<Triplet> entries;
  const auto add = [&](const SpMat& M, long row0, long col0, bool transpose) {
    for (Eigen::Index j = 0; j < M.outerSize(); ++j)
      for (SpMat::InnerIterator it(M, j); it; ++it)
        entries.emplace_back(row0 + (transpose ? it.col() : it.row()),
                             col0 + (transpose ? it.row() : it.col()),
                             it.value());
  };
  add(W, 0, 0, false);
  if (e > 0) {
    add(*V, 0, m, false);
    add(*V, m, 0, true);
    add(*R, m, m, false);
  }
  p.A.resize(m + e, m + e);
  p.A.setFromTriplets(entries.begin(), entries.end());
  p.b.resize(m + e);
  for (long k = 0; k < m; ++k) p.b(k) = -q[static_cast<std::size_t>(k)];
  for (long k = 0; k < e; ++k) p.b(m + k) = -s[static_cast<std::size_t>(k)];
  in_cones(p, m, e, mu);
  return p;
}

/// Datasets written into one open file; any failure is an InputError naming the dataset.
class Writer {
 public:
  Writer(std::string what, hid_t file) : what_(std::move(what)), file_(file) {}

  void group(const std::string& name) const {
    const hid_t g = H5Gcreate2(file_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (g < 0) fail(name);
    H5Gclose(g);
  }
  void ints(const std::string& name, const std::vector<int>& v) const {
    const hsize_t n = v.size();
    if (H5LTmake_dataset_int(file_, name.c_str(), 1, &n, v.data()) < 0) fail(name);
  }
  void doubles(const std::string& name, const VecX& v) const {
    const hsize_t n = static_cast<hsize_t>(v.size());
    if (H5LTmake_dataset_double(file_, name.c_str(), 1, &n, v.data()) < 0) fail(name);
  }
  void text(const std::string& name, const std::string& s) const {
    if (H5LTmake_dataset_string(file_, name.c_str(), s.c_str()) < 0) fail(name);
  }
  /// The group `name` holding info's title, description and math_info.
  void info(const std::string& name, const FclibInfo& info) const {
    group(name);
    text(name + "/title", info.title);
    text(name + "/description", info.description);
    text(name + "/math_info", info.math_info);
  }
  /// M in compressed columns (nz = −1), the form FCLIB's merit function reads.
  void matrix(const std::string& name, SpMat M) const {
    M.makeCompressed();
    group(name);
    const int nnz = static_cast<int>(M.nonZeros());
    ints(name + "/nzmax", {nnz});
    ints(name + "/m", {static_cast<int>(M.rows())});
    ints(name + "/n", {static_cast<int>(M.cols())});
    ints(name + "/nz", {-1});
    ints(name + "/p", std::vector<int>(M.outerIndexPtr(), M.outerIndexPtr() + M.cols() + 1));
    ints(name + "/i", std::vector<int>(M.innerIndexPtr(), M.innerIndexPtr() + nnz));
    doubles(name + "/x", Eigen::Map<const VecX>(M.valuePtr(), nnz));
  }

 private:
  [[noreturn]] void fail(const std::string& name) const {
    throw InputError(what_ + ": writing " + name + " failed (HDF5)");
  }
  std::string what_;
  hid_t file_;
};

/// Each contact's mu, in contact order.
VecX contact_mu(const StoredProblem& p) {
  VecX mu(p.cones.contacts());
  for (long i = 0; i < p.cones.contacts(); ++i) mu(i) = p.cones.mu(i);
  return mu;
}

/// A new HDF5 file at `path`, whole or not at all (write_file_atomically), its datasets written
/// by `body`; HDF5's own messages off (cbps's name the dataset).
void write_hdf5(const std::string& path,
                const std::string& what,
                const std::function<void(const Writer&)>& body) {
  const QuietHdf5 quiet;
  write_file_atomically(path, what, [&](const std::string& temporary) {
    File file(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
    if (file.id() < 0) throw InputError(what + ": cannot create " + temporary);
    body(Writer(what, file.id()));
  });
}

/// The file's row order: each contact's rows (normal, t1, t2) in contact order, then every
/// free row; file_row[k] is row k's place. InputError for a row that is neither.
Eigen::PermutationMatrix<Eigen::Dynamic> file_order(const StoredProblem& p, long& contact_rows) {
  const std::vector<char> in_cone = p.cones.rows_in_cones(p.rows());
  Eigen::PermutationMatrix<Eigen::Dynamic> file_row(p.rows());
  int next = 0;
  for (const int n : p.cones.normal)
    for (int k = n; k < n + 3; ++k) file_row.indices()(k) = next++;
  contact_rows = next;
  for (long k = 0; k < p.rows(); ++k) {
    if (in_cone[static_cast<std::size_t>(k)]) continue;
    if (p.cmin(k) != -kInf || p.cmax(k) != kInf)
      throw InputError("row " + std::to_string(k) + " has bounds [" + std::to_string(p.cmin(k)) +
                       ", " + std::to_string(p.cmax(k)) +
                       "] and is in no cone; an FCLIB problem holds contacts in cones and free "
                       "(equality) rows only");
    file_row.indices()(k) = next++;
  }
  return file_row;
}

/// An FCLIB global problem, M v = H r + G l + f, Gᵀ v + b = 0, u = Hᵀ v + w (fclib.h), with v
/// eliminated: J = [Hᵀ; Gᵀ] (r's rows, then l's), A = J M⁻¹ Jᵀ (6.2.9),
/// b = −[Hᵀ M⁻¹ f + w; Gᵀ M⁻¹ f + b_G]. With a block-diagonal M (rigid bodies) J and M⁻¹ are
/// kept, as a `cbps matrices` folder's; else A comes from a sparse LDLᵀ of M.
StoredProblem read_global(const Reader& in, VecX* solution) {
  const int spacedim = in.integer("/fclib_global/spacedim");
  if (spacedim != 3)
    in.fail("/fclib_global/spacedim",
            std::to_string(spacedim) + "; cbps reads three-dimensional contact (spacedim 3)");
  const SpMat M = in.matrix("/fclib_global/M");
  const long n = M.rows();
  if (M.cols() != n)
    in.fail("/fclib_global/M",
            std::to_string(n) + " x " + std::to_string(M.cols()) + ": M must be square");
  const SpMat H = in.matrix("/fclib_global/H");
  if (H.rows() != n || H.cols() % 3 != 0)
    in.fail("/fclib_global/H",
            std::to_string(H.rows()) + " x " + std::to_string(H.cols()) + ": H must have M's " +
                std::to_string(n) + " rows and 3 columns per contact");
  const long m = H.cols();
  SpMat G(n, 0);
  if (in.exists("/fclib_global/G")) {
    G = in.matrix("/fclib_global/G");
    if (G.rows() != n)
      in.fail("/fclib_global/G", std::to_string(G.rows()) + " rows; M has " + std::to_string(n));
  }
  const long e = G.cols();
  const std::vector<double> f = in.doubles("/fclib_global/vectors/f", n);
  const std::vector<double> w = in.doubles("/fclib_global/vectors/w", m);
  const std::vector<double> bG =
      e > 0 ? in.doubles("/fclib_global/vectors/b", e) : std::vector<double>{};
  const std::vector<double> mu = friction_coefficients(in, "/fclib_global/vectors/mu", m / 3);
  GlobalProblem g{M,
                  H,
                  G,
                  Eigen::Map<const VecX>(f.data(), n),
                  Eigen::Map<const VecX>(w.data(), m),
                  Eigen::Map<const VecX>(bG.data(), e),
                  mu};
  StoredProblem p =
      eliminate_velocities(g, [&](const std::string& why) { in.fail("/fclib_global/M", why); });
  if (solution != nullptr && in.exists("/solution/r")) {
    const std::vector<double> r = in.doubles("/solution/r", m);
    *solution = VecX::Zero(m + e);
    for (long k = 0; k < m; ++k) (*solution)(k) = r[static_cast<std::size_t>(k)];
    if (e > 0 && in.exists("/solution/l")) {
      const std::vector<double> l = in.doubles("/solution/l", e);
      for (long k = 0; k < e; ++k) (*solution)(m + k) = l[static_cast<std::size_t>(k)];
    }
  }
  return p;
}

/// The global form of write_fclib: M = Minv⁻¹, H and G the transposes of J's contact and free
/// rows in the file's order, f = 0, w and b the negated b of those rows, so that
/// u = Hᵀ v + w = A r − b at v = Minv Jᵀ lambda; /solution with v, u, r and l.
void write_global(const std::string& path,
                  const std::string& what,
                  const StoredProblem& p,
                  const FclibInfo& info,
                  const VecX* lambda) {
  if (!p.has_jacobian())
    throw InputError(what + ": a global problem needs the step's J and Minv (" +
                     p.without_jacobian + ")");
  SpMat M;
  std::string failure;
  if (!block_inverse(p.Minv, M, failure))
    throw InputError(what + ": Minv " +
                     (failure.empty() ? "couples more than " + std::to_string(kInverseBlock) +
                                            " rows; a global problem is written from "
                                            "rigid bodies' blocks"
                                      : failure));
  long m = 0;
  const auto order = file_order(p, m);
  const long e = p.rows() - m;
  const SpMatRow J = order * p.J;  // J's row k at file_row[k]
  const SpMat Ht = J.topRows(m), Gt = J.bottomRows(e);
  const VecX b = order * p.b;
  const VecX mu = contact_mu(p);
  write_hdf5(path, what, [&](const Writer& out) {
    out.group("/fclib_global");
    out.ints("/fclib_global/spacedim", {3});
    out.matrix("/fclib_global/M", M);
    out.matrix("/fclib_global/H", Ht.transpose());
    if (e > 0) out.matrix("/fclib_global/G", Gt.transpose());
    out.group("/fclib_global/vectors");
    out.doubles("/fclib_global/vectors/f", VecX::Zero(M.rows()));
    out.doubles("/fclib_global/vectors/w", -b.head(m));
    out.doubles("/fclib_global/vectors/mu", mu);
    if (e > 0) out.doubles("/fclib_global/vectors/b", -b.tail(e));
    out.info("/fclib_global/info", info);
    if (lambda != nullptr) {
      const VecX x = order * (*lambda);
      const VecX v = p.Minv * (SpMat(J.transpose()) * x);
      out.group("/solution");
      out.doubles("/solution/v", v);
      out.doubles("/solution/u", Ht * v - b.head(m));
      out.doubles("/solution/r", x.head(m));
      if (e > 0) out.doubles("/solution/l", x.tail(e));
    }
  });
}
}  // namespace

bool is_hdf5_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[8] = {};
  in.read(head, sizeof head);
  return in.gcount() == 8 && std::memcmp(head, "\x89HDF\r\n\x1a\n", 8) == 0;
}

StoredProblem read_fclib(const std::string& path, VecX* solution) {
  const QuietHdf5 quiet;
  File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (file.id() < 0) throw InputError(path + ": not an HDF5 file HDF5 can open");
  const Reader in(path, file.id());
  if (!in.exists("/fclib_local")) {
    if (!in.exists("/fclib_global"))
      in.fail("/fclib_local", "missing: neither an FCLIB local problem nor a global one");
    StoredProblem p = read_global(in, solution);
    p.fclib = true;
    return p;
  }
  const int spacedim = in.integer("/fclib_local/spacedim");
  if (spacedim != 3)
    in.fail("/fclib_local/spacedim",
            std::to_string(spacedim) + "; cbps reads three-dimensional contact (spacedim 3)");
  const SpMat W = in.matrix("/fclib_local/W");
  if (W.rows() != W.cols() || W.rows() % 3 != 0)
    in.fail("/fclib_local/W",
            std::to_string(W.rows()) + " x " + std::to_string(W.cols()) +
                ": W must be square with 3 rows per contact");
  const long m = W.rows();
  SpMat V, R;
  std::vector<double> s;
  const bool equalities = in.exists("/fclib_local/V") || in.exists("/fclib_local/R");
  if (equalities) {
    V = in.matrix("/fclib_local/V");
    R = in.matrix("/fclib_local/R");
    if (V.rows() != m || R.rows() != R.cols() || V.cols() != R.rows())
      in.fail("/fclib_local/V",
              "V is " + std::to_string(V.rows()) + " x " + std::to_string(V.cols()) + " and R " +
                  std::to_string(R.rows()) + " x " + std::to_string(R.cols()) + "; W is " +
                  std::to_string(m) + " x " + std::to_string(m));
    s = in.doubles("/fclib_local/vectors/s", R.rows());
  }
  const std::vector<double> q = in.doubles("/fclib_local/vectors/q", m);
  const std::vector<double> mu = friction_coefficients(in, "/fclib_local/vectors/mu", m / 3);
  StoredProblem p = assemble(W, equalities ? &V : nullptr, equalities ? &R : nullptr, q, s, mu);
  p.fclib = true;
  p.without_jacobian = "an FCLIB local problem carries no J and Minv";
  if (solution != nullptr && in.exists("/solution/r")) {
    const std::vector<double> r = in.doubles("/solution/r", m);
    *solution = VecX::Zero(p.rows());
    for (long k = 0; k < m; ++k) (*solution)(k) = r[static_cast<std::size_t>(k)];
    if (equalities && in.exists("/solution/l")) {
      const std::vector<double> l = in.doubles("/solution/l", R.rows());
      for (long k = 0; k < R.rows(); ++k) (*solution)(m + k) = l[static_cast<std::size_t>(k)];
    }
  }
  return p;
}

void write_fclib(const std::string& path,
                 const StoredProblem& p,
                 const FclibInfo& info,
                 const VecX* lambda,
                 FclibForm form) {
  const std::string what = "--fclib " + path;
  if (p.cfm > 0.0)
    throw InputError(
        what + ": the problem was solved with constraint-force mixing eps = " + number_text(p.cfm) +
        " kg^-1 (A + eps E), which an FCLIB file cannot hold apart from W; set the "
        "scene's cfm to 0");
  if (form == FclibForm::Global) {
    write_global(path, what, p, info, lambda);
    return;
  }
  long m = 0;
  const auto order = file_order(p, m);
  const long e = p.rows() - m;
  const SpMat A = order * p.A * order.transpose();  // A(file_row[i], file_row[j]) = A(i, j)
  const SpMat W = A.topLeftCorner(m, m), V = A.topRightCorner(m, e);
  if (e > 0) {
    const SpMat mismatch = SpMat(A.bottomLeftCorner(e, m)) - SpMat(V.transpose());
    const double scale = std::max(1.0, SpMat(A).coeffs().cwiseAbs().maxCoeff());
    if (mismatch.nonZeros() > 0 && mismatch.coeffs().cwiseAbs().maxCoeff() > 1e-12 * scale)
      throw InputError(what +
                       ": the free rows' columns are not V^T (A is not symmetric there); "
                       "FCLIB's local problem has 0 = V^T r + R l + s");
  }
  const VecX b = order * p.b;
  const VecX q = -b.head(m), s = -b.tail(e);
  const VecX mu = contact_mu(p);
  write_hdf5(path, what, [&](const Writer& out) {
    out.group("/fclib_local");
    out.ints("/fclib_local/spacedim", {3});
    out.matrix("/fclib_local/W", W);
    if (e > 0) {
      out.matrix("/fclib_local/V", V);
      out.matrix("/fclib_local/R", A.bottomRightCorner(e, e));
    }
    out.group("/fclib_local/vectors");
    out.doubles("/fclib_local/vectors/q", q);
    out.doubles("/fclib_local/vectors/mu", mu);
    if (e > 0) out.doubles("/fclib_local/vectors/s", s);
    out.info("/fclib_local/info", info);
    if (lambda != nullptr) {
      const VecX x = order * (*lambda);
      out.group("/solution");
      out.doubles("/solution/r", x.head(m));
      out.doubles("/solution/u", W * x.head(m) + V * x.tail(e) + q);
      if (e > 0) out.doubles("/solution/l", x.tail(e));
    }
  });
}

}  // namespace cbps
