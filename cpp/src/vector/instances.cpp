#include "ifsforge/vector/instances.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "address_tree.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/tone_map.h"

namespace ifsforge {

int default_instance_depth(std::size_t maps, std::uint64_t max_instances) {
  if (maps < 2) return 1;
  int depth = 1;
  double count = static_cast<double>(maps);
  while (depth < kMaxAddressDepth && count * maps <= static_cast<double>(max_instances)) {
    count *= maps;
    ++depth;
  }
  return depth;
}

double instance_bytes(int depth) {
  return sizeof(std::array<float, 3>) + sizeof(std::array<float, 9>) + sizeof(float) + sizeof(std::uint16_t) +
         sizeof(std::array<float, 4>) + sizeof(double) + sizeof(std::uint8_t) + sizeof(std::uint16_t) * depth;
}

bool InstanceList::bounds(std::array<double, 3>& lo, std::array<double, 3>& hi) const {
  lo.fill(INFINITY);
  hi.fill(-INFINITY);
  std::vector<double> radius(primitives.size());
  for (std::size_t p = 0; p < primitives.size(); ++p) radius[p] = primitives[p].bounding_radius();
  bool any = false;
  for (std::size_t i = 0; i < size(); ++i) {
    if (!(scales[i] > 0.0f)) continue;
    any = true;
    const double r = scales[i] * radius[primitive[i]];
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], positions[i][c] - r);
      hi[c] = std::max(hi[c], positions[i][c] + r);
    }
  }
  return any;
}

namespace {

// A ten-colour qualitative palette for systems without colour channels.
constexpr float kPalette[][3] = {{0.12f, 0.47f, 0.71f}, {1.00f, 0.50f, 0.05f}, {0.17f, 0.63f, 0.17f},
                                 {0.84f, 0.15f, 0.16f}, {0.58f, 0.40f, 0.74f}, {0.55f, 0.34f, 0.29f},
                                 {0.89f, 0.47f, 0.76f}, {0.50f, 0.50f, 0.50f}, {0.74f, 0.74f, 0.13f},
                                 {0.09f, 0.75f, 0.81f}};
constexpr std::size_t kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

/// Everything a leaf needs besides its node: how to turn channels into a colour and an index,
/// and how to normalise the vector.
struct LeafRules {
  int spatial = 3;
  Normalization normalization = Normalization::Proportional;
  double scale_factor = 1.0, length = 0.0;
  ColorSource color_source = ColorSource::FirstMap;
  ColorModel color_model = ColorModel::None;
  int color_index = -1, alpha_index = -1, k_index = -1;
  std::vector<double> lo, hi;  // per channel (Eq. 101 ranges)
  std::array<float, 4> constant_color{};
  std::size_t primitives = 1;

  bool normalize = true;

  float unit(const Point& p, int channel) const {
    if (!normalize) return static_cast<float>(std::clamp(p[channel], 0.0, 1.0));
    const double range = hi[channel] - lo[channel];
    if (!(range > 0.0)) return 0.5f;
    return static_cast<float>(std::clamp((p[channel] - lo[channel]) / range, 0.0, 1.0));
  }

  std::array<float, 4> color(const Point& p, const std::uint32_t* address, int length) const {
    std::array<float, 4> c{0.0f, 0.0f, 0.0f, 1.0f};
    switch (color_source) {
      case ColorSource::Channels: {
        const int ci = color_index;
        if (color_model == ColorModel::Gray) {
          c[0] = c[1] = c[2] = unit(p, ci);
        } else if (color_model == ColorModel::Hsi) {
          // Hue is an angle: as given, it wraps instead of clamping.
          hsi_to_rgb(normalize ? unit(p, ci) : p[ci], unit(p, ci + 1), unit(p, ci + 2), c.data());
        } else if (color_model == ColorModel::Rgb || color_model == ColorModel::Rgba) {
          for (int k = 0; k < 3; ++k) c[k] = unit(p, ci + k);
        } else {
          c[0] = c[1] = c[2] = 0.8f;  // alpha alone
        }
        if (alpha_index >= 0) c[3] = unit(p, alpha_index);
        return c;
      }
      case ColorSource::FirstMap:
      case ColorSource::LastMap: {
        const std::uint32_t map = color_source == ColorSource::FirstMap ? address[0] : address[length - 1];
        const float* rgb = kPalette[map % kPaletteSize];
        return {rgb[0], rgb[1], rgb[2], 1.0f};
      }
      default:
        return constant_color;
    }
  }

