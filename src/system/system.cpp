// The whole system (paper 6.1) and the system equation (6.2).
#include "cbps/system/system.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "cbps/base/error.hpp"

namespace cbps {

void map_bodies(const std::vector<Body>& bodies, System& sys) {
  sys.block_of_body.assign(bodies.size(), -1);
  sys.body_of_block.clear();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].is_static) continue;  // static bodies get no columns (5.3)
    sys.block_of_body[i] = static_cast<int>(sys.body_of_block.size());
    sys.body_of_block.push_back(static_cast<int>(i));
  }
}

SpMatRow assemble_J(const std::vector<Row>& rows,
                    const std::vector<int>& block_of_body,
                    int blocks) {
  SpMatRow J;
  assemble_J(rows, block_of_body, blocks, J);
  return J;
}

void assemble_J(const std::vector<Row>& rows,
                const std::vector<int>& block_of_body,
                int blocks,
                SpMatRow& J) {
  // Row k's entries: the nonzeros of j_a in body a's 6 columns and of j_b in body b's, in
  // increasing column order. Two passes over the rows: count, then fill the compressed arrays.
  auto count = [](int body, const Row6& j) {
    return body < 0 ? 0 : int((j.array() != 0.0).count());
  };
  J.resize(static_cast<Eigen::Index>(rows.size()), 6 * blocks);
  Eigen::Index nnz = 0;
  for (const Row& row : rows) nnz += count(row.body_a, row.j_a) + count(row.body_b, row.j_b);
  J.resizeNonZeros(nnz);
  int* outer = J.outerIndexPtr();
  int* inner = J.innerIndexPtr();
  double* value = J.valuePtr();
  int e = 0;
  auto put = [&](int body, const Row6& j) {
    if (body < 0) return;
    const int col = 6 * block_of_body[static_cast<std::size_t>(body)];
    for (int c = 0; c < 6; ++c) {
      if (j(c) == 0.0) continue;
      inner[e] = col + c;
      value[e] = j(c);
      ++e;
    }
  };
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& row = rows[k];
    outer[k] = e;
    const bool a_first =
        row.body_b < 0 ||
        (row.body_a >= 0 && block_of_body[static_cast<std::size_t>(row.body_a)] <
                                block_of_body[static_cast<std::size_t>(row.body_b)]);
    put(a_first ? row.body_a : row.body_b, a_first ? row.j_a : row.j_b);
    put(a_first ? row.body_b : row.body_a, a_first ? row.j_b : row.j_a);
  }
  outer[rows.size()] = e;
}

SpMat assemble_Minv(const std::vector<Body>& bodies, const std::vector<int>& body_of_block) {
  SpMat Minv;
  assemble_Minv(bodies, body_of_block, Minv);
  return Minv;
}

void assemble_Minv(const std::vector<Body>& bodies,
                   const std::vector<int>& body_of_block,
                   SpMat& Minv) {
  // Column by column: three columns holding m⁻¹, three holding a column of I⁻¹ each.
  const auto n6 = static_cast<Eigen::Index>(6 * body_of_block.size());
  std::vector<Mat3> Iinv(body_of_block.size());
  Eigen::Index nnz = 0;
  for (std::size_t blk = 0; blk < body_of_block.size(); ++blk) {
    Iinv[blk] = bodies[static_cast<std::size_t>(body_of_block[blk])].Iinv_world();
    nnz += 3 + (Iinv[blk].array() != 0.0).count();
  }
  Minv.resize(n6, n6);
  Minv.resizeNonZeros(nnz);
  int* outer = Minv.outerIndexPtr();
  int* inner = Minv.innerIndexPtr();
  double* value = Minv.valuePtr();
  int e = 0;
  for (std::size_t blk = 0; blk < body_of_block.size(); ++blk) {
    const Body& body = bodies[static_cast<std::size_t>(body_of_block[blk])];
    const int o = 6 * static_cast<int>(blk);
    for (int c = 0; c < 3; ++c) {  // m⁻¹ E₃
      outer[o + c] = e;
      inner[e] = o + c;
      value[e] = body.minv();
      ++e;
    }
    for (int c = 0; c < 3; ++c) {  // I⁻¹
      outer[o + 3 + c] = e;
      for (int r = 0; r < 3; ++r) {
        if (Iinv[blk](r, c) == 0.0) continue;
        inner[e] = o + 3 + r;
        value[e] = Iinv[blk](r, c);
        ++e;
      }
    }
  }
  outer[n6] = e;
}

