// The whole system (paper 6.1) and the system equation (6.2).
#include "cbps/system.hpp"

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

SpMat assemble_J(const std::vector<Row>& rows, const std::vector<int>& block_of_body, int blocks) {
  std::vector<Triplet> t;
  t.reserve(rows.size() * 12);
  auto put = [&](int k, int body, const Row6& j) {
    if (body < 0) return;
    const int col = 6 * block_of_body[static_cast<std::size_t>(body)];
    for (int c = 0; c < 6; ++c) {
      if (j(c) != 0.0) t.emplace_back(k, col + c, j(c));
    }
  };
  for (std::size_t k = 0; k < rows.size(); ++k) {
    put(static_cast<int>(k), rows[k].body_a, rows[k].j_a);
    put(static_cast<int>(k), rows[k].body_b, rows[k].j_b);
  }
  SpMat J(static_cast<Eigen::Index>(rows.size()), 6 * blocks);
  J.setFromTriplets(t.begin(), t.end());
  return J;
}

SpMat assemble_Minv(const std::vector<Body>& bodies, const std::vector<int>& body_of_block) {
  std::vector<Triplet> t;
  t.reserve(body_of_block.size() * 12);
  for (std::size_t blk = 0; blk < body_of_block.size(); ++blk) {
    const Body& body = bodies[static_cast<std::size_t>(body_of_block[blk])];
    const int o = 6 * static_cast<int>(blk);
    for (int c = 0; c < 3; ++c) t.emplace_back(o + c, o + c, body.minv());  // m⁻¹ E₃
    const Mat3 Iinv = body.Iinv_world();                                    // I⁻¹
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        if (Iinv(r, c) != 0.0) t.emplace_back(o + 3 + r, o + 3 + c, Iinv(r, c));
      }
    }
  }
  const auto n6 = static_cast<Eigen::Index>(6 * body_of_block.size());
  SpMat Minv(n6, n6);
  Minv.setFromTriplets(t.begin(), t.end());
  return Minv;
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

SpMat compute_A(const SpMat& J, const SpMat& Minv) {
  const SpMat Jt = J.transpose();
  SpMat A = J * (Minv * Jt);  // A = J M⁻¹ Jᵀ (6.2.9)
  return A;
}

VecX compute_b(const VecX& upsilon,
               const SpMat& J,
               const VecX& v1,
               const SpMat& Minv,
               const VecX& fext,
               double dt) {
  const VecX rhs = v1 / dt + Minv * fext;
  return upsilon / dt - J * rhs;  // b = υ/Δt − J (v1/Δt + M⁻¹ f_ext) (6.2.9)
}

VecX compute_v2(const VecX& v1,
                const SpMat& Minv,
                const SpMat& J,
                const VecX& lambda,
                const VecX& fext,
                double dt) {
  const VecX f = J.transpose() * lambda + fext;  // f_c + f_ext, f_c = Jᵀ λ (6.2.1)
  return v1 + dt * (Minv * f);                   // v2 = v1 + Δt M⁻¹ (Jᵀ λ + f_ext) (12.3.1)
}

System assemble_system(const std::vector<Body>& bodies,
                       const std::vector<Row>& rows,
                       const Vec3& gravity,
                       double dt) {
  System sys;
  sys.dt = dt;
  map_bodies(bodies, sys);
  const auto c = static_cast<Eigen::Index>(rows.size());
  sys.labels.reserve(rows.size());
  sys.ids.reserve(rows.size());
  sys.upsilon.resize(c);
  sys.cmin.resize(c);
  sys.cmax.resize(c);
  for (Eigen::Index k = 0; k < c; ++k) {
    const Row& row = rows[static_cast<std::size_t>(k)];
    sys.labels.push_back(row.label);
    sys.ids.push_back(row.id);
    sys.upsilon(k) = row.upsilon;
    sys.cmin(k) = row.cmin;
    sys.cmax(k) = row.cmax;
  }
  sys.J = assemble_J(rows, sys.block_of_body, sys.blocks());
  sys.Minv = assemble_Minv(bodies, sys.body_of_block);
  sys.v1 = stack_velocities(bodies, sys.body_of_block);
  sys.fext = stack_forces(bodies, sys.body_of_block, gravity);
  sys.A = compute_A(sys.J, sys.Minv);
  sys.b = compute_b(sys.upsilon, sys.J, sys.v1, sys.Minv, sys.fext, dt);
  return sys;
}

}  // namespace cbps
