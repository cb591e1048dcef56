// MuJoCo's constraint problem of a step as a cbps problem (mujoco_problem.hpp, docs/mujoco.md).
#include "cbps/io/mujoco_problem.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/system/unit_free.hpp"

#ifdef CBPS_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace cbps {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void write_json_file(const std::string& path, const nlohmann::json& j) {
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  out.flush();
  if (!out) throw std::runtime_error(path + ": write failed");
}

nlohmann::json ladder_json(const std::vector<MujocoRung>& ladder) {
  nlohmann::json out = nlohmann::json::array();
  for (const MujocoRung& r : ladder)
    out.push_back({{"solver", r.solver},
                   {"iterations", r.iterations},
                   {"used", r.used},
                   {"unit_free", r.unit_free}});
  return out;
}

/// The files every step writes beside the problem's.
void write_files(const MujocoStep& s, const std::string& model, const FileSink& sink) {
  const auto matrix = [&](const char* name, const MatX& M, const std::string& comment) {
    sink(name, [&](const std::string& path) {
      write_matrix_market(path, SpMat(M.sparseView(0.0, 0.0)), comment);
    });
  };
  const auto vector = [&](const char* name, const VecX& v, const std::string& comment) {
    sink(name, [&](const std::string& path) { write_matrix_market(path, v, comment); });
  };
  const std::string step = " (MuJoCo, " + model + ", step " + std::to_string(s.step) + ")";
  matrix("A.mtx",
         s.problem.A,
         "A = J M^-1 J^T + R: MuJoCo's efc_J, mass matrix and efc_R, symmetrized" + step);
  vector("b.mtx", s.problem.b, "b = aref - J qacc_smooth (MuJoCo's efc_aref, qacc_smooth)" + step);
  vector("cmin.mtx", s.problem.cmin, "cmin: each row's lower bound from its MuJoCo type" + step);
  vector("cmax.mtx", s.problem.cmax, "cmax: each row's upper bound from its MuJoCo type" + step);
  vector("lambda_mujoco.mtx", s.force, "MuJoCo's efc_force: its answer to this problem" + step);
  matrix("mujoco_J.mtx", s.J, "J: MuJoCo's efc_J, rows x nv" + step);
  matrix("mujoco_M.mtx", s.M, "M: MuJoCo's joint-space mass matrix (mj_fullM), nv x nv" + step);
  vector("mujoco_R.mtx", s.R, "R: MuJoCo's efc_R, the soft constraints' regularizer" + step);
  if (!s.problem.cones.empty()) {
    sink("cones.json", [&](const std::string& path) {
      nlohmann::json contacts = nlohmann::json::array();
      for (long i = 0; i < s.problem.cones.contacts(); ++i)
        contacts.push_back({{"normal_row", s.problem.cones.normal[std::size_t(i)]},
                            {"mu", s.problem.cones.mu(i)}});
      write_json_file(path, {{"law", "ccp"}, {"contacts", contacts}});
    });
  }
  sink("labels.json", [&](const std::string& path) {
    write_json_file(path, {{"rows", s.labels}});
  });
  sink("mujoco.json", [&](const std::string& path) {
    const MujocoSolve& v = s.solve;
    write_json_file(path,
                    {{"model", model},
                     {"mujoco", mujoco_version()},
                     {"step", s.step},
                     {"time_s", s.time},
                     {"solver", v.solver},
                     {"cone", v.cone},
                     {"iterations", v.iterations},
                     {"max_iterations", v.max_iterations},
                     {"tolerance", v.tolerance},
                     {"improvement", v.improvement},
                     {"gradient", v.gradient},
                     {"rows", s.problem.rows()},
                     {"nv", s.M.rows()},
                     {"contacts", v.contacts},
                     {"ladder", ladder_json(s.ladder)}});
  });
}

}  // namespace

void write_mujoco_step(const MujocoStep& step, const std::string& model, const FileSink& sink) {
  write_files(step, model, sink);
}

#ifndef CBPS_HAVE_MUJOCO

namespace {
[[noreturn]] void not_built() {
  throw InputError(
      "cbps mujoco: this cbps was built without MuJoCo; install it (Debian: libmujoco-dev, "
      "which scripts/setup.sh installs) and build again (docs/mujoco.md)");
}
}  // namespace

bool mujoco_built() { return false; }
std::string mujoco_version() { not_built(); }
void run_mujoco(const MujocoRun&, const std::function<void(const MujocoStep&)>&) { not_built(); }

#else

