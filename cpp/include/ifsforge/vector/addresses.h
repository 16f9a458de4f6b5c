#pragma once
/// @file Addresses of the pieces of an attractor (seed 5.6 and 5.7): the string-rewriting
/// algorithm, the tesseral synecdoche algorithm (TSA) with probability pruning, and the
/// composition that turns an address back into a point.
///
/// Convention (the one of render/recursion.h): an address lists 0-based map indices from the
/// outermost map in: (a0, a1, ..., a_{L-1}) names the piece w_{a0} o w_{a1} o ... o w_{a_{L-1}} (A)
/// of the attractor A, and the point w_{a0}(w_{a1}( ... w_{a_{L-1}}(q0))). a0 picks one of the N
/// first-level copies, a1 a copy inside it, and so on: the tesseral (coarse-to-fine) reading, in
/// which the probability p_{a0} ... p_{a_{L-1}} is the invariant measure of the piece. Strings
/// write it "a0.a1.....a_{L-1}", the seed's composition "w_{a0} w_{a1} ..." with 0-based numbers.
/// The recursive algorithms list leaves depth-first, i.e. in lexicographic address order, so
/// every first-level copy is one contiguous run of the list.
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/core/progress.h"
#include "ifsforge/model/ifs.h"

namespace ifsforge {

/// Marks the unused digits of an address shorter than the table's depth.
constexpr std::uint16_t kNoMap = 0xFFFF;
/// Deepest address the recursive algorithms build.
constexpr int kMaxAddressDepth = 64;

/// @brief The leaves of an address tree, in depth-first order.
struct AddressTable {
  int depth = 0;                      ///< columns of `digits`: the longest address
  std::vector<std::uint16_t> digits;  ///< size() x depth, row-major; kNoMap past each length
  std::vector<std::uint8_t> lengths;  ///< digits in use per leaf
  std::vector<double> probabilities;  ///< product of the map probabilities along the address

  std::size_t size() const { return lengths.size(); }
  const std::uint16_t* address(std::size_t i) const { return digits.data() + i * depth; }
  /// @brief "a0.a1.....a_{L-1}".
  std::string to_string(std::size_t i) const;
};

/// @brief What the TSA plots: the leaf addresses and the leaf points (dim per leaf).
struct AddressLeaves {
  AddressTable addresses;
  int dim = 0;
  std::vector<double> points;
};

/// How string_rewriting() spells an address: Digits "1.0.3" (maps from 0, joined by '.', this
/// layer's addresses), Seed "w2w1w4" (the seed's 5.6 spelling, maps from 1).
enum class AddressSpelling { Digits, Seed };
template <>
struct EnumNames<AddressSpelling> {
  static constexpr const char* what = "address spelling";
  static constexpr NamedValue<AddressSpelling> values[] = {{AddressSpelling::Digits, "digits"},
                                                           {AddressSpelling::Seed, "seed"}};
};

/// @brief The seed's string-rewriting algorithm (5.6), rewrite_map_strings() over the maps'
/// symbols: each of the depth - 1 rewrites replaces every string s by "0.s", "1.s", ...,
/// "(N-1).s" (a new outermost map; "w1s" ... "wNs" spelled as the seed). The N^depth strings
/// come in the seed's order (by the old string, then the new map): the same addresses as
/// tesseral_synecdoche(ifs, depth) without pruning, in another order. Refuses what the address
/// tree refuses (count_leaves()).
std::vector<std::string> string_rewriting(const Ifs& ifs, int depth,
                                          AddressSpelling spelling = AddressSpelling::Digits);

/// @brief The tesseral synecdoche algorithm (5.7, with its comparison signs corrected): descend the address
/// tree from the outermost map in, multiplying the probability by p_i; a branch stops, and
/// plots w_address(start), at `depth` or as soon as its probability is below `min_probability`
/// (pv: pieces of the attractor whose measure is below pv are not subdivided further). `start`
/// defaults to the system's start point. Address-prefix jobs, identical for any thread count.
AddressLeaves tesseral_synecdoche(const Ifs& ifs, int depth, double min_probability = 0.0,
                                  const std::vector<double>& start = {}, int threads = 0,
                                  const ProgressCallback& progress = nullptr);

/// @brief w_{a0}(w_{a1}( ... w_{a_{L-1}}(point))).
Point apply_address(const Ifs& ifs, const std::uint16_t* address, int length, const Point& point);

/// @brief "a0.a1.....a_{L-1}" of `length` digits.
std::string address_string(const std::uint16_t* address, int length);

/// @brief Leaves an address tree of `depth` with pruning at `min_probability` has (counted
/// without building it); InputError for a depth outside 1..kMaxAddressDepth or pv outside [0, 1).
std::uint64_t count_leaves(const Ifs& ifs, int depth, double min_probability = 0.0);

}  // namespace ifsforge
