// FCLIB files (io/fclib_file.hpp) against FCLIB's own library (libfclib): a problem of the FCLIB
// collection read alike by both, cbps's files read by FCLIB's reader, round trips exact, FCLIB's
// merit function equal to cbps's computation of it, and malformed files named precisely.
extern "C" {  // fclib.h declares C functions without saying so
#include <fclib.h>
}
#include <hdf5.h>
#include <hdf5_hl.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/output_file.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/cone_problem.hpp"
#include "fixture.hpp"

using namespace cbps;
namespace fs = std::filesystem;

namespace {

const std::string kBoxesStack =
    std::string(CBPS_DATA_DIR) + "/fclib/Boxes_Stack_local_problem_test.hdf5";

/// An FCLIB matrix as a dense matrix, from any of its three forms (CSparse's conventions).
MatX dense_of(const fclib_matrix& M) {
  MatX D = MatX::Zero(M.m, M.n);
  if (M.nz >= 0) {
    for (int k = 0; k < M.nz; ++k) D(M.i[k], M.p[k]) += M.x[k];
  } else {
    const bool columns = M.nz == -1;
    for (int j = 0; j < (columns ? M.n : M.m); ++j)
      for (int k = M.p[j]; k < M.p[j + 1]; ++k) (columns ? D(M.i[k], j) : D(j, M.i[k])) += M.x[k];
  }
  return D;
}

/// fclib_delete_local (Debian's FCLIB 3.1.0) frees what the problem holds but not the struct
/// fclib_read_local allocated (LeakSanitizer shows its 64 bytes): both are freed here.
struct LocalDeleter {
  void operator()(fclib_local* p) const {
    fclib_delete_local(p);
    std::free(p);
  }
};
using Local = std::unique_ptr<fclib_local, LocalDeleter>;

/// nsgs on p for `sweeps` sweeps from zero.
VecX nsgs(const StoredProblem& p, int sweeps) {
  SolverOptions o;
  o.method = Method::Nsgs;
  o.max_iterations = sweeps;
  VecX lambda;
  solve(p.problem(), lambda, o);
  return lambda;
}

/// FCLIB's MERIT_1 of r on a problem FCLIB read (its W in compressed columns).
double merit_by_fclib(fclib_local& problem, const VecX& r) {
  VecX u = VecX::Zero(r.size());  // not read by MERIT_1
  VecX copy = r;
  fclib_solution s{nullptr, u.data(), copy.data(), nullptr};
  return fclib_merit_local(&problem, MERIT_1, &s);
}

}  // namespace

TEST_CASE("an FCLIB collection problem reads the same in cbps and in FCLIB's own reader",
          "[fclib]") {
  VecX stored_solution;
  const StoredProblem p = read_fclib(kBoxesStack, &stored_solution);
  Local theirs(fclib_read_local(kBoxesStack.c_str()));
  REQUIRE(theirs);
  REQUIRE(theirs->spacedim == 3);
  REQUIRE(p.rows() == theirs->W->m);
  CHECK(p.rows() == 144);
  CHECK(p.cones.contacts() == 48);
  CHECK(p.fclib);
  CHECK(MatX(p.A) == dense_of(*theirs->W));  // W as compressed rows in the file
  for (long k = 0; k < p.rows(); ++k) CHECK(p.b(k) == -theirs->q[k]);
  for (long i = 0; i < p.cones.contacts(); ++i) {
    CHECK(p.cones.normal[static_cast<std::size_t>(i)] == 3 * i);
    CHECK(p.cones.mu(i) == theirs->mu[i]);
  }
  CHECK(p.cones.law == FrictionLaw::CoulombCone);
  // Through read_problem too (by the HDF5 signature, whatever the name).
  CHECK(read_problem(kBoxesStack).cones.contacts() == 48);
  REQUIRE(stored_solution.size() == 144);
}