namespace {

/// A model and its data, freed together.
struct Model {
  mjModel* m = nullptr;
  mjData* d = nullptr;
  ~Model() {
    if (d != nullptr) mj_deleteData(d);
    if (m != nullptr) mj_deleteModel(m);
  }
};

std::string name_of(const mjModel* m, int type, int id, const char* kind) {
  const char* name = mj_id2name(m, type, id);
  std::string text = name != nullptr && *name != '\0' ? name : kind + std::to_string(id);
  std::replace(text.begin(), text.end(), ' ', '_');  // one word in a label
  return text;
}

/// MuJoCo's solvers, the ladder's order.
constexpr int kSolvers[] = {mjSOL_PGS, mjSOL_CG, mjSOL_NEWTON};

/// What MuJoCo's options say, as words.
const char* solver_word(int solver) {
  return solver == mjSOL_PGS ? "pgs" : solver == mjSOL_CG ? "cg" : "newton";
}

/// The step's matrices as MuJoCo holds them: J (efc_J, dense or sparse), M (mj_fullM), R,
/// MuJoCo's forces and, where its PGS formed it, efc_AR; and A = J M⁻¹ Jᵀ + R (symmetrized: the
/// two halves of J M⁻¹ Jᵀ differ by round-off), b = aref − J qacc_smooth.
void read_matrices(const mjModel* m, mjData* d, MujocoStep& s) {
  const int nefc = d->nefc, nv = m->nv;
  s.J = MatX::Zero(nefc, nv);
  if (mj_isSparse(m)) {
    for (int i = 0; i < nefc; ++i)
      for (int k = 0; k < d->efc_J_rownnz[i]; ++k) {
        const int a = d->efc_J_rowadr[i] + k;
        s.J(i, d->efc_J_colind[a]) = d->efc_J[a];
      }
  } else {
    for (int i = 0; i < nefc; ++i)
      for (int j = 0; j < nv; ++j) s.J(i, j) = d->efc_J[i * nv + j];
  }
  s.M = MatX::Zero(nv, nv);
  std::vector<mjtNum> full(static_cast<std::size_t>(nv) * nv);
  mj_fullM(m, full.data(), d->qM);
  for (int i = 0; i < nv; ++i)
    for (int j = 0; j < nv; ++j) s.M(i, j) = full[std::size_t(i) * nv + j];
  // M⁻¹ Jᵀ by MuJoCo's own factor of M (mj_solveM on each row of J), then J M⁻¹ Jᵀ + R.
  MatX MinvJt(nv, nefc);
  std::vector<mjtNum> row(static_cast<std::size_t>(nv)), x(static_cast<std::size_t>(nv));
  for (int i = 0; i < nefc; ++i) {
    for (int j = 0; j < nv; ++j) row[std::size_t(j)] = s.J(i, j);
    mj_solveM(m, d, x.data(), row.data(), 1);
    for (int j = 0; j < nv; ++j) MinvJt(j, i) = x[std::size_t(j)];
  }
  s.R = Eigen::Map<const VecX>(d->efc_R, nefc);
  MatX A = s.J * MinvJt;
  A = 0.5 * (A + A.transpose());
  A.diagonal() += s.R;
  StoredProblem& p = s.problem;
  p.folder = true;
  p.without_jacobian = "a MuJoCo step's folder keeps J and M apart (A holds R as well)";
  p.A = A.sparseView(0.0, 0.0);
  const VecX qacc_smooth = Eigen::Map<const VecX>(d->qacc_smooth, nv);
  p.b = Eigen::Map<const VecX>(d->efc_aref, nefc) - s.J * qacc_smooth;
  s.force = Eigen::Map<const VecX>(d->efc_force, nefc);
  if (mj_isDual(m) && !mj_isSparse(m)) {
    s.AR = MatX(nefc, nefc);
    for (int i = 0; i < nefc; ++i)
      for (int j = 0; j < nefc; ++j) s.AR(i, j) = d->efc_AR[i * nefc + j];
  }
}

/// Each row's set and label from its MuJoCo type (the header's mapping); InputError naming a
/// row cbps has no law for.
void map_rows(const mjModel* m, const mjData* d, const std::string& model, MujocoStep& s) {
  const int nefc = d->nefc;
  const long step = s.step;
  StoredProblem& p = s.problem;
  p.cmin = VecX::Constant(nefc, -kInf);
  p.cmax = VecX::Constant(nefc, kInf);
  p.blocks.assign(std::size_t(nefc), -1);
  s.labels.resize(std::size_t(nefc));
  std::vector<double> mu;
  for (int i = 0; i < nefc;) {
    const int id = d->efc_id[i];
    const std::size_t k = std::size_t(i);
    switch (d->efc_type[i]) {
      case mjCNSTR_EQUALITY:
        s.labels[k] = "equality " + name_of(m, mjOBJ_EQUALITY, id, "equality");
        ++i;
        continue;
      case mjCNSTR_FRICTION_DOF:
      case mjCNSTR_FRICTION_TENDON: {
        const bool dof = d->efc_type[i] == mjCNSTR_FRICTION_DOF;
        s.labels[k] =
            dof ? "frictionloss joint " + name_of(m, mjOBJ_JOINT, m->dof_jntid[id], "joint")
                : "frictionloss tendon " + name_of(m, mjOBJ_TENDON, id, "tendon");
        p.cmin(i) = -d->efc_frictionloss[i];
        p.cmax(i) = d->efc_frictionloss[i];
        ++i;
        continue;
      }
      case mjCNSTR_LIMIT_JOINT:
      case mjCNSTR_LIMIT_TENDON:
        s.labels[k] = d->efc_type[i] == mjCNSTR_LIMIT_JOINT
                          ? "limit joint " + name_of(m, mjOBJ_JOINT, id, "joint")
                          : "limit tendon " + name_of(m, mjOBJ_TENDON, id, "tendon");
        p.cmin(i) = 0.0;
        ++i;
        continue;
      default:
        break;
    }
    // A contact: its rows from efc_address on.
    const mjContact& c = d->contact[id];
    const std::string pair = name_of(m, mjOBJ_GEOM, c.geom1, "geom") + "-" +
                             name_of(m, mjOBJ_GEOM, c.geom2, "geom") + " #" + std::to_string(id);
    const int type = d->efc_type[i];
    if (type == mjCNSTR_CONTACT_FRICTIONLESS) {
      s.labels[k] = "contact " + pair;
      p.cmin(i) = 0.0;
      ++i;
    } else if (type == mjCNSTR_CONTACT_PYRAMIDAL) {
      for (int e = 0; e < 2 * (c.dim - 1); ++e, ++i) {
        s.labels[std::size_t(i)] = "pyramid-edge " + pair + " e" + std::to_string(e + 1);
        p.cmin(i) = 0.0;
      }
    } else if (type == mjCNSTR_CONTACT_ELLIPTIC) {
      if (c.dim != 3)
        throw InputError(model + ": step " + std::to_string(step) + ": contact " + pair +
                         " has condim " + std::to_string(c.dim) +
                         " in an elliptic cone; cbps's cones hold condim 3 (a normal and two "
                         "sliding rows), not torsional or rolling friction");
      if (c.friction[0] != c.friction[1])
        throw InputError(model + ": step " + std::to_string(step) + ": contact " + pair +
                         " has anisotropic friction (" + std::to_string(c.friction[0]) + ", " +
                         std::to_string(c.friction[1]) + "); cbps's cones have one mu per contact");
      p.cones.normal.push_back(i);
      mu.push_back(c.friction[0]);  // not c.mu: impratio changes R only (measured)
      s.labels[k] = "contact " + pair;
      s.labels[k + 1] = "friction " + pair + " t1";
      s.labels[k + 2] = "friction " + pair + " t2";
      p.cmin(i) = 0.0;
      i += 3;
    } else {
      throw InputError(model + ": step " + std::to_string(step) + ": row " + std::to_string(i) +
                       " has MuJoCo constraint type " + std::to_string(type) +
                       ", which cbps does not map");
    }
  }
  p.cones.mu = Eigen::Map<const VecX>(mu.data(), Eigen::Index(mu.size()));
  p.cones.law = FrictionLaw::Relaxation;
  p.labels = s.labels;
}

/// MuJoCo's own account of the solve: its solver, cone, iterations and their statistics.
MujocoSolve solve_of(const mjModel* m, const mjData* d) {
  MujocoSolve v;
  v.solver = solver_word(m->opt.solver);
  v.cone = m->opt.cone == mjCONE_ELLIPTIC ? "elliptic" : "pyramidal";
  v.iterations = d->solver_iter;
  v.max_iterations = m->opt.iterations;
  v.tolerance = m->opt.tolerance;
  v.contacts = d->ncon;
  for (int k = 0; k < std::min(d->solver_iter, mjNSOLVER); ++k) {
    v.improvement.push_back(d->solver[k].improvement);
    v.gradient.push_back(d->solver[k].gradient);
  }
  return v;
}

/// MuJoCo's problem of the current forward pass as a cbps problem (the header's mapping).
MujocoStep capture(const mjModel* m, mjData* d, const std::string& model, long step) {
  MujocoStep s;
  s.step = step;
  s.time = d->time;
  read_matrices(m, d, s);
  map_rows(m, d, model, s);
  s.solve = solve_of(m, d);
  return s;
}

/// The ladder of MujocoRun::ladder on the state of the forward pass just made (its problem in
/// s), each rung from the step's own warm start `warm`; the model's options restored after.
void climb_ladder(mjModel* m, mjData* d, int top, const std::vector<mjtNum>& warm, MujocoStep& s) {
  const mjOption own = m->opt;
  const BoxedProblem problem = s.problem.problem();
  for (const int solver : kSolvers) {
    for (int k = 1; k <= top; k *= 2) {
      m->opt.solver = solver;
      m->opt.iterations = k;
      m->opt.tolerance = 0.0;  // exactly k iterations, unless MuJoCo stops by itself (used)
      std::copy(warm.begin(), warm.end(), d->qacc_warmstart);  // the step's own warm start
      mj_forward(m, d);
      if (d->nefc != s.problem.rows())
        throw std::logic_error("MuJoCo's rows changed between two forward passes of one state");
      const VecX force = Eigen::Map<const VecX>(d->efc_force, d->nefc);
      s.ladder.push_back(
          {solver_word(solver), k, d->solver_iter, unit_free_residual(problem, force).relative});
      if (k > top / 2) break;
    }
  }
  m->opt = own;
}

}  // namespace