VecX stack_velocities(const std::vector<Body>& bodies, const std::vector<int>& body_of_block) {
  VecX v(static_cast<Eigen::Index>(6 * body_of_block.size()));
  for (std::size_t blk = 0; blk < body_of_block.size(); ++blk) {
    const Body& body = bodies[static_cast<std::size_t>(body_of_block[blk])];
    v.segment<3>(static_cast<Eigen::Index>(6 * blk)) = body.v();
    v.segment<3>(static_cast<Eigen::Index>(6 * blk + 3)) = body.omega();
  }
  return v;
}

VecX stack_forces(const std::vector<Body>& bodies,
                  const std::vector<int>& body_of_block,
                  const Vec3& gravity) {
  VecX f(static_cast<Eigen::Index>(6 * body_of_block.size()));
  for (std::size_t blk = 0; blk < body_of_block.size(); ++blk) {
    const Body& body = bodies[static_cast<std::size_t>(body_of_block[blk])];
    f.segment<3>(static_cast<Eigen::Index>(6 * blk)) = body.f + body.m * gravity;
    f.segment<3>(static_cast<Eigen::Index>(6 * blk + 3)) = body.tau;
  }
  return f;
}

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

/// The 6×6 blocks of Minv by body; empty when Minv is not block diagonal in 6×6 blocks.
std::vector<Eigen::Matrix<double, 6, 6>> minv_blocks(const SpMat& Minv) {
  const Eigen::Index n6 = Minv.cols();
  if (n6 % 6 != 0 || Minv.rows() != n6) return {};
  std::vector<Eigen::Matrix<double, 6, 6>> blocks(static_cast<std::size_t>(n6 / 6));
  for (auto& block : blocks) block.setZero();
  for (Eigen::Index j = 0; j < n6; ++j) {
    for (SpMat::InnerIterator it(Minv, j); it; ++it) {
      if (it.row() / 6 != j / 6) return {};
      blocks[std::size_t(j / 6)](it.row() % 6, j % 6) = it.value();
    }
  }
  return blocks;
}

/// Σ_i a_i b_i in the order of i.
double dot6(const Vec6& a, const Vec6& b) {
  double sum = 0.0;
  for (int i = 0; i < 6; ++i) sum += a(i) * b(i);
  return sum;
}

}  // namespace

