#include "ifsforge/model/super_ifs.h"

#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/model/probabilities.h"

namespace ifsforge {

std::size_t SuperIfs::first_map(std::size_t n) const {
  std::size_t first = 0;
  for (std::size_t k = 0; k < n; ++k) first += sizes[k];
  return first;
}

Ifs make_super_ifs(const std::string& name, const std::vector<Ifs>& members,
                   std::vector<double> probabilities, int variability) {
  if (members.empty()) throw InputError("a super IFS needs at least one member system");
  if (probabilities.empty()) probabilities.assign(members.size(), 1.0);
  if (probabilities.size() != members.size())
    throw InputError(std::to_string(probabilities.size()) + " probabilities for " +
                     std::to_string(members.size()) + " member systems");
  SuperIfs parts;
  std::vector<AffineMap> maps;
  std::vector<double> map_probabilities;
  double total = 0.0;
  for (double p : probabilities) {
    if (!std::isfinite(p) || p < 0.0) throw InputError("the probability of a member system must be a finite number >= 0");
    total += p;
  }
  if (!(total > 0.0)) throw InputError("the member systems' probabilities must sum to a positive number");
  normalise_probabilities(probabilities, total);
  parts.probabilities = probabilities;
  for (std::size_t n = 0; n < members.size(); ++n) {
    const Ifs& member = members[n];
    if (!(member.layout() == members[0].layout()))
      throw InputError("member system " + std::to_string(n + 1) + " ('" + member.name() + "') has layout '" +
                       member.layout().text() + "' but member 1 has '" + members[0].layout().text() + "'");
    if (member.recurrent() || !member.super_ifs().empty() || !member.condensation().empty() || member.polar())
      throw InputError("member system " + std::to_string(n + 1) + " ('" + member.name() +
                       "') must be an ordinary IFS (no transitions, members, condensation set or polar maps)");
    parts.sizes.push_back(member.size());
    parts.names.push_back(member.name());
    for (std::size_t m = 0; m < member.size(); ++m) {
      maps.push_back(member.map(m));
      map_probabilities.push_back(parts.probabilities[n] * member.probabilities()[m]);
    }
  }
  // A member chosen with probability 0 still contributes its maps to the union; give them a
  // tiny weight so that the union's probabilities stay valid.
  double sum = 0.0;
  for (double p : map_probabilities) sum += p;
  for (double& p : map_probabilities) p = std::max(p, 1e-9 * sum);
  parts.variability = variability;
  Ifs combined(name, members[0].layout(), maps, map_probabilities);
  combined.set_super_ifs(parts);
  return combined;
}

Ifs super_member(const Ifs& ifs, std::size_t n) {
  const SuperIfs& parts = ifs.super_ifs();
  if (parts.empty()) {
    if (n == 0) return ifs;
    throw InputError("system '" + ifs.name() + "' is not a super IFS: it has only member 1");
  }
  if (n >= parts.members())
    throw InputError("super IFS '" + ifs.name() + "' has " + std::to_string(parts.members()) +
                     " member systems, not " + std::to_string(n + 1));
  const std::size_t first = parts.first_map(n);
  std::vector<AffineMap> maps(ifs.maps().begin() + first, ifs.maps().begin() + first + parts.sizes[n]);
  std::vector<double> p(ifs.probabilities().begin() + first, ifs.probabilities().begin() + first + parts.sizes[n]);
  Ifs member(parts.names[n], ifs.layout(), maps, p);
  member.set_render_defaults(ifs.render_defaults());
  return member;
}

void Ifs::set_super_ifs(SuperIfs parts) {
  if (parts.empty()) {
    super_ = SuperIfs();
    return;
  }
  std::size_t total = 0;
  for (std::size_t size : parts.sizes) {
    if (size == 0) throw InputError("a member system of super IFS '" + name_ + "' has no maps");
    total += size;
  }
  if (total != maps_.size())
    throw InputError("super IFS '" + name_ + "': its members have " + std::to_string(total) + " maps in all, the system " +
                     std::to_string(maps_.size()));
  if (parts.probabilities.size() != parts.sizes.size())
    throw InputError("super IFS '" + name_ + "': one probability per member system is needed");
  double sum = 0.0;
  for (double p : parts.probabilities) {
    if (!std::isfinite(p) || p < 0.0) throw InputError("super IFS '" + name_ + "': member probabilities must be >= 0");
    sum += p;
  }
  if (!(sum > 0.0)) throw InputError("super IFS '" + name_ + "': member probabilities must sum to a positive number");
  for (double& p : parts.probabilities) p /= sum;
  parts.names.resize(parts.sizes.size());
  for (std::size_t n = 0; n < parts.names.size(); ++n)
    if (parts.names[n].empty()) parts.names[n] = "member " + std::to_string(n + 1);
  if (parts.variability < 1 || parts.variability > 64)
    throw InputError("super IFS '" + name_ + "': the variability V must be 1..64");
  if (recurrent() || !condensation_.empty() || polar())
    throw InputError("system '" + name_ + "': a super IFS cannot also be recurrent, have a condensation set or polar maps");
  super_ = std::move(parts);
}

}  // namespace ifsforge
