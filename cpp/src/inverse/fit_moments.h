#pragma once
// The structural candidates of the planar cover start: pieces of the target (its parts once small
// gaps are closed, and its k-means clusters) and, for each, the similarities that carry the whole
// target's second moments onto the piece's (each piece of an attractor is a copy of the whole, Eq. 41);
// and the copies a symmetric target's copies imply.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ifsforge {

/// Centroid and covariance of a set of plane points.
struct Moments {
  std::array<double, 2> centroid{0, 0};
  double xx = 0, xy = 0, yy = 0;
  /// The principal axis' angle (radians, modulo pi) of the covariance ellipse.
  double axis() const;
  /// Trace of the covariance: a similarity of scale s multiplies it by s^2.
  double spread() const { return xx + yy; }
};

Moments moments_of(const std::vector<std::array<double, 2>>& points);

/// decode_map parameters (signed scales, turns, translation) of the similarities w with
/// w(whole) having the piece's centroid, spread and principal axis: the axis taken both ways and
/// with and without a mirror, and `turns` turns over the full circle besides (for a round piece,
/// whose axis means little): 2 (4 + turns) maps, the scale clamped to [0.05, max_contraction].
std::vector<std::array<double, 6>> moment_maps(const Moments& whole, const Moments& piece, double max_contraction,
                                               int turns);

/// decode_map parameters of the affine map w(x) = P^(1/2) Q W^(-1/2) (x - c_W) + c_P that carries
/// the whole's centroid and covariance ellipse exactly onto the piece's, Q the turn `angle`
/// (radians) after a mirror in x when `mirror`: every Q does, Q picks how the whole lies in the
/// piece. Unlike moment_maps' similarities it squashes the whole into a long, thin piece, as a
/// drawn letter's strokes are thin copies of the letter (Eq. 5 has two scales and two turns).
std::array<double, 6> ellipse_map(const Moments& whole, const Moments& piece, double angle, bool mirror);

/// The copies of a cover (`x0`, similarities) carried by the symmetries the target may have:
/// reflected in either principal axis of `whole` through its centroid, and turned half a turn
/// about it. A symmetric target's copies come in such pairs (a leaf's two side branches, a
/// terdragon's turned ends), which the lattice finds only roughly.
std::vector<std::array<double, 6>> symmetric_copies(const std::vector<double>& x0, const Moments& whole);

/// `mask` (w x h) grown by one cell each way (Chebyshev), its border row and column left as they are.
std::vector<std::uint8_t> grow_cells(const std::vector<std::uint8_t>& mask, int w, int h);

/// The 8-connected parts of `grown` (a w x h mask), each as the indices of its cells set in `on`,
/// largest first, at most `most` of them; none when `grown` is in one part.
std::vector<std::vector<std::size_t>> mask_parts(const std::vector<std::uint8_t>& grown,
                                                 const std::vector<std::uint8_t>& on, int w, int h, std::size_t most);

}  // namespace ifsforge
