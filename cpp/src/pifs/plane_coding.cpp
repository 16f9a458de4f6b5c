#include "ifsforge/pifs/plane_coding.h"

#include <cmath>
#include <functional>

#include "ifsforge/core/error.h"
#include "ifsforge/pifs/range_coder.h"

namespace ifsforge {
namespace {

constexpr int kLevels = 16;

int bits_for(int count) {  // bits to index `count` values
  int b = 0;
  while ((1 << b) < count) ++b;
  return b;
}

unsigned zigzag(int v) { return v >= 0 ? unsigned(v) * 2 : unsigned(-v) * 2 - 1; }
int unzigzag(unsigned z) { return (z & 1) ? -int((z + 1) / 2) : int(z / 2); }

/// The adaptive models of one plane; encoder and decoder walk the same quadtree with them.
struct Models {
  explicit Models(const PifsCode& code, int pw, int ph)
      : min_log(code.min_log), cells_x(pw >> code.min_log), cells_y(ph >> code.min_log),
        dc_map(std::size_t(cells_x) * cells_y, -1) {
    for (int l = 0; l < kLevels; ++l) {
      s[l].resize(std::size_t(1) << code.s_bits);
      const int nx = std::max(1, domain_count(pw, l)), ny = std::max(1, domain_count(ph, l));
      dx_bits[l] = bits_for(nx);
      dy_bits[l] = bits_for(ny);
      dx[l].resize(std::size_t(1) << dx_bits[l]);
      dy[l].resize(std::size_t(1) << dy_bits[l]);
    }
  }
  /// The mean predicted from the coded neighbours left of and above the block (Step 6's
  /// variable-length code gets short where the image is smooth).
  int predict(const PifsLeaf& leaf, int fallback) const {
    const int cx = leaf.x >> min_log, cy = leaf.y >> min_log;
    const int left = cx > 0 ? dc_map[std::size_t(cy) * cells_x + cx - 1] : -1;
    const int top = cy > 0 ? dc_map[std::size_t(cy - 1) * cells_x + cx] : -1;
    if (left >= 0 && top >= 0) return (left + top + 1) / 2;
    if (left >= 0) return left;
    if (top >= 0) return top;
    return fallback;
  }
  void remember(const PifsLeaf& leaf) {
    const int cx = leaf.x >> min_log, cy = leaf.y >> min_log, n = 1 << (leaf.log_size - min_log);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) dc_map[std::size_t(cy + j) * cells_x + cx + i] = leaf.dc;
  }

  int min_log, cells_x, cells_y;
  std::vector<int> dc_map;
  BitModel split[kLevels];
  std::vector<BitModel> s[kLevels];
  BitModel flat_length[2][32];
  BitModel flat_tail[2][25][24];
  std::vector<BitModel> iso = std::vector<BitModel>(8);
  int dx_bits[kLevels], dy_bits[kLevels];
  std::vector<BitModel> dx[kLevels], dy[kLevels];
};

/// Visits the quadtree of a padded plane in coding order: `node(x, y, log)` returns true when
/// the node is a leaf (it then codes it) and false when it splits.
void walk(const PifsCode& code, int pw, int ph, const std::function<bool(int, int, int)>& node) {
  const int top = 1 << code.max_log;
  std::function<void(int, int, int)> visit = [&](int x, int y, int log) {
    if (node(x, y, log)) return;
    const int h = 1 << (log - 1);
    visit(x, y, log - 1);
    visit(x + h, y, log - 1);
    visit(x, y + h, log - 1);
    visit(x + h, y + h, log - 1);
  };
  for (int y = 0; y < ph; y += top)
    for (int x = 0; x < pw; x += top) visit(x, y, code.max_log);
}

}  // namespace

