// What a row constrains: made by the rows (rows/), read by the solvers (their sweep order), the
// step (its warm-start factors), the studies and the Python module. Here, below all of them,
// so that no stage includes a later one to name it.
#pragma once

namespace cbps {

/// What a row constrains, set where the row is made (rows/): the solvers may order their
/// sweeps by it (SolverOptions::contacts_first) and a step scales its warm start by it
/// (SolverSettings::warm, warm_friction).
enum class RowKind {
  Distance,  ///< a distance constraint (5.2)
  Contact,   ///< a contact's normal row (5.3)
  Friction   ///< a friction row along a tangent of a contact (5.4)
};

/// "distance", "contact" or "friction": the first word of a row's label and the name the Python
/// module and the teaching page use.
inline const char* to_string(RowKind kind) {
  switch (kind) {
    case RowKind::Distance:
      return "distance";
    case RowKind::Contact:
      return "contact";
    case RowKind::Friction:
      return "friction";
  }
  return "distance";
}

}  // namespace cbps
