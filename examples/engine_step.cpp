// One step of a small engine of your own, dumped as a cbps problem folder and judged by
// `cbps check` (docs/check-any-engine.md). Standard C++ only: no cbps, no Eigen; copy the
// writers into your engine.
//
// The engine: a ball (m = 2 kg, radius 0.1 m) resting on the ground y = 0, gravity −9.81 m/s²
// along y, dt = 1/60 s, one contact (a normal row and two friction rows) in Coulomb's cone with
// mu = 0.4, and a second ball hanging 1 m below a fixed point on a distance row (a free row:
// cmin = −∞, cmax = +∞). Its λ is what its solver returned; here the exact values m g, written
// with an error `--error E` (N) on the contact's normal row, so that `cbps check` has something
// to find.
//
//     engine_step OUT [--error E]
//     cbps check OUT --lambda OUT/lambda_engine.txt
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using Matrix = std::vector<std::vector<double>>;

/// A dense matrix as Matrix Market "coordinate real general": 1-based indices, its nonzeros.
void write_matrix(const std::filesystem::path& path, const Matrix& m, const char* comment) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) std::exit(2);
  std::size_t nonzeros = 0;
  for (const auto& row : m)
    for (double x : row) nonzeros += x != 0.0;
  std::fprintf(f, "%%%%MatrixMarket matrix coordinate real general\n%% %s\n", comment);
  std::fprintf(f, "%zu %zu %zu\n", m.size(), m[0].size(), nonzeros);
  for (std::size_t i = 0; i < m.size(); ++i)
    for (std::size_t j = 0; j < m[i].size(); ++j)
      if (m[i][j] != 0.0) std::fprintf(f, "%zu %zu %.17g\n", i + 1, j + 1, m[i][j]);
  std::fclose(f);
}

/// A vector as Matrix Market "array real general", one column; ±∞ as inf and -inf.
void write_vector(const std::filesystem::path& path,
                  const std::vector<double>& v,
                  const char* comment) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) std::exit(2);
  std::fprintf(f, "%%%%MatrixMarket matrix array real general\n%% %s\n%zu 1\n", comment, v.size());
  for (double x : v) std::fprintf(f, "%.17g\n", x);
  std::fclose(f);
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) std::exit(2);
  std::fputs(text.c_str(), f);
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && !(argc == 4 && std::string(argv[2]) == "--error")) {
    std::fprintf(stderr, "usage: engine_step OUT [--error E]\n");
    return 2;
  }
  const std::filesystem::path out = argv[1];
  const double error = argc == 4 ? std::atof(argv[3]) : 0.0;  // N
  std::filesystem::create_directories(out);

  const double m = 2.0, radius = 0.1, g = 9.81, dt = 1.0 / 60.0, mu = 0.4;
  const double inertia = 0.4 * m * radius * radius;  // solid ball, kg m²
  // Velocities (v, ω) of ball 0 (on the ground), then ball 1 (hanging): 12 columns. Rows: the
  // contact's normal n = +y, its tangents t1 = +x, t2 = +z at r = (0, −radius, 0) from ball 0's
  // centre, each (d, r × d); the distance row along the string, +y at ball 1's top.
  Matrix J(4, std::vector<double>(12, 0.0));
  J[0][1] = 1.0;  // n · v
  J[1][0] = 1.0;  // t1 · v + (r × t1) · ω, with r × x̂ = (0, 0, radius)
  J[1][5] = radius;
  J[2][2] = 1.0;  // t2 · v + (r × t2) · ω, with r × ẑ = (−radius, 0, 0)
  J[2][3] = -radius;
  J[3][7] = 1.0;  // ball 1's velocity along the string, +y: its λ > 0 holds the ball up
  const double minv[12] = {1 / m,
                           1 / m,
                           1 / m,
                           1 / inertia,
                           1 / inertia,
                           1 / inertia,
                           1 / m,
                           1 / m,
                           1 / m,
                           1 / inertia,
                           1 / inertia,
                           1 / inertia};
  Matrix Minv(12, std::vector<double>(12, 0.0));
  for (int k = 0; k < 12; ++k) Minv[k][k] = minv[k];
  // A = J Minv Jᵀ (1/kg) and b = υ/dt − J (v1/dt + Minv fext) (m/s²) with v1 = 0, υ = 0 and
  // fext = (0, −m g, 0) on each ball's force.
  const std::size_t c = J.size();
  Matrix A(c, std::vector<double>(c, 0.0));
  std::vector<double> b(c, 0.0);
  for (std::size_t i = 0; i < c; ++i) {
    for (std::size_t j = 0; j < c; ++j)
      for (int k = 0; k < 12; ++k) A[i][j] += J[i][k] * minv[k] * J[j][k];
    b[i] = -(J[i][1] * minv[1] * (-m * g) + J[i][7] * minv[7] * (-m * g));
  }
  const double inf = INFINITY;
  write_matrix(out / "A.mtx", A, "A = J Minv J^T, 1/kg");
  write_matrix(out / "J.mtx", J, "J, c x 6n");
  write_matrix(out / "Minv.mtx", Minv, "Minv, 6n x 6n");
  write_vector(out / "b.mtx", b, "b = upsilon/dt - J (v1/dt + Minv fext), m/s^2");
  write_vector(out / "cmin.mtx", {0.0, -inf, -inf, -inf}, "cmin, N");
  write_vector(out / "cmax.mtx", {inf, inf, inf, inf}, "cmax, N");
  write_text(out / "labels.json",
             "{\"rows\": [\"contact ground-ball #0\", \"friction ground-ball #0 t1\",\n"
             "          \"friction ground-ball #0 t2\", \"string world-hanging\"]}\n");
  char cones[128];
  std::snprintf(cones,
                sizeof cones,
                "{\"law\": \"coulomb\", \"contacts\": [{\"normal_row\": 0, \"mu\": %.17g}]}\n",
                mu);
  write_text(out / "cones.json", cones);
  // The engine's answer: m g on the contact (plus the error asked for) and on the string.
  char lambda[256];
  std::snprintf(lambda, sizeof lambda, "%.17g\n0\n0\n%.17g\n", m * g + error, m * g);
  write_text(out / "lambda_engine.txt", lambda);
  std::printf("wrote %s: %zu rows\n", out.c_str(), c);
  return 0;
}