TEST_CASE("what cbps writes FCLIB reads, and a round trip is exact", "[fclib]") {
  const StoredProblem p = read_fclib(kBoxesStack);
  const VecX lambda = nsgs(p, 200);
  const fs::path dir = test::scratch_dir("fclib_round_trip");
  const std::string file = (dir / "stack.hdf5").string();
  write_fclib(file, p, {"Boxes Stack", "round trip", "none"}, &lambda);
  CHECK(is_hdf5_file(file));
  CHECK(!fs::exists(temporary_name(file)));

  VecX back_solution;
  const StoredProblem back = read_fclib(file, &back_solution);
  CHECK(MatX(back.A) == MatX(p.A));
  CHECK(back.b == p.b);
  CHECK(back.cones.normal == p.cones.normal);
  CHECK(back.cones.mu == p.cones.mu);
  CHECK(back_solution == lambda);

  Local theirs(fclib_read_local(file.c_str()));
  REQUIRE(theirs);
  CHECK(theirs->W->nz == -1);  // compressed columns, which FCLIB's merit function reads
  CHECK(dense_of(*theirs->W) == MatX(p.A));
  CHECK(std::string(theirs->info->title) == "Boxes Stack");
  fclib_solution* solution = fclib_read_solution(file.c_str());
  REQUIRE(solution != nullptr);
  const VecX w = p.A * lambda - p.b;
  for (long k = 0; k < p.rows(); ++k) {
    CHECK(solution->r[k] == lambda(k));
    CHECK(solution->u[k] == Approx(w(k)).margin(1e-15));
  }
  fclib_delete_solutions(solution, 1);
  CHECK_THROWS_AS(write_fclib((dir / "missing" / "x.hdf5").string(), p, {}), InputError);
}

TEST_CASE("FCLIB's merit function is cbps's computation of it, small exactly with the residual",
          "[fclib]") {
  const StoredProblem p = read_fclib(kBoxesStack);
  const fs::path dir = test::scratch_dir("fclib_merit");
  const std::string file = (dir / "stack.hdf5").string();
  write_fclib(file, p, {});
  Local theirs(fclib_read_local(file.c_str()));  // W in compressed columns
  REQUIRE(theirs);
  // sqrt(‖q‖₂) in MERIT_1's denominator; the merit is a 2-norm over contacts, the residual the
  // largest contact's norm: residual ≤ merit (1 + sqrt‖q‖) ≤ residual sqrt(contacts).
  const double denominator = 1.0 + std::sqrt(p.b.norm());
  const double contacts = static_cast<double>(p.cones.contacts());
  for (const int sweeps : {0, 10, 1000, 20000}) {
    const VecX lambda = sweeps == 0 ? VecX::Zero(p.rows()) : nsgs(p, sweeps);
    const VecX w = p.A * lambda - p.b;
    const ConeMeasures m = cone_measures(p.cones, lambda, w, p.b);
    const double merit = merit_by_fclib(*theirs, lambda);
    INFO("sweeps " << sweeps << ": FCLIB merit " << merit << ", cbps residual " << m.natural_map);
    // Equal to rounding: near a solution the natural map is a difference of nearly equal numbers,
    // and FCLIB sums W r in its own order (1e-9 relative of a merit of 1e-6 is 1e-15 of q).
    CHECK(m.fclib_merit == Approx(merit).epsilon(1e-9));
    const double residual = natural_map_residual(p.problem(), lambda);
    CHECK(residual == m.natural_map);
    CHECK(residual <= merit * denominator * (1 + 1e-12));
    CHECK(merit * denominator <= residual * std::sqrt(contacts) * (1 + 1e-12));
  }
}

TEST_CASE("the exact path's answer on the collection problem is a solution by FCLIB's merit",
          "[fclib]") {
  // FCLIB's own merit function (MERIT_1, Coulomb's law), computed by libfclib, judges what cbps's
  // direct path returns for the file: an external check of the answer and of the law.
  const StoredProblem p = read_fclib(kBoxesStack);
  const fs::path dir = test::scratch_dir("fclib_direct");
  const std::string file = (dir / "stack.hdf5").string();
  write_fclib(file, p, {});  // W in compressed columns, the only form fclib_merit_local reads
  Local theirs(fclib_read_local(file.c_str()));
  REQUIRE(theirs);
  SolverOptions o;
  o.method = Method::Direct;
  o.tolerance = 1e-10;
  VecX lambda;
  const SolverSummary s = solve(p.problem(), lambda, o);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  const double merit = merit_by_fclib(*theirs, lambda);
  CHECK(merit <= 1e-9);
  CHECK(merit > 0.0);  // computed, not a default
}

