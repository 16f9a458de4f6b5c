#pragma once
/// @file Super IFS (seed 3.3.5, Definition 20, Eq. 38-40): several IFS chosen at random.
#include <cstddef>
#include <string>
#include <vector>

namespace ifsforge {

class Ifs;

/// @brief How the maps of one Ifs split into the M member systems Omega_1..Omega_M of a super
/// IFS: member n owns `sizes[n]` consecutive maps and is chosen with probability P_n.
/// V-variable fractals (5.2.2) keep `variability` buffers.
struct SuperIfs {
  std::vector<std::size_t> sizes;
  std::vector<double> probabilities;  ///< P_n, normalised
  std::vector<std::string> names;
  int variability = 2;                ///< V

  bool empty() const { return sizes.empty(); }
  std::size_t members() const { return sizes.size(); }
  std::size_t first_map(std::size_t n) const;
};

/// @brief The super IFS of Eq. 38 as one Ifs: the members' maps one after another, map m of
/// member n with probability P_n p_nm. Other algorithms see the union of the members, whose
/// attractor contains every member of the superfractal. Members share one layout and are
/// ordinary systems (no transitions, condensation or members of their own).
Ifs make_super_ifs(const std::string& name, const std::vector<Ifs>& members,
                   std::vector<double> probabilities, int variability = 2);

/// @brief Member n of a super IFS as its own Ifs (its maps, probabilities p_nm).
Ifs super_member(const Ifs& ifs, std::size_t n);

}  // namespace ifsforge
