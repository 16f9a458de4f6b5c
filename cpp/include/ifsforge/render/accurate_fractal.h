#pragma once
/// @file The accurate fractal rendering algorithm (seed 5.10, AFRA) for tile systems.
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// AFRA works on tiles: rectangles whose images under the maps are again axis-aligned
/// rectangles, i.e. systems whose spatial maps have no rotation or shear (x' = sx x + ex,
/// y' = sy y + ey, reflections allowed; the Sierpinski triangle, Cantor dust, ...). The
/// parent block Q is the attractor's box, the exact fixed point of Q -> box(t_1(Q) u ...).
/// Rather than points it carries integrals over tiles: the mass mu and the integrals of x, y
/// and every extra channel g (a gray value, colour ...). At the root they solve the
/// self-similarity equations in closed form (Eq. 68: X = sum p_k ex_k / (1 - sum p_k sx_k), and
/// (I - sum p_k A_gg,k) G = sum p_k (A_gx,k (X, Y) + b_g,k)): the attractor's centroid. A tile
/// with address a1 ... ak is M(Q), M = t_a1 o ... o t_ak, and its integrals follow exactly
/// (Eq. 69 applied k times): mass p_a1 ... p_ak times M(centroid), the integral of an affine
/// function being the function of the mean. With the seed's weights J(t_k) = p_k
/// (probabilities proportional to area, tiles covering the parent) these are Eq. 68-69
/// verbatim. Tiles are split until they fit a pixel (M ~ log4 of the pixel count, Eq. 66 ff.),
/// which then receives their integrals exactly; a tile straddling pixels is split until it is
/// a quarter of a pixel and its integrals shared among the pixels it overlaps in proportion to
/// the area (exact when tiles align with pixels, as the seed notes for power-of-two squares).
/// Raster: density = the measure of each pixel, channels = G / mu (the mean value over the
/// pixel, Eq. 66); points = tiles visited.
class AccurateFractal : public Renderer {
 public:
  std::string name() const override { return "afra"; }
  std::string description() const override {
    return "accurate fractal rendering (5.10): exact tile integrals (Eq. 68-69) for rectangle-preserving maps";
  }
  Capabilities capabilities() const override;

 protected:
  Raster draw(const Ifs& ifs, const RenderOptions& options) const override;
};

}  // namespace ifsforge
