// Inputs that once crashed, hung, allocated gigabytes or read silently as non-finite values in
// the readers, found by the fuzz targets in fuzz/ or while writing them. Each must now be an
// InputError naming the source and the line or JSON path.
#include <catch2/catch.hpp>
#include <chrono>
#include <sstream>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/scene/scene_json.hpp"

using namespace cbps;

namespace {

SpMat sparse(const std::string& text) {
  std::istringstream in(text);
  return parse_matrix_market_sparse(in, "fuzz.mtx");
}

VecX vector(const std::string& text) {
  std::istringstream in(text);
  return parse_matrix_market_vector(in, "fuzz.mtx");
}

StoredLcp siconos(const std::string& text, bool relay) {
  std::istringstream in(text);
  return parse_siconos(in, "fuzz.dat", relay);
}

const std::string kCoordinate = "%%MatrixMarket matrix coordinate real general\n";
const std::string kArray = "%%MatrixMarket matrix array real general\n";

/// A scene of one movable body with the given keys besides its shape.
std::string one_body(const std::string& shape, const std::string& keys) {
  return R"({"bodies": [{"shape": )" + shape + ", " + keys + "}]}";
}

const std::string kSphere = R"({"type": "sphere", "radius": 0.5})";

}  // namespace

TEST_CASE("fuzz: the stream readers name the source as the path readers do", "[fuzz]") {
  REQUIRE_THROWS_WITH(sparse(kCoordinate + "2 2 1\n3 1 1\n"),
                      "fuzz.mtx: line 3: row index 3 is out of range 1..2");
  REQUIRE_THROWS_WITH(vector(""), "fuzz.mtx: line 0: empty file, expected a %%MatrixMarket header");
  REQUIRE_THROWS_WITH(
      siconos("2\n1\n", false),
      "fuzz.dat: line 2: storage type 1 (sparse-block) is not read; only 0 (dense)");
  CHECK(sparse(kCoordinate + "2 2 1\n2 1 7\n").coeff(1, 0) == 7.0);
  CHECK(vector(kArray + "2 1\n1\n-inf\n")(1) == -kInf);
  CHECK(siconos("1\n0\n1 1\n1 1\n2\n-1\n", false).q(0) == -1.0);
}

TEST_CASE("fuzz: Matrix Market headers that claim more than the input holds", "[fuzz]") {
  const auto start = std::chrono::steady_clock::now();
  // 2^31 - 1 entries declared: the reader reserved 32 GB of triplets before reading one.
  REQUIRE_THROWS_AS(sparse(kCoordinate + "1 1 2147483647\n1 1 1\n"), InputError);
  REQUIRE_THROWS_WITH(sparse(kCoordinate + "1 1 2147483647\n1 1 1\n"),
                      Catch::Contains("fuzz.mtx: line 3: end of file where entry 2 of 2147483647"));
  REQUIRE_THROWS_AS(sparse("%%MatrixMarket matrix coordinate real symmetric\n"
                           "2 2 2147483647\n1 1 1\n"),
                    InputError);
  // 2^31 - 1 columns: SpMat(rows, cols) alone allocates 8 GB of column starts.
  REQUIRE_THROWS_AS(sparse(kCoordinate + "1 2147483647 0\n"), InputError);
  REQUIRE_THROWS_WITH(sparse(kCoordinate + "2147483647 2147483647 0\n"),
                      Catch::Contains("fuzz.mtx: line 2: size 2147483647 is larger than"));
  REQUIRE_THROWS_AS(sparse(kCoordinate + "10000001 1 0\n"), InputError);
  // An n×1 vector sized from the header: VecX(2^31 - 1) is 16 GB.
  REQUIRE_THROWS_AS(vector(kArray + "2147483647 1\n1\n"), InputError);
  REQUIRE_THROWS_AS(vector(kArray + "9999999 1\n1\n"), InputError);
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
}

TEST_CASE("fuzz: Matrix Market duplicates that sum to NaN", "[fuzz]") {
  REQUIRE_THROWS_AS(sparse(kCoordinate + "2 2 2\n1 1 inf\n1 1 -inf\n"), InputError);
  REQUIRE_THROWS_WITH(sparse(kCoordinate + "2 2 3\n1 1 inf\n2 2 1\n1 1 -Infinity\n"),
                      "fuzz.mtx: line 5: duplicate entries at (1, 1) sum to NaN (inf + -inf)");
  REQUIRE_THROWS_AS(sparse("%%MatrixMarket matrix coordinate real symmetric\n"
                           "2 2 2\n2 1 inf\n2 1 -inf\n"),
                    InputError);
  // Duplicates that sum to a number are still summed, as scipy does.
  CHECK(sparse(kCoordinate + "1 1 2\n1 1 inf\n1 1 5\n").coeff(0, 0) == kInf);
}

TEST_CASE("fuzz: a Siconos header of the largest n over a short file", "[fuzz]") {
  const auto start = std::chrono::steady_clock::now();
  // n = 5000 made the reader allocate M (200 MB) before finding the file short, every time.
  for (const bool relay : {false, true}) {
    REQUIRE_THROWS_AS(siconos("5000\n0\n5000 5000\n5000 5000\n1 2 3\n", relay), InputError);
    REQUIRE_THROWS_WITH(siconos("5000\n0\n5000 5000\n5000 5000\n1 2 3\n", relay),
                        "fuzz.dat: line 5: end of file where M(3, 0) was expected");
  }
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
}