std::vector<std::uint8_t> encode_plane(const PifsCode& code, const PifsPlane& plane, PifsPlaneCost* cost) {
  const int pw = code.padded(plane.width), ph = code.padded(plane.height);
  Models m(code, pw, ph);
  RangeEncoder rc;
  std::size_t next = 0;
  const int mid = 128 / code.dc_step;
  // Costs are measured as -log2 of each model's probability just before the bit is coded.
  auto price = [&](double& into, const BitModel& model, int bit) {
    if (!cost) return;
    const double p0 = model.p / 2048.0;
    into -= std::log2(bit ? 1.0 - p0 : p0);
  };
  auto tree_cost = [&](double& into, const std::vector<BitModel>& t, int bits, unsigned v) {
    if (!cost) return;
    unsigned node = 1;
    for (int i = bits - 1; i >= 0; --i) {
      const int b = (v >> i) & 1;
      price(into, t[node], b);
      node = node * 2 + b;
    }
  };
  PifsPlaneCost local;
  walk(code, pw, ph, [&](int x, int y, int log) {
    if (next >= plane.leaves.size()) throw InputError("PIFS plane: fewer leaves than the quadtree needs");
    const PifsLeaf& leaf = plane.leaves[next];
    const bool is_leaf = leaf.x == x && leaf.y == y && leaf.log_size == log;
    if (!is_leaf && log <= code.min_log) throw InputError("PIFS plane: leaves do not tile the quadtree");
    if (log > code.min_log) {
      price(local.quadtree, m.split[log], is_leaf ? 0 : 1);
      rc.bit(m.split[log], is_leaf ? 0 : 1);
    }
    if (!is_leaf) return false;
    ++next;
    const unsigned s_symbol = unsigned(leaf.s + code.s_limit());
    tree_cost(local.contrast, m.s[log], code.s_bits, s_symbol);
    rc.tree(m.s[log].data(), code.s_bits, s_symbol);
    const int flat = leaf.s == 0 ? 1 : 0;
    const unsigned z = zigzag(int(leaf.dc) - m.predict(leaf, mid));
    if (cost) {  // the integer code's bits, priced the same way
      unsigned n = 0;
      for (unsigned v = z; v; v >>= 1) ++n;
      for (unsigned i = 0; i < n; ++i) price(local.mean, m.flat_length[flat][i], 1);
      if (n < 24) price(local.mean, m.flat_length[flat][n], 0);
      for (int i = int(n) - 2; i >= 0; --i) price(local.mean, m.flat_tail[flat][n][i], (z >> i) & 1);
    }
    rc.integer(m.flat_length[flat], m.flat_tail[flat], z);
    m.remember(leaf);
    if (leaf.s != 0) {
      tree_cost(local.isometry, m.iso, 3, leaf.isometry);
      rc.tree(m.iso.data(), 3, leaf.isometry);
      tree_cost(local.domain, m.dx[log], m.dx_bits[log], leaf.dx);
      rc.tree(m.dx[log].data(), m.dx_bits[log], leaf.dx);
      tree_cost(local.domain, m.dy[log], m.dy_bits[log], leaf.dy);
      rc.tree(m.dy[log].data(), m.dy_bits[log], leaf.dy);
    }
    return true;
  });
  if (next != plane.leaves.size()) throw InputError("PIFS plane: more leaves than the quadtree holds");
  if (cost) *cost = local;
  return rc.finish();
}

PifsPlane decode_plane(const PifsCode& code, int width, int height, const std::uint8_t* data, std::size_t size,
                       const std::string& where) {
  PifsPlane plane;
  plane.width = width;
  plane.height = height;
  const int pw = code.padded(width), ph = code.padded(height);
  Models m(code, pw, ph);
  RangeDecoder rc(data, size, where);
  const int mid = 128 / code.dc_step;
  const int dc_max = 255 / code.dc_step;
  walk(code, pw, ph, [&](int x, int y, int log) {
    if (log > code.min_log && rc.bit(m.split[log])) return false;
    PifsLeaf leaf;
    leaf.x = std::uint16_t(x);
    leaf.y = std::uint16_t(y);
    leaf.log_size = std::uint8_t(log);
    const int s = int(rc.tree(m.s[log].data(), code.s_bits)) - code.s_limit();
    if (s > code.s_limit()) throw InputError(where + ": corrupt (contrast out of range)");
    leaf.s = std::int8_t(s);
    const int flat = s == 0 ? 1 : 0;
    const int dc = m.predict(leaf, mid) + unzigzag(rc.integer(m.flat_length[flat], m.flat_tail[flat]));
    if (dc < 0 || dc > dc_max) throw InputError(where + ": corrupt (block mean out of range)");
    leaf.dc = std::uint8_t(dc);
    m.remember(leaf);
    if (s != 0) {
      leaf.isometry = std::uint8_t(rc.tree(m.iso.data(), 3));
      const unsigned dx = rc.tree(m.dx[log].data(), m.dx_bits[log]);
      const unsigned dy = rc.tree(m.dy[log].data(), m.dy_bits[log]);
      if (int(dx) >= domain_count(pw, log) || int(dy) >= domain_count(ph, log))
        throw InputError(where + ": corrupt (domain cell outside the plane)");
      leaf.dx = std::uint16_t(dx);
      leaf.dy = std::uint16_t(dy);
    }
    plane.leaves.push_back(leaf);
    return true;
  });
  if (rc.consumed() != size) throw InputError(where + ": corrupt (bytes left after the transforms)");
  return plane;
}

}  // namespace ifsforge