  /// Eq. 99 / 107: the index channel, rounded and wrapped into the primitive list.
  std::uint16_t primitive(const Point& p) const {
    if (k_index < 0 || primitives == 1) return 0;
    const double v = p[k_index];
    if (!std::isfinite(v)) return 0;
    const long long n = static_cast<long long>(primitives);
    long long i = std::llround(std::fmod(v, static_cast<double>(n)));
    i %= n;
    if (i < 0) i += n;
    return static_cast<std::uint16_t>(i);
  }
};

using Vec3 = std::array<double, 3>;

double norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// A unit vector orthogonal to unit `e`.
Vec3 any_perpendicular(const Vec3& e) {
  const Vec3 axis = std::abs(e[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 p = cross(e, axis);
  const double l = norm(p);
  return {p[0] / l, p[1] / l, p[2] / l};
}

/// Whether a tangent of length `l` still carries a direction: not collapsed by a singular map
/// (relative to the other tangent, which shrinks alike under conformal maps).
bool directed(double l, double other) { return l > 1e-290 && l > 1e-12 * other; }

/// The rotation whose first row follows t1 (Eq. 61 with atan2: the normalised vector) and
/// whose second row is the part of t2 orthogonal to it; 2D: e2 is e1 turned by +90 degrees.
void frame_from_tangents(int spatial, const double* t1, const double* t2, float* frame) {
  Vec3 a{t1[0], t1[1], spatial == 3 ? t1[2] : 0.0}, b{t2[0], t2[1], spatial == 3 ? t2[2] : 0.0};
  const double la = norm(a), lb = norm(b);
  Vec3 e1, e2;
  if (spatial == 2) {
    if (directed(la, lb)) {
      e1 = {a[0] / la, a[1] / la, 0};
    } else if (directed(lb, la)) {
      e1 = {b[1] / lb, -b[0] / lb, 0};  // e2 along t2
    } else {
      e1 = {1, 0, 0};
    }
    e2 = {-e1[1], e1[0], 0};
  } else {
    if (directed(la, lb)) {
      e1 = {a[0] / la, a[1] / la, a[2] / la};
    } else if (directed(lb, la)) {
      const Vec3 u{b[0] / lb, b[1] / lb, b[2] / lb};
      e1 = any_perpendicular(u);
    } else {
      e1 = {1, 0, 0};
    }
    const double dot = b[0] * e1[0] + b[1] * e1[1] + b[2] * e1[2];
    Vec3 r{b[0] - dot * e1[0], b[1] - dot * e1[1], b[2] - dot * e1[2]};
    const double lr = norm(r);
    e2 = directed(lr, lb) ? Vec3{r[0] / lr, r[1] / lr, r[2] / lr} : any_perpendicular(e1);
  }
  const Vec3 e3 = cross(e1, e2);
  for (int c = 0; c < 3; ++c) {
    frame[c] = static_cast<float>(e1[c]);
    frame[3 + c] = static_cast<float>(e2[c]);
    frame[6 + c] = static_cast<float>(e3[c]);
  }
}

std::vector<double> spatial_vector(const std::vector<double>& given, int k, const std::string& what) {
  if (static_cast<int>(given.size()) != k)
    throw InputError(what + " needs " + std::to_string(k) + " coordinates, got " + std::to_string(given.size()));
  double l = 0.0;
  for (double v : given) {
    if (!std::isfinite(v)) throw InputError(what + " has a coordinate that is NaN or infinite");
    l += v * v;
  }
  if (!(l > 0.0)) throw InputError(what + " must not be zero");
  return given;
}

}  // namespace

InstanceList instances(const Ifs& ifs, const InstanceOptions& options) {
  ifs.require_affine("an instance list");
  ifs.require_attractor();
  const int k = ifs.spatial_dims(), n = ifs.dim();
  const int depth = options.depth > 0 ? options.depth : default_instance_depth(ifs.size());
  const detail::TreeShape shape = detail::plan_tree(ifs, depth, options.min_probability);
  if (options.primitives.empty()) throw InputError("give at least one primitive");
  if (options.primitives.size() >= kNoMap) throw InputError("at most 65534 primitives");
  for (const auto& p : options.primitives)
    if (p.shape == Shape::Mesh && (!p.mesh || p.mesh->positions.empty()))
      throw InputError("primitive '" + p.name() + "' has no mesh loaded");
  if (!(options.scale_factor > 0.0) || !std::isfinite(options.scale_factor))
    throw InputError("the scale factor sf must be a positive number");
  if (!(options.length >= 0.0) || !std::isfinite(options.length))
    throw InputError("the vector length must be a number >= 0 (0: automatic)");

  // q0, the base vector and the second axis (defaults from the attractor's bounds).
  const Bounds bounds = ifs.attractor_bounds(1u << 18);
  Point q0{};
  if (options.base_point.empty()) {
    for (int c = 0; c < n; ++c) q0[c] = 0.5 * (bounds.lo[c] + bounds.hi[c]);
  } else {
    if (static_cast<int>(options.base_point.size()) != n)
      throw InputError("the base point needs " + std::to_string(n) + " coordinates (layout " + ifs.layout().text() + ")");
    for (int c = 0; c < n; ++c) {
      if (!std::isfinite(options.base_point[c])) throw InputError("the base point has a coordinate that is NaN or infinite");
      q0[c] = options.base_point[c];
    }
  }
  double radius = 0.0;
  for (int c = 0; c < k; ++c) radius += 0.25 * (bounds.hi[c] - bounds.lo[c]) * (bounds.hi[c] - bounds.lo[c]);
  radius = std::sqrt(radius);
  if (!(radius > 0.0)) radius = 1.0;
  std::vector<double> v0(k, 0.0), u0(k, 0.0);
  v0[0] = radius;
  if (!options.base_vector.empty()) v0 = spatial_vector(options.base_vector, k, "the base vector");
  const double v_len = std::sqrt(std::inner_product(v0.begin(), v0.end(), v0.begin(), 0.0));
  if (!options.base_up.empty()) {
    u0 = spatial_vector(options.base_up, k, "the second axis (base up)");
    const double u_len = std::sqrt(std::inner_product(u0.begin(), u0.end(), u0.begin(), 0.0));
    if (std::abs(std::inner_product(u0.begin(), u0.end(), v0.begin(), 0.0)) > (1.0 - 1e-9) * u_len * v_len)
      throw InputError("the second axis (base up) must not be parallel to the base vector");
  } else if (k == 2) {
    u0 = {-v0[1], v0[0]};  // 2D: the vector turned by +90 degrees
  } else {
    // y, or z when the vector runs nearly along y.
    u0[std::abs(v0[1]) > 0.9 * v_len ? 2 : 1] = v_len;
  }

  LeafRules rules;
  rules.spatial = k;
  rules.normalization = options.normalization;
  rules.scale_factor = options.scale_factor;
  rules.length = options.length;
  if (rules.normalization == Normalization::Constant && rules.length == 0.0) {
    double log_sum = 0.0;
    int counted = 0;
    for (double s : ifs.spatial_contraction_factors())
      if (s > 0.0) {
        log_sum += std::log(s);
        ++counted;
      }
    rules.length = v_len * (counted ? std::exp(depth * log_sum / counted) : 1.0);
  }
  const ChannelLayout& layout = ifs.layout();
  rules.color_model = layout.color_model();
  rules.color_index = layout.color_index();
  rules.alpha_index = layout.index("alpha");
  rules.k_index = layout.primitive_index();
  rules.lo = bounds.lo;
  rules.hi = bounds.hi;
  rules.constant_color = options.color;
  rules.normalize = options.normalize_colors;
  rules.primitives = options.primitives.size();
  const bool has_color = rules.color_model != ColorModel::None || rules.alpha_index >= 0;
  rules.color_source = options.color_source;
  if (rules.color_source == ColorSource::Auto) rules.color_source = has_color ? ColorSource::Channels : ColorSource::FirstMap;
  if (rules.color_source == ColorSource::Channels && !has_color)
    throw InputError("layout '" + layout.text() + "' has no color channels to color instances with");

  // Where each job writes; then everything is allocated once.
  const std::vector<std::uint64_t> offsets =
      detail::job_offsets(ifs, shape, options.threads, {instance_bytes(depth), "instances"});
  const std::uint64_t total = offsets.back();

  InstanceList out;
  out.name = ifs.name();
  out.spatial_dims = k;
  out.primitives = options.primitives;
  out.positions.resize(total);
  out.frames.resize(total);
  out.scales.resize(total);
  out.primitive.resize(total);
  out.colors.resize(total);
  AddressTable& table = out.addresses;
  table.depth = depth;
  table.digits.assign(total * depth, kNoMap);
  table.lengths.resize(total);
  table.probabilities.resize(total);

  parallel_jobs(shape.plan.jobs, options.threads, [&](std::size_t job, int) {
    std::uint64_t slot = offsets[job];
    walk_job(ifs, shape.plan, job, detail::ProbabilityStop{options.min_probability}, [&](const RecursionNode& node) {
      const AffineMap& m = node.map;  // w_{a0} o ... o w_{a_{L-1}}
      Point p;
      m.apply(q0.data(), p.data());
      // The pushed vector q1' - q0' and second axis: the linear part on the spatial block (the
      // base vectors have no other channels).
      double t1[3] = {0, 0, 0}, t2[3] = {0, 0, 0};
      for (int r = 0; r < k; ++r)
        for (int c = 0; c < k; ++c) {
          t1[r] += m.a(r, c) * v0[c];
          t2[r] += m.a(r, c) * u0[c];
        }
      out.positions[slot] = {static_cast<float>(p[0]), static_cast<float>(p[1]), k == 3 ? static_cast<float>(p[2]) : 0.0f};
      frame_from_tangents(k, t1, t2, out.frames[slot].data());
      // Eq. 60: d = sf |q1' - q0'| (proportional) or the constant length.
      out.scales[slot] = static_cast<float>(rules.normalization == Normalization::Constant
                                                ? rules.length
                                                : rules.scale_factor * std::sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]));
      out.primitive[slot] = rules.primitive(p);
      out.colors[slot] = rules.color(p, node.address, node.length);
      std::copy(node.address, node.address + node.length, table.digits.begin() + slot * depth);
      table.lengths[slot] = static_cast<std::uint8_t>(node.length);
      table.probabilities[slot] = node.mass;
      ++slot;
    });
  }, options.progress);
  return out;
}

}  // namespace ifsforge
