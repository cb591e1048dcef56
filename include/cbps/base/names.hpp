// Choices named by strings (integrators, step schemes): one lookup for every enumeration whose
// names are listed in its enumerators' order.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace cbps {

/// The enumerator of E whose name is `name`, with `names` listing E's names in enumerator order
/// (the k-th name is static_cast<E>(k)); nullopt for any other name.
template <class E>
std::optional<E> enumerator_named(const std::vector<std::string>& names, const std::string& name) {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return static_cast<E>(k);
  return std::nullopt;
}

}  // namespace cbps
