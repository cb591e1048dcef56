// The Matrix Market reader against the writer (bit-exact round trips, ±inf), symmetric
// expansion, and every malformed input named by file and line.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/siconos.hpp"
#include "fixture.hpp"

namespace fs = std::filesystem;

namespace {

fs::path mm_scratch(const std::string& name) {
  static const fs::path dir = cbps::test::scratch_dir("mm");
  return dir / name;
}

fs::path mm_file(const std::string& name, const std::string& text) {
  const fs::path p = mm_scratch(name);
  std::ofstream(p) << text;
  return p;
}

/// The InputError message of reading `text` as a sparse matrix (or vector), "" if none.
std::string mm_error(const std::string& text, bool vector) {
  const fs::path p = mm_file("bad.mtx", text);
  try {
    if (vector)
      cbps::read_matrix_market_vector(p.string());
    else
      cbps::read_matrix_market_sparse(p.string());
  } catch (const cbps::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("Matrix Market: a sparse matrix reads back bit for bit", "[matrix_market]") {
  cbps::SpMat M(4, 3);
  M.insert(0, 0) = 1.0 / 3.0;
  M.insert(3, 1) = -2.5e-300;
  M.insert(1, 2) = 6.02214076e23;
  M.insert(2, 0) = -0.1;
  M.makeCompressed();
  const fs::path p = mm_scratch("M.mtx");
  cbps::write_matrix_market(p.string(), M, "a comment");
  const cbps::SpMat R = cbps::read_matrix_market_sparse(p.string());
  REQUIRE(R.rows() == 4);
  REQUIRE(R.cols() == 3);
  CHECK(R.nonZeros() == 4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) CHECK(R.coeff(i, j) == M.coeff(i, j));
}

TEST_CASE("Matrix Market: a vector with ±inf reads back bit for bit", "[matrix_market]") {
  cbps::VecX v(5);
  v << 0.1, -cbps::kInf, cbps::kInf, -1.0 / 7.0, 0.0;
  const fs::path p = mm_scratch("v.mtx");
  cbps::write_matrix_market(p.string(), v, "");
  const cbps::VecX r = cbps::read_matrix_market_vector(p.string());
  REQUIRE(r.size() == 5);
  for (int k = 0; k < 5; ++k) CHECK(r(k) == v(k));
}

TEST_CASE("Matrix Market: Inf, Infinity and integer fields as scipy writes them",
          "[matrix_market]") {
  const fs::path p = mm_file("scipy.mtx",
                             "%%MatrixMarket matrix array real general\n%\n4 1\nInf\n-Infinity\n"
                             "1e-3\n\n-inf\n");
  const cbps::VecX r = cbps::read_matrix_market_vector(p.string());
  REQUIRE(r.size() == 4);
  CHECK(r(0) == cbps::kInf);
  CHECK(r(1) == -cbps::kInf);
  CHECK(r(2) == 1e-3);
  CHECK(r(3) == -cbps::kInf);
  const fs::path q =
      mm_file("int.mtx", "%%MatrixMarket matrix coordinate integer general\n2 2 1\n2 1 7\n");
  CHECK(cbps::read_matrix_market_sparse(q.string()).coeff(1, 0) == 7.0);
}

TEST_CASE("Matrix Market: a symmetric file is expanded to both triangles", "[matrix_market]") {
  const fs::path p = mm_file("sym.mtx",
                             "%%MatrixMarket matrix coordinate real symmetric\n"
                             "% lower triangle only\n3 3 4\n1 1 2\n2 1 -1\n3 2 -1\n3 3 2\n");
  const cbps::SpMat A = cbps::read_matrix_market_sparse(p.string());
  REQUIRE(A.rows() == 3);
  CHECK(A.nonZeros() == 6);
  CHECK(A.coeff(0, 1) == -1.0);
  CHECK(A.coeff(1, 0) == -1.0);
  CHECK(A.coeff(1, 2) == -1.0);
  CHECK(A.coeff(2, 1) == -1.0);
  CHECK(A.coeff(0, 0) == 2.0);
  CHECK(A.coeff(1, 1) == 0.0);
}

TEST_CASE("Matrix Market: malformed files are InputErrors naming the file and line",
          "[matrix_market]") {
  struct Case {
    const char* why;
    bool vector;
    std::string text;
    std::string expected;  // a piece of the message
  };
  const std::string sp = "%%MatrixMarket matrix coordinate real general\n";
  const std::string ar = "%%MatrixMarket matrix array real general\n";
  const Case cases[] = {
      {"bad header", false, "%%MatrixMarket tensor coordinate real general\n1 1 0\n", "line 1:"},
      {"no header", true, "3 1\n1\n2\n3\n", "line 1:"},
      {"complex field", false, "%%MatrixMarket matrix coordinate complex general\n", "line 1:"},
      {"array as sparse", false, ar + "1 1\n1\n", "line 1:"},
      {"coordinate as vector", true, sp + "1 1 0\n", "line 1:"},
      {"empty file", true, "", "line 0:"},
      {"short size line", false, sp + "2 2\n", "line 2:"},
      {"too few entries", false, sp + "2 2 2\n1 1 1\n", "line 3:"},
      {"too many entries", false, sp + "2 2 1\n1 1 1\n2 2 1\n", "line 4:"},
      {"row out of range", false, sp + "2 2 1\n3 1 1\n", "line 3: row index 3 is out of range"},
      {"column zero", false, sp + "2 2 1\n1 0 1\n", "line 3: column index 0 is out of range"},
      {"not a number", false, sp + "2 2 1\n1 1 x1\n", "line 3: expected a number"},
      {"NaN", true, ar + "2 1\n1\nnan\n", "line 4: NaN"},
      {"trailing text", true, ar + "1 1\n1.5abc\n", "line 3: expected a number"},
      {"two columns", true, ar + "2 2\n1\n2\n3\n4\n", "line 2:"},
      {"too few values", true, ar + "3 1\n1\n2\n", "line 4:"},
      {"upper triangle in symmetric",
       false,
       "%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n1 2 1\n",
       "line 3:"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.why);
    const std::string message = mm_error(c.text, c.vector);
    INFO(message);
    CHECK(message.find("bad.mtx: ") != std::string::npos);
    CHECK(message.find(c.expected) != std::string::npos);
  }
  SECTION("a missing file") {
    try {
      cbps::read_matrix_market_vector("/nonexistent/b.mtx");
      FAIL("no InputError");
    } catch (const cbps::InputError& e) {
      CHECK(std::string(e.what()) == "/nonexistent/b.mtx: no such file or folder");
    }
  }
}

TEST_CASE("the text readers name a missing file, a folder and a binary file as such",
          "[matrix_market][siconos]") {
  // Not "line 0: cannot open the file", and never the bytes of a binary file echoed back.
  const std::filesystem::path dir = cbps::test::scratch_dir("input_files");
  const auto message = [](const std::function<void()>& read) {
    try {
      read();
    } catch (const cbps::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no InputError");
  };
  const std::string missing = (dir / "missing.dat").string();
  CHECK(message([&] { cbps::read_siconos(missing, cbps::SiconosKind::Auto); }) ==
        missing + ": no such file or folder");
  CHECK(message([&] { cbps::read_matrix_market_sparse(dir.string()); }) ==
        dir.string() + ": is a folder, not a Matrix Market text file");
  const std::string hdf5 = (dir / "problem.hdf5").string();
  {
    std::ofstream out(hdf5, std::ios::binary);
    out.write("\x89HDF\r\n\x1a\n\0\0\0\0\x01\x08\x08\0", 16);  // HDF5's superblock start
  }
  const std::string h = message([&] { cbps::read_siconos(hdf5, cbps::SiconosKind::Auto); });
  CHECK(h.rfind(hdf5 + ": an HDF5 file, not a Siconos .dat text file", 0) == 0);
  CHECK(h.find("HDF\r") == std::string::npos);  // no raw bytes in the message
  const std::string binary = (dir / "A.mtx").string();
  {
    std::ofstream out(binary, std::ios::binary);
    out.write("%%Matrix\0\xff\xfe", 11);
  }
  CHECK(message([&] { cbps::read_matrix_market_sparse(binary); }) ==
        binary + ": a binary file (a NUL byte at offset 8), not a Matrix Market text file");
  std::filesystem::remove_all(dir);
}

TEST_CASE("Matrix Market by rows: every split of the rows puts the whole back together",
          "[matrix_market]") {
  // A symmetric file (each off-diagonal entry stored once, kept by whichever part holds its
  // row), with a duplicate entry summed, and a general vector; expected from the whole reads.
  const fs::path a = mm_file("rows-A.mtx",
                             "%%MatrixMarket matrix coordinate real symmetric\n"
                             "5 5 7\n1 1 4\n2 1 -1\n3 3 2.5\n5 2 0.25\n5 5 1\n4 4 3\n3 3 0.5\n");
  const fs::path v =
      mm_file("rows-b.mtx", "%%MatrixMarket matrix array real general\n5 1\n1\n-2\ninf\n4\n5\n");
  const cbps::SpMat whole = cbps::read_matrix_market_sparse(a.string());
  const cbps::VecX whole_v = cbps::read_matrix_market_vector(v.string());
  CHECK(cbps::read_matrix_market_size(a.string()) == std::pair<long, long>{5, 5});
  CHECK(cbps::read_matrix_market_size(v.string()) == std::pair<long, long>{5, 1});
  for (const std::vector<long>& cuts : {std::vector<long>{0, 5},
                                        std::vector<long>{0, 2, 5},
                                        std::vector<long>{0, 1, 3, 5},
                                        std::vector<long>{0, 0, 4, 4, 5}}) {
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const cbps::RowRange keep{cuts[k], cuts[k + 1]};
      const cbps::SpMat part = cbps::read_matrix_market_sparse_rows(a.string(), keep);
      const cbps::VecX part_v = cbps::read_matrix_market_vector_rows(v.string(), keep);
      REQUIRE(part.rows() == keep.last - keep.first);
      REQUIRE(part.cols() == 5);
      REQUIRE(part_v.size() == keep.last - keep.first);
      const Eigen::MatrixXd expected =
          Eigen::MatrixXd(whole).middleRows(keep.first, keep.last - keep.first);
      CHECK(Eigen::MatrixXd(part) == expected);  // also an empty part (rows [4, 4))
      CHECK(part.nonZeros() == cbps::SpMat(whole.middleRows(keep.first, part.rows())).nonZeros());
      for (Eigen::Index i = 0; i < part_v.size(); ++i) CHECK(part_v[i] == whole_v[keep.first + i]);
    }
  }
  // The duplicate (3, 3) is summed on the part that keeps row 3.
  CHECK(cbps::read_matrix_market_sparse_rows(a.string(), {2, 3}).coeff(0, 2) == 3.0);
}

TEST_CASE("Matrix Market by rows: bad files and bad ranges are InputErrors with the line",
          "[matrix_market]") {
  const auto error = [](const std::string& text, cbps::RowRange keep, bool vector) {
    const fs::path p = mm_file("rows-bad.mtx", text);
    try {
      if (vector)
        cbps::read_matrix_market_vector_rows(p.string(), keep);
      else
        cbps::read_matrix_market_sparse_rows(p.string(), keep);
    } catch (const cbps::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string good = "%%MatrixMarket matrix coordinate real general\n3 3 2\n1 1 1\n3 2 2\n";
  CHECK_THAT(error(good, {1, 4}, false),
             Catch::Contains("line 2: rows [1, 4) asked of a matrix of 3 rows"));
  CHECK_THAT(error(good, {2, 1}, false), Catch::Contains("rows [2, 1)"));
  // A bad entry in rows another part keeps is still found: every part parses every line.
  CHECK_THAT(
      error("%%MatrixMarket matrix coordinate real general\n3 3 2\n1 1 1\n3 x 2\n", {0, 1}, false),
      Catch::Contains("line 4: expected an integer column index, found 'x'"));
  CHECK_THAT(
      error("%%MatrixMarket matrix coordinate real general\n3 3 3\n1 1 1\n3 2 2\n", {0, 1}, false),
      Catch::Contains("end of file where entry 3 of 3 was expected"));
  CHECK_THAT(error("%%MatrixMarket matrix array real general\n3 1\n1\nnan\n3\n", {0, 1}, true),
             Catch::Contains("line 4: NaN"));
  CHECK_THAT(error("%%MatrixMarket matrix array real general\n3 1\n1\n2\n3\n", {0, 4}, true),
             Catch::Contains("rows [0, 4) asked of a vector of 3 rows"));
  CHECK_THAT(error("%%MatrixMarket matrix coordinate real general\n3 3 2\n", {0, 1}, false),
             Catch::Contains("end of file"));
  CHECK(error(good, {0, 3}, false).empty());
}