SpMat compute_A(const SpMatRow& J, const SpMat& Minv) {
  // A = J M⁻¹ Jᵀ (6.2.9). Where M⁻¹ is block diagonal by body (every step's), A_kl =
  // Σ_B J_kB · (M⁻¹_B J_lBᵀ) over the bodies B that rows k and l share, in ascending B, formed
  // column by column from the rows of each body without the general sparse products (most of
  // the assembly's time). A_kl above the diagonal is the same expression as A_lk below it
  // (J_lB · M⁻¹_B J_kBᵀ), so A is exactly symmetric. Otherwise (an FCLIB file's M), the
  // general products J (M⁻¹ Jᵀ).
  const auto blocks = minv_blocks(Minv);
  if (blocks.empty() && J.cols() > 0) {
    const SpMat MinvJt = Minv * J.transpose();
    return J * MinvJt;
  }
  const Eigen::Index c = J.rows();
  // For every row k and body B it acts on (bodies ascending within a row): J_kB and
  // w_kB = M⁻¹_B J_kBᵀ; and for every body, its pairs, rows ascending (body_start, by_body).
  std::vector<long> row_start(std::size_t(c) + 1, 0);
  std::vector<int> pair_body, pair_row;
  std::vector<Vec6> pair_j, pair_w;
  pair_body.reserve(std::size_t(J.nonZeros()));
  std::vector<long> body_start(blocks.size() + 1, 0);
  for (Eigen::Index k = 0; k < c; ++k) {
    row_start[std::size_t(k)] = static_cast<long>(pair_body.size());
    for (SpMatRow::InnerIterator it(J, k); it;) {
      const Eigen::Index B = it.col() / 6;
      Vec6 jB = Vec6::Zero();
      for (; it && it.col() / 6 == B; ++it) jB(it.col() % 6) = it.value();
      ++body_start[std::size_t(B) + 1];
      pair_body.push_back(static_cast<int>(B));
      pair_row.push_back(static_cast<int>(k));
      pair_j.push_back(jB);
      pair_w.push_back(blocks[std::size_t(B)] * jB);
    }
  }
  row_start[std::size_t(c)] = static_cast<long>(pair_body.size());
  for (std::size_t B = 0; B < blocks.size(); ++B) body_start[B + 1] += body_start[B];
  std::vector<long> by_body(pair_body.size());
  {
    std::vector<long> next(body_start.begin(), body_start.end() - 1);
    for (std::size_t p = 0; p < pair_body.size(); ++p)
      by_body[std::size_t(next[std::size_t(pair_body[p])]++)] = static_cast<long>(p);
  }
  // At most Σ_l Σ_(B of l) (rows of B) entries (rows sharing two bodies count twice).
  long bound = 0;
  for (const int B : pair_body)
    bound += body_start[std::size_t(B) + 1] - body_start[std::size_t(B)];

  SpMat A(c, c);
  A.resizeNonZeros(static_cast<Eigen::Index>(bound));
  int* outer = A.outerIndexPtr();
  int* inner = A.innerIndexPtr();
  double* value = A.valuePtr();
  long nnz = 0;
  VecX sum = VecX::Zero(c);
  std::vector<char> seen(std::size_t(c), 0);
  std::vector<int> touched;
  outer[0] = 0;
  for (Eigen::Index l = 0; l < c; ++l) {
    touched.clear();
    for (long q = row_start[std::size_t(l)]; q < row_start[std::size_t(l) + 1]; ++q) {
      const std::size_t B = std::size_t(pair_body[std::size_t(q)]);
      for (long b = body_start[B]; b < body_start[B + 1]; ++b) {
        const long p = by_body[std::size_t(b)];
        const int k = pair_row[std::size_t(p)];
        // Below the diagonal J_kB · w_lB; above it the entry (l, k)'s own expression.
        sum(k) += k >= l ? dot6(pair_j[std::size_t(p)], pair_w[std::size_t(q)])
                         : dot6(pair_j[std::size_t(q)], pair_w[std::size_t(p)]);
        if (!seen[std::size_t(k)]) {
          seen[std::size_t(k)] = 1;
          touched.push_back(k);
        }
      }
    }
    std::sort(touched.begin(), touched.end());
    for (const int k : touched) {
      inner[nnz] = k;
      value[nnz] = sum(k);
      ++nnz;
      sum(k) = 0.0;
      seen[std::size_t(k)] = 0;
    }
    outer[l + 1] = static_cast<int>(nnz);
  }
  A.resizeNonZeros(static_cast<Eigen::Index>(nnz));  // shrinking keeps the storage
  return A;
}

VecX compute_b(const VecX& upsilon,
               const SpMatRow& J,
               const VecX& v1,
               const SpMat& Minv,
               const VecX& fext,
               double dt) {
  const VecX rhs = v1 / dt + Minv * fext;
  return upsilon / dt - J * rhs;  // b = υ/Δt − J (v1/Δt + M⁻¹ f_ext) (6.2.9)
}

VecX compute_v2(const VecX& v1,
                const SpMat& Minv,
                const SpMatRow& J,
                const VecX& lambda,
                const VecX& fext,
                double dt) {
  const VecX f = J.transpose() * lambda + fext;  // f_c + f_ext, f_c = Jᵀ λ (6.2.1)
  return v1 + dt * (Minv * f);                   // v2 = v1 + Δt M⁻¹ (Jᵀ λ + f_ext) (12.3.1)
}

VecX compute_v2(const System& sys, const VecX& lambda) {
  return compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, sys.dt);
}

System assemble_system(const std::vector<Body>& bodies,
                       const std::vector<Row>& rows,
                       const Vec3& gravity,
                       double dt,
                       PushMode push,
                       bool form_A) {
  System sys;
  assemble_system(bodies, rows, gravity, dt, push, sys, form_A);
  return sys;
}