bool mujoco_built() { return true; }

std::string mujoco_version() {
  const int v = mj_version();
  return std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." + std::to_string(v % 10);
}

void run_mujoco(const MujocoRun& run, const std::function<void(const MujocoStep&)>& each) {
  for (const long k : run.at)
    if (k < 0 || k >= run.steps)
      throw InputError("--step " + std::to_string(k) + ": not one of the " +
                       std::to_string(run.steps) + " steps run (0 to " +
                       std::to_string(run.steps - 1) + ")");
  Model model;
  char error[1000] = "";
  const bool binary = run.model.size() > 4 && run.model.substr(run.model.size() - 4) == ".mjb";
  model.m = binary ? mj_loadModel(run.model.c_str(), nullptr)
                   : mj_loadXML(run.model.c_str(), nullptr, error, sizeof error);
  if (model.m == nullptr)
    throw InputError(run.model + ": MuJoCo cannot load it" +
                     (error[0] != '\0' ? std::string(": ") + error : std::string()));
  mjModel* m = model.m;
  if (!run.solver.empty()) {
    const int* named = nullptr;
    for (const int& solver : kSolvers)
      if (run.solver == solver_word(solver)) named = &solver;
    if (named == nullptr)
      throw InputError("--mujoco-solver " + run.solver + ": not pgs, cg or newton");
    m->opt.solver = *named;
  }
  if (run.iterations >= 0) m->opt.iterations = run.iterations;
  if (run.tolerance >= 0.0) m->opt.tolerance = run.tolerance;
  if (m->opt.noslip_iterations > 0)
    throw InputError(run.model + ": noslip_iterations " + std::to_string(m->opt.noslip_iterations) +
                     ": MuJoCo's noslip pass changes the forces after its solve, so they are no "
                     "longer the answer of the problem cbps would export; set it to 0");
  model.d = mj_makeData(m);
  if (model.d == nullptr) throw InputError(run.model + ": MuJoCo could not allocate its data");
  mjData* d = model.d;
  if (!run.keyframe.empty()) {
    const int key = mj_name2id(m, mjOBJ_KEY, run.keyframe.c_str());
    if (key < 0)
      throw InputError("--keyframe " + run.keyframe + ": " + run.model +
                       " has no keyframe of that name");
    mj_resetDataKeyframe(m, d, key);
  }
  for (long k = 0; k < run.steps; ++k) {
    const bool exported = (run.every > 0 && k % run.every == 0) ||
                          std::find(run.at.begin(), run.at.end(), k) != run.at.end();
    if (exported) {
      // mj_forward writes its answer into qacc_warmstart: every pass of this state starts from
      // the warm start the step had, so that mj_step repeats the exported pass exactly and the
      // run is the run without export.
      const std::vector<mjtNum> warm(d->qacc_warmstart, d->qacc_warmstart + m->nv);
      mj_forward(m, d);
      MujocoStep s = capture(m, d, run.model, k);
      if (run.ladder > 0) climb_ladder(m, d, run.ladder, warm, s);
      each(s);
      std::copy(warm.begin(), warm.end(), d->qacc_warmstart);
    }
    mj_step(m, d);
    for (int w = 0; w < mjNWARNING; ++w)
      if (d->warning[w].number > 0 && (w == mjWARN_BADQACC || w == mjWARN_CNSTRFULL))
        throw InputError(run.model + ": step " + std::to_string(k) +
                         ": MuJoCo warns: " + mju_warningText(w, d->warning[w].lastinfo));
  }
}

#endif

}  // namespace cbps
