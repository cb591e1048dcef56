// MuJoCo's own constraint problem as a cbps problem (`cbps mujoco`, docs/mujoco.md): an MJCF
// model run under MuJoCo's step (the Debian package libmujoco-dev, 2.2.2), and for the steps
// asked, the problem MuJoCo's solver was given in that step, mapped row by row:
//   A = J M⁻¹ Jᵀ + R   (efc_J, M from mj_fullM, efc_R: MuJoCo's soft constraints' regularizer)
//   b = aref − J qacc_smooth   (= −efc_b), so that w = A λ − b is MuJoCo's J qacc − aref + R f
// with λ = efc_force (MuJoCo's constraint forces, in its units: N for contacts, N m or N for a
// joint's rows). Each row's set from efc_type: an equality free; a friction loss the box
// ±efc_frictionloss; a joint or tendon limit, a frictionless contact and each edge of a
// pyramidal cone [0, ∞); an elliptic cone of condim 3 the cone ‖λ_t‖ ≤ mu λ_n under the convex
// relaxation (ccp), which is the law MuJoCo's convex model solves. Anything else (condim 4 and
// 6, anisotropic friction) is refused by name. Built only where MuJoCo was found (CBPS_HAVE_MUJOCO,
// cmake/CbpsPeers.cmake); elsewhere every call says how to get it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cbps/base/types.hpp"
#include "cbps/io/stored_problem.hpp"

namespace cbps {

/// What `cbps mujoco` runs.
struct MujocoRun {
  std::string model;        ///< an MJCF file (or a MuJoCo binary model, .mjb)
  std::string keyframe;     ///< start from this keyframe of the model; empty: its qpos0
  long steps = 1;           ///< mj_step calls
  long every = 0;           ///< export steps 0, K, 2K, ... (0: only those in `at`)
  std::vector<long> at;     ///< steps to export (0: the first)
  std::string solver;       ///< MuJoCo's solver: pgs, cg or newton; empty: the model's
  int iterations = -1;      ///< MuJoCo's opt.iterations; negative: the model's
  double tolerance = -1.0;  ///< MuJoCo's opt.tolerance; negative: the model's
  /// For each exported step, MuJoCo's three solvers again on its state, 1, 2, 4, ... up to
  /// this many iterations (MujocoRung); 0: none.
  int ladder = 0;
};

/// MuJoCo's own account of one step's solve.
struct MujocoSolve {
  std::string solver;  ///< pgs, cg or newton
  std::string cone;    ///< pyramidal or elliptic
  int iterations = 0;  ///< solver_iter
  int max_iterations = 0;
  double tolerance = 0.0;
  /// Per iteration (at most mjNSOLVER = 1000 kept by MuJoCo): its improvement and gradient.
  std::vector<double> improvement, gradient;
  int contacts = 0;  ///< ncon
};

/// How far each MuJoCo solver gets on one step's problem in a given number of iterations: the
/// step's state solved again by pgs, cg and newton with opt.iterations = 1, 2, 4, ... and
/// opt.tolerance 0, each answer's unit-free residual (system/unit_free.hpp) on the exported
/// problem. MujocoRun::ladder asks for it.
struct MujocoRung {
  std::string solver;
  int iterations = 0;  ///< the iterations allowed
  int used = 0;        ///< the iterations MuJoCo ran (fewer where it stopped by itself)
  double unit_free = 0.0;
};

/// One exported step: the problem, MuJoCo's forces and the matrices it was made of.
struct MujocoStep {
  long step = 0;
  double time = 0.0;  ///< d->time before the step, s
  StoredProblem problem;
  std::vector<std::string> labels;  ///< one a row, as labels.json holds them
  MatX J;                           ///< efc_J, rows × nv
  MatX M;                           ///< the joint-space mass matrix, nv × nv
  VecX R;                           ///< efc_R, one a row
  VecX force;                       ///< efc_force: MuJoCo's answer
  MatX
      AR;  ///< efc_AR (J M⁻¹ Jᵀ + R) where MuJoCo formed it (its PGS, a dense Jacobian); else empty
  MujocoSolve solve;
  std::vector<MujocoRung> ladder;  ///< with MujocoRun::ladder
};

/// True in a build with MuJoCo.
bool mujoco_built();
/// MuJoCo's version as "2.2.2"; InputError without MuJoCo.
std::string mujoco_version();

/// Runs the model and calls `each` with every exported step, in order. InputError naming the
/// model for a file MuJoCo cannot load, a row MuJoCo made that has no cbps law (named), a step
/// out of range, or a build without MuJoCo (saying how to get it).
void run_mujoco(const MujocoRun& run, const std::function<void(const MujocoStep&)>& each);

/// The step's files through `sink` (stored_problem.hpp's FileSink): the problem folder's A.mtx,
/// b.mtx, cmin.mtx, cmax.mtx, cones.json (elliptic cones), labels.json, and MuJoCo's own
/// lambda_mujoco.mtx (efc_force), mujoco_J.mtx, mujoco_M.mtx, mujoco_R.mtx and mujoco.json
/// (the step, the solver's settings and statistics, each row's MuJoCo type); docs/outputs.md.
void write_mujoco_step(const MujocoStep& step, const std::string& model, const FileSink& sink);

}  // namespace cbps
