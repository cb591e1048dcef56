// cbps: the constraint-based rigid-body solver of Tamis & Maggiore (2015), one header per stage.
// A step runs the stages in this order; each line is paper section → header:
//                        types, errors, row kinds, numbers        base/ (below every stage)
//   3.1, 3.2, 12.4–12.5  bodies, inertia, integration           body/body.hpp
//   4                    collision: broad and narrow phase        collision/collision.hpp
//   5.1.3                a row: j_c, upsilon, cmin, cmax          rows/row.hpp
//   5.2                  distance rows                            rows/distance.hpp
//   5.3, 8.2.1           contact rows, restitution                rows/contact.hpp
//   5.4                  friction rows                            rows/friction.hpp
//   5.2–5.4              the row stage                            rows/build_rows.hpp
//   6.1, 6.2.9, 12.3.1   J, Minv, v1, fext, A, b, v2              system/system.hpp
//   6.2                  the boxed problem, its residual          system/boxed_problem.hpp
//   6.2, 7               solve(), methods, options, summaries     solvers/solver.hpp
//   7.1.1                PGS, PSOR, SGS, Jacobi                   solvers/paper/pgs.hpp
//                        block PGS                                solvers/compared/pgs_block.hpp
//                        matrix-free PGS                          solvers/paper/pgs_matrix_free.hpp
//   6.2                  the exact path (interior point, CHOLMOD) solvers/exact/direct.hpp
//                        the previous exact path (active set)     solvers/exact/active_set.hpp
//                        Lemke's method (dense reference)         solvers/exact/lemke.hpp
//                        CHOLMOD's factor of A + eps I            solvers/exact/cholmod_factor.hpp
//                        islands of A                             solvers/islands.hpp
//   5.4                  Coulomb bounds ±mu lambda_n              solvers/paper/coulomb.hpp
//                        Siconos' and Bullet's solvers (peers)    solvers/peers/peers.hpp
//   3.2 with all above   the step                                 step/simulation.hpp
//   8.1                  the improved push factor                 step/push.hpp
//                        the divergence guard                     step/guard.hpp
// The solvers in three parts: paper/ (7.1.1, 5.4), exact/ (the exact paths), compared/ (the
// methods PGS is compared with; solver.hpp's solve() reaches every one).
// Beside the pipeline: scene/ (scenes, JSON files, built-in scenes, 9 unit rescaling) and io/
// (Matrix Market, Siconos, stored problems, output written whole or not at all, CSV and JSON
// numbers). The studies (cbps_studies: a run's step loop and observers, convergence, profiles,
// stress catalogue, lcp's verdict, explain, verification, conditioning, the GSL reference, the
// --solver grammar) are not included here.
#pragma once

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/base/row_kind.hpp"
#include "cbps/base/types.hpp"
#include "cbps/body/body.hpp"
#include "cbps/collision/collision.hpp"
#include "cbps/io/csv_file.hpp"
#include "cbps/io/json_numbers.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/output_dir.hpp"
#include "cbps/io/output_file.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/rows/build_rows.hpp"
#include "cbps/rows/contact.hpp"
#include "cbps/rows/distance.hpp"
#include "cbps/rows/friction.hpp"
#include "cbps/rows/row.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/scene/scene_json.hpp"
#include "cbps/solvers/compared/pgs_block.hpp"
#include "cbps/solvers/exact/active_set.hpp"
#include "cbps/solvers/exact/cholmod_factor.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/islands.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/paper/pgs_matrix_free.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/guard.hpp"
#include "cbps/step/push.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