namespace {

/// A copy of the collection file with one integer dataset of W replaced.
std::string with_bad_index(const fs::path& dir) {
  const std::string file = (dir / "bad.hdf5").string();
  fs::copy_file(kBoxesStack, file, fs::copy_options::overwrite_existing);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  REQUIRE(f >= 0);
  hsize_t dims[1] = {0};
  H5T_class_t cls{};
  size_t bytes = 0;
  REQUIRE(H5LTget_dataset_info(f, "/fclib_local/W/i", dims, &cls, &bytes) >= 0);
  std::vector<int> i(dims[0]);
  REQUIRE(H5LTread_dataset_int(f, "/fclib_local/W/i", i.data()) >= 0);
  i[5] = 1000;  // W is 144 x 144
  const hid_t d = H5Dopen2(f, "/fclib_local/W/i", H5P_DEFAULT);
  REQUIRE(H5Dwrite(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, i.data()) >= 0);
  H5Dclose(d);
  H5Fclose(f);
  return file;
}

}  // namespace

TEST_CASE("a malformed FCLIB file is an InputError naming the file and the dataset", "[fclib]") {
  const fs::path dir = test::scratch_dir("fclib_bad");
  const std::string bad = with_bad_index(dir);
  CHECK_THROWS_WITH(
      read_fclib(bad),
      Catch::Contains(bad) && Catch::Contains("/fclib_local/W/i") && Catch::Contains("1000"));
  // An HDF5 file that holds no FCLIB problem.
  const std::string empty = (dir / "empty.h5").string();
  H5Fclose(H5Fcreate(empty.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  CHECK_THROWS_WITH(read_problem(empty), Catch::Contains("/fclib_local"));
  // A problem with a row FCLIB cannot hold (a box [0, 1] in no cone) is refused on writing.
  StoredProblem p = read_fclib(kBoxesStack);
  p.cmax(4) = 1.0;
  p.cones.normal.erase(p.cones.normal.begin() + 1);
  p.cones.mu = VecX::Constant(47, 0.7);
  CHECK_THROWS_WITH(write_fclib((dir / "x.hdf5").string(), p, {}), Catch::Contains("row 3"));
  CHECK(!fs::exists(dir / "x.hdf5"));
}

TEST_CASE("FCLIB's equality rows (V, R, s) are free rows of cbps's problem", "[fclib]") {
  // One contact (W = 2 I) and one equality row written by FCLIB's own writer: A = [W V; Vᵀ R],
  // b = −[q; s], the last row free.
  double W_x[] = {2.0, 2.0, 2.0};
  int W_p[] = {0, 1, 2, 3}, W_i[] = {0, 1, 2};
  fclib_matrix W{3, 3, 3, W_p, W_i, W_x, -1, nullptr};
  double V_x[] = {0.5};
  int V_p[] = {0, 1}, V_i[] = {0};
  fclib_matrix V{1, 3, 1, V_p, V_i, V_x, -1, nullptr};
  double R_x[] = {4.0};
  int R_p[] = {0, 1}, R_i[] = {0};
  fclib_matrix R{1, 1, 1, R_p, R_i, R_x, -1, nullptr};
  double q[] = {-1.0, 0.2, 0.0}, s[] = {3.0}, mu[] = {0.4};
  fclib_local local{&W, &V, &R, mu, q, s, 3, nullptr};
  const fs::path dir = test::scratch_dir("fclib_equality");
  const std::string file = (dir / "vr.hdf5").string();
  REQUIRE(fclib_write_local(&local, file.c_str()) == 1);
  const StoredProblem p = read_fclib(file);
  REQUIRE(p.rows() == 4);
  MatX A(4, 4);
  A << 2, 0, 0, 0.5, 0, 2, 0, 0, 0, 0, 2, 0, 0.5, 0, 0, 4;
  CHECK(MatX(p.A) == A);
  CHECK(p.b == (VecX(4) << 1.0, -0.2, 0.0, -3.0).finished());
  CHECK(p.cmin(3) == -kInf);
  CHECK(p.cmax(3) == kInf);
  CHECK(p.cones.contacts() == 1);
  // Written back by cbps, read by FCLIB: the same V, R and s.
  const std::string again = (dir / "again.hdf5").string();
  write_fclib(again, p, {});
  Local theirs(fclib_read_local(again.c_str()));
  REQUIRE(theirs);
  REQUIRE(theirs->V != nullptr);
  CHECK(dense_of(*theirs->V)(0, 0) == 0.5);
  CHECK(dense_of(*theirs->R)(0, 0) == 4.0);
  CHECK(theirs->s[0] == 3.0);
}