void assemble_system(const std::vector<Body>& bodies,
                     const std::vector<Row>& rows,
                     const Vec3& gravity,
                     double dt,
                     PushMode push,
                     System& sys,
                     bool form_A) {
  sys.dt = dt;
  sys.push = push;
  map_bodies(bodies, sys);
  const auto c = static_cast<Eigen::Index>(rows.size());
  sys.labels.resize(rows.size());
  sys.ids.resize(rows.size());
  sys.kind.resize(rows.size());
  sys.upsilon.resize(c);
  sys.upsilon_push.resize(c);
  sys.manifold.resize(rows.size());
  sys.cmin.resize(c);
  sys.cmax.resize(c);
  for (Eigen::Index k = 0; k < c; ++k) {
    const Row& row = rows[static_cast<std::size_t>(k)];
    sys.labels[static_cast<std::size_t>(k)] = row.label;
    sys.ids[static_cast<std::size_t>(k)] = row.id;
    sys.kind[static_cast<std::size_t>(k)] = row.kind;
    // The one system holds the push (5.2.3, 5.3); 8.1's velocity system does not.
    sys.upsilon(k) =
        push == PushMode::Original ? with_push(row.upsilon, row.upsilon_push) : row.upsilon;
    sys.upsilon_push(k) = row.upsilon_push;
    sys.manifold[static_cast<std::size_t>(k)] = row.manifold;
    sys.cmin(k) = row.cmin;
    sys.cmax(k) = row.cmax;
  }
  // The contacts and their law, as the rows carry them (Row::mu, Row::law).
  sys.contacts.normal.clear();
  sys.contacts.law = FrictionLaw::PaperBox;
  std::vector<double> mu;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (rows[k].mu < 0.0) continue;
    if (!mu.empty() && rows[k].law != sys.contacts.law)
      throw std::logic_error("assemble_system: the contacts' rows carry more than one law");
    sys.contacts.normal.push_back(static_cast<int>(k));
    sys.contacts.law = rows[k].law;
    mu.push_back(rows[k].mu);
  }
  sys.contacts.mu = Eigen::Map<const VecX>(mu.data(), Eigen::Index(mu.size()));
  assemble_J(rows, sys.block_of_body, sys.blocks(), sys.J);
  assemble_Minv(bodies, sys.body_of_block, sys.Minv);
  sys.v1 = stack_velocities(bodies, sys.body_of_block);
  sys.fext = stack_forces(bodies, sys.body_of_block, gravity);
  if (form_A)
    sys.A = compute_A(sys.J, sys.Minv);
  else
    sys.A.resize(0, 0);
  sys.b = compute_b(sys.upsilon, sys.J, sys.v1, sys.Minv, sys.fext, dt);
  sys.softness.resize(0);  // rigid rows until a scheme softens them
  sys.A_soft.resize(0, 0);
}

void soften(System& sys, const VecX& softness) {
  if (softness.size() != sys.rows() || sys.A.rows() != sys.rows())
    throw std::logic_error("soften: needs A formed and one softness per row");
  if (softness.isZero(0.0)) {
    sys.softness.resize(0);
    sys.A_soft.resize(0, 0);
    return;
  }
  sys.softness = softness;
  SpMat E(sys.rows(), sys.rows());
  E.setIdentity();
  E = softness.asDiagonal() * E;  // kg⁻¹
  sys.A_soft = sys.A + E;
}

FrictionContacts contacts_in_cones(const System& sys, FrictionLaw law) {
  if (!is_cone(law)) throw std::logic_error("contacts_in_cones: not a cone law");
  std::size_t next = 0;  // the next contact of sys.contacts
  for (int k = 0; k < sys.rows(); ++k) {
    if (sys.kind[static_cast<std::size_t>(k)] != RowKind::Contact) continue;
    if (next < sys.contacts.normal.size() && sys.contacts.normal[next] == k) {
      ++next;
      continue;
    }
    throw InputError(
        "row " + std::to_string(k) + " (" + sys.labels[std::size_t(k)] +
        ") is a contact without two friction rows after it (mu = 0 makes none); a cone needs "
        "both");
  }
  FrictionContacts cones = sys.contacts;
  cones.law = law;
  return cones;
}

}  // namespace cbps