TEST_CASE("fuzz: scene masses and inertias whose inverse is not finite", "[fuzz]") {
  // 1/m overflows.
  REQUIRE_THROWS_WITH(parse_scene(one_body(kSphere, R"("mass": 1e-320)"), "s.json"),
                      Catch::Contains("s.json: /bodies/0/mass: too small: 1/mass is not finite"));
  // I = 0.4 m r² is ~4e-111; det I underflows to 0, and I⁻¹ was inf (a division by zero).
  REQUIRE_THROWS_WITH(
      parse_scene(one_body(R"({"type": "sphere", "radius": 1e-5})", R"("mass": 1e-100)"), "s.json"),
      Catch::Contains("s.json: /bodies/0/mass: gives an inertia tensor or inverse that is not"));
  REQUIRE_THROWS_WITH(
      parse_scene(
          one_body(R"({"type": "box", "half_extents": [1e-30, 1e-30, 1e-30]})", R"("density": 1)"),
          "s.json"),
      Catch::Contains("s.json: /bodies/0/density: "));
  // I overflows to inf.
  REQUIRE_THROWS_AS(
      parse_scene(one_body(R"({"type": "sphere", "radius": 1e200})", R"("mass": 1e10)"), "s.json"),
      InputError);
  // An explicit inertia, positive definite, with a determinant out of range.
  REQUIRE_THROWS_WITH(
      parse_scene(one_body(kSphere, R"("mass": 1, "inertia": [1e-110, 1e-110, 1e-110])"), "s.json"),
      Catch::Contains("s.json: /bodies/0/inertia: its inverse is not finite"));
  REQUIRE_THROWS_AS(
      parse_scene(one_body(kSphere, R"("mass": 1, "inertia": [1e200, 1e200, 1e200])"), "s.json"),
      InputError);
  // The solid's inertia may be out of range when "inertia" replaces it.
  CHECK(parse_scene(one_body(R"({"type": "sphere", "radius": 1e200})",
                             R"("mass": 1e10, "inertia": [1, 2, 3])"),
                    "s.json")
            .bodies[0]
            .I_body_inv(2, 2) == 1.0 / 3.0);
}

TEST_CASE("fuzz: scene velocities and lengths that overflow", "[fuzz]") {
  REQUIRE_THROWS_WITH(
      parse_scene(one_body(kSphere, R"("mass": 1e100, "velocity": [1e300, 0, 0])"), "s.json"),
      Catch::Contains("s.json: /bodies/0/velocity: gives a speed of 1e+300 m/s, beyond "
                      "/world/divergence_speed"));
  REQUIRE_THROWS_WITH(
      parse_scene(one_body(kSphere, R"("mass": 1e-100, "momentum": [0, 1e300, 0])"), "s.json"),
      Catch::Contains("s.json: /bodies/0/momentum: "));
  REQUIRE_THROWS_WITH(
      parse_scene(one_body(kSphere, R"("mass": 1e100, "angular_velocity": [0, 0, 1e300])"),
                  "s.json"),
      Catch::Contains("s.json: /bodies/0/angular_velocity: gives a spin of 1e+300 rad/s, beyond "
                      "/world/divergence_spin"));
  // The default length of a distance constraint, |p_b − p_a|, overflows to inf.
  REQUIRE_THROWS_WITH(parse_scene(R"({"bodies": [
      {"name": "a", "shape": {"type": "sphere", "radius": 1}, "mass": 1, "position": [1e308, 0, 0]},
      {"name": "b", "shape": {"type": "sphere", "radius": 1}, "mass": 1, "position": [-1e308, 0, 0]}],
      "constraints": [{"a": "a", "b": "b"}]})",
                                  "s.json"),
                      Catch::Contains("s.json: /constraints/0: the default length"));
}

TEST_CASE("fuzz: Matrix Market sizes cost no row-sized work", "[fuzz]") {
  const auto start = std::chrono::steady_clock::now();
  // setFromTriplets built a row-major copy: an empty 10^7 x 1 matrix took seconds.
  const SpMat tall = sparse(kCoordinate + "10000000 1 1\n10000000 1 2.5\n");
  CHECK(tall.rows() == 10000000);
  CHECK(tall.coeff(9999999, 0) == 2.5);
  CHECK(sparse(kCoordinate + "10000000 10000000 0\n").nonZeros() == 0);
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
  // Duplicates are summed in file order, column by column, as before.
  const SpMat M = sparse(kCoordinate + "3 2 5\n3 2 1\n1 2 2\n2 1 3\n3 2 1e-17\n1 2 -2\n");
  CHECK(M.nonZeros() == 3);
  CHECK(M.coeff(2, 1) == 1.0 + 1e-17);
  CHECK(M.coeff(0, 1) == 0.0);
  CHECK(M.coeff(1, 0) == 3.0);
}

TEST_CASE("fuzz: deeply nested JSON is refused before it overflows the stack", "[fuzz]") {
  // 30000 nested objects under "parameters", then another key: nlohmann copied the nested
  // value recursively when the root object grew, and the stack overflowed.
  std::string deep;
  for (int k = 0; k < 30000; ++k) deep += R"({"a": )";
  deep += "1";
  for (int k = 0; k < 30000; ++k) deep += "}";
  REQUIRE_THROWS_AS(parse_scene(R"({"parameters": )" + deep + R"(, "bodies": []})", "s.json"),
                    InputError);
  REQUIRE_THROWS_AS(
      parse_scene(R"({"bodies": )" + std::string(100000, '[') + std::string(100000, ']') + "}",
                  "s.json"),
      InputError);
  // The message names the value at the limit, 64 levels down.
  std::string path;
  for (int k = 1; k < 64; ++k) path += "/a";
  REQUIRE_THROWS_WITH(parse_scene(R"({"parameters": )" + deep + "}", "s.json"),
                      "s.json: /parameters" + path + ": nested deeper than 64 arrays and objects");
}
